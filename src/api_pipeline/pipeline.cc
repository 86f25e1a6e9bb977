// SPDX-License-Identifier: LGPL-2.1-only
// ml_pipeline_construct/destroy/get_state/start/stop/flush, the registry of live pipelines and
// handles, and the bus handler that reports state changes and keeps the last error.
#include <set>
#include <unordered_map>

#include "api_pipeline/pipeline_internal.h"

namespace nns::capi {

GST_DEBUG_CATEGORY(capi_debug);

namespace {

std::mutex g_mu;
std::set<Pipeline *> g_pipes;
std::unordered_map<void *, Handle *> g_handles;
std::atomic<uint64_t> g_next_id{1};
thread_local Pipeline *t_state_cb_pipe = nullptr;

NodeKind kind_of(const std::string &factory, bool *known) {
  *known = true;
  if (factory == "tensor_sink") return NodeKind::kTensorSink;
  if (factory == "appsink") return NodeKind::kAppSink;
  if (factory == "appsrc") return NodeKind::kAppSrc;
  if (factory == "valve") return NodeKind::kValve;
  if (factory == "input-selector") return NodeKind::kInputSelector;
  if (factory == "output-selector") return NodeKind::kOutputSelector;
  *known = factory == "tensor_filter" || factory == "tensor_if";
  return NodeKind::kCommon;
}

GstBusSyncReply on_bus(GstBus *, GstMessage *msg, gpointer user) {
  auto *p = static_cast<Pipeline *>(user);
  switch (GST_MESSAGE_TYPE(msg)) {
    case GST_MESSAGE_EOS:
      p->eos = true;
      break;
    case GST_MESSAGE_ERROR: {
      GError *err = nullptr;
      gchar *dbg = nullptr;
      gst_message_parse_error(msg, &err, &dbg);
      std::string text = std::string(GST_MESSAGE_SRC_NAME(msg) ? GST_MESSAGE_SRC_NAME(msg) : "?") +
                         ": " + (err ? err->message : "error") +
                         (dbg ? std::string(" (") + dbg + ")" : "");
      g_clear_error(&err);
      g_free(dbg);
      GST_CAT_WARNING(capi_debug, "%s: %s", p->describe().c_str(), text.c_str());
      std::lock_guard lk(p->err_mu);
      if (p->last_error.empty()) p->last_error = std::move(text);  // the first says most
      break;
    }
    case GST_MESSAGE_STATE_CHANGED:
      if (GST_MESSAGE_SRC(msg) == GST_OBJECT_CAST(p->bin)) {
        GstState olds, news;
        gst_message_parse_state_changed(msg, &olds, &news, nullptr);
        p->state = static_cast<int>(news);
        std::lock_guard lk(p->state_mu);
        if (p->state_cb) {
          Pipeline *prev = t_state_cb_pipe;
          t_state_cb_pipe = p;
          p->state_cb(static_cast<ml_pipeline_state_e>(news), p->state_user);
          t_state_cb_pipe = prev;
        }
      }
      break;
    default:
      break;
  }
  // Nobody pops this bus: drop every message once seen (a sync handler that drops a message
  // owns it and must unref it).
  gst_message_unref(msg);
  return GST_BUS_DROP;
}

// Adds a node for every element the API can address by type (sinks, sources, valves,
// selectors) and for tensor_filter/tensor_if (custom references).
void collect_nodes(Pipeline *p) {
  GstIterator *it = gst_bin_iterate_recurse(GST_BIN(p->bin));
  GValue item = G_VALUE_INIT;
  bool done = false;
  while (!done) {
    switch (gst_iterator_next(it, &item)) {
      case GST_ITERATOR_OK: {
        auto *e = GST_ELEMENT(g_value_get_object(&item));
        GstElementFactory *f = gst_element_get_factory(e);
        std::string factory = f ? GST_OBJECT_NAME(f) : "";
        bool known = false;
        NodeKind k = kind_of(factory, &known);
        gchar *name = gst_element_get_name(e);
        if (known && name && !p->nodes.count(name)) {
          auto n = std::make_unique<Node>();
          n->pipe = p;
          n->element = GST_ELEMENT(gst_object_ref(e));
          n->name = name;
          n->factory = factory;
          n->kind = k;
          if (factory == "tensor_filter") {
            gchar *fw = nullptr, *model = nullptr;
            g_object_get(e, "framework", &fw, "model", &model, nullptr);
            if (fw && model && g_ascii_strcasecmp(fw, "custom-easy") == 0 &&
                custom_easy_known(model)) {
              n->custom_easy = model;
              custom_easy_ref(model, +1);
            }
            g_free(fw);
            g_free(model);
          } else if (factory == "tensor_if") {
            gchar *opt = nullptr;
            g_object_get(e, "compared-value-option", &opt, nullptr);
            if (opt && if_custom_known(opt)) {
              n->if_custom = opt;
              if_custom_ref(opt, +1);
            }
            g_free(opt);
          }
          p->nodes.emplace(n->name, std::move(n));
        }
        g_free(name);
        g_value_reset(&item);
        break;
      }
      case GST_ITERATOR_RESYNC:
        gst_iterator_resync(it);
        break;
      case GST_ITERATOR_ERROR:
      case GST_ITERATOR_DONE:
        done = true;
        break;
    }
  }
  g_value_unset(&item);
  gst_iterator_free(it);
}

// Frees everything of a pipeline that is no longer in the registry.
void teardown(Pipeline *p) {
  // No sink or src callback after this point; running ones finish first.
  for (auto &[name, n] : p->nodes) {
    close_sinks(n.get());
    for (Handle *h : n->handles)
      if (h->kind == HandleKind::kSrc) close_src(h);
  }
  {
    std::lock_guard lk(p->state_mu);
    p->state_cb = nullptr;
  }
  if (p->bin) {
    gst_element_set_state(p->bin, GST_STATE_NULL);
    GstBus *bus = gst_element_get_bus(p->bin);
    gst_bus_set_sync_handler(bus, nullptr, nullptr, nullptr);
    gst_object_unref(bus);
  }
  {
    std::unique_lock lk(p->use_mu);
    p->dying = true;
    p->use_cv.wait(lk, [p] { return p->uses == 0; });
  }
  for (auto &[name, n] : p->nodes) {
    for (Handle *h : n->handles) delete h;  // sink handles already went with close_sinks()
    for (Handle *h : n->retired) delete h;
    if (!n->custom_easy.empty()) custom_easy_ref(n->custom_easy, -1);
    if (!n->if_custom.empty()) if_custom_ref(n->if_custom, -1);
    gst_object_unref(n->element);
  }
  p->nodes.clear();
  if (p->bin) gst_object_unref(p->bin);
  p->magic = 0;
  delete p;
}

int set_state(Pipeline *p, GstState s, const char *func) {
  p->take_error();
  GstStateChangeReturn r = gst_element_set_state(p->bin, s);
  if (r == GST_STATE_CHANGE_FAILURE) {
    std::string why = p->take_error();
    return fail(ML_ERROR_STREAMS_PIPE,
                std::string(func) + ": " + p->describe() + " cannot go to " +
                    gst_element_state_get_name(s) +
                    (why.empty() ? std::string(" (no error was posted)") : ": " + why));
  }
  return ML_ERROR_NONE;
}

}  // namespace

const char *handle_kind_name(HandleKind k) {
  switch (k) {
    case HandleKind::kSink:
      return "sink";
    case HandleKind::kSrc:
      return "src";
    case HandleKind::kSwitch:
      return "switch";
    case HandleKind::kValve:
      return "valve";
    case HandleKind::kElement:
      return "element";
  }
  return "?";
}

std::string Pipeline::describe() const {
  return "pipeline #" + std::to_string(id);
}

std::string Pipeline::take_error() {
  std::lock_guard lk(err_mu);
  std::string s = std::move(last_error);
  last_error.clear();
  return s;
}

std::mutex &registry_lock() {
  return g_mu;
}

int fail(int code, const std::string &msg) {
  if (capi_debug) GST_CAT_INFO(capi_debug, "%s", msg.c_str());
  return api::report(code, msg);
}

int ensure_gst(const char *func) {
  static std::once_flag once;
  static std::string init_error;
  std::call_once(once, [] {
    GError *err = nullptr;
    if (!gst_init_check(nullptr, nullptr, &err)) {
      init_error = err ? err->message : "unknown reason";
      g_clear_error(&err);
      return;
    }
    GST_DEBUG_CATEGORY_INIT(capi_debug, "nnstreamer-capi", 0, "ML Pipeline API");
  });
  if (!init_error.empty())
    return fail(ML_ERROR_STREAMS_PIPE,
                std::string(func) + ": GStreamer cannot be initialised: " + init_error);
  return ML_ERROR_NONE;
}

Pipeline *live_pipeline(ml_pipeline_h h, const char *func) {
  auto *p = static_cast<Pipeline *>(h);
  if (!p) {
    fail(ML_ERROR_INVALID_PARAMETER, std::string(func) + ": the pipeline handle (pipe) is NULL");
    return nullptr;
  }
  if (!g_pipes.count(p)) {
    fail(ML_ERROR_INVALID_PARAMETER,
         std::string(func) +
             ": pipe is not a live pipeline handle (destroyed, or not made by "
             "ml_pipeline_construct)");
    return nullptr;
  }
  return p;
}

Handle *live_handle(void *h, HandleKind want, const char *func, const char *arg) {
  if (!h) {
    fail(ML_ERROR_INVALID_PARAMETER, std::string(func) + ": the " + arg + " handle is NULL");
    return nullptr;
  }
  auto it = g_handles.find(h);
  if (it == g_handles.end()) {
    fail(ML_ERROR_INVALID_PARAMETER,
         std::string(func) + ": " + arg +
             " is not a live handle (already released or unregistered, or its pipeline was "
             "destroyed)");
    return nullptr;
  }
  Handle *x = it->second;
  if (x->kind != want) {
    fail(ML_ERROR_INVALID_PARAMETER,
         std::string(func) + ": " + arg + (x->kind == HandleKind::kElement ? " is an " : " is a ") +
             handle_kind_name(x->kind) + " handle of " + x->node->factory + " '" + x->node->name +
             "' in " + x->pipe->describe() + ", not " +
             (want == HandleKind::kElement ? "an " : "a ") + handle_kind_name(want) + " handle");
    return nullptr;
  }
  return x;
}

void add_handle(Handle *h) {
  g_handles[h] = h;
  h->node->handles.push_back(h);
}

void remove_handle(Handle *h) {
  g_handles.erase(h);
  auto &v = h->node->handles;
  for (auto it = v.begin(); it != v.end(); ++it)
    if (*it == h) {
      v.erase(it);
      break;
    }
}

Use::Use(Pipeline *p) : p_(p) {
  std::lock_guard lk(p->use_mu);
  ++p->uses;
}

Use::~Use() {
  std::lock_guard lk(p_->use_mu);
  if (--p_->uses == 0 && p_->dying) p_->use_cv.notify_all();
}

void fill_info_handle(api::TensorsInfoHandle &h, const TensorsInfo &info) {
  h.info = info;
  h.extended = false;
  for (const auto &t : info.tensors)
    if (t.rank() > 4) h.extended = true;
}

}  // namespace nns::capi

using namespace nns;
using namespace nns::capi;

NNS_CAPI int ml_pipeline_construct(const char *pipeline_description, ml_pipeline_state_cb cb,
                                   void *user_data, ml_pipeline_h *pipe) {
  constexpr const char *F = "ml_pipeline_construct";
  if (!pipe)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": pipe (the output) is NULL");
  *pipe = nullptr;
  if (!pipeline_description)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": pipeline_description is NULL");
  if (int rc = ensure_gst(F); rc != ML_ERROR_NONE) return rc;

  GError *err = nullptr;
  GstElement *top =
      gst_parse_launch_full(pipeline_description, nullptr, GST_PARSE_FLAG_FATAL_ERRORS, &err);
  if (!top || err) {
    std::string why = err ? err->message : "unknown reason";
    bool no_element = err && g_error_matches(err, GST_PARSE_ERROR, GST_PARSE_ERROR_NO_SUCH_ELEMENT);
    g_clear_error(&err);
    if (top) gst_object_unref(top);
    return fail(ML_ERROR_STREAMS_PIPE,
                std::string(F) + ": cannot build the pipeline \"" + pipeline_description +
                    "\": " + why +
                    (no_element ? " (unknown element name; gst-inspect-1.0 lists the "
                                  "elements this system has)"
                                : ""));
  }
  if (!GST_IS_PIPELINE(top)) {  // a one-element description gives the element itself
    GstElement *bin = gst_pipeline_new(nullptr);
    gst_bin_add(GST_BIN(bin), top);
    top = bin;
  }

  auto *p = new Pipeline();
  p->id = g_next_id++;
  p->bin = top;
  p->state_cb = cb;
  p->state_user = user_data;
  GstBus *bus = gst_element_get_bus(top);
  gst_bus_set_sync_handler(bus, on_bus, p, nullptr);
  gst_object_unref(bus);
  {
    std::lock_guard lk(g_mu);
    collect_nodes(p);
  }
  int rc = set_state(p, GST_STATE_PAUSED, F);
  if (rc != ML_ERROR_NONE) {
    teardown(p);
    return rc;
  }
  // Let the preroll finish so properties and caps are ready: 10 ms as NNStreamer waits; a
  // pipeline without appsrc prerolls by itself, so it gets up to 1 s more (the documented
  // post-condition is PAUSED; a loaded machine can need more than 10 ms). An appsrc pipeline
  // cannot preroll before the application pushes data, and a live one does not preroll.
  if (gst_element_get_state(top, nullptr, nullptr, 10 * GST_MSECOND) == GST_STATE_CHANGE_ASYNC) {
    bool has_appsrc = false;
    for (auto &[name, n] : p->nodes) has_appsrc = has_appsrc || n->kind == NodeKind::kAppSrc;
    if (!has_appsrc) gst_element_get_state(top, nullptr, nullptr, GST_SECOND);
  }
  {
    std::lock_guard lk(g_mu);
    g_pipes.insert(p);
  }
  *pipe = p;
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_destroy(ml_pipeline_h pipe) {
  constexpr const char *F = "ml_pipeline_destroy";
  Pipeline *p;
  {
    std::lock_guard lk(g_mu);
    p = live_pipeline(pipe, F);
    if (!p) return ML_ERROR_INVALID_PARAMETER;
    if (dispatching_pipeline() == p)
      return fail(ML_ERROR_STREAMS_PIPE,
                  std::string(F) + ": " + p->describe() +
                      " cannot be destroyed from its own sink callback (a streaming thread "
                      "of the pipeline); destroy it from another thread");
    if (t_state_cb_pipe == p)
      return fail(ML_ERROR_STREAMS_PIPE, std::string(F) + ": " + p->describe() +
                                             " cannot be destroyed from its own state callback");
    g_pipes.erase(p);
    for (auto &[name, n] : p->nodes)
      for (Handle *h : n->handles) g_handles.erase(h);
  }
  teardown(p);
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_get_state(ml_pipeline_h pipe, ml_pipeline_state_e *state) {
  constexpr const char *F = "ml_pipeline_get_state";
  if (!state) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": state is NULL");
  *state = ML_PIPELINE_STATE_UNKNOWN;
  std::unique_lock lk(g_mu);
  Pipeline *p = live_pipeline(pipe, F);
  if (!p) return ML_ERROR_INVALID_PARAMETER;
  Use use(p);
  lk.unlock();
  GstState cur = GST_STATE_VOID_PENDING;
  if (gst_element_get_state(p->bin, &cur, nullptr, GST_MSECOND) == GST_STATE_CHANGE_FAILURE) {
    std::string why = p->take_error();
    return fail(ML_ERROR_STREAMS_PIPE, std::string(F) + ": " + p->describe() +
                                           " failed a state change" +
                                           (why.empty() ? "" : ": " + why));
  }
  *state = static_cast<ml_pipeline_state_e>(cur);
  return ML_ERROR_NONE;
}

namespace {

int change_state(ml_pipeline_h pipe, GstState s, const char *func) {
  std::unique_lock lk(g_mu);
  Pipeline *p = live_pipeline(pipe, func);
  if (!p) return ML_ERROR_INVALID_PARAMETER;
  Use use(p);
  lk.unlock();
  return set_state(p, s, func);
}

}  // namespace

NNS_CAPI int ml_pipeline_start(ml_pipeline_h pipe) {
  return change_state(pipe, GST_STATE_PLAYING, "ml_pipeline_start");
}

NNS_CAPI int ml_pipeline_stop(ml_pipeline_h pipe) {
  return change_state(pipe, GST_STATE_PAUSED, "ml_pipeline_stop");
}

NNS_CAPI int ml_pipeline_flush(ml_pipeline_h pipe, bool start) {
  constexpr const char *F = "ml_pipeline_flush";
  std::unique_lock lk(g_mu);
  Pipeline *p = live_pipeline(pipe, F);
  if (!p) return ML_ERROR_INVALID_PARAMETER;
  Use use(p);
  lk.unlock();
  if (int rc = set_state(p, GST_STATE_PAUSED, F); rc != ML_ERROR_NONE) return rc;
  if (!gst_element_send_event(p->bin, gst_event_new_flush_start()))
    GST_CAT_WARNING(capi_debug, "%s: flush-start was not handled", p->describe().c_str());
  if (!gst_element_send_event(p->bin, gst_event_new_flush_stop(TRUE)))
    GST_CAT_WARNING(capi_debug, "%s: flush-stop was not handled", p->describe().c_str());
  return start ? set_state(p, GST_STATE_PLAYING, F) : ML_ERROR_NONE;
}

// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_filter
 *
 * Runs a neural network model on each tensor frame. The framework (filter back end) is
 * built in (custom, custom-easy, cpp) or loaded from libnnstreamer_filter_<name>.so in the
 * folders of nnstreamer.ini / NNSTREAMER_FILTERS; framework=auto picks it from the model file
 * extension. Caps come from the model when it knows its shapes; input=/output= (+ types)
 * override them and are checked against the model.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=224,height=224 !
 *     tensor_converter ! tensor_filter framework=onnxruntime model=mobilenet.onnx ! tensor_sink
 *
 * See docs/elements/tensor_filter.md for every property.
 */
#include <gst/base/gstbasetransform.h>

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>

#include "core/error.h"
#include "core/filter_registry.h"
#include "gst/config_file.h"
#include "gst/element_glue.h"
#include "gst/filter_async.h"
#include "gst/filter_engine.h"
#include "gst/filter_properties.h"
#include "gst/filter_settings.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_filter_debug);
#define GST_CAT_DEFAULT tensor_filter_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_FILTER (gst_tensor_filter_get_type())
G_DECLARE_FINAL_TYPE(GstTensorFilter, gst_tensor_filter, GST, TENSOR_FILTER, GstBaseTransform)
G_END_DECLS

namespace {

using nns::gst::FilterSettings;

constexpr const char *kUpdateModelEvent = "evt_update_model";

struct FilterPriv {
  explicit FilterPriv(GstBaseTransform *self) : engine(self) {}

  std::mutex settings_mu;
  FilterSettings settings;
  std::vector<std::string> config_problems;
  std::string last_caps_error;  // streaming thread only

  std::mutex engine_mu;  // start/stop/caps/transform/reload
  nns::gst::FilterEngine engine;
  // Settings whose model could not be opened for a caps query before start (engine_mu): not
  // retried on every query; start() opens again and reports the error.
  std::optional<FilterSettings> query_open_failed;
  bool started = false;  // between start() and stop() (engine_mu)

  // invoke-async (nullptr when off or unsupported); set in start, cleared in stop.
  // async_on lets the per-buffer path skip the lock when invoke-async is off.
  std::mutex async_mu;
  std::shared_ptr<nns::gst::AsyncDispatcher> async;
  std::atomic<bool> async_on{false};

  std::mutex info_mu;  // snapshots for get_property
  nns::TensorsInfo in_info, out_info;
  // The framework framework=auto chose when the model was opened (read back as `framework`,
  // as NNStreamer); cleared when framework or model change.
  std::string chosen_framework;

  // suspend=
  std::thread suspend_thread;
  std::mutex suspend_mu;
  std::condition_variable suspend_cv;
  bool suspend_stop = false;
};

using nns::gst::FilterProp;

}  // namespace

struct _GstTensorFilter {
  GstBaseTransform parent;
  FilterPriv *priv;
};

G_DEFINE_TYPE(GstTensorFilter, gst_tensor_filter, GST_TYPE_BASE_TRANSFORM)
GST_ELEMENT_REGISTER_DEFINE(tensor_filter, "tensor_filter", GST_RANK_NONE, GST_TYPE_TENSOR_FILTER)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_TENSOR_CAPS_ANY_STR));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_TENSOR_CAPS_ANY_STR));

static void update_profiling(GstTensorFilter *self) {
  FilterPriv *p = self->priv;
  FilterSettings s;
  {
    std::lock_guard lk(p->settings_mu);
    s = p->settings;
  }
  p->engine.set_profiling(s.latency_mode > 0, s.throughput_mode > 0, s.latency_report);
}

// is-updatable: a new model while running is loaded into the open instance. A model that
// cannot be loaded, or whose tensors differ from the negotiated ones, is refused: the old model
// stays loaded and running, `model` reads the old value again, and a WARNING message (not an
// error: the stream goes on; NNStreamer only logs it) says which model and why.
static void reload_model(GstTensorFilter *self, const std::string &model,
                         const std::string &old_model) {
  FilterPriv *p = self->priv;
  std::string refused;
  nns::gst::guard_void(self, [&] {
    std::lock_guard lk(p->engine_mu);
    if (!p->started || !p->engine.is_open()) return;  // opened for a query only: reopened
    GST_INFO_OBJECT(self, "reloading model %s", model.c_str());
    try {
      p->engine.reload(nns::gst::split_models(model));
    } catch (const nns::Error &e) {
      refused = e.what();
    }
  });
  if (refused.empty()) return;
  {
    std::lock_guard lk(p->settings_mu);
    if (p->settings.model == model) p->settings.model = old_model;
  }
  NNS_POST_WARNING(
      self, "is-updatable: reload refused, still running model '" + old_model + "': " + refused);
}

static void gst_tensor_filter_set_property(GObject *object, guint id, const GValue *value,
                                           GParamSpec *pspec) {
  auto *self = GST_TENSOR_FILTER(object);
  FilterPriv *p = self->priv;
  const auto prop = static_cast<FilterProp>(id);
  std::string config_path;
  bool reload = false;
  std::string new_model, old_model;
  {
    std::lock_guard lk(p->settings_mu);
    FilterSettings &s = p->settings;
    if (std::string *str = nns::gst::string_setting(s, g_param_spec_get_name(pspec))) {
      const gchar *v = g_value_get_string(value);
      std::string nv = v ? v : "";
      if (prop == FilterProp::kFramework && nv.empty()) nv = "auto";
      if ((prop == FilterProp::kFramework || prop == FilterProp::kModel) && nv != *str) {
        std::lock_guard ilk(p->info_mu);
        p->chosen_framework.clear();
      }
      if (prop == FilterProp::kModel && s.is_updatable && nv != s.model) {
        reload = true;
        new_model = nv;
        old_model = s.model;
      }
      *str = nv;
      if (prop == FilterProp::kConfigFile) config_path = nv;
    } else if (!nns::gst::set_filter_value(s, id, value)) {
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
      return;
    }
  }
  if (prop == FilterProp::kLatency || prop == FilterProp::kThroughput ||
      prop == FilterProp::kLatencyReport)
    update_profiling(self);
  if (reload) reload_model(self, new_model, old_model);
  if (!config_path.empty()) {
    // Applied now, as NNStreamer does; problems are posted when the element starts.
    auto problems = nns::gst::apply_config_file(object, config_path);
    std::lock_guard lk(p->settings_mu);
    p->config_problems = std::move(problems);
  }
}

static void set_info_string(GValue *value, const nns::TensorsInfo &info, const std::string &user,
                            int what) {
  if (info.size() == 0) {
    g_value_set_string(value, user.c_str());
    return;
  }
  std::string s = what == 0   ? info.dims_string()
                  : what == 1 ? info.types_string()
                              : info.names_string();
  g_value_set_string(value, s.c_str());
}

static std::string framework_readback(FilterPriv *p, const FilterSettings &s);

static void gst_tensor_filter_get_property(GObject *object, guint id, GValue *value,
                                           GParamSpec *pspec) {
  auto *self = GST_TENSOR_FILTER(object);
  FilterPriv *p = self->priv;
  FilterSettings s;
  {
    std::lock_guard lk(p->settings_mu);
    s = p->settings;
  }
  nns::TensorsInfo in, out;
  {
    std::lock_guard lk(p->info_mu);
    in = p->in_info;
    out = p->out_info;
  }
  const auto prop = static_cast<FilterProp>(id);
  switch (prop) {
    case FilterProp::kInput:
      set_info_string(value, in, s.input, 0);
      break;
    case FilterProp::kInputType:
      set_info_string(value, in, s.inputtype, 1);
      break;
    case FilterProp::kInputName:
      set_info_string(value, in, s.inputname, 2);
      break;
    case FilterProp::kOutput:
      set_info_string(value, out, s.output, 0);
      break;
    case FilterProp::kOutputType:
      set_info_string(value, out, s.outputtype, 1);
      break;
    case FilterProp::kOutputName:
      set_info_string(value, out, s.outputname, 2);
      break;
    case FilterProp::kInputLayout:
    case FilterProp::kOutputLayout: {
      bool is_in = prop == FilterProp::kInputLayout;
      const std::string &user = is_in ? s.inputlayout : s.outputlayout;
      std::size_t n = (is_in ? in : out).size();
      g_value_set_string(
          value,
          n ? nns::gst::layouts_string(nns::gst::parse_layouts(user), n).c_str() : user.c_str());
      break;
    }
    case FilterProp::kInputRanks:
    case FilterProp::kOutputRanks: {
      nns::TensorsInfo info = prop == FilterProp::kInputRanks ? in : out;
      if (info.size() == 0) {
        try {
          info = prop == FilterProp::kInputRanks
                     ? nns::gst::parse_tensor_props(s.input, s.inputtype, "", "input")
                     : nns::gst::parse_tensor_props(s.output, s.outputtype, "", "output");
        } catch (const nns::Error &) {
          info = nns::TensorsInfo{};
        }
      }
      g_value_set_string(value, nns::gst::ranks_string(info).c_str());
      break;
    }
    case FilterProp::kSubPlugins:
      g_value_set_string(value, nns::gst::available_filters().c_str());
      break;
    case FilterProp::kLatency:
      g_value_set_int(value, s.latency_mode > 0 ? p->engine.stats().latency_us() : -1);
      break;
    case FilterProp::kThroughput:
      g_value_set_int(value, s.throughput_mode > 0 ? p->engine.stats().throughput() : -1);
      break;
    case FilterProp::kFramework:
      g_value_set_string(value, framework_readback(p, s).c_str());
      break;
    default:
      if (std::string *str = nns::gst::string_setting(s, g_param_spec_get_name(pspec)))
        g_value_set_string(value, str->c_str());
      else if (!nns::gst::get_filter_value(s, id, value))
        G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static std::shared_ptr<nns::gst::AsyncDispatcher> get_async(FilterPriv *p) {
  if (!p->async_on.load(std::memory_order_acquire)) return nullptr;
  std::lock_guard lk(p->async_mu);
  return p->async;
}

// Closes the dispatcher: later dispatches of the back end return -ESHUTDOWN.
static void stop_async(FilterPriv *p) {
  std::shared_ptr<nns::gst::AsyncDispatcher> d;
  {
    std::lock_guard lk(p->async_mu);
    d = std::move(p->async);
    p->async_on.store(false, std::memory_order_release);
  }
  if (d) d->close();
}

// invoke-async=true: outputs go through a dispatcher when the back end supports it; otherwise
// the filter invokes synchronously and says so on the bus.
static void start_async(GstTensorFilter *self) {
  FilterPriv *p = self->priv;
  if (!p->engine.async_supported()) {
    NNS_POST_WARNING(self, "invoke-async=true, but framework '" + p->engine.instance()->name() +
                               "' does not support asynchronous invoke (no invoke_async); "
                               "invoking synchronously, one output per input");
    return;
  }
  auto d = nns::gst::AsyncDispatcher::create(GST_BASE_TRANSFORM(self));
  p->engine.set_async(d);
  std::lock_guard lk(p->async_mu);
  p->async = std::move(d);
  p->async_on.store(true, std::memory_order_release);
}

static void update_info_snapshot(GstTensorFilter *self) {
  FilterPriv *p = self->priv;
  nns::TensorsInfo in = p->engine.current_input(), out = p->engine.current_output();
  std::string chosen = p->engine.is_open() ? p->engine.instance()->name() : std::string();
  std::lock_guard lk(p->info_mu);
  p->in_info = std::move(in);
  p->out_info = std::move(out);
  if (!chosen.empty()) p->chosen_framework = std::move(chosen);
}

static bool is_auto_framework(const std::string &fw) {
  return fw.empty() || g_ascii_strcasecmp(fw.c_str(), "auto") == 0;
}

// What `framework` reads back: the name given, or for framework=auto the framework chosen when
// the model was opened, else the one the model's extension selects now (NNStreamer detects it
// when the properties are set), else "auto".
static std::string framework_readback(FilterPriv *p, const FilterSettings &s) {
  if (!is_auto_framework(s.framework)) return s.framework;
  {
    std::lock_guard lk(p->info_mu);
    if (!p->chosen_framework.empty()) return p->chosen_framework;
  }
  if (s.model.empty()) return s.framework;
  try {
    auto conf = nns::current_filter_conf();
    nns::BackendRef be =
        nns::FilterRegistry::get().resolve("auto", nns::gst::split_models(s.model), *conf);
    if (be.iface && be.iface->name) return be.iface->name;
  } catch (const std::exception &) {
    // No framework for this model (yet): start() reports why.
  }
  return s.framework;
}

static void stop_suspend_thread(FilterPriv *p) {
  if (!p->suspend_thread.joinable()) return;
  {
    std::lock_guard lk(p->suspend_mu);
    p->suspend_stop = true;
  }
  p->suspend_cv.notify_all();
  p->suspend_thread.join();
}

// suspend=N: after N ms without data the model is suspended (NNS_FILTER_EVENT_SUSPEND or
// closed); the next buffer resumes it.
static void start_suspend_thread(GstTensorFilter *self, uint32_t ms) {
  FilterPriv *p = self->priv;
  auto inst = p->engine.instance();
  p->suspend_stop = false;
  inst->track_use();  // idle time is the instance's: shared instances count every user
  auto period = std::chrono::milliseconds(std::max<uint32_t>(1, std::min<uint32_t>(ms / 4, 100)));
  p->suspend_thread = std::thread([self, p, inst, ms, period] {
    std::unique_lock lk(p->suspend_mu);
    while (!p->suspend_cv.wait_for(lk, period, [p] { return p->suspend_stop; })) {
      if (inst->idle_us() < static_cast<int64_t>(ms) * 1000 || inst->suspended()) continue;
      GST_INFO_OBJECT(self, "idle for %u ms: suspending %s", ms, inst->describe().c_str());
      inst->suspend();
    }
  });
}

static gboolean gst_tensor_filter_start(GstBaseTransform *trans) {
  auto *self = GST_TENSOR_FILTER(trans);
  FilterPriv *p = self->priv;
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    FilterSettings s;
    {
      std::lock_guard lk(p->settings_mu);
      if (!p->config_problems.empty()) {
        std::string msg;
        for (auto &x : p->config_problems) msg += (msg.empty() ? "" : "; ") + x;
        nns::fail(nns::ErrorKind::kSettings, msg);
      }
      s = p->settings;
    }
    if (s.invoke_async && !s.output_combination.empty())
      nns::fail(nns::ErrorKind::kSettings,
                "output-combination='" + s.output_combination +
                    "' cannot be used with invoke-async=true (the outputs are dispatched by "
                    "the back end, apart from the input)");
    p->last_caps_error.clear();
    {
      std::lock_guard lk(p->engine_mu);
      p->engine.set_async(nullptr);
      // A caps query before start may have opened the model with these very settings.
      if (!p->engine.is_open() || !(p->engine.open_settings() == s)) p->engine.open(s);
      p->engine.post_open_warnings();
      p->query_open_failed.reset();
      p->started = true;
      p->engine.set_profiling(s.latency_mode > 0, s.throughput_mode > 0, s.latency_report);
      if (s.invoke_async) start_async(self);
    }
    update_info_snapshot(self);
    if (s.suspend_ms > 0) start_suspend_thread(self, s.suspend_ms);
    return TRUE;
  });
}

static gboolean gst_tensor_filter_stop(GstBaseTransform *trans) {
  auto *self = GST_TENSOR_FILTER(trans);
  FilterPriv *p = self->priv;
  stop_suspend_thread(p);
  stop_async(p);  // before the back end closes: its late outputs are refused, not pushed
  std::lock_guard lk(p->engine_mu);
  p->engine.set_async(nullptr);
  p->engine.close();
  p->started = false;
  return TRUE;
}

// A caps query before start (the element still in NULL or READY: an application asking what
// the model takes, a filter downstream of another one that negotiates first) is answered with
// the model's shapes, as NNStreamer does: the model is opened now, when the settings name one,
// and start() keeps that instance. A model that cannot be opened leaves the template answer;
// start() opens it again and posts the error. Called with engine_mu held.
static void open_for_query(GstTensorFilter *self) {
  FilterPriv *p = self->priv;
  if (p->started) return;
  FilterSettings s;
  {
    std::lock_guard lk(p->settings_mu);
    if (!p->config_problems.empty()) return;
    s = p->settings;
  }
  // Opened for an earlier query: kept unless a property changed since.
  if (p->engine.is_open() && p->engine.open_settings() == s) return;
  p->engine.close();
  if (s.model.empty() || (s.invoke_async && !s.output_combination.empty())) return;
  if (p->query_open_failed && *p->query_open_failed == s) return;
  try {
    p->engine.open(s);
    p->query_open_failed.reset();
    GST_INFO_OBJECT(self, "opened %s to answer a caps query before start",
                    p->engine.instance()->describe().c_str());
  } catch (const std::exception &e) {
    p->engine.close();
    p->query_open_failed = s;
    GST_INFO_OBJECT(self, "cannot open the model for a caps query yet: %s", e.what());
    return;
  }
  update_info_snapshot(self);
}

static GstCaps *gst_tensor_filter_transform_caps(GstBaseTransform *trans, GstPadDirection direction,
                                                 GstCaps *caps, GstCaps *filter) {
  auto *self = GST_TENSOR_FILTER(trans);
  GstCaps *result = nullptr;
  {
    std::lock_guard lk(self->priv->engine_mu);
    open_for_query(self);
    result = self->priv->engine.transform_caps(direction, caps);
  }
  GstPad *pad = direction == GST_PAD_SINK ? GST_BASE_TRANSFORM_SRC_PAD(trans)
                                          : GST_BASE_TRANSFORM_SINK_PAD(trans);
  // The model's shapes come first (preferred); the template follows so that a peer fixed on
  // other shapes still links and set_caps() reports both shapes instead of a bare
  // not-negotiated.
  if (result)
    gst_caps_append(result, gst_pad_get_pad_template_caps(pad));
  else
    result = gst_pad_get_pad_template_caps(pad);
  if (filter && !gst_caps_is_empty(filter)) {
    GstCaps *x = gst_caps_intersect_full(result, filter, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(result);
    result = x;
  }
  return result;
}

// Fixation prefers this filter's own caps (the model's shapes) over the order the peer gave.
// A peer that cannot tell its shapes yet (another tensor_filter whose model learns its input
// from the caps, a tee, a queue...) answers with the template, legacy other/tensor first; the
// default fixation would take that structure and drop the model's tensors. When nothing of ours
// fits the peer, the peer's caps are fixated as they are, so set_caps() can name both shapes.
static GstCaps *gst_tensor_filter_fixate_caps(GstBaseTransform *trans, GstPadDirection direction,
                                              GstCaps *caps, GstCaps *othercaps) {
  GstCaps *ours = gst_tensor_filter_transform_caps(trans, direction, caps, nullptr);
  GstCaps *result = gst_caps_intersect_full(ours, othercaps, GST_CAPS_INTERSECT_FIRST);
  gst_caps_unref(ours);
  if (gst_caps_is_empty(result)) {
    gst_caps_unref(result);
    result = othercaps;
  } else {
    gst_caps_unref(othercaps);
  }
  return gst_caps_fixate(result);
}

static gboolean gst_tensor_filter_set_caps(GstBaseTransform *trans, GstCaps *incaps,
                                           GstCaps *outcaps) {
  auto *self = GST_TENSOR_FILTER(trans);
  FilterPriv *p = self->priv;
  std::string error;
  nns::ErrorKind kind = nns::ErrorKind::kNegotiation;
  try {
    std::lock_guard lk(p->engine_mu);
    p->engine.configure(incaps, outcaps);
  } catch (const nns::Error &e) {
    error = e.what();
    kind = e.kind();
  } catch (const std::exception &e) {
    error = std::string("internal error: ") + e.what();
    kind = nns::ErrorKind::kInternal;
  }
  if (error.empty()) {
    p->last_caps_error.clear();
    update_info_snapshot(self);
    return TRUE;
  }
  // GstBaseTransform retries the same caps several times; post each distinct problem once.
  if (error != p->last_caps_error) NNS_POST_ERROR(self, kind, error);
  p->last_caps_error = error;
  return FALSE;
}

static GstFlowReturn gst_tensor_filter_prepare_output_buffer(GstBaseTransform *trans,
                                                             GstBuffer *inbuf, GstBuffer **outbuf) {
  (void)trans;
  *outbuf = gst_buffer_new();
  gst_buffer_copy_into(
      *outbuf, inbuf,
      static_cast<GstBufferCopyFlags>(GST_BUFFER_COPY_FLAGS | GST_BUFFER_COPY_TIMESTAMPS |
                                      GST_BUFFER_COPY_META),
      0, static_cast<gsize>(-1));
  return GST_FLOW_OK;
}

static GstFlowReturn gst_tensor_filter_transform(GstBaseTransform *trans, GstBuffer *inbuf,
                                                 GstBuffer *outbuf) {
  auto *self = GST_TENSOR_FILTER(trans);
  auto d = get_async(self->priv);
  if (d) {
    // A fatal flow return of an async push (downstream EOS, not negotiated, error) stops
    // upstream here.
    GstFlowReturn f = d->take_flow();
    if (f != GST_FLOW_OK) return f;
  }
  if (self->priv->engine.throttled(inbuf)) return GST_BASE_TRANSFORM_FLOW_DROPPED;
  GstFlowReturn ret = nns::gst::guard(self, GST_FLOW_ERROR, [&] {
    std::lock_guard lk(self->priv->engine_mu);
    return self->priv->engine.process(inbuf, outbuf);
  });
  // Outputs the back end dispatched from this thread during the invoke go out now, without
  // engine_mu (downstream may query back upstream while handling them).
  if (d) d->push_deferred();
  return ret;
}

static gboolean gst_tensor_filter_query(GstBaseTransform *trans, GstPadDirection direction,
                                        GstQuery *query) {
  auto *self = GST_TENSOR_FILTER(trans);
  FilterPriv *p = self->priv;
  if (GST_QUERY_TYPE(query) == GST_QUERY_LATENCY) {
    bool report;
    {
      std::lock_guard lk(p->settings_mu);
      report = p->settings.latency_report;
    }
    int estimated = p->engine.stats().latency_us();
    if (report && estimated > 0 && gst_pad_peer_query(GST_BASE_TRANSFORM_SINK_PAD(trans), query)) {
      gboolean live;
      GstClockTime min, max;
      gst_query_parse_latency(query, &live, &min, &max);
      auto add = static_cast<GstClockTime>(estimated * GST_USECOND * 1.05);
      p->engine.reported_ns() = static_cast<int64_t>(add);
      min += add;
      if (GST_CLOCK_TIME_IS_VALID(max)) max += add;
      GST_DEBUG_OBJECT(self, "latency query: adding %" GST_TIME_FORMAT, GST_TIME_ARGS(add));
      gst_query_set_latency(query, live, min, max);
      return TRUE;
    }
  }
  return GST_BASE_TRANSFORM_CLASS(gst_tensor_filter_parent_class)->query(trans, direction, query);
}

static gboolean gst_tensor_filter_sink_event(GstBaseTransform *trans, GstEvent *event) {
  auto *self = GST_TENSOR_FILTER(trans);
  if (GST_EVENT_TYPE(event) == GST_EVENT_CUSTOM_DOWNSTREAM) {
    const GstStructure *st = gst_event_get_structure(event);
    if (st && gst_structure_has_name(st, kUpdateModelEvent)) {
      bool updatable;
      {
        std::lock_guard lk(self->priv->settings_mu);
        updatable = self->priv->settings.is_updatable;
      }
      const GValue *v = gst_structure_get_value(st, "model_files");
      gboolean ok = updatable && v && G_VALUE_HOLDS_STRING(v);
      if (ok) g_object_set(self, "model", g_value_get_string(v), nullptr);
      gst_event_unref(event);
      return ok;
    }
  }
  auto parent = [&] {
    return GST_BASE_TRANSFORM_CLASS(gst_tensor_filter_parent_class)->sink_event(trans, event);
  };
  auto d = get_async(self->priv);
  if (!d) return parent();
  // invoke-async: serialized events must not interleave with outputs pushed by the back end's
  // threads, and EOS waits for the inputs the back end announced as pending.
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_FLUSH_START:
      d->flush();
      return parent();
    case GST_EVENT_EOS:
      d->wait_drained();
      return d->serialized(parent);
    default:
      return GST_EVENT_IS_SERIALIZED(event) ? d->serialized(parent) : parent();
  }
}

static gboolean gst_tensor_filter_src_event(GstBaseTransform *trans, GstEvent *event) {
  auto *self = GST_TENSOR_FILTER(trans);
  if (GST_EVENT_TYPE(event) == GST_EVENT_QOS) {
    GstQOSType type;
    GstClockTimeDiff diff;
    gst_event_parse_qos(event, &type, nullptr, &diff, nullptr);
    if (type == GST_QOS_TYPE_THROTTLE && diff > 0) {
      self->priv->engine.set_throttling_delay(diff);
      gst_event_unref(event);
      g_object_set(self, "latency", 1, nullptr);  // the drop decision uses the latency
      return TRUE;
    }
  }
  return GST_BASE_TRANSFORM_CLASS(gst_tensor_filter_parent_class)->src_event(trans, event);
}

// A model opened for a caps query while the element never started is released on the way
// back to NULL (stop() releases it otherwise).
static GstStateChangeReturn gst_tensor_filter_change_state(GstElement *element,
                                                           GstStateChange transition) {
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_filter_parent_class)->change_state(element, transition);
  if (transition == GST_STATE_CHANGE_READY_TO_NULL) {
    FilterPriv *p = GST_TENSOR_FILTER(element)->priv;
    std::lock_guard lk(p->engine_mu);
    p->engine.close();
    p->query_open_failed.reset();
  }
  return ret;
}

static void gst_tensor_filter_finalize(GObject *object) {
  auto *self = GST_TENSOR_FILTER(object);
  stop_suspend_thread(self->priv);
  stop_async(self->priv);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_filter_parent_class)->finalize(object);
}

static void gst_tensor_filter_class_init(GstTensorFilterClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_filter_debug, "tensor_filter", 0, "tensor_filter element");
  auto *k = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *trans_class = GST_BASE_TRANSFORM_CLASS(klass);
  k->set_property = gst_tensor_filter_set_property;
  k->get_property = gst_tensor_filter_get_property;
  k->finalize = gst_tensor_filter_finalize;

  nns::gst::install_filter_properties(k, static_cast<GParamFlags>(GST_PARAM_MUTABLE_PLAYING));

  gst_element_class_set_static_metadata(
      element_class, "TensorFilter", "Filter/Tensor",
      "Handles NN Frameworks (e.g., tensorflow) as Media Filters with other/tensor type stream",
      "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->change_state = gst_tensor_filter_change_state;

  trans_class->passthrough_on_same_caps = FALSE;
  trans_class->start = gst_tensor_filter_start;
  trans_class->stop = gst_tensor_filter_stop;
  trans_class->transform_caps = gst_tensor_filter_transform_caps;
  trans_class->fixate_caps = gst_tensor_filter_fixate_caps;
  trans_class->set_caps = gst_tensor_filter_set_caps;
  trans_class->prepare_output_buffer = gst_tensor_filter_prepare_output_buffer;
  trans_class->transform = gst_tensor_filter_transform;
  trans_class->query = gst_tensor_filter_query;
  trans_class->sink_event = gst_tensor_filter_sink_event;
  trans_class->src_event = gst_tensor_filter_src_event;
}

static void gst_tensor_filter_init(GstTensorFilter *self) {
  self->priv = new FilterPriv(GST_BASE_TRANSFORM(self));
  gst_base_transform_set_in_place(GST_BASE_TRANSFORM(self), FALSE);
}

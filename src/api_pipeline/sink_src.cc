// SPDX-License-Identifier: LGPL-2.1-only
// ml_pipeline_sink_* (tensor_sink new-data / appsink new-sample -> application callbacks) and
// ml_pipeline_src_* (application data -> appsrc).
//
// A sink callback gets a data handle whose buffers point into the mapped GstMemory (no copy)
// and an info handle cached per node from the sink pad's caps (rebuilt per buffer only for
// flexible streams, whose memories carry their own headers).
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>

#include <array>
#include <cstring>

#include "api_pipeline/pipeline_internal.h"
#include "core/error.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

namespace nns::capi {
namespace {

thread_local Pipeline *t_dispatch_pipe = nullptr;

// Reads the sink pad's caps into n->info. cb_mu held.
bool read_sink_format(Node *n) {
  GstPad *pad = gst_element_get_static_pad(n->element, "sink");
  if (!pad) return false;
  GstCaps *caps = gst_pad_get_current_caps(pad);
  gst_object_unref(pad);
  if (!caps) return false;
  bool ok = false;
  try {
    if (gst::is_tensor_caps(caps)) {
      TensorsConfig c = gst::config_from_caps(caps);
      n->flexible = c.info.format != TensorFormat::kStatic;
      fill_info_handle(n->info, c.info);
      n->data.info = c.info;
      ok = true;
    }
  } catch (const std::exception &e) {
    GST_CAT_WARNING(capi_debug, "sink '%s': caps not usable: %s", n->name.c_str(), e.what());
  }
  gst_caps_unref(caps);
  return ok;
}

void dispatch(Node *n, GstBuffer *buf) {
  std::lock_guard lk(n->cb_mu);
  if (n->sinks.empty()) return;
  if (n->format_stale.load(std::memory_order_acquire)) {  // first buffer, or new caps
    n->format_stale.store(false, std::memory_order_relaxed);
    n->have_format = read_sink_format(n);
  }
  if (!n->have_format) {
    GST_CAT_WARNING(capi_debug, "sink '%s': no tensor caps yet; buffer not delivered",
                    n->name.c_str());
    return;
  }
  std::size_t count = gst::buffer_tensor_count(buf);
  if (count == 0 || count > ML_TENSOR_SIZE_LIMIT) return;
  std::array<GstMemory *, ML_TENSOR_SIZE_LIMIT> mems{};
  std::array<GstMapInfo, ML_TENSOR_SIZE_LIMIT> maps{};
  std::size_t mapped = 0;
  auto &d = n->data;
  bool ok = true;
  if (!n->flexible && count != n->info.info.size()) {
    GST_CAT_WARNING(capi_debug, "sink '%s': buffer has %zu tensors, caps say %zu", n->name.c_str(),
                    count, n->info.info.size());
    return;
  }
  d.buffers.resize(count);
  d.sizes.resize(count);
  TensorsInfo flex;
  for (; mapped < count; ++mapped) {
    mems[mapped] = gst::buffer_get_tensor(buf, mapped);
    if (!mems[mapped] || !gst_memory_map(mems[mapped], &maps[mapped], GST_MAP_READ)) {
      if (mems[mapped]) gst_memory_unref(mems[mapped]);
      ok = false;
      break;
    }
    uint8_t *ptr = maps[mapped].data;
    std::size_t size = maps[mapped].size;
    if (n->flexible) {
      try {
        MetaHeader h = parse_meta_header(ptr, size);
        flex.tensors.push_back(h.info());
        ptr += kMetaHeaderSize;
        size -= kMetaHeaderSize;
      } catch (const std::exception &e) {
        GST_CAT_WARNING(capi_debug, "sink '%s': %s", n->name.c_str(), e.what());
        ++mapped;
        ok = false;
        break;
      }
    } else if (size != n->info.info[mapped].byte_size()) {
      GST_CAT_WARNING(capi_debug, "sink '%s': tensor %zu has %zu bytes, caps say %zu",
                      n->name.c_str(), mapped, size, n->info.info[mapped].byte_size());
      ++mapped;
      ok = false;
      break;
    }
    d.buffers[mapped].reset(ptr);
    d.sizes[mapped] = size;
  }
  if (ok) {
    if (n->flexible) {
      flex.format = TensorFormat::kStatic;
      fill_info_handle(n->info, flex);
    }
    if (n->flexible) d.info = n->info.info;
    Pipeline *prev = t_dispatch_pipe;
    t_dispatch_pipe = n->pipe;
    n->dispatching = true;
    n->dispatch_thread = std::this_thread::get_id();
    // By index: a callback may register more sinks (appended) or unregister (marked dead).
    for (std::size_t i = 0; i < n->sinks.size(); ++i) {
      Handle *h = n->sinks[i];
      if (!h->dead && h->sink_cb) h->sink_cb(&d, &n->info, h->sink_user);
    }
    n->dispatching = false;
    t_dispatch_pipe = prev;
    for (auto it = n->sinks.begin(); it != n->sinks.end();) {
      if ((*it)->dead) {
        delete *it;
        it = n->sinks.erase(it);
      } else {
        ++it;
      }
    }
  }
  for (auto &b : d.buffers) (void)b.release();
  for (std::size_t i = 0; i < mapped; ++i) {
    if (i < count && maps[i].memory) gst_memory_unmap(mems[i], &maps[i]);
    gst_memory_unref(mems[i]);
  }
}

void on_caps(GObject *, GParamSpec *, gpointer user) {
  static_cast<Node *>(user)->format_stale.store(true, std::memory_order_release);
}

void on_new_data(GstElement *, GstBuffer *buf, gpointer user) {
  dispatch(static_cast<Node *>(user), buf);
}

GstFlowReturn on_new_sample(GstElement *e, gpointer user) {
  GstSample *s = gst_app_sink_pull_sample(GST_APP_SINK(e));
  if (!s) return GST_FLOW_OK;
  if (GstBuffer *b = gst_sample_get_buffer(s)) dispatch(static_cast<Node *>(user), b);
  gst_sample_unref(s);
  return GST_FLOW_OK;
}

Node *find_node(Pipeline *p, const char *name) {
  auto it = p->nodes.find(name);
  return it == p->nodes.end() ? nullptr : it->second.get();
}

std::string typed_names(Pipeline *p, std::initializer_list<NodeKind> kinds) {
  std::string out;
  for (auto &[name, n] : p->nodes)
    for (NodeKind k : kinds)
      if (n->kind == k) out += (out.empty() ? "'" : ", '") + name + "'";
  return out.empty() ? "none" : out;
}

// Tensors the appsrc produces, from its caps (current, else allowed). cb: caps not tensors.
int src_format(Node *n, TensorsInfo *info, bool *media, const char *func) {
  GstPad *pad = gst_element_get_static_pad(n->element, "src");
  if (!pad)
    return fail(ML_ERROR_STREAMS_PIPE,
                std::string(func) + ": appsrc '" + n->name + "' has no src pad");
  // The caps property (what the next buffer will carry), else the negotiated caps, else what
  // the peer allows.
  GstCaps *caps = gst_app_src_get_caps(GST_APP_SRC(n->element));
  if (!caps) caps = gst_pad_get_current_caps(pad);
  if (!caps) caps = gst_pad_get_allowed_caps(pad);
  gst_object_unref(pad);
  if (caps && !gst_caps_is_fixed(caps) && !gst_caps_is_empty(caps) && !gst_caps_is_any(caps))
    caps = gst_caps_fixate(caps);
  if (!caps)
    return fail(ML_ERROR_TRY_AGAIN, std::string(func) + ": appsrc '" + n->name +
                                        "' is not linked or negotiated yet; try again");
  int rc = ML_ERROR_NONE;
  *media = false;
  try {
    if (gst_caps_is_empty(caps) || gst_caps_is_any(caps) || !gst::is_tensor_caps(caps)) {
      *media = true;
    } else {
      *info = gst::config_from_caps(caps).info;
    }
  } catch (const std::exception &e) {
    rc = fail(ML_ERROR_STREAMS_PIPE,
              std::string(func) + ": appsrc '" + n->name + "' caps cannot be read: " + e.what());
  }
  gst_caps_unref(caps);
  return rc;
}

thread_local Handle *t_src_cb = nullptr;  // src handle whose event callback runs on this thread

// Runs `call(callbacks, user)` unless the handle was released; counted so release can wait.
template <typename F>
void src_event(gpointer user, F call) {
  auto *h = static_cast<Handle *>(user);
  ml_pipeline_src_callbacks_s cbs;
  void *data;
  {
    std::lock_guard lk(h->src_mu);
    if (!h->src_alive) return;
    cbs = h->src_cb;
    data = h->src_user;
    ++h->src_running;
  }
  Handle *prev = t_src_cb;
  t_src_cb = h;
  call(cbs, data, h);
  t_src_cb = prev;
  std::lock_guard lk(h->src_mu);
  if (--h->src_running == 0) h->src_cv.notify_all();
}

void src_need_data(GstAppSrc *, guint length, gpointer user) {
  src_event(user, [length](const ml_pipeline_src_callbacks_s &c, void *d, Handle *h) {
    if (c.need_data) c.need_data(h, length, d);
  });
}

void src_enough_data(GstAppSrc *, gpointer user) {
  src_event(user, [](const ml_pipeline_src_callbacks_s &c, void *d, Handle *h) {
    if (c.enough_data) c.enough_data(h, d);
  });
}

gboolean src_seek_data(GstAppSrc *, guint64 offset, gpointer user) {
  src_event(user, [offset](const ml_pipeline_src_callbacks_s &c, void *d, Handle *h) {
    if (c.seek_data) c.seek_data(h, offset, d);
  });
  return TRUE;
}

}  // namespace

Pipeline *dispatching_pipeline() {
  return t_dispatch_pipe;
}

void close_sinks(Node *n) {
  if (n->kind != NodeKind::kTensorSink && n->kind != NodeKind::kAppSink) return;
  std::lock_guard lk(n->cb_mu);  // waits for a running callback
  n->closed = true;
  if (n->signal_id) {
    g_signal_handler_disconnect(n->element, n->signal_id);
    n->signal_id = 0;
  }
  if (n->caps_pad) {
    g_signal_handler_disconnect(n->caps_pad, n->caps_id);
    gst_object_unref(n->caps_pad);
    n->caps_pad = nullptr;
  }
  for (Handle *h : n->sinks) {
    std::erase(n->handles, h);
    delete h;
  }
  n->sinks.clear();
}

void close_src(Handle *h) {
  std::unique_lock lk(h->src_mu);
  bool had = h->src_cb.need_data || h->src_cb.enough_data || h->src_cb.seek_data;
  h->src_alive = false;
  lk.unlock();
  if (had) {
    GstAppSrcCallbacks none{};
    gst_app_src_set_callbacks(GST_APP_SRC(h->node->element), &none, nullptr, nullptr);
  }
  lk.lock();
  // Wait for a callback running on another thread (not for one that called this itself).
  int own = t_src_cb == h ? 1 : 0;
  h->src_cv.wait(lk, [&] { return h->src_running <= own; });
}

}  // namespace nns::capi

using namespace nns;
using namespace nns::capi;

NNS_CAPI int ml_pipeline_sink_register(ml_pipeline_h pipe, const char *sink_name,
                                       ml_pipeline_sink_cb cb, void *user_data,
                                       ml_pipeline_sink_h *sink_handle) {
  constexpr const char *F = "ml_pipeline_sink_register";
  if (!sink_handle)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": sink_handle is NULL");
  *sink_handle = nullptr;
  if (!sink_name) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": sink_name is NULL");
  if (!cb) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": cb is NULL");
  std::unique_lock lk(registry_lock());
  Pipeline *p = live_pipeline(pipe, F);
  if (!p) return ML_ERROR_INVALID_PARAMETER;
  Node *n = find_node(p, sink_name);
  if (!n || (n->kind != NodeKind::kTensorSink && n->kind != NodeKind::kAppSink)) {
    GstElement *e = gst_bin_get_by_name(GST_BIN(p->bin), sink_name);
    std::string what = e ? std::string("'") + sink_name + "' is a " +
                               GST_OBJECT_NAME(gst_element_get_factory(e)) +
                               ", not a tensor_sink or appsink"
                         : std::string("there is no element named '") + sink_name + "'";
    if (e) gst_object_unref(e);
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": " + what + " in " + p->describe() + " (its sinks: " +
                    typed_names(p, {NodeKind::kTensorSink, NodeKind::kAppSink}) + ")");
  }
  auto *h = new Handle();
  h->kind = HandleKind::kSink;
  h->pipe = p;
  h->node = n;
  h->sink_cb = cb;
  h->sink_user = user_data;
  add_handle(h);  // from here on the pipeline's teardown frees it if it is not handed out
  Use use(p);
  lk.unlock();  // a running callback (holding cb_mu) may call the API
  std::lock_guard cl(n->cb_mu);
  if (n->closed)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": " + p->describe() + " is being destroyed");
  n->sinks.push_back(h);
  if (!n->signal_id) {
    if (n->kind == NodeKind::kTensorSink) {
      g_object_set(n->element, "emit-signal", TRUE, nullptr);
      n->signal_id = g_signal_connect(n->element, "new-data", G_CALLBACK(on_new_data), n);
    } else {
      g_object_set(n->element, "emit-signals", TRUE, nullptr);
      n->signal_id = g_signal_connect(n->element, "new-sample", G_CALLBACK(on_new_sample), n);
    }
  }
  if (n->signal_id && !n->caps_pad) {
    n->caps_pad = gst_element_get_static_pad(n->element, "sink");
    if (n->caps_pad)
      n->caps_id = g_signal_connect(n->caps_pad, "notify::caps", G_CALLBACK(on_caps), n);
    n->format_stale = true;
  }
  *sink_handle = h;
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_sink_unregister(ml_pipeline_sink_h sink_handle) {
  std::unique_lock lk(registry_lock());
  Handle *h =
      live_handle(sink_handle, HandleKind::kSink, "ml_pipeline_sink_unregister", "sink_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  Node *n = h->node;
  remove_handle(h);
  Use use(h->pipe);
  lk.unlock();
  std::lock_guard cl(n->cb_mu);  // waits for a callback running on another thread
  if (n->dispatching && n->dispatch_thread == std::this_thread::get_id()) {
    h->dead = true;  // called from a callback of this node: the dispatcher frees it
    return ML_ERROR_NONE;
  }
  // Not there when a concurrent destroy's close_sinks() already freed it.
  for (auto it = n->sinks.begin(); it != n->sinks.end(); ++it)
    if (*it == h) {
      n->sinks.erase(it);
      delete h;
      break;
    }
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_src_get_handle(ml_pipeline_h pipe, const char *src_name,
                                        ml_pipeline_src_h *src_handle) {
  constexpr const char *F = "ml_pipeline_src_get_handle";
  if (!src_handle) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": src_handle is NULL");
  *src_handle = nullptr;
  if (!src_name) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": src_name is NULL");
  std::lock_guard lk(registry_lock());
  Pipeline *p = live_pipeline(pipe, F);
  if (!p) return ML_ERROR_INVALID_PARAMETER;
  Node *n = find_node(p, src_name);
  if (!n || n->kind != NodeKind::kAppSrc) {
    GstElement *e = gst_bin_get_by_name(GST_BIN(p->bin), src_name);
    std::string what = e ? std::string("'") + src_name + "' is a " +
                               GST_OBJECT_NAME(gst_element_get_factory(e)) + ", not an appsrc"
                         : std::string("there is no element named '") + src_name + "'";
    if (e) gst_object_unref(e);
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": " + what + " in " + p->describe() +
                    " (its appsrc elements: " + typed_names(p, {NodeKind::kAppSrc}) + ")");
  }
  auto *h = new Handle();
  h->kind = HandleKind::kSrc;
  h->pipe = p;
  h->node = n;
  add_handle(h);
  *src_handle = h;
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_src_release_handle(ml_pipeline_src_h src_handle) {
  std::unique_lock lk(registry_lock());
  Handle *h =
      live_handle(src_handle, HandleKind::kSrc, "ml_pipeline_src_release_handle", "src_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  remove_handle(h);
  h->node->retired.push_back(h);  // appsrc may still hold it as callback data
  Use use(h->pipe);
  lk.unlock();
  close_src(h);  // waits for a running event callback of it
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_src_input_data(ml_pipeline_src_h src_handle, ml_tensors_data_h data,
                                        ml_pipeline_buf_policy_e policy) {
  constexpr const char *F = "ml_pipeline_src_input_data";
  std::unique_lock lk(registry_lock());
  Handle *h = live_handle(src_handle, HandleKind::kSrc, F, "src_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  Node *n = h->node;
  Pipeline *p = h->pipe;
  GstAppSrc *src = GST_APP_SRC(n->element);
  if (policy == ML_PIPELINE_BUF_SRC_EVENT_EOS) {
    Use use(p);
    lk.unlock();
    gst_app_src_end_of_stream(src);
    return ML_ERROR_NONE;
  }
  if (policy != ML_PIPELINE_BUF_POLICY_AUTO_FREE && policy != ML_PIPELINE_BUF_POLICY_DO_NOT_FREE)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": policy " + std::to_string(static_cast<int>(policy)) +
                    " is not AUTO_FREE (0), DO_NOT_FREE (1) or SRC_EVENT_EOS (0x10000)");
  api::TensorsDataHandle *d = api::as_data(data);
  if (!d)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": data is NULL or not a tensors-data handle");
  if (d->buffers.empty() || d->buffers.size() > ML_TENSOR_SIZE_LIMIT)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": data has " + std::to_string(d->buffers.size()) +
                    " tensors; 1 to " + std::to_string(ML_TENSOR_SIZE_LIMIT) + " are accepted");
  TensorsInfo want;
  bool media = false;
  if (int rc = src_format(n, &want, &media, F); rc != ML_ERROR_NONE) return rc;
  bool flexible = !media && want.format != TensorFormat::kStatic;
  if (!media && !flexible) {
    if (want.size() != d->buffers.size())
      return fail(ML_ERROR_INVALID_PARAMETER,
                  std::string(F) + ": appsrc '" + n->name + "' expects " +
                      std::to_string(want.size()) + " tensor(s) (" + want.to_string() +
                      ") but the data has " + std::to_string(d->buffers.size()));
    for (std::size_t i = 0; i < want.size(); ++i)
      if (want[i].byte_size() != d->sizes[i])
        return fail(ML_ERROR_INVALID_PARAMETER,
                    std::string(F) + ": tensor " + std::to_string(i) + " of the data has " +
                        std::to_string(d->sizes[i]) + " bytes but appsrc '" + n->name +
                        "' expects " + std::to_string(want[i].byte_size()) + " bytes (" +
                        want[i].to_string() + ")");
  }
  const bool give = policy == ML_PIPELINE_BUF_POLICY_AUTO_FREE;
  if (give)
    for (const auto &b : d->buffers)
      if (!b.get_deleter().owned)  // nns_ml_tensors_data_wrap: the caller's memory
        return fail(ML_ERROR_INVALID_PARAMETER,
                    std::string(F) +
                        ": data wraps memory it does not own; it cannot be given away with "
                        "ML_PIPELINE_BUF_POLICY_AUTO_FREE (use DO_NOT_FREE)");
  GstBuffer *buf = gst_buffer_new();
  try {
    for (std::size_t i = 0; i < d->buffers.size(); ++i) {
      uint8_t *ptr = give ? d->buffers[i].release() : d->buffers[i].get();
      GstMemory *mem =
          gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, ptr, d->sizes[i], 0, d->sizes[i],
                                 give ? ptr : nullptr, give ? GDestroyNotify(std::free) : nullptr);
      TensorInfo ti = i < d->info.size() ? d->info[i] : TensorInfo{};
      if (flexible) {
        const MetaHeader mh = flexible_header(ti.type, ti.dims);
        GstMemory *with = gst::memory_with_header(mh, mem);
        gst_memory_unref(mem);
        mem = with;
      }
      gst::buffer_append_tensor(buf, mem, ti);
    }
  } catch (const std::exception &e) {
    gst_buffer_unref(buf);
    if (give) delete d;
    return fail(ML_ERROR_STREAMS_PIPE, std::string(F) + ": " + e.what());
  }
  if (give) delete d;  // the buffers now belong to the GstBuffer
  Use use(p);
  GstElement *keep = GST_ELEMENT(gst_object_ref(n->element));
  lk.unlock();
  GstFlowReturn r = gst_app_src_push_buffer(GST_APP_SRC(keep), buf);
  gst_object_unref(keep);
  if (r == GST_FLOW_FLUSHING)
    return fail(ML_ERROR_TRY_AGAIN,
                std::string(F) + ": appsrc '" + n->name +
                    "' is flushing (the pipeline is not PAUSED or PLAYING); the data was dropped");
  if (r == GST_FLOW_EOS)
    return fail(ML_ERROR_STREAMS_PIPE, std::string(F) + ": appsrc '" + n->name +
                                           "' is at end-of-stream; the data was dropped");
  if (r != GST_FLOW_OK)
    return fail(ML_ERROR_STREAMS_PIPE, std::string(F) + ": appsrc '" + n->name +
                                           "' refused the data: " + gst_flow_get_name(r));
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_src_set_event_cb(ml_pipeline_src_h src_handle,
                                          ml_pipeline_src_callbacks_s *cb, void *user_data) {
  constexpr const char *F = "ml_pipeline_src_set_event_cb";
  std::lock_guard lk(registry_lock());
  Handle *h = live_handle(src_handle, HandleKind::kSrc, F, "src_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  if (!cb) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": cb is NULL");
  {
    std::lock_guard cl(h->src_mu);
    h->src_cb = *cb;
    h->src_user = user_data;
  }
  GstAppSrcCallbacks c{};
  c.need_data = src_need_data;
  c.enough_data = src_enough_data;
  c.seek_data = src_seek_data;
  gst_app_src_set_callbacks(GST_APP_SRC(h->node->element), &c, h, nullptr);
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_src_get_tensors_info(ml_pipeline_src_h src_handle,
                                              ml_tensors_info_h *info) {
  constexpr const char *F = "ml_pipeline_src_get_tensors_info";
  std::lock_guard lk(registry_lock());
  Handle *h = live_handle(src_handle, HandleKind::kSrc, F, "src_handle");
  if (!h) return ML_ERROR_INVALID_PARAMETER;
  if (!info) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": info is NULL");
  TensorsInfo t;
  bool media = false;
  if (int rc = src_format(h->node, &t, &media, F); rc != ML_ERROR_NONE) return rc;
  if (int rc = ml_tensors_info_create(info); rc != ML_ERROR_NONE) return rc;
  if (!media) fill_info_handle(*api::as_info(*info), t);
  return ML_ERROR_NONE;
}

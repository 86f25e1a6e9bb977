// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_sink_grpc
 *
 * Sends static tensor frames over NNStreamer's gRPC TensorService (idl=protobuf or flatbuf): as a
 * client (server=FALSE, default) it streams them to a tensor_src_grpc server with SendTensors; as a
 * server (server=TRUE) connected tensor_src_grpc clients receive them with RecvTensors. Either
 * peer can be NNStreamer's. `out` counts the messages sent. See docs/elements/tensor_grpc.md.
 *
 *   gst-launch-1.0 videotestsrc ! tensor_converter ! tensor_sink_grpc host=localhost port=55115
 */
#include <gst/base/gstbasesink.h>

#include <algorithm>
#include <atomic>
#include <cstring>
#include <memory>
#include <mutex>

#include "gst/element_glue.h"
#include "gst/grpc_glue.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_sink_grpc_debug);
#define GST_CAT_DEFAULT tensor_sink_grpc_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_SINK_GRPC (gst_tensor_sink_grpc_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSinkGRPC, gst_tensor_sink_grpc, GST, TENSOR_SINK_GRPC, GstBaseSink)
G_END_DECLS

namespace {

namespace gg = nns::gst::grpc;

struct SinkPriv {
  std::mutex lock;  // guards settings
  gg::Settings settings{gg::kSinkRole};
  std::unique_ptr<nns::grpclink::Link> link;
  nns::TensorsConfig config;
  std::atomic<guint> out{0};
  std::mutex err_lock;
  std::string error;  // the stream ended badly (worker thread)
};

}  // namespace

struct _GstTensorSinkGRPC {
  GstBaseSink parent;
  SinkPriv *priv;
};

G_DEFINE_TYPE(GstTensorSinkGRPC, gst_tensor_sink_grpc, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(tensor_sink_grpc, "tensor_sink_grpc", GST_RANK_NONE,
                            GST_TYPE_TENSOR_SINK_GRPC)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_GRPC_CAPS_STR));

static void gst_tensor_sink_grpc_set_property(GObject *object, guint id, const GValue *value,
                                              GParamSpec *pspec) {
  auto *p = GST_TENSOR_SINK_GRPC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (!gg::set_property(p->settings, id, value))
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static void gst_tensor_sink_grpc_get_property(GObject *object, guint id, GValue *value,
                                              GParamSpec *pspec) {
  auto *p = GST_TENSOR_SINK_GRPC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (!gg::get_property(p->settings, p->out, id, value))
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static gboolean sink_grpc_start(GstBaseSink *sink) {
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    auto *p = GST_TENSOR_SINK_GRPC(sink)->priv;
    gg::Settings s{gg::kSinkRole};
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->settings;
    }
    p->out = 0;
    {
      std::lock_guard<std::mutex> l(p->err_lock);
      p->error.clear();
    }
    const nns::grpclink::LinkOptions o = gg::link_options(s, nns::grpclink::Direction::kSend);
    GstElement *self = GST_ELEMENT(sink);
    p->link = std::make_unique<nns::grpclink::Link>(
        o, nullptr, [self, p](bool ok, const std::string &why) {
          if (ok) return;
          {
            std::lock_guard<std::mutex> l(p->err_lock);
            p->error = why;
          }
          NNS_POST_ERROR(self, nns::ErrorKind::kStream, why);
        });
    p->link->start();
    if (s.server) gg::record_bound_port(p->lock, p->settings, *p->link);
    return TRUE;
  });
}

static gboolean sink_grpc_stop(GstBaseSink *sink) {
  auto *p = GST_TENSOR_SINK_GRPC(sink)->priv;
  if (p->link) p->link->stop();
  p->link.reset();
  return TRUE;
}

static gboolean sink_grpc_unlock(GstBaseSink *sink) {
  auto *p = GST_TENSOR_SINK_GRPC(sink)->priv;
  if (p->link) p->link->set_flushing(true);
  return TRUE;
}

static gboolean sink_grpc_unlock_stop(GstBaseSink *sink) {
  auto *p = GST_TENSOR_SINK_GRPC(sink)->priv;
  if (p->link) p->link->set_flushing(false);
  return TRUE;
}

static gboolean sink_grpc_set_caps(GstBaseSink *sink, GstCaps *caps) {
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    auto *p = GST_TENSOR_SINK_GRPC(sink)->priv;
    nns::TensorsConfig c = nns::gst::config_from_caps(caps);
    if (!c.valid() || c.info.format != nns::TensorFormat::kStatic)
      nns::fail(nns::ErrorKind::kNegotiation,
                "caps " + nns::gst::caps_to_string(caps) +
                    " must be static tensors with every dimension, type and the framerate");
    p->config = c;
    return TRUE;
  });
}

static GstFlowReturn sink_grpc_render(GstBaseSink *sink, GstBuffer *buf) {
  return nns::gst::guard(sink, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_TENSOR_SINK_GRPC(sink)->priv;
    {
      std::lock_guard<std::mutex> l(p->err_lock);
      if (!p->error.empty()) return GST_FLOW_ERROR;  // already posted
    }
    const auto &info = p->config.info;
    nns::grpclink::Frame f;
    f.rate_n = p->config.rate_n;
    f.rate_d = p->config.rate_d;
    const guint nmem = gst_buffer_n_memory(buf);
    gsize offset = 0;
    for (std::size_t i = 0; i < info.size(); ++i) {
      nns::grpclink::Tensor t;
      t.type = static_cast<uint32_t>(info[i].type);
      t.dims.assign(info[i].dims.begin(), info[i].dims.end());
      const gsize want = info[i].byte_size();
      t.data.resize(want);
      // One memory per tensor, or (other layouts) the tensors back to back.
      GstMemory *mem =
          nmem == info.size() ? gst_buffer_peek_memory(buf, static_cast<guint>(i)) : nullptr;
      const gsize have =
          mem ? mem->size : gst_buffer_get_size(buf) - std::min(offset, gst_buffer_get_size(buf));
      if (have < want || (mem && mem->size != want))
        nns::fail(nns::ErrorKind::kStream, "tensor " + std::to_string(i) + " has " +
                                               std::to_string(mem ? mem->size : have) +
                                               " bytes; the caps give " + info[i].to_string() +
                                               " = " + std::to_string(want) + " bytes");
      if (mem) {
        GstMapInfo map;
        if (!gst_memory_map(mem, &map, GST_MAP_READ))
          nns::fail(nns::ErrorKind::kStream, "cannot read tensor " + std::to_string(i));
        std::memcpy(t.data.data(), map.data, want);
        gst_memory_unmap(mem, &map);
      } else {
        gst_buffer_extract(buf, offset, t.data.data(), want);
      }
      offset += want;
      f.tensors.push_back(std::move(t));
    }
    if (!p->link->send(std::move(f))) {
      std::lock_guard<std::mutex> l(p->err_lock);
      return p->error.empty() ? GST_FLOW_FLUSHING : GST_FLOW_ERROR;
    }
    ++p->out;
    return GST_FLOW_OK;
  });
}

static gboolean sink_grpc_event(GstBaseSink *sink, GstEvent *event) {
  auto *p = GST_TENSOR_SINK_GRPC(sink)->priv;
  if (GST_EVENT_TYPE(event) == GST_EVENT_EOS && p->link) {
    // Everything queued reaches the peer before EOS goes on.
    if (!p->link->finish(std::chrono::seconds(5)))
      NNS_POST_WARNING(
          sink, "EOS: frames still queued for " + p->link->peer() + " after 5 s; they are dropped");
  }
  return GST_BASE_SINK_CLASS(gst_tensor_sink_grpc_parent_class)->event(sink, event);
}

static void gst_tensor_sink_grpc_finalize(GObject *object) {
  delete GST_TENSOR_SINK_GRPC(object)->priv;
  G_OBJECT_CLASS(gst_tensor_sink_grpc_parent_class)->finalize(object);
}

static void gst_tensor_sink_grpc_init(GstTensorSinkGRPC *self) {
  self->priv = new SinkPriv();
}

static void gst_tensor_sink_grpc_class_init(GstTensorSinkGRPCClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_sink_grpc_debug, "tensor_sink_grpc", 0, "gRPC tensor sink");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *sink_class = GST_BASE_SINK_CLASS(klass);
  gobject_class->set_property = gst_tensor_sink_grpc_set_property;
  gobject_class->get_property = gst_tensor_sink_grpc_get_property;
  gobject_class->finalize = gst_tensor_sink_grpc_finalize;
  gg::install_properties(gobject_class, gg::kSinkRole);
  sink_class->start = sink_grpc_start;
  sink_class->stop = sink_grpc_stop;
  sink_class->unlock = sink_grpc_unlock;
  sink_class->unlock_stop = sink_grpc_unlock_stop;
  sink_class->set_caps = sink_grpc_set_caps;
  sink_class->render = sink_grpc_render;
  sink_class->event = sink_grpc_event;
  gst_element_class_set_static_metadata(element_class, "TensorSinkGRPC", "Sink/Network",
                                        "Send nnstreamer protocol buffers as gRPC server/client",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
}

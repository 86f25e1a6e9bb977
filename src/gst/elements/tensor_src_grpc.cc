// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_src_grpc
 *
 * Receives static tensor frames over NNStreamer's gRPC TensorService (idl=protobuf or flatbuf): as
 * a server (server=TRUE, default) tensor_sink_grpc clients stream to it with SendTensors; as a
 * client (server=FALSE) it reads a tensor_sink_grpc server's RecvTensors stream. Either peer can
 * be NNStreamer's. The caps come from the frames (types, dimensions, framerate); timestamps
 * are count x framerate as upstream, and a framerate of 0/1 ends the stream after one frame as
 * upstream does. `out` counts the buffers pushed. See docs/elements/tensor_grpc.md.
 *
 *   gst-launch-1.0 tensor_src_grpc port=55115 ! tensor_sink
 */
#include <gst/base/gstpushsrc.h>

#include <atomic>
#include <condition_variable>
#include <deque>
#include <memory>
#include <mutex>

#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/grpc_glue.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_src_grpc_debug);
#define GST_CAT_DEFAULT tensor_src_grpc_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_SRC_GRPC (gst_tensor_src_grpc_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSrcGRPC, gst_tensor_src_grpc, GST, TENSOR_SRC_GRPC, GstPushSrc)
G_END_DECLS

namespace {

namespace gg = nns::gst::grpc;

constexpr std::size_t kQueueLimit = 32;

struct SrcPriv {
  std::mutex lock;  // guards everything below but `out`
  std::condition_variable cv;
  gg::Settings settings{gg::kSrcRole};
  std::unique_ptr<nns::grpclink::Link> link;
  std::deque<nns::grpclink::Frame> queue;
  bool flushing = false;
  bool running = false;
  bool ended = false;         // the peer finished
  std::string error;          // the stream broke or a bad message came
  nns::TensorsConfig config;  // of the caps set
  bool eos_next = false;      // framerate 0/1: EOS after this frame (upstream)
  std::atomic<guint> out{0};
};

}  // namespace

struct _GstTensorSrcGRPC {
  GstPushSrc parent;
  SrcPriv *priv;
};

G_DEFINE_TYPE(GstTensorSrcGRPC, gst_tensor_src_grpc, GST_TYPE_PUSH_SRC)
GST_ELEMENT_REGISTER_DEFINE(tensor_src_grpc, "tensor_src_grpc", GST_RANK_NONE,
                            GST_TYPE_TENSOR_SRC_GRPC)

static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_GRPC_CAPS_STR));

static void gst_tensor_src_grpc_set_property(GObject *object, guint id, const GValue *value,
                                             GParamSpec *pspec) {
  auto *p = GST_TENSOR_SRC_GRPC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (!gg::set_property(p->settings, id, value))
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static void gst_tensor_src_grpc_get_property(GObject *object, guint id, GValue *value,
                                             GParamSpec *pspec) {
  auto *p = GST_TENSOR_SRC_GRPC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (!gg::get_property(p->settings, p->out, id, value))
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static gboolean src_grpc_start(GstBaseSrc *src) {
  return nns::gst::guard(src, FALSE, [&]() -> gboolean {
    auto *p = GST_TENSOR_SRC_GRPC(src)->priv;
    gg::Settings s{gg::kSrcRole};
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->settings;
      p->queue.clear();
      p->flushing = false;
      p->running = true;
      p->ended = false;
      p->error.clear();
      p->config = {};
      p->eos_next = false;
    }
    p->out = 0;
    const nns::grpclink::LinkOptions o = gg::link_options(s, nns::grpclink::Direction::kReceive);
    p->link = std::make_unique<nns::grpclink::Link>(
        o,
        [p](nns::grpclink::Frame &&f) {
          std::unique_lock<std::mutex> l(p->lock);
          p->cv.wait(l, [&] { return !p->running || p->queue.size() < kQueueLimit; });
          if (!p->running) return;
          p->queue.push_back(std::move(f));
          p->cv.notify_all();
        },
        [p](bool ok, const std::string &why) {
          std::lock_guard<std::mutex> l(p->lock);
          if (ok)
            p->ended = true;
          else if (p->error.empty())
            p->error = why;
          p->cv.notify_all();
        });
    p->link->start();
    if (s.server) gg::record_bound_port(p->lock, p->settings, *p->link);
    return TRUE;
  });
}

static gboolean src_grpc_stop(GstBaseSrc *src) {
  auto *p = GST_TENSOR_SRC_GRPC(src)->priv;
  {
    std::lock_guard<std::mutex> l(p->lock);
    p->running = false;
    p->cv.notify_all();
  }
  if (p->link) p->link->stop();
  p->link.reset();
  std::lock_guard<std::mutex> l(p->lock);
  p->queue.clear();
  return TRUE;
}

static gboolean src_grpc_unlock(GstBaseSrc *src) {
  auto *p = GST_TENSOR_SRC_GRPC(src)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  p->flushing = true;
  p->cv.notify_all();
  return TRUE;
}

static gboolean src_grpc_unlock_stop(GstBaseSrc *src) {
  auto *p = GST_TENSOR_SRC_GRPC(src)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  p->flushing = false;
  return TRUE;
}

// Caps are set from the frames in create().
static gboolean src_grpc_negotiate(GstBaseSrc *) {
  return TRUE;
}

static void free_string(gpointer s) {
  delete static_cast<std::string *>(s);
}

static GstFlowReturn src_grpc_create(GstPushSrc *psrc, GstBuffer **out) {
  GstBaseSrc *src = GST_BASE_SRC(psrc);
  return nns::gst::guard(src, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_TENSOR_SRC_GRPC(src)->priv;
    nns::grpclink::Frame f;
    {
      std::unique_lock<std::mutex> l(p->lock);
      if (p->eos_next) return GST_FLOW_EOS;
      p->cv.wait(l,
                 [&] { return p->flushing || !p->error.empty() || p->ended || !p->queue.empty(); });
      if (p->flushing) return GST_FLOW_FLUSHING;
      if (p->queue.empty()) {
        if (!p->error.empty()) nns::fail(nns::ErrorKind::kStream, p->error);
        return GST_FLOW_EOS;
      }
      f = std::move(p->queue.front());
      p->queue.pop_front();
      p->cv.notify_all();
    }
    nns::TensorsConfig c = gg::config_of(f);
    if (!c.same_as(p->config)) {
      // Variant spellings: downstream may write several tensors' fields with '.'.
      nns::gst::CapsPtr mine(nns::gst::caps_from_config(c, true));
      nns::gst::CapsPtr caps(gst_pad_peer_query_caps(GST_BASE_SRC_PAD(src), mine.get()));
      if (!caps || gst_caps_is_empty(caps.get())) {
        nns::gst::CapsPtr plain(nns::gst::caps_from_config(c));
        nns::gst::CapsPtr peer(gst_pad_peer_query_caps(GST_BASE_SRC_PAD(src), nullptr));
        nns::fail(nns::ErrorKind::kNegotiation,
                  "downstream does not accept the caps of the frames from " + p->link->peer() +
                      ": " + nns::gst::caps_to_string(plain.get()) + " (it accepts " +
                      nns::gst::caps_to_string(peer.get()) + ")");
      }
      caps.reset(gst_caps_fixate(caps.release()));
      if (!gst_base_src_set_caps(src, caps.get()))
        nns::fail(nns::ErrorKind::kNegotiation,
                  "downstream does not accept the caps of the frames from " + p->link->peer() +
                      ": " + nns::gst::caps_to_string(caps.get()));
      p->config = c;
    }
    GstBuffer *buf = gst_buffer_new();
    for (auto &t : f.tensors) {
      auto *s = new std::string(std::move(t.data));
      gst_buffer_append_memory(
          buf, gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, s->data(), s->size(), 0, s->size(),
                                      s, free_string));
    }
    const guint n = p->out++;
    if (c.rate_n > 0) {
      GST_BUFFER_PTS(buf) = gst_util_uint64_scale(n, static_cast<guint64>(c.rate_d) * GST_SECOND,
                                                  static_cast<guint64>(c.rate_n));
      GST_BUFFER_DURATION(buf) = gst_util_uint64_scale(
          1, static_cast<guint64>(c.rate_d) * GST_SECOND, static_cast<guint64>(c.rate_n));
    } else {
      GST_BUFFER_PTS(buf) = 0;
      GST_BUFFER_DURATION(buf) = 0;
      std::lock_guard<std::mutex> l(p->lock);
      p->eos_next = true;  // upstream ends a framerate-0 stream after one frame
    }
    *out = buf;
    return GST_FLOW_OK;
  });
}

static void gst_tensor_src_grpc_finalize(GObject *object) {
  delete GST_TENSOR_SRC_GRPC(object)->priv;
  G_OBJECT_CLASS(gst_tensor_src_grpc_parent_class)->finalize(object);
}

static void gst_tensor_src_grpc_init(GstTensorSrcGRPC *self) {
  self->priv = new SrcPriv();
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
}

static void gst_tensor_src_grpc_class_init(GstTensorSrcGRPCClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_src_grpc_debug, "tensor_src_grpc", 0, "gRPC tensor source");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *basesrc_class = GST_BASE_SRC_CLASS(klass);
  auto *pushsrc_class = GST_PUSH_SRC_CLASS(klass);
  gobject_class->set_property = gst_tensor_src_grpc_set_property;
  gobject_class->get_property = gst_tensor_src_grpc_get_property;
  gobject_class->finalize = gst_tensor_src_grpc_finalize;
  gg::install_properties(gobject_class, gg::kSrcRole);
  basesrc_class->start = src_grpc_start;
  basesrc_class->stop = src_grpc_stop;
  basesrc_class->unlock = src_grpc_unlock;
  basesrc_class->unlock_stop = src_grpc_unlock_stop;
  basesrc_class->negotiate = src_grpc_negotiate;
  pushsrc_class->create = src_grpc_create;
  gst_element_class_set_static_metadata(element_class, "TensorSrcGRPC", "Source/Network",
                                        "Receive nnstreamer protocol buffers as a gRPC "
                                        "server/client",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &src_template);
}

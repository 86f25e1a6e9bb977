// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_reposink
 *
 * Hands every buffer (and its caps) to slot `slot-index` of the process-wide tensor repository
 * (src/gst/tensor_repo.h), where tensor_reposrc with the same slot-index picks it up. The
 * hand-off holds one buffer: render waits until the previous one was taken. With a
 * tensor_reposrc upstream in the same pipeline this closes a cycle, e.g. an RNN whose state
 * goes around:
 *
 *   gst-launch-1.0 tensor_mux name=mux sync-mode=nosync ! tensor_filter ... ! tee name=t
 *     t. ! queue ! tensor_reposink slot-index=0
 *     tensor_reposrc slot-index=0 caps="other/tensors,format=static,num_tensors=1,
 *       dimensions=(string)16,types=(string)float32,framerate=(fraction)0/1" ! mux.sink_0
 *     ... ! mux.sink_1
 *
 * EOS marks the slot ended (the source then ends too). Like upstream, it neither syncs on the
 * clock nor prerolls asynchronously; `signal-rate` limits hand-offs per second (0 = all).
 */
#include <gst/base/gstbasesink.h>

#include <atomic>

#include "gst/element_glue.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_repo.h"

GST_DEBUG_CATEGORY_STATIC(tensor_reposink_debug);
#define GST_CAT_DEFAULT tensor_reposink_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_REPOSINK (gst_tensor_reposink_get_type())
G_DECLARE_FINAL_TYPE(GstTensorRepoSink, gst_tensor_reposink, GST, TENSOR_REPOSINK, GstBaseSink)
G_END_DECLS

namespace {

struct RepoSinkPriv {
  std::atomic<guint> signal_rate{0};
  nns::gst::RepoSlot slot{false};
  std::atomic<bool> silent{true};
  GstCaps *caps = nullptr;  // streaming thread
  gint64 last_push_us = -1;
};

enum { PROP_0, PROP_SIGNAL_RATE, PROP_SLOT, PROP_SILENT };

}  // namespace

struct _GstTensorRepoSink {
  GstBaseSink parent;
  RepoSinkPriv *priv;
};

G_DEFINE_TYPE(GstTensorRepoSink, gst_tensor_reposink, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(tensor_reposink, "tensor_reposink", GST_RANK_NONE,
                            GST_TYPE_TENSOR_REPOSINK)

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_REPO_CAPS));

static void gst_tensor_reposink_set_property(GObject *object, guint id, const GValue *value,
                                             GParamSpec *pspec) {
  auto *p = GST_TENSOR_REPOSINK(object)->priv;
  switch (id) {
    case PROP_SIGNAL_RATE:
      p->signal_rate = g_value_get_uint(value);
      break;
    case PROP_SLOT:
      p->slot.set_property(g_value_get_uint(value));
      break;
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_reposink_get_property(GObject *object, guint id, GValue *value,
                                             GParamSpec *pspec) {
  auto *p = GST_TENSOR_REPOSINK(object)->priv;
  switch (id) {
    case PROP_SIGNAL_RATE:
      g_value_set_uint(value, p->signal_rate);
      break;
    case PROP_SLOT:
      g_value_set_uint(value, p->slot.property());
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static gboolean reposink_start(GstBaseSink *sink) {
  auto *p = GST_TENSOR_REPOSINK(sink)->priv;
  p->slot.unlock_stop();
  p->last_push_us = -1;
  nns::gst::TensorRepo::instance().reset(p->slot.slot());
  return TRUE;
}

static gboolean reposink_stop(GstBaseSink *sink) {
  auto *p = GST_TENSOR_REPOSINK(sink)->priv;
  gst_caps_replace(&p->caps, nullptr);
  return TRUE;
}

static gboolean reposink_unlock(GstBaseSink *sink) {
  GST_TENSOR_REPOSINK(sink)->priv->slot.unlock();
  return TRUE;
}

static gboolean reposink_unlock_stop(GstBaseSink *sink) {
  GST_TENSOR_REPOSINK(sink)->priv->slot.unlock_stop();
  return TRUE;
}

static gboolean reposink_event(GstBaseSink *sink, GstEvent *event) {
  auto *p = GST_TENSOR_REPOSINK(sink)->priv;
  if (GST_EVENT_TYPE(event) == GST_EVENT_EOS)
    nns::gst::TensorRepo::instance().set_eos(p->slot.slot());
  if (GST_EVENT_TYPE(event) == GST_EVENT_FLUSH_STOP)
    nns::gst::TensorRepo::instance().reset(p->slot.slot());
  return GST_BASE_SINK_CLASS(gst_tensor_reposink_parent_class)->event(sink, event);
}

static gboolean reposink_set_caps(GstBaseSink *sink, GstCaps *caps) {
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    auto cfg = nns::gst::config_from_caps(caps);
    if (!cfg.info.valid())
      nns::fail(nns::ErrorKind::kNegotiation,
                "sink caps need the dimensions and types of every tensor, got " +
                    nns::gst::caps_to_string(caps));
    gst_caps_replace(&GST_TENSOR_REPOSINK(sink)->priv->caps, caps);
    return TRUE;
  });
}

static GstFlowReturn reposink_render(GstBaseSink *sink, GstBuffer *buf) {
  auto *self = GST_TENSOR_REPOSINK(sink);
  auto *p = self->priv;
  guint rate = p->signal_rate;
  if (rate > 0) {
    gint64 now = g_get_monotonic_time();
    if (p->last_push_us >= 0 && now < p->last_push_us + G_USEC_PER_SEC / rate) return GST_FLOW_OK;
    p->last_push_us = now;
  }
  auto &repo = nns::gst::TensorRepo::instance();
  guint slot = 0;
  auto st = p->slot.wait(
      [&](uint32_t s, const std::function<bool()> &cancelled) {
        return repo.push(s, buf, p->caps, cancelled);
      },
      &slot);
  if (st == nns::gst::TensorRepo::Status::kEos) return GST_FLOW_EOS;
  if (st == nns::gst::TensorRepo::Status::kCancelled) return GST_FLOW_FLUSHING;
  if (!p->silent)
    GST_INFO_OBJECT(self, "slot %u <- buffer pts %" GST_TIME_FORMAT, slot,
                    GST_TIME_ARGS(GST_BUFFER_PTS(buf)));
  return GST_FLOW_OK;
}

static void gst_tensor_reposink_finalize(GObject *object) {
  auto *p = GST_TENSOR_REPOSINK(object)->priv;
  gst_caps_replace(&p->caps, nullptr);
  delete p;
  G_OBJECT_CLASS(gst_tensor_reposink_parent_class)->finalize(object);
}

static void gst_tensor_reposink_class_init(GstTensorRepoSinkClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_reposink_debug, "tensor_reposink", 0, "tensor_reposink");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *sink_class = GST_BASE_SINK_CLASS(klass);
  gobject_class->set_property = gst_tensor_reposink_set_property;
  gobject_class->get_property = gst_tensor_reposink_get_property;
  gobject_class->finalize = gst_tensor_reposink_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_SIGNAL_RATE,
      g_param_spec_uint("signal-rate", "Signal rate",
                        "Hand-offs per second at most (0 = every buffer, max 500)", 0, 500, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_SLOT,
      g_param_spec_uint("slot-index", "Slot Index", "Repository slot to write", 0, G_MAXUINT, 0,
                        rw));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log each hand-off", TRUE, rw));
  gst_element_class_set_static_metadata(element_class, "TensorRepoSink", "Sink/Tensor/Repository",
                                        "Writes tensor frames into a repository slot",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  sink_class->start = reposink_start;
  sink_class->stop = reposink_stop;
  sink_class->unlock = reposink_unlock;
  sink_class->unlock_stop = reposink_unlock_stop;
  sink_class->event = reposink_event;
  sink_class->set_caps = reposink_set_caps;
  sink_class->render = reposink_render;
}

static void gst_tensor_reposink_init(GstTensorRepoSink *self) {
  self->priv = new RepoSinkPriv();
  auto *base = GST_BASE_SINK(self);
  gst_base_sink_set_qos_enabled(base, TRUE);
  gst_base_sink_set_sync(base, FALSE);
  gst_base_sink_set_async_enabled(base, FALSE);
}

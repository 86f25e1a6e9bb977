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

// Rate limit of `signal-rate`: whether this buffer is handed off (the first always is).
static bool rate_allows(RepoSinkPriv *p) {
  guint rate = p->signal_rate;
  if (rate == 0) return true;
  gint64 now = g_get_monotonic_time();
  if (p->last_push_us >= 0 && now < p->last_push_us + G_USEC_PER_SEC / rate) return false;
  p->last_push_us = now;
  return true;
}

// Called with the preroll lock held (GstBaseSink holds it around render). A full slot is waited
// for with that lock released, as GstBaseSink's own clock waits do: a state change that takes
// the lock without calling unlock() first (PAUSED->PLAYING, which can run while render already
// runs when the streaming thread committed the PLAYING state) must not wait for the reader.
// unlock() (PLAYING->PAUSED, flushing, shutdown) cancels the wait; then, as GstBaseSink asks of
// a render that blocks, we wait for PLAYING again and retry the same buffer, so pausing neither
// drops it nor stops upstream.
static GstFlowReturn reposink_render(GstBaseSink *sink, GstBuffer *buf) {
  using Status = nns::gst::TensorRepo::Status;
  auto *self = GST_TENSOR_REPOSINK(sink);
  auto *p = self->priv;
  if (!rate_allows(p)) return GST_FLOW_OK;
  auto &repo = nns::gst::TensorRepo::instance();
  for (;;) {
    // Under the preroll lock: an unlock() before this point is still pending (its unlock_stop
    // needs the lock), a later one changes the ticket.
    uint64_t ticket = p->slot.ticket();
    guint slot = p->slot.slot();
    Status st = p->slot.unlocking() ? Status::kCancelled : repo.try_push(slot, buf, p->caps);
    if (st == Status::kFull) {
      GST_BASE_SINK_PREROLL_UNLOCK(sink);
      st = p->slot.wait(
          ticket,
          [&](uint32_t s, const std::function<bool()> &cancelled) {
            return repo.push(s, buf, p->caps, cancelled);
          },
          &slot);
      GST_BASE_SINK_PREROLL_LOCK(sink);
    }
    if (st == Status::kOk) {
      if (!p->silent)
        GST_INFO_OBJECT(self, "slot %u <- buffer pts %" GST_TIME_FORMAT, slot,
                        GST_TIME_ARGS(GST_BUFFER_PTS(buf)));
      return GST_FLOW_OK;
    }
    if (st == Status::kEos) return GST_FLOW_EOS;
    // Cancelled.
    if (sink->flushing) return GST_FLOW_FLUSHING;
    // An unlock() still pending: its caller is about to take the preroll lock; wait_preroll
    // lets it, and returns on PLAYING (OK) or flushing. Otherwise the state change is done
    // (we may be PAUSED, or already PLAYING again): do_preroll commits the state and waits only
    // while not PLAYING, as GstBaseSink does after a clock wait was unscheduled.
    GstFlowReturn ret = p->slot.unlocking()
                            ? gst_base_sink_wait_preroll(sink)
                            : gst_base_sink_do_preroll(sink, GST_MINI_OBJECT_CAST(buf));
    if (ret != GST_FLOW_OK) return ret;  // FLUSHING, or a step (GstBaseSink then retries)
  }
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

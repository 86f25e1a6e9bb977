// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_sink
 *
 * Hands tensor frames to the application: each buffer is emitted with the `new-data` signal
 * (at most `signal-rate` per second when set), and `stream-start` / `eos` signals mark the
 * stream's ends. Like NNStreamer's tensor_sink it does not sync on the clock by default.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=3 ! tensor_converter ! tensor_sink
 */
#include <gst/base/gstbasesink.h>

#include <atomic>

#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_sink_debug);
#define GST_CAT_DEFAULT tensor_sink_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_SINK (gst_tensor_sink_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSink, gst_tensor_sink, GST, TENSOR_SINK, GstBaseSink)
G_END_DECLS

namespace {

struct SinkPriv {
  // Settings (properties); atomics because the streaming thread reads them.
  std::atomic<guint> signal_rate{0};
  std::atomic<bool> emit_signal{true};
  std::atomic<bool> silent{true};
  // State
  GstClockTime last_render = GST_CLOCK_TIME_NONE;
};

enum { PROP_0, PROP_SIGNAL_RATE, PROP_EMIT_SIGNAL, PROP_SILENT };
enum { SIGNAL_NEW_DATA, SIGNAL_STREAM_START, SIGNAL_EOS, N_SIGNALS };
guint tensor_sink_signals[N_SIGNALS];

}  // namespace

struct _GstTensorSink {
  GstBaseSink parent;
  SinkPriv *priv;
};

G_DEFINE_TYPE(GstTensorSink, gst_tensor_sink, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(tensor_sink, "tensor_sink", GST_RANK_NONE, GST_TYPE_TENSOR_SINK)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_TENSOR_CAPS_ALL_FORMATS_STR));

static void gst_tensor_sink_set_property(GObject *object, guint id, const GValue *value,
                                         GParamSpec *pspec) {
  auto *self = GST_TENSOR_SINK(object);
  switch (id) {
    case PROP_SIGNAL_RATE:
      self->priv->signal_rate = g_value_get_uint(value);
      break;
    case PROP_EMIT_SIGNAL:
      self->priv->emit_signal = g_value_get_boolean(value);
      break;
    case PROP_SILENT:
      self->priv->silent = g_value_get_boolean(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_sink_get_property(GObject *object, guint id, GValue *value,
                                         GParamSpec *pspec) {
  auto *self = GST_TENSOR_SINK(object);
  switch (id) {
    case PROP_SIGNAL_RATE:
      g_value_set_uint(value, self->priv->signal_rate);
      break;
    case PROP_EMIT_SIGNAL:
      g_value_set_boolean(value, self->priv->emit_signal);
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, self->priv->silent);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_sink_finalize(GObject *object) {
  delete GST_TENSOR_SINK(object)->priv;
  G_OBJECT_CLASS(gst_tensor_sink_parent_class)->finalize(object);
}

static gboolean gst_tensor_sink_start(GstBaseSink *sink) {
  GST_TENSOR_SINK(sink)->priv->last_render = GST_CLOCK_TIME_NONE;
  return TRUE;
}

static gboolean gst_tensor_sink_event(GstBaseSink *sink, GstEvent *event) {
  auto *self = GST_TENSOR_SINK(sink);
  if (self->priv->emit_signal) {
    if (GST_EVENT_TYPE(event) == GST_EVENT_STREAM_START)
      g_signal_emit(self, tensor_sink_signals[SIGNAL_STREAM_START], 0);
    else if (GST_EVENT_TYPE(event) == GST_EVENT_EOS)
      g_signal_emit(self, tensor_sink_signals[SIGNAL_EOS], 0);
  }
  return GST_BASE_SINK_CLASS(gst_tensor_sink_parent_class)->event(sink, event);
}

// True when `caps` parse once their num_tensors field is left out.
static bool caps_valid_without_num_tensors(GstCaps *caps) {
  if (gst_caps_get_size(caps) != 1) return false;
  const GstStructure *st = gst_caps_get_structure(caps, 0);
  if (!gst_structure_has_field(st, "num_tensors")) return false;
  nns::gst::CapsPtr copy(gst_caps_copy(caps));
  gst_structure_remove_field(gst_caps_get_structure(copy.get(), 0), "num_tensors");
  try {
    return nns::gst::config_from_caps(copy.get()).info.valid();
  } catch (const nns::Error &) {
    return false;
  }
}

static gboolean gst_tensor_sink_set_caps(GstBaseSink *sink, GstCaps *caps) {
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    nns::TensorsConfig config;
    try {
      config = nns::gst::config_from_caps(caps);  // validates the caps strings
    } catch (const nns::Error &e) {
      // The sink does not use the description: as NNStreamer's, it takes caps whose num_tensors
      // disagrees with the lists (its extraTensors test: num_tensors=20 with two dimensions),
      // saying so. Malformed or missing lists stay errors.
      if (!caps_valid_without_num_tensors(caps)) throw;
      NNS_POST_WARNING(
          sink, std::string(e.what()) + " (accepted: the sink delivers the buffers as they come)");
      return TRUE;
    }
    if (!config.info.valid())
      nns::fail(nns::ErrorKind::kNegotiation,
                "format=static caps need the dimensions and types of every tensor, got " +
                    nns::gst::caps_to_string(caps));
    GST_DEBUG_OBJECT(sink, "negotiated %s", config.info.to_string().c_str());
    return TRUE;
  });
}

static GstFlowReturn gst_tensor_sink_render(GstBaseSink *sink, GstBuffer *buf) {
  auto *self = GST_TENSOR_SINK(sink);
  SinkPriv *p = self->priv;
  if (!p->silent)
    GST_INFO_OBJECT(self, "buffer pts %" GST_TIME_FORMAT ", %" G_GSIZE_FORMAT " bytes, %u memories",
                    GST_TIME_ARGS(GST_BUFFER_PTS(buf)), gst_buffer_get_size(buf),
                    gst_buffer_n_memory(buf));
  if (!p->emit_signal) return GST_FLOW_OK;
  guint rate = p->signal_rate;
  if (rate > 0) {
    // Throttle on the clock of the process, not the stream: the rate is for the application.
    GstClockTime now = g_get_monotonic_time() * GST_USECOND;
    GstClockTime gap = GST_SECOND / rate;
    if (GST_CLOCK_TIME_IS_VALID(p->last_render) && now < p->last_render + gap) return GST_FLOW_OK;
    p->last_render = now;
  }
  g_signal_emit(self, tensor_sink_signals[SIGNAL_NEW_DATA], 0, buf);
  return GST_FLOW_OK;
}

static void gst_tensor_sink_class_init(GstTensorSinkClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_sink_debug, "tensor_sink", 0, "tensor_sink element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *sink_class = GST_BASE_SINK_CLASS(klass);
  gobject_class->set_property = gst_tensor_sink_set_property;
  gobject_class->get_property = gst_tensor_sink_get_property;
  gobject_class->finalize = gst_tensor_sink_finalize;

  g_object_class_install_property(
      gobject_class, PROP_SIGNAL_RATE,
      g_param_spec_uint("signal-rate", "Signal rate",
                        "Maximum new-data signals per second (0 = every buffer)", 0, 500, 0,
                        static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject_class, PROP_EMIT_SIGNAL,
      g_param_spec_boolean("emit-signal", "Emit signal",
                           "Emit new-data, stream-start and eos signals", TRUE,
                           static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not print per-buffer details", TRUE,
                           static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS)));

  tensor_sink_signals[SIGNAL_NEW_DATA] =
      g_signal_new("new-data", G_TYPE_FROM_CLASS(klass), G_SIGNAL_RUN_LAST, 0, nullptr, nullptr,
                   nullptr, G_TYPE_NONE, 1, GST_TYPE_BUFFER | G_SIGNAL_TYPE_STATIC_SCOPE);
  tensor_sink_signals[SIGNAL_STREAM_START] =
      g_signal_new("stream-start", G_TYPE_FROM_CLASS(klass), G_SIGNAL_RUN_LAST, 0, nullptr, nullptr,
                   nullptr, G_TYPE_NONE, 0);
  tensor_sink_signals[SIGNAL_EOS] = g_signal_new("eos", G_TYPE_FROM_CLASS(klass), G_SIGNAL_RUN_LAST,
                                                 0, nullptr, nullptr, nullptr, G_TYPE_NONE, 0);

  gst_element_class_set_static_metadata(element_class, "TensorSink", "Sink/Tensor",
                                        "Hands tensor frames to the application through signals",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  sink_class->start = gst_tensor_sink_start;
  sink_class->event = gst_tensor_sink_event;
  sink_class->set_caps = gst_tensor_sink_set_caps;
  sink_class->render = gst_tensor_sink_render;
}

static void gst_tensor_sink_init(GstTensorSink *self) {
  self->priv = new SinkPriv();
  // NNStreamer's defaults: no clock sync, QoS on.
  gst_base_sink_set_sync(GST_BASE_SINK(self), FALSE);
  gst_base_sink_set_qos_enabled(GST_BASE_SINK(self), TRUE);
}

// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_aggregator
 *
 * Aggregates (or dis-aggregates) the frames of a single-tensor stream in time: each input
 * buffer holds `frames-in` frames along dimension `frames-dim`; each output holds
 * `frames-out` frames, after which `frames-flush` frames are dropped (0 = all frames-out, so
 * frames-flush < frames-out gives a sliding window). With `concat` (default) the frames are
 * laid out along frames-dim even when higher dimensions are > 1. The output PTS is that of
 * the oldest frame in it.
 *
 *   gst-launch-1.0 videotestsrc ! video/x-raw,format=RGB,width=640,height=480 ! \
 *     tensor_converter ! tensor_aggregator frames-out=10 frames-flush=5 frames-dim=3 ! \
 *     tensor_sink
 */
#include <gst/base/gstadapter.h>

#include <atomic>
#include <map>
#include <memory>
#include <mutex>
#include <optional>

#include "core/error.h"
#include "core/tensor_concat.h"
#include "gst/edge_glue.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_aggregator_debug);
#define GST_CAT_DEFAULT tensor_aggregator_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_AGGREGATOR (gst_tensor_aggregator_get_type())
G_DECLARE_FINAL_TYPE(GstTensorAggregator, gst_tensor_aggregator, GST, TENSOR_AGGREGATOR, GstElement)
G_END_DECLS

#define AGG_CAPS                                                     \
  "other/tensor, framerate = (fraction) [ 0, max ]; "                \
  "other/tensors, format = (string) static, num_tensors = (int) 1, " \
  "framerate = (fraction) [ 0, max ]"

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(AGG_CAPS));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(AGG_CAPS));

namespace {

struct AggPriv {
  // Settings
  std::mutex lock;
  nns::AggregatorConfig cfg;
  std::atomic<bool> silent{true};
  // State (streaming thread)
  nns::AggregatorConfig active;  // settings when the caps were set
  std::optional<nns::AggregatorPlan> plan;
  int rate_n = -1, rate_d = -1;
  // One adapter per client (the GstMetaQuery client id a tensor_query server puts on each
  // buffer; 0 without one), as NNStreamer: frames of different clients are never mixed.
  struct AdapterUnref {
    void operator()(GstAdapter *a) const { g_object_unref(a); }
  };
  std::map<int64_t, std::unique_ptr<GstAdapter, AdapterUnref>> adapters;

  GstAdapter *adapter_for(GstBuffer *buf) {
    const GstMetaQuery *meta = nns::gst::buffer_get_meta_query(buf);
    const int64_t key = meta ? meta->client_id : 0;
    auto &a = adapters[key];
    if (!a) a.reset(gst_adapter_new());
    return a.get();
  }
  void clear_all() { adapters.clear(); }
};

enum {
  PROP_0,
  PROP_FRAMES_IN,
  PROP_FRAMES_OUT,
  PROP_FRAMES_FLUSH,
  PROP_FRAMES_DIM,
  PROP_CONCAT,
  PROP_SILENT
};

}  // namespace

struct _GstTensorAggregator {
  GstElement parent;
  GstPad *sinkpad, *srcpad;
  AggPriv *priv;
};

G_DEFINE_TYPE(GstTensorAggregator, gst_tensor_aggregator, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_aggregator, "tensor_aggregator", GST_RANK_NONE,
                            GST_TYPE_TENSOR_AGGREGATOR)

namespace {

bool on_caps(GstTensorAggregator *self, GstCaps *caps) {
  AggPriv *p = self->priv;
  nns::TensorsConfig in = nns::gst::config_from_caps(caps);
  if (in.info.format != nns::TensorFormat::kStatic || in.info.size() != 1 || !in.info.valid())
    nns::fail(nns::ErrorKind::kNegotiation,
              "needs one static tensor, got " + nns::gst::caps_to_string(caps));
  {
    std::lock_guard<std::mutex> g(p->lock);
    p->active = p->cfg;
  }
  p->plan = nns::plan_aggregator(in.info[0], p->active);
  p->rate_n = in.rate_n;
  p->rate_d = in.rate_d;
  nns::TensorsConfig out = in;
  out.info.tensors[0] = p->plan->out;
  // Same caps form as the input where downstream allows it.
  nns::gst::CapsPtr want(nns::gst::caps_from_config(out));
  nns::gst::CapsPtr peer(gst_pad_peer_query_caps(self->srcpad, want.get()));
  if (!peer || gst_caps_is_empty(peer.get()))
    nns::fail(nns::ErrorKind::kNegotiation,
              "downstream does not accept " + nns::gst::caps_to_string(want.get()));
  GstCaps *fixed = gst_caps_fixate(peer.release());
  bool ok = gst_pad_set_caps(self->srcpad, fixed);
  gst_caps_unref(fixed);
  p->clear_all();
  return ok;
}

// Pushes one output of frames_out frames (re-ordered along frames-dim if needed).
GstFlowReturn push_out(GstTensorAggregator *self, GstBuffer *out) {
  const nns::AggregatorPlan &plan = *self->priv->plan;
  if (plan.reorder) {
    nns::gst::BufferPtr src(out);
    GstMemory *mem = gst_allocator_alloc(nullptr, plan.out_size, nullptr);
    {
      nns::gst::BufferMap in(src.get(), GST_MAP_READ);
      nns::gst::MemoryMap dst(mem, GST_MAP_WRITE);
      if (!in.ok() || !dst.ok()) {
        gst_memory_unref(mem);
        nns::fail(nns::ErrorKind::kStream, "cannot map buffers to re-order frames");
      }
      const uint8_t *frames[64];
      std::vector<const uint8_t *> many;
      const uint8_t **fp = frames;
      const std::size_t n = plan.concat.block.size();
      if (n > 64) {
        many.resize(n);
        fp = many.data();
      }
      for (std::size_t f = 0; f < n; ++f) fp[f] = in.data() + f * plan.frame_size;
      nns::run_concat(plan.concat, fp, dst.data());
    }
    out = gst_buffer_new();
    gst_buffer_append_memory(out, mem);
    gst_buffer_copy_into(out, src.get(), GST_BUFFER_COPY_METADATA, 0, -1);
  }
  return gst_pad_push(self->srcpad, out);
}

GstFlowReturn aggregate(GstTensorAggregator *self, GstBuffer *buf) {
  AggPriv *p = self->priv;
  if (!p->plan) {
    gst_buffer_unref(buf);
    nns::fail(nns::ErrorKind::kNegotiation, "received data before caps");
  }
  const nns::AggregatorPlan &plan = *p->plan;
  const nns::AggregatorConfig &cfg = p->active;
  gsize size = gst_buffer_get_size(buf);
  if (size != plan.in_size) {
    gst_buffer_unref(buf);
    nns::fail(nns::ErrorKind::kStream, "buffer has " + std::to_string(size) + " bytes, expected " +
                                           std::to_string(plan.in_size) +
                                           " (frames-in=" + std::to_string(cfg.frames_in) +
                                           " frames of " + plan.frame.to_string() + ")");
  }
  if (cfg.frames_in == cfg.frames_out) return push_out(self, buf);

  GstClockTime duration = GST_BUFFER_DURATION(buf);
  if (GST_CLOCK_TIME_IS_VALID(duration))
    duration = gst_util_uint64_scale_int(duration, cfg.frames_out, cfg.frames_in);
  const GstMetaQuery *meta = nns::gst::buffer_get_meta_query(buf);
  const bool has_client = meta != nullptr;
  const int64_t client = meta ? meta->client_id : 0;
  GstAdapter *adapter = p->adapter_for(buf);
  gst_adapter_push(adapter, buf);
  GstFlowReturn ret = GST_FLOW_OK;
  gsize avail;
  while (ret == GST_FLOW_OK && (avail = gst_adapter_available(adapter)) >= plan.out_size) {
    guint64 pts_dist = 0, dts_dist = 0;
    GstClockTime pts = gst_adapter_prev_pts(adapter, &pts_dist);
    GstClockTime dts = gst_adapter_prev_dts(adapter, &dts_dist);
    // Frames inside one input buffer are spaced by the caps frame rate (as upstream).
    if (cfg.frames_in > 1 && p->rate_n > 0 && p->rate_d > 0) {
      guint64 den = static_cast<guint64>(p->rate_n) * plan.frame_size;
      if (GST_CLOCK_TIME_IS_VALID(pts))
        pts += gst_util_uint64_scale(pts_dist * p->rate_d, GST_SECOND, den);
      if (GST_CLOCK_TIME_IS_VALID(dts))
        dts += gst_util_uint64_scale(dts_dist * p->rate_d, GST_SECOND, den);
    }
    GstBuffer *out = gst_adapter_get_buffer(adapter, plan.out_size);
    out = gst_buffer_make_writable(out);
    GST_BUFFER_PTS(out) = pts;
    GST_BUFFER_DTS(out) = dts;
    GST_BUFFER_DURATION(out) = duration;
    // The output goes back to the client whose frames it holds.
    if (has_client && !nns::gst::buffer_get_meta_query(out))
      nns::gst::buffer_add_meta_query(out, client);
    ret = push_out(self, out);
    gst_adapter_flush(adapter, std::min<gsize>(plan.flush_size, avail));
  }
  return ret;
}

}  // namespace

static GstFlowReturn gst_tensor_aggregator_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_AGGREGATOR(parent);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&] { return aggregate(self, buf); });
}

static gboolean gst_tensor_aggregator_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_AGGREGATOR(parent);
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_CAPS: {
      GstCaps *caps = nullptr;
      gst_event_parse_caps(event, &caps);
      gboolean ok = nns::gst::guard(self, FALSE, [&]() -> gboolean { return on_caps(self, caps); });
      gst_event_unref(event);
      return ok;
    }
    case GST_EVENT_FLUSH_STOP:
      self->priv->clear_all();
      break;
    default:
      break;
  }
  return gst_pad_event_default(pad, parent, event);
}

static GstStateChangeReturn gst_tensor_aggregator_change_state(GstElement *element,
                                                               GstStateChange transition) {
  auto *self = GST_TENSOR_AGGREGATOR(element);
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_aggregator_parent_class)->change_state(element, transition);
  if (transition == GST_STATE_CHANGE_PAUSED_TO_READY) {
    self->priv->clear_all();
    self->priv->plan.reset();
  }
  return ret;
}

static void gst_tensor_aggregator_set_property(GObject *object, guint id, const GValue *value,
                                               GParamSpec *pspec) {
  AggPriv *p = GST_TENSOR_AGGREGATOR(object)->priv;
  std::lock_guard<std::mutex> g(p->lock);
  switch (id) {
    case PROP_FRAMES_IN:
      p->cfg.frames_in = g_value_get_uint(value);
      break;
    case PROP_FRAMES_OUT:
      p->cfg.frames_out = g_value_get_uint(value);
      break;
    case PROP_FRAMES_FLUSH:
      p->cfg.frames_flush = g_value_get_uint(value);
      break;
    case PROP_FRAMES_DIM:
      p->cfg.frames_dim = g_value_get_uint(value);
      break;
    case PROP_CONCAT:
      p->cfg.concat = g_value_get_boolean(value);
      break;
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_aggregator_get_property(GObject *object, guint id, GValue *value,
                                               GParamSpec *pspec) {
  AggPriv *p = GST_TENSOR_AGGREGATOR(object)->priv;
  std::lock_guard<std::mutex> g(p->lock);
  switch (id) {
    case PROP_FRAMES_IN:
      g_value_set_uint(value, p->cfg.frames_in);
      break;
    case PROP_FRAMES_OUT:
      g_value_set_uint(value, p->cfg.frames_out);
      break;
    case PROP_FRAMES_FLUSH:
      g_value_set_uint(value, p->cfg.frames_flush);
      break;
    case PROP_FRAMES_DIM:
      g_value_set_uint(value, p->cfg.frames_dim);
      break;
    case PROP_CONCAT:
      g_value_set_boolean(value, p->cfg.concat);
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_aggregator_finalize(GObject *object) {
  AggPriv *p = GST_TENSOR_AGGREGATOR(object)->priv;
  delete p;
  G_OBJECT_CLASS(gst_tensor_aggregator_parent_class)->finalize(object);
}

static void gst_tensor_aggregator_class_init(GstTensorAggregatorClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_aggregator_debug, "tensor_aggregator", 0,
                          "tensor_aggregator element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_aggregator_set_property;
  gobject_class->get_property = gst_tensor_aggregator_get_property;
  gobject_class->finalize = gst_tensor_aggregator_finalize;
  auto flags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_FRAMES_IN,
      g_param_spec_uint("frames-in", "Frames in", "Number of frames in each input buffer", 1,
                        G_MAXUINT, 1, flags));
  g_object_class_install_property(
      gobject_class, PROP_FRAMES_OUT,
      g_param_spec_uint("frames-out", "Frames out", "Number of frames in each output buffer", 1,
                        G_MAXUINT, 1, flags));
  g_object_class_install_property(
      gobject_class, PROP_FRAMES_FLUSH,
      g_param_spec_uint("frames-flush", "Frames flush",
                        "Frames dropped after each output (0 = frames-out)", 0, G_MAXUINT, 0,
                        flags));
  g_object_class_install_property(
      gobject_class, PROP_FRAMES_DIM,
      g_param_spec_uint("frames-dim", "Frames dimension",
                        "Index of the dimension that counts frames (innermost first)", 0,
                        nns::kRankLimit - 1, nns::kRankLimit - 1, flags));
  g_object_class_install_property(
      gobject_class, PROP_CONCAT,
      g_param_spec_boolean("concat", "Concat", "Lay the output frames out along frames-dim", TRUE,
                           flags));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log each buffer", TRUE, flags));
  element_class->change_state = gst_tensor_aggregator_change_state;
  gst_element_class_set_static_metadata(element_class, "TensorAggregator", "Filter/Tensor",
                                        "Groups or splits the frames of a tensor stream in time",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
}

static void gst_tensor_aggregator_init(GstTensorAggregator *self) {
  self->priv = new AggPriv();
  self->sinkpad = gst_pad_new_from_static_template(&sink_template, "sink");
  gst_pad_set_chain_function(self->sinkpad, gst_tensor_aggregator_chain);
  gst_pad_set_event_function(self->sinkpad, gst_tensor_aggregator_sink_event);
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
  self->srcpad = gst_pad_new_from_static_template(&src_template, "src");
  gst_pad_use_fixed_caps(self->srcpad);
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
}

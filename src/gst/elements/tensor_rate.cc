// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_rate
 *
 * Converts the frame rate of a tensor stream by dropping and duplicating frames (like
 * videorate; the timing logic is src/core/rate_control.h). `framerate` fixes the output rate;
 * without it the output keeps the input rate (passthrough). With `throttle` (default) a QoS
 * event of type THROTTLE goes upstream whenever a frame is dropped (and once in passthrough),
 * carrying 0.999 x the output frame interval as its diff and the frame's running time as its
 * timestamp - upstream's values - so an upstream tensor_filter skips the frames that would be
 * dropped here. Read-only counters: in, out, duplicate, drop. Duplicates carry the GAP flag.
 * The sink pad accepts any rate and its caps query leaves the framerate open, so upstream keeps
 * its own rate.
 *
 *   gst-launch-1.0 videotestsrc ! video/x-raw,framerate=30/1 ! tensor_converter !
 *     tensor_rate framerate=10/1 throttle=true ! tensor_sink
 */
#include <gst/base/gstbasetransform.h>

#include <atomic>
#include <cstdio>
#include <mutex>

#include "core/rate_control.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_rate_debug);
#define GST_CAT_DEFAULT tensor_rate_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_RATE (gst_tensor_rate_get_type())
G_DECLARE_FINAL_TYPE(GstTensorRate, gst_tensor_rate, GST, TENSOR_RATE, GstBaseTransform)
G_END_DECLS

namespace {

struct RatePriv {
  std::mutex settings_lock;  // guards the three properties
  bool silent = true;
  bool throttle = true;
  int rate_n = -1, rate_d = -1;  // `framerate` property; -1 = unset
  // A malformed `framerate` is refused when set (the previous value stays, as upstream); the
  // element then fails to start, naming it.
  std::string refused_framerate;
  // Counters readable while the streaming thread pushes.
  std::atomic<uint64_t> in{0}, out{0}, dup{0}, drop{0};
  std::mutex lock;  // streaming state below
  nns::RateAdjuster adj;
  GstBuffer *prev = nullptr;
  bool sent_qos_passthrough = false;
  GstSegment segment;
};

enum { PROP_0, PROP_IN, PROP_OUT, PROP_DUP, PROP_DROP, PROP_SILENT, PROP_THROTTLE, PROP_FRAMERATE };
GParamSpec *pspec_drop = nullptr;
GParamSpec *pspec_dup = nullptr;

}  // namespace

struct _GstTensorRate {
  GstBaseTransform parent;
  RatePriv *priv;
};

G_DEFINE_TYPE(GstTensorRate, gst_tensor_rate, GST_TYPE_BASE_TRANSFORM)
GST_ELEMENT_REGISTER_DEFINE(tensor_rate, "tensor_rate", GST_RANK_NONE, GST_TYPE_TENSOR_RATE)

#define RATE_CAPS                                                             \
  "other/tensor, framerate = (fraction) [ 0, max ]; "                         \
  "other/tensors, format = (string) static, num_tensors = (int) [ 1, 256 ], " \
  "framerate = (fraction) [ 0, max ]"

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(RATE_CAPS));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(RATE_CAPS));

static void swap_prev(RatePriv *p, GstBuffer *buf) {
  if (p->prev) gst_buffer_unref(p->prev);
  p->prev = buf ? gst_buffer_ref(buf) : nullptr;
}

static void publish(RatePriv *p) {
  const auto &c = p->adj.counters();
  p->in = c.in;
  p->out = c.out;
  p->dup = c.duplicate;
  p->drop = c.drop;
}

struct Flags {
  bool silent, throttle;
};
static Flags flags(RatePriv *p) {
  std::lock_guard<std::mutex> l(p->settings_lock);
  return {p->silent, p->throttle};
}

static void send_throttle(GstTensorRate *self, GstClockTime running) {
  auto *p = self->priv;
  gint64 delay = p->adj.throttle_delay();
  if (delay <= 0 || !GST_CLOCK_TIME_IS_VALID(running)) return;
  // Proportion is unused by receivers of THROTTLE QoS; upstream sends 0.9.
  GstEvent *ev = gst_event_new_qos(GST_QOS_TYPE_THROTTLE, 0.9, delay, running);
  if (!flags(p).silent)
    GST_INFO_OBJECT(self, "throttle QoS upstream: diff %" G_GINT64_FORMAT " ns", delay);
  gst_pad_push_event(GST_BASE_TRANSFORM_SINK_PAD(self), ev);
}

// Pushes the stored frame with the given timing; called with the lock held.
static bool push_prev(GstTensorRate *self, uint64_t pts, uint64_t dur, bool dup,
                      GstFlowReturn *ret) {
  auto *p = self->priv;
  GstBuffer *out = gst_buffer_make_writable(gst_buffer_ref(p->prev));  // shares the memories
  GST_BUFFER_PTS(out) = pts;
  GST_BUFFER_DTS(out) = GST_CLOCK_TIME_NONE;
  GST_BUFFER_DURATION(out) = dur;
  GST_BUFFER_OFFSET(out) = p->adj.counters().out - 1;
  GST_BUFFER_OFFSET_END(out) = p->adj.counters().out;
  GST_BUFFER_FLAG_UNSET(out, GST_BUFFER_FLAG_DISCONT);
  if (dup)
    GST_BUFFER_FLAG_SET(out, GST_BUFFER_FLAG_GAP);
  else
    GST_BUFFER_FLAG_UNSET(out, GST_BUFFER_FLAG_GAP);
  *ret = gst_pad_push(GST_BASE_TRANSFORM_SRC_PAD(self), out);
  return *ret == GST_FLOW_OK;
}

static GstFlowReturn tensor_rate_transform_ip(GstBaseTransform *trans, GstBuffer *buf) {
  auto *self = GST_TENSOR_RATE(trans);
  auto *p = self->priv;
  const Flags f = flags(p);
  std::unique_lock<std::mutex> l(p->lock);
  GstClockTime ts = GST_BUFFER_PTS(buf);
  if (!GST_CLOCK_TIME_IS_VALID(ts)) {
    GST_WARNING_OBJECT(self, "dropping a frame without timestamp");
    return GST_BASE_TRANSFORM_FLOW_DROPPED;
  }
  if (gst_base_transform_is_passthrough(trans)) {
    p->adj.count_passthrough();
    publish(p);
    if (!p->sent_qos_passthrough && f.throttle) {
      p->sent_qos_passthrough = true;
      GstClockTime running = ts + p->segment.base;
      l.unlock();
      send_throttle(self, running);
    }
    return GST_FLOW_OK;
  }
  GstFlowReturn ret = GST_FLOW_OK;
  nns::RateAdjuster::Result res;
  auto before = p->adj.counters();
  bool ok = p->adj.on_frame(
      ts, GST_BUFFER_DURATION_IS_VALID(buf) ? GST_BUFFER_DURATION(buf) : nns::RateAdjuster::kNone,
      [&](uint64_t pts, uint64_t dur, bool dup) { return push_prev(self, pts, dur, dup, &ret); },
      &res);
  publish(p);
  if (!ok) return ret;
  if (res.store_new) swap_prev(p, buf);
  auto after = p->adj.counters();
  bool notify_drop = after.drop != before.drop && !f.silent;
  bool notify_dup = after.duplicate != before.duplicate && !f.silent;
  bool qos = res.dropped_prev && f.throttle;
  GstClockTime running = ts + p->segment.base;
  l.unlock();
  if (notify_drop) g_object_notify_by_pspec(G_OBJECT(self), pspec_drop);
  if (notify_dup) g_object_notify_by_pspec(G_OBJECT(self), pspec_dup);
  if (qos) send_throttle(self, running);
  return GST_BASE_TRANSFORM_FLOW_DROPPED;  // frames go out through push_prev
}

static GstCaps *tensor_rate_transform_caps(GstBaseTransform *trans, GstPadDirection dir,
                                           GstCaps *caps, GstCaps *filter) {
  auto *p = GST_TENSOR_RATE(trans)->priv;
  int rn, rd;
  {
    std::lock_guard<std::mutex> l(p->settings_lock);
    rn = p->rate_n;
    rd = p->rate_d;
  }
  GstCaps *result = gst_caps_new_empty();
  for (guint i = 0; i < gst_caps_get_size(caps); ++i) {
    GstStructure *s = gst_structure_copy(gst_caps_get_structure(caps, i));
    if (dir == GST_PAD_SINK && rn >= 0 && rd > 0)
      gst_structure_set(s, "framerate", GST_TYPE_FRACTION, rn, rd, nullptr);
    else
      gst_structure_set(s, "framerate", GST_TYPE_FRACTION_RANGE, 0, 1, G_MAXINT, 1, nullptr);
    result = gst_caps_merge_structure_full(result, s,
                                           gst_caps_features_copy(gst_caps_get_features(caps, i)));
  }
  if (filter && gst_caps_get_size(filter) > 0) {
    GstCaps *both = gst_caps_intersect_full(filter, result, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(result);
    result = both;
  }
  return result;
}

// CAPS query on the sink pad while `framerate` is set. GstBaseTransform's default answer puts
// downstream's own caps (at the target rate) first to favour passthrough, which would make
// upstream fixate on the target rate; tensor_rate converts any input rate, so the answer keeps
// the querier's (filter's) order and leaves the framerate open.
static bool answer_sink_caps_query(GstBaseTransform *trans, GstQuery *query) {
  GstCaps *filter = nullptr;
  gst_query_parse_caps(query, &filter);
  GstPad *srcpad = GST_BASE_TRANSFORM_SRC_PAD(trans);
  GstPad *sinkpad = GST_BASE_TRANSFORM_SINK_PAD(trans);
  GstCaps *peer = gst_pad_peer_query_caps(srcpad, nullptr);
  GstCaps *src_templ = gst_pad_get_pad_template_caps(srcpad);
  GstCaps *down = gst_caps_intersect_full(peer, src_templ, GST_CAPS_INTERSECT_FIRST);
  gst_caps_unref(peer);
  gst_caps_unref(src_templ);
  GstCaps *any_rate = tensor_rate_transform_caps(trans, GST_PAD_SRC, down, nullptr);
  gst_caps_unref(down);
  GstCaps *sink_templ = gst_pad_get_pad_template_caps(sinkpad);
  GstCaps *result = gst_caps_intersect_full(any_rate, sink_templ, GST_CAPS_INTERSECT_FIRST);
  gst_caps_unref(any_rate);
  gst_caps_unref(sink_templ);
  if (filter) {
    GstCaps *both = gst_caps_intersect_full(filter, result, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(result);
    result = both;
  }
  gst_query_set_caps_result(query, result);
  gst_caps_unref(result);
  return true;
}

static gboolean tensor_rate_query(GstBaseTransform *trans, GstPadDirection dir, GstQuery *query) {
  if (GST_QUERY_TYPE(query) == GST_QUERY_CAPS && dir == GST_PAD_SINK) {
    auto *p = GST_TENSOR_RATE(trans)->priv;
    bool rate_set;
    {
      std::lock_guard<std::mutex> l(p->settings_lock);
      rate_set = p->rate_n >= 0 && p->rate_d > 0;
    }
    if (rate_set) return answer_sink_caps_query(trans, query);
  }
  return GST_BASE_TRANSFORM_CLASS(gst_tensor_rate_parent_class)->query(trans, dir, query);
}

static GstCaps *tensor_rate_fixate_caps(GstBaseTransform *, GstPadDirection, GstCaps *caps,
                                        GstCaps *othercaps) {
  int n, d;
  if (!gst_structure_get_fraction(gst_caps_get_structure(caps, 0), "framerate", &n, &d))
    return gst_caps_fixate(othercaps);
  othercaps = gst_caps_make_writable(gst_caps_truncate(othercaps));
  gst_structure_fixate_field_nearest_fraction(gst_caps_get_structure(othercaps, 0), "framerate", n,
                                              d);
  return gst_caps_fixate(othercaps);
}

static gboolean tensor_rate_set_caps(GstBaseTransform *trans, GstCaps *in, GstCaps *out) {
  auto *self = GST_TENSOR_RATE(trans);
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    auto icfg = nns::gst::config_from_caps(in);
    auto ocfg = nns::gst::config_from_caps(out);
    if (icfg.rate_n < 0 || ocfg.rate_n < 0)
      nns::fail(nns::ErrorKind::kNegotiation, "caps need a framerate, got " +
                                                  nns::gst::caps_to_string(in) + " -> " +
                                                  nns::gst::caps_to_string(out));
    if (ocfg.rate_n > 0 && icfg.rate_n == 0)
      nns::fail(nns::ErrorKind::kNegotiation,
                "framerate=" + std::to_string(ocfg.rate_n) + "/" + std::to_string(ocfg.rate_d) +
                    " needs an input with a known rate, got framerate 0/1 (variable)");
    auto *p = self->priv;
    std::lock_guard<std::mutex> l(p->lock);
    p->adj.set_output_rate(ocfg.rate_n, ocfg.rate_d);
    swap_prev(p, nullptr);
    return TRUE;
  });
}

static gboolean tensor_rate_sink_event(GstBaseTransform *trans, GstEvent *event) {
  auto *self = GST_TENSOR_RATE(trans);
  auto *p = self->priv;
  auto drain = [&] {
    std::lock_guard<std::mutex> l(p->lock);
    if (!p->prev) return;
    GstFlowReturn ret;
    p->adj.drain(
        [&](uint64_t pts, uint64_t dur, bool dup) { return push_prev(self, pts, dur, dup, &ret); });
    publish(p);
    swap_prev(p, nullptr);
  };
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_SEGMENT: {
      GstSegment seg;
      gst_event_copy_segment(event, &seg);
      if (seg.format != GST_FORMAT_TIME) {
        NNS_POST_ERROR(self, nns::ErrorKind::kStream,
                       std::string("needs a TIME segment, got ") + gst_format_get_name(seg.format));
        gst_event_unref(event);
        return FALSE;
      }
      if (!gst_base_transform_is_passthrough(trans)) drain();
      std::lock_guard<std::mutex> l(p->lock);
      p->segment = seg;
      p->adj.new_segment(seg.base, seg.start,
                         GST_CLOCK_TIME_IS_VALID(seg.stop) ? seg.stop : nns::RateAdjuster::kNone);
      break;
    }
    case GST_EVENT_EOS:
    case GST_EVENT_SEGMENT_DONE:
      if (!gst_base_transform_is_passthrough(trans)) drain();
      break;
    case GST_EVENT_FLUSH_STOP: {
      std::lock_guard<std::mutex> l(p->lock);
      swap_prev(p, nullptr);
      p->adj.forget_prev();
      break;
    }
    case GST_EVENT_GAP:
      gst_event_unref(event);  // duplicates fill gaps; nothing to forward
      return TRUE;
    default:
      break;
  }
  return GST_BASE_TRANSFORM_CLASS(gst_tensor_rate_parent_class)->sink_event(trans, event);
}

static gboolean tensor_rate_start(GstBaseTransform *trans) {
  auto *p = GST_TENSOR_RATE(trans)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  p->adj.reset();
  publish(p);
  swap_prev(p, nullptr);
  p->sent_qos_passthrough = false;
  gst_segment_init(&p->segment, GST_FORMAT_TIME);
  return TRUE;
}

static gboolean tensor_rate_stop(GstBaseTransform *trans) {
  auto *p = GST_TENSOR_RATE(trans)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  swap_prev(p, nullptr);
  return TRUE;
}

static void gst_tensor_rate_set_property(GObject *object, guint id, const GValue *value,
                                         GParamSpec *pspec) {
  auto *self = GST_TENSOR_RATE(object);
  auto *p = self->priv;
  std::lock_guard<std::mutex> l(p->settings_lock);
  switch (id) {
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    case PROP_THROTTLE:
      p->throttle = g_value_get_boolean(value);
      break;
    case PROP_FRAMERATE: {
      const char *s = g_value_get_string(value);
      std::string str = s ? nns::trim(s) : "";
      if (str.empty()) {
        p->rate_n = p->rate_d = -1;
        p->refused_framerate.clear();
        break;
      }
      int n = -1, d = -1;
      char extra;
      if (std::sscanf(str.c_str(), "%d/%d%c", &n, &d, &extra) != 2 || n < 0 || d <= 0) {
        // Refused: the previous value stays; reported when the element starts.
        GST_WARNING_OBJECT(self, "framerate '%s' is not N/D: refused", str.c_str());
        p->refused_framerate = str;
        break;
      }
      p->refused_framerate.clear();
      p->rate_n = n;
      p->rate_d = d;
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_rate_get_property(GObject *object, guint id, GValue *value,
                                         GParamSpec *pspec) {
  auto *p = GST_TENSOR_RATE(object)->priv;
  std::lock_guard<std::mutex> l(p->settings_lock);
  switch (id) {
    case PROP_IN:
      g_value_set_uint64(value, p->in);
      break;
    case PROP_OUT:
      g_value_set_uint64(value, p->out);
      break;
    case PROP_DUP:
      g_value_set_uint64(value, p->dup);
      break;
    case PROP_DROP:
      g_value_set_uint64(value, p->drop);
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    case PROP_THROTTLE:
      g_value_set_boolean(value, p->throttle);
      break;
    case PROP_FRAMERATE:
      if (p->rate_n >= 0 && p->rate_d > 0) {
        g_value_take_string(value, g_strdup_printf("%d/%d", p->rate_n, p->rate_d));
      } else {
        g_value_set_string(value, "");
      }
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static GstStateChangeReturn tensor_rate_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_RATE(element);
  if (t == GST_STATE_CHANGE_NULL_TO_READY) {
    std::lock_guard<std::mutex> l(self->priv->settings_lock);
    if (!self->priv->refused_framerate.empty()) {
      const RatePriv *p = self->priv;
      std::string kept = p->rate_n >= 0 && p->rate_d > 0 ? "'" + std::to_string(p->rate_n) + "/" +
                                                               std::to_string(p->rate_d) + "'"
                                                         : std::string("no value");
      NNS_POST_ERROR(self, nns::ErrorKind::kSettings,
                     "framerate '" + p->refused_framerate +
                         "' was refused: it must be N/D with N >= 0 and D > 0 (e.g. "
                         "framerate=10/1); 'framerate' kept " +
                         kept);
      return GST_STATE_CHANGE_FAILURE;
    }
  }
  return GST_ELEMENT_CLASS(gst_tensor_rate_parent_class)->change_state(element, t);
}

static void gst_tensor_rate_finalize(GObject *object) {
  auto *p = GST_TENSOR_RATE(object)->priv;
  swap_prev(p, nullptr);
  delete p;
  G_OBJECT_CLASS(gst_tensor_rate_parent_class)->finalize(object);
}

static void gst_tensor_rate_class_init(GstTensorRateClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_rate_debug, "tensor_rate", 0, "tensor_rate element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *trans_class = GST_BASE_TRANSFORM_CLASS(klass);
  gobject_class->set_property = gst_tensor_rate_set_property;
  gobject_class->get_property = gst_tensor_rate_get_property;
  gobject_class->finalize = gst_tensor_rate_finalize;
  auto ro = static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS);
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_IN,
      g_param_spec_uint64("in", "In", "Frames received", 0, G_MAXUINT64, 0, ro));
  g_object_class_install_property(
      gobject_class, PROP_OUT,
      g_param_spec_uint64("out", "Out", "Frames sent", 0, G_MAXUINT64, 0, ro));
  pspec_dup = g_param_spec_uint64("duplicate", "Duplicate", "Frames sent more than once", 0,
                                  G_MAXUINT64, 0, ro);
  g_object_class_install_property(gobject_class, PROP_DUP, pspec_dup);
  pspec_drop = g_param_spec_uint64("drop", "Drop", "Frames dropped", 0, G_MAXUINT64, 0, ro);
  g_object_class_install_property(gobject_class, PROP_DROP, pspec_drop);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log or notify dropped/duplicated frames",
                           TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_THROTTLE,
      g_param_spec_boolean("throttle", "Throttle",
                           "Send QoS events upstream so it produces only frames that are used",
                           TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_FRAMERATE,
      g_param_spec_string("framerate", "Framerate",
                          "Output frame rate N/D (e.g. 10/1); empty keeps the input rate", "", rw));
  gst_element_class_set_static_metadata(element_class, "TensorRate", "Filter/Tensor",
                                        "Adjusts the frame rate of a tensor stream",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->change_state = tensor_rate_change_state;
  trans_class->passthrough_on_same_caps = TRUE;
  trans_class->transform_ip_on_passthrough = TRUE;
  trans_class->transform_ip = tensor_rate_transform_ip;
  trans_class->transform_caps = tensor_rate_transform_caps;
  trans_class->fixate_caps = tensor_rate_fixate_caps;
  trans_class->query = tensor_rate_query;
  trans_class->set_caps = tensor_rate_set_caps;
  trans_class->sink_event = tensor_rate_sink_event;
  trans_class->start = tensor_rate_start;
  trans_class->stop = tensor_rate_stop;
}

static void gst_tensor_rate_init(GstTensorRate *self) {
  self->priv = new RatePriv();
  gst_segment_init(&self->priv->segment, GST_FORMAT_TIME);
}

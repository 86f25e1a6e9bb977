// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_split
 *
 * Cuts a single tensor into segments, one src pad each (the opposite of tensor_merge).
 * `tensorseg` lists the segments' dimensions; segments are consecutive byte ranges of the
 * input, in order, and keep its type. `tensorpick` keeps only some segments (they leave on
 * src_0, src_1, ... in ascending index order). Segments are not copied: each output memory
 * shares the input memory's region.
 *
 *   gst-launch-1.0 ... ! video/x-raw,format=RGB,width=100,height=100 ! tensor_converter ! \
 *     tensor_split name=s tensorseg=1:100:100,2:100:100 \
 *     s.src_0 ! queue ! tensor_sink  s.src_1 ! queue ! tensor_sink
 */
#include <atomic>
#include <mutex>

#include "core/error.h"
#include "core/tensor_select.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_srcpads.h"

GST_DEBUG_CATEGORY_STATIC(tensor_split_debug);
#define GST_CAT_DEFAULT tensor_split_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_SPLIT (gst_tensor_split_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSplit, gst_tensor_split, GST, TENSOR_SPLIT, GstElement)
G_END_DECLS

#define SPLIT_CAPS                                                   \
  "other/tensor, framerate = (fraction) [ 0, max ]; "                \
  "other/tensors, format = (string) static, num_tensors = (int) 1, " \
  "framerate = (fraction) [ 0, max ]"

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(SPLIT_CAPS));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src_%u", GST_PAD_SRC, GST_PAD_SOMETIMES, GST_STATIC_CAPS(SPLIT_CAPS));

namespace {

struct SplitPriv {
  explicit SplitPriv(GstElement *e) : pads(e, &src_template) {}
  // Settings
  std::mutex lock;
  std::string tensorseg, tensorpick;
  std::atomic<bool> silent{true};
  // State (streaming thread)
  std::vector<nns::Dims> seg;
  std::vector<uint32_t> pick;
  nns::TensorInfo in;
  std::vector<nns::Segment> plan;
  nns::gst::SrcPads pads;
};

enum { PROP_0, PROP_SILENT, PROP_TENSORPICK, PROP_TENSORSEG };

}  // namespace

struct _GstTensorSplit {
  GstElement parent;
  GstPad *sinkpad;
  SplitPriv *priv;
};

G_DEFINE_TYPE(GstTensorSplit, gst_tensor_split, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_split, "tensor_split", GST_RANK_NONE, GST_TYPE_TENSOR_SPLIT)

namespace {

void on_caps(GstTensorSplit *self, GstCaps *caps) {
  SplitPriv *p = self->priv;
  nns::TensorsConfig c = nns::gst::config_from_caps(caps);
  if (c.info.format != nns::TensorFormat::kStatic || c.info.size() != 1 || !c.info.valid())
    nns::fail(nns::ErrorKind::kNegotiation,
              "needs one static tensor, got " + nns::gst::caps_to_string(caps));
  p->in = c.info[0];
  p->plan = nns::plan_split(p->in, p->seg, p->pick);
  std::vector<nns::TensorsConfig> configs;
  for (const auto &s : p->plan) {
    nns::TensorsConfig o;
    o.info.tensors.push_back(s.info);
    o.rate_n = c.rate_n < 0 ? 0 : c.rate_n;
    o.rate_d = c.rate_n < 0 ? 1 : c.rate_d;
    configs.push_back(o);
  }
  p->pads.configure(self->sinkpad, configs);
}

GstFlowReturn split_chain(GstTensorSplit *self, GstBuffer *buf) {
  SplitPriv *p = self->priv;
  if (p->pads.size() == 0) nns::fail(nns::ErrorKind::kNegotiation, "received data before caps");
  // One memory normally; several are merged (a copy) to get one contiguous tensor.
  nns::gst::MemoryPtr mem(gst_buffer_n_memory(buf) == 1 ? gst_buffer_get_memory(buf, 0)
                                                        : gst_buffer_get_all_memory(buf));
  gsize size = mem ? gst_memory_get_sizes(mem.get(), nullptr, nullptr) : 0;
  if (size != p->in.byte_size())
    nns::fail(nns::ErrorKind::kStream, "buffer has " + std::to_string(size) + " bytes, expected " +
                                           std::to_string(p->in.byte_size()) + " for " +
                                           p->in.to_string());
  GstFlowReturn ret = GST_FLOW_OK;
  for (std::size_t i = 0; i < p->plan.size() && ret == GST_FLOW_OK; ++i) {
    const nns::Segment &s = p->plan[i];
    GstBuffer *out = gst_buffer_new();
    gst_buffer_append_memory(out, gst_memory_share(mem.get(), static_cast<gssize>(s.offset),
                                                   static_cast<gssize>(s.size)));
    gst_buffer_copy_into(out, buf, GST_BUFFER_COPY_METADATA, 0, -1);
    ret = p->pads.push(i, out);
  }
  return ret;
}

}  // namespace

static GstFlowReturn gst_tensor_split_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_SPLIT(parent);
  nns::gst::BufferPtr guard(buf);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&] { return split_chain(self, buf); });
}

static gboolean gst_tensor_split_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_SPLIT(parent);
  return self->priv->pads.sink_event(pad, event,
                                     "got EOS before any output pad was created (no caps)",
                                     [self](GstCaps *caps) { on_caps(self, caps); });
}

static GstStateChangeReturn gst_tensor_split_change_state(GstElement *element,
                                                          GstStateChange transition) {
  SplitPriv *p = GST_TENSOR_SPLIT(element)->priv;
  return p->pads.change_state(GST_ELEMENT_CLASS(gst_tensor_split_parent_class), transition, [p] {
    std::lock_guard<std::mutex> g(p->lock);
    p->seg = nns::parse_tensorseg(p->tensorseg);
    if (p->seg.empty())
      nns::fail(nns::ErrorKind::kSettings, "tensorseg is not set: nothing to split");
    p->pick = nns::parse_split_tensorpick(p->tensorpick);
  });
}

static void gst_tensor_split_set_property(GObject *object, guint id, const GValue *value,
                                          GParamSpec *pspec) {
  SplitPriv *p = GST_TENSOR_SPLIT(object)->priv;
  if (id == PROP_SILENT) {
    p->silent = g_value_get_boolean(value);
    return;
  }
  std::lock_guard<std::mutex> g(p->lock);
  const char *s = g_value_get_string(value);
  switch (id) {
    case PROP_TENSORPICK:
      p->tensorpick = s ? s : "";
      break;
    case PROP_TENSORSEG:
      p->tensorseg = s ? s : "";
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_split_get_property(GObject *object, guint id, GValue *value,
                                          GParamSpec *pspec) {
  SplitPriv *p = GST_TENSOR_SPLIT(object)->priv;
  if (id == PROP_SILENT) {
    g_value_set_boolean(value, p->silent);
    return;
  }
  std::lock_guard<std::mutex> g(p->lock);
  switch (id) {
    case PROP_TENSORPICK:
      g_value_set_string(value, p->tensorpick.c_str());
      break;
    case PROP_TENSORSEG:
      g_value_set_string(value, p->tensorseg.c_str());
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_split_finalize(GObject *object) {
  delete GST_TENSOR_SPLIT(object)->priv;
  G_OBJECT_CLASS(gst_tensor_split_parent_class)->finalize(object);
}

static void gst_tensor_split_class_init(GstTensorSplitClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_split_debug, "tensor_split", 0, "tensor_split element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_split_set_property;
  gobject_class->get_property = gst_tensor_split_get_property;
  gobject_class->finalize = gst_tensor_split_finalize;
  auto flags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  auto ready = static_cast<GParamFlags>(flags | GST_PARAM_MUTABLE_READY);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log each buffer", TRUE, flags));
  g_object_class_install_property(
      gobject_class, PROP_TENSORPICK,
      g_param_spec_string("tensorpick", "Tensor pick",
                          "Indices of the segments to output, separated by ',' (empty = all)", "",
                          ready));
  g_object_class_install_property(
      gobject_class, PROP_TENSORSEG,
      g_param_spec_string("tensorseg", "Tensor segments",
                          "Dimensions of each segment, in input order, separated by ',' "
                          "(e.g. 1:100:100,2:100:100)",
                          "", ready));
  element_class->change_state = gst_tensor_split_change_state;
  gst_element_class_set_static_metadata(element_class, "TensorSplit", "Demuxer/Tensor",
                                        "Cuts a tensor into consecutive segments",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
}

static void gst_tensor_split_init(GstTensorSplit *self) {
  self->priv = new SplitPriv(GST_ELEMENT(self));
  self->sinkpad = gst_pad_new_from_static_template(&sink_template, "sink");
  gst_pad_set_chain_function(self->sinkpad, gst_tensor_split_chain);
  gst_pad_set_event_function(self->sinkpad, gst_tensor_split_sink_event);
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
}

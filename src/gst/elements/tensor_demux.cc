// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_demux
 *
 * Splits an other/tensors stream into several streams: by default one src pad per tensor;
 * with `tensorpick` one src pad per group, pads separated by ',' and tensors of one pad by ':'
 * ("0,1:2" = src_0 gets tensor 0, src_1 gets tensors 1 and 2). Pads are created when the
 * caps arrive (for flexible input without tensorpick, at the first buffer). No data is
 * copied: output buffers hold the input's memories.
 *
 *   gst-launch-1.0 ... ! tensor_demux name=d tensorpick=0,1:2 \
 *     d.src_0 ! queue ! tensor_sink  d.src_1 ! queue ! tensor_sink
 */
#include <atomic>
#include <mutex>
#include <optional>

#include "core/error.h"
#include "core/tensor_select.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_srcpads.h"

GST_DEBUG_CATEGORY_STATIC(tensor_demux_debug);
#define GST_CAT_DEFAULT tensor_demux_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_DEMUX (gst_tensor_demux_get_type())
G_DECLARE_FINAL_TYPE(GstTensorDemux, gst_tensor_demux, GST, TENSOR_DEMUX, GstElement)
G_END_DECLS

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensors, format = (string) { static, flexible }, "
                    "framerate = (fraction) [ 0, max ]"));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src_%u", GST_PAD_SRC, GST_PAD_SOMETIMES, GST_STATIC_CAPS(NNS_TENSOR_CAPS_ANY_STR));

namespace {

struct DemuxPriv {
  explicit DemuxPriv(GstElement *e) : pads(e, &src_template) {}
  // Settings
  std::mutex lock;
  std::string tensorpick;
  std::atomic<bool> silent{true};
  // State (streaming thread)
  nns::PickGroups groups;  // parsed tensorpick, or empty
  nns::TensorsConfig in;
  std::optional<nns::PickGroups> out;  // the groups the pads carry; unset until configured
  nns::gst::SrcPads pads;
};

enum { PROP_0, PROP_SILENT, PROP_TENSORPICK };

}  // namespace

struct _GstTensorDemux {
  GstElement parent;
  GstPad *sinkpad;
  DemuxPriv *priv;
};

G_DEFINE_TYPE(GstTensorDemux, gst_tensor_demux, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_demux, "tensor_demux", GST_RANK_NONE, GST_TYPE_TENSOR_DEMUX)

namespace {

// Creates the pads for `groups` of the negotiated input.
void make_pads(GstTensorDemux *self, const nns::PickGroups &groups) {
  DemuxPriv *p = self->priv;
  std::vector<nns::TensorsConfig> configs;
  for (const auto &g : groups) {
    nns::TensorsConfig c;
    c.rate_n = p->in.rate_n;
    c.rate_d = p->in.rate_d;
    c.info.format = p->in.info.format;
    if (p->in.info.format == nns::TensorFormat::kStatic)
      for (uint32_t idx : g) c.info.tensors.push_back(p->in.info[idx]);
    if (c.rate_n < 0) {
      c.rate_n = 0;
      c.rate_d = 1;
    }
    configs.push_back(c);
  }
  p->pads.configure(self->sinkpad, configs);
  p->out = groups;
}

void on_caps(GstTensorDemux *self, GstCaps *caps) {
  DemuxPriv *p = self->priv;
  p->in = nns::gst::config_from_caps(caps);
  if (p->in.info.format == nns::TensorFormat::kStatic) {
    if (!p->in.info.valid())
      nns::fail(nns::ErrorKind::kNegotiation,
                "caps do not describe complete tensors: " + nns::gst::caps_to_string(caps));
    nns::PickGroups g =
        p->groups.empty() ? nns::default_demux_groups(p->in.info.size()) : p->groups;
    nns::check_demux_tensorpick(g, p->in.info.size());
    make_pads(self, g);
  } else if (!p->groups.empty()) {
    make_pads(self, p->groups);
  } else {
    p->out.reset();  // flexible: the tensor count is known at the first buffer
  }
}

GstFlowReturn demux_chain(GstTensorDemux *self, GstBuffer *buf) {
  DemuxPriv *p = self->priv;
  const bool is_static = p->in.info.format == nns::TensorFormat::kStatic;
  const std::size_t count =
      is_static ? nns::gst::buffer_tensor_count(buf) : gst_buffer_n_memory(buf);
  if (is_static && count != p->in.info.size())
    nns::fail(nns::ErrorKind::kStream, "buffer has " + std::to_string(count) +
                                           " tensors, the caps say " +
                                           std::to_string(p->in.info.size()));
  if (!p->out) make_pads(self, nns::default_demux_groups(count));
  const nns::PickGroups &groups = *p->out;
  if (!is_static) nns::check_demux_tensorpick(groups, count);
  GstFlowReturn ret = GST_FLOW_OK;
  for (std::size_t i = 0; i < groups.size(); ++i) {
    GstBuffer *out = gst_buffer_new();
    for (uint32_t idx : groups[i]) {
      GstMemory *mem = nns::gst::buffer_get_tensor(buf, idx);
      if (is_static) {
        gsize size = gst_memory_get_sizes(mem, nullptr, nullptr);
        if (size != p->in.info[idx].byte_size()) {
          gst_memory_unref(mem);
          gst_buffer_unref(out);
          nns::fail(nns::ErrorKind::kStream, "tensor " + std::to_string(idx) + " has " +
                                                 std::to_string(size) + " bytes, expected " +
                                                 std::to_string(p->in.info[idx].byte_size()) +
                                                 " for " + p->in.info[idx].to_string());
        }
        nns::gst::buffer_append_tensor(out, mem, p->in.info[idx]);
      } else {
        gst_buffer_append_memory(out, mem);
      }
    }
    gst_buffer_copy_into(out, buf, GST_BUFFER_COPY_METADATA, 0, -1);
    ret = p->pads.push(i, out);
    if (ret != GST_FLOW_OK) break;
  }
  return ret;
}

}  // namespace

static GstFlowReturn gst_tensor_demux_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_DEMUX(parent);
  nns::gst::BufferPtr guard(buf);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&] { return demux_chain(self, buf); });
}

static gboolean gst_tensor_demux_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_DEMUX(parent);
  return self->priv->pads.sink_event(
      pad, event, "got EOS before any output pad was created (no caps or no data)",
      [self](GstCaps *caps) { on_caps(self, caps); });
}

static GstStateChangeReturn gst_tensor_demux_change_state(GstElement *element,
                                                          GstStateChange transition) {
  DemuxPriv *p = GST_TENSOR_DEMUX(element)->priv;
  return p->pads.change_state(
      GST_ELEMENT_CLASS(gst_tensor_demux_parent_class), transition,
      [p] {
        {
          std::lock_guard<std::mutex> g(p->lock);
          p->groups = nns::parse_demux_tensorpick(p->tensorpick);
        }
        p->out.reset();
      },
      [p] { p->out.reset(); });
}

static void gst_tensor_demux_set_property(GObject *object, guint id, const GValue *value,
                                          GParamSpec *pspec) {
  DemuxPriv *p = GST_TENSOR_DEMUX(object)->priv;
  switch (id) {
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    case PROP_TENSORPICK: {
      std::lock_guard<std::mutex> g(p->lock);
      const char *s = g_value_get_string(value);
      p->tensorpick = s ? s : "";
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_demux_get_property(GObject *object, guint id, GValue *value,
                                          GParamSpec *pspec) {
  DemuxPriv *p = GST_TENSOR_DEMUX(object)->priv;
  switch (id) {
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    case PROP_TENSORPICK: {
      std::lock_guard<std::mutex> g(p->lock);
      g_value_set_string(value, p->tensorpick.c_str());
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_demux_finalize(GObject *object) {
  delete GST_TENSOR_DEMUX(object)->priv;
  G_OBJECT_CLASS(gst_tensor_demux_parent_class)->finalize(object);
}

static void gst_tensor_demux_class_init(GstTensorDemuxClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_demux_debug, "tensor_demux", 0, "tensor_demux element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_demux_set_property;
  gobject_class->get_property = gst_tensor_demux_get_property;
  gobject_class->finalize = gst_tensor_demux_finalize;
  auto flags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log each buffer", TRUE, flags));
  g_object_class_install_property(
      gobject_class, PROP_TENSORPICK,
      g_param_spec_string("tensorpick", "Tensor pick",
                          "Tensors per src pad: pads separated by ',', tensors of one pad by "
                          "':' (e.g. 0,1:2); empty = one pad per tensor",
                          "", static_cast<GParamFlags>(flags | GST_PARAM_MUTABLE_READY)));
  element_class->change_state = gst_tensor_demux_change_state;
  gst_element_class_set_static_metadata(element_class, "TensorDemux", "Demuxer/Tensor",
                                        "Splits an other/tensors stream into tensor streams",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
}

static void gst_tensor_demux_init(GstTensorDemux *self) {
  self->priv = new DemuxPriv(GST_ELEMENT(self));
  self->sinkpad = gst_pad_new_from_static_template(&sink_template, "sink");
  gst_pad_set_chain_function(self->sinkpad, gst_tensor_demux_chain);
  gst_pad_set_event_function(self->sinkpad, gst_tensor_demux_sink_event);
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
}

// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_crop
 *
 * Crops regions out of a tensor frame. The `raw` pad takes one NHWC tensor (static or
 * flexible; dimension 0 = channels, 1 = width, 2 = height), the `info` pad takes flexible crop
 * info: {x, y, w, h} quadruples of any numeric type (tensor_decoder mode=tensor_region's
 * output). The output is a flexible stream with one memory per region ([C, w, h, 1], the raw
 * type), timestamped like the raw frame. Region logic: src/core/crop.h. A region reaching past
 * the frame is clipped (as upstream; a warning is posted once), a region starting outside it
 * is a bus error naming the region and the frame size. `lateness` (ms, -1 = off): when both
 * timestamps are valid and differ by more, the older buffer is dropped and the next awaited.
 * A frame with no region produces no output.
 *
 *   gst-launch-1.0 ... ! tensor_converter ! crop.raw
 *     ... ! tensor_decoder mode=tensor_region ... ! crop.info
 *     tensor_crop name=crop lateness=50 ! other/tensors,format=flexible ! ...
 */
#include <gst/base/gstcollectpads.h>

#include <atomic>
#include <cstring>

#include "core/crop.h"
#include "gst/element_glue.h"
#include "gst/flow_util.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_crop_debug);
#define GST_CAT_DEFAULT tensor_crop_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_CROP (gst_tensor_crop_get_type())
G_DECLARE_FINAL_TYPE(GstTensorCrop, gst_tensor_crop, GST, TENSOR_CROP, GstElement)
G_END_DECLS

namespace {

struct CropPad {
  GstCollectData data;  // must be first
  nns::TensorsConfig *config;
  bool has_caps;
};

struct CropPriv {
  std::atomic<gint> lateness{-1};
  std::atomic<bool> silent{true};
  bool warned_clip = false;
  bool eos_sent = false;
};

enum { PROP_0, PROP_LATENESS, PROP_SILENT };

}  // namespace

struct _GstTensorCrop {
  GstElement parent;
  GstPad *raw;
  GstPad *info;
  GstPad *srcpad;
  GstCollectPads *collect;
  CropPad *raw_data;
  CropPad *info_data;
  CropPriv *priv;
};

G_DEFINE_TYPE(GstTensorCrop, gst_tensor_crop, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_crop, "tensor_crop", GST_RANK_NONE, GST_TYPE_TENSOR_CROP)

static GstStaticPadTemplate raw_template = GST_STATIC_PAD_TEMPLATE(
    "raw", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensor, framerate = (fraction) [ 0, max ]; "
                    "other/tensors, format = (string) { static, flexible }, "
                    "framerate = (fraction) [ 0, max ]"));
static GstStaticPadTemplate info_template = GST_STATIC_PAD_TEMPLATE(
    "info", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS(
        "other/tensors, format = (string) flexible, framerate = (fraction) [ 0, max ]"));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS(
        "other/tensors, format = (string) flexible, framerate = (fraction) [ 0, max ]"));

static void crop_pad_destroy(GstCollectData *data) {
  delete reinterpret_cast<CropPad *>(data)->config;
}

static gboolean crop_sink_event(GstCollectPads *pads, GstCollectData *data, GstEvent *event,
                                gpointer user) {
  auto *self = GST_TENSOR_CROP(user);
  auto *cp = reinterpret_cast<CropPad *>(data);
  if (GST_EVENT_TYPE(event) == GST_EVENT_CAPS) {
    nns::gst::EventPtr owned(event);
    return nns::gst::guard(self, FALSE, [&]() -> gboolean {
      GstCaps *caps;
      gst_event_parse_caps(event, &caps);
      auto cfg = nns::gst::config_from_caps(caps);
      if (data->pad == self->raw && cfg.info.format == nns::TensorFormat::kStatic &&
          !cfg.info.valid())
        nns::fail(nns::ErrorKind::kNegotiation,
                  "raw pad caps need the dimension and type of the tensor, got " +
                      nns::gst::caps_to_string(caps));
      *cp->config = cfg;
      cp->has_caps = true;
      return TRUE;
    });
  }
  if (GST_EVENT_TYPE(event) == GST_EVENT_STREAM_START ||
      GST_EVENT_TYPE(event) == GST_EVENT_SEGMENT) {
    gst_event_unref(event);  // the src pad gets its own
    return TRUE;
  }
  return gst_collect_pads_event_default(pads, data, event, FALSE);
}

// Output caps (flexible, the lower of the two rates) and stream-start/segment, once.
static void negotiate(GstTensorCrop *self) {
  nns::gst::CapsPtr cur(gst_pad_get_current_caps(self->srcpad));
  if (cur) return;
  nns::TensorsConfig out;
  out.info.format = nns::TensorFormat::kFlexible;
  for (CropPad *cp : {self->raw_data, self->info_data}) {
    const auto &c = *cp->config;
    if (c.rate_n < 0 || c.rate_d <= 0) continue;
    if (out.rate_n < 0 ||
        gst_util_fraction_compare(c.rate_n, c.rate_d, out.rate_n, out.rate_d) < 0) {
      out.rate_n = c.rate_n;
      out.rate_d = c.rate_d;
    }
  }
  if (out.rate_n < 0) {
    out.rate_n = 0;
    out.rate_d = 1;
  }
  nns::gst::start_src_pad(GST_ELEMENT(self), self->srcpad, "src", out);
}

// Crops `raw` by the regions of `info` into a new flexible buffer (nullptr: no region).
static GstBuffer *do_crop(GstTensorCrop *self, GstBuffer *raw, GstBuffer *info) {
  // Regions.
  if (gst_buffer_n_memory(info) == 0)
    nns::fail(nns::ErrorKind::kStream, "info buffer has no memory");
  std::vector<nns::CropRegion> regions;
  {
    nns::gst::MemoryMap m(gst_buffer_peek_memory(info, 0), GST_MAP_READ);
    if (!m.ok()) nns::fail(nns::ErrorKind::kStream, "cannot map the info buffer");
    nns::MetaHeader h;
    try {
      h = nns::parse_meta_header(m.data(), m.size());
    } catch (const nns::Error &e) {
      nns::fail(nns::ErrorKind::kStream, std::string("info pad: ") + e.what());
    }
    regions = nns::parse_crop_regions(h.type, m.data() + nns::kMetaHeaderSize,
                                      m.size() - nns::kMetaHeaderSize);
  }
  if (regions.empty()) return nullptr;
  // Raw frame.
  const auto &rcfg = *self->raw_data->config;
  nns::gst::MemoryMap m(gst_buffer_peek_memory(raw, 0), GST_MAP_READ);
  if (!m.ok()) nns::fail(nns::ErrorKind::kStream, "cannot map the raw buffer");
  nns::TensorInfo t;
  nns::MediaType media = nns::MediaType::kTensor;
  const uint8_t *data = m.data();
  std::size_t size = m.size();
  if (rcfg.info.format == nns::TensorFormat::kFlexible) {
    nns::MetaHeader h;
    try {
      h = nns::parse_meta_header(m.data(), m.size());
    } catch (const nns::Error &e) {
      nns::fail(nns::ErrorKind::kStream, std::string("raw pad: ") + e.what());
    }
    t = h.info();
    media = h.media_type;
    data += nns::kMetaHeaderSize;
    size -= nns::kMetaHeaderSize;
  } else {
    t = rcfg.info[0];
  }
  if (size != t.byte_size())
    nns::fail(nns::ErrorKind::kStream, "raw tensor has " + std::to_string(size) +
                                           " bytes, expected " + std::to_string(t.byte_size()) +
                                           " for " + t.to_string());
  const uint32_t ch = t.dims[0] ? t.dims[0] : 1, width = t.dims[1] ? t.dims[1] : 1,
                 height = t.dims[2] ? t.dims[2] : 1;
  if (std::size_t(ch) * width * height != t.element_count())
    nns::fail(nns::ErrorKind::kStream,
              "raw tensor " + t.to_string() + " is not one NHWC frame (channel:width:height:1)");
  const std::size_t esize = nns::type_size(t.type);
  nns::gst::BufferPtr out(gst_buffer_new());
  for (std::size_t i = 0; i < regions.size(); ++i) {
    bool clipped = false;
    nns::CropRegion r = nns::fit_crop_region(regions[i], width, height, i, &clipped);
    if (clipped) {
      GST_DEBUG_OBJECT(self, "region %zu %s clipped to %s", i, regions[i].to_string().c_str(),
                       r.to_string().c_str());
      if (!self->priv->warned_clip) {
        self->priv->warned_clip = true;
        NNS_POST_WARNING(self, "crop region " + std::to_string(i) + " " + regions[i].to_string() +
                                   " reaches past the " + std::to_string(width) + "x" +
                                   std::to_string(height) + " frame; clipped to " + r.to_string());
      }
    }
    const nns::MetaHeader oh = nns::flexible_header(t.type, nns::make_dims({ch, r.w, r.h, 1}),
                                                    media, nns::FlexHeaderKind::kMarkedFlexible);
    std::size_t payload = std::size_t(r.w) * r.h * ch * esize;
    GstMemory *mem = nns::gst::alloc_memory(nns::kMetaHeaderSize + payload);
    {
      nns::gst::MemoryMap w(mem, GST_MAP_WRITE);
      nns::write_meta_header(oh, w.data());
      nns::crop_nhwc(data, ch, width, esize, r, w.data() + nns::kMetaHeaderSize);
    }
    gst_buffer_append_memory(out.get(), mem);
  }
  gst_buffer_copy_into(out.get(), raw, GST_BUFFER_COPY_METADATA, 0, -1);
  return out.release();
}

static GstFlowReturn crop_collected(GstCollectPads *pads, gpointer user) {
  auto *self = GST_TENSOR_CROP(user);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    nns::gst::BufferPtr raw(gst_collect_pads_peek(pads, &self->raw_data->data));
    nns::gst::BufferPtr info(gst_collect_pads_peek(pads, &self->info_data->data));
    if (!raw || !info) {
      // One side ended: nothing more can be cropped.
      if (!self->priv->eos_sent) {
        self->priv->eos_sent = true;
        gst_pad_push_event(self->srcpad, gst_event_new_eos());
      }
      return GST_FLOW_EOS;
    }
    gint lateness = self->priv->lateness;
    GstClockTime tr = GST_BUFFER_PTS(raw.get()), ti = GST_BUFFER_PTS(info.get());
    if (lateness >= 0 && GST_CLOCK_TIME_IS_VALID(tr) && GST_CLOCK_TIME_IS_VALID(ti)) {
      GstClockTime diff = tr > ti ? tr - ti : ti - tr;
      if (diff > GstClockTime(lateness) * GST_MSECOND) {
        // Drop the older buffer and wait for its next one.
        CropPad *older = tr < ti ? self->raw_data : self->info_data;
        GST_DEBUG_OBJECT(self,
                         "raw %" GST_TIME_FORMAT " / info %" GST_TIME_FORMAT
                         " differ by more than %d ms: dropping %s",
                         GST_TIME_ARGS(tr), GST_TIME_ARGS(ti), lateness,
                         GST_PAD_NAME(older->data.pad));
        gst_buffer_unref(gst_collect_pads_pop(pads, &older->data));
        return GST_FLOW_OK;
      }
    }
    gst_buffer_unref(gst_collect_pads_pop(pads, &self->raw_data->data));
    gst_buffer_unref(gst_collect_pads_pop(pads, &self->info_data->data));
    if (!self->raw_data->has_caps || !self->info_data->has_caps)
      nns::fail(nns::ErrorKind::kNegotiation, "buffer before caps");
    negotiate(self);
    GstBuffer *out = do_crop(self, raw.get(), info.get());
    if (!out) return GST_FLOW_OK;
    return gst_pad_push(self->srcpad, out);
  });
}

static gboolean crop_src_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  if (GST_EVENT_TYPE(event) == GST_EVENT_SEEK) {
    gst_event_unref(event);
    return FALSE;
  }
  return gst_pad_event_default(pad, parent, event);
}

static GstStateChangeReturn crop_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_CROP(element);
  if (t == GST_STATE_CHANGE_READY_TO_PAUSED) {
    self->priv->warned_clip = false;
    self->priv->eos_sent = false;
    gst_collect_pads_start(self->collect);
  } else if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
    gst_collect_pads_stop(self->collect);
  }
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_crop_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
    self->raw_data->has_caps = false;
    self->info_data->has_caps = false;
  }
  return ret;
}

static void gst_tensor_crop_set_property(GObject *object, guint id, const GValue *value,
                                         GParamSpec *pspec) {
  auto *p = GST_TENSOR_CROP(object)->priv;
  switch (id) {
    case PROP_LATENESS:
      p->lateness = g_value_get_int(value);
      break;
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_crop_get_property(GObject *object, guint id, GValue *value,
                                         GParamSpec *pspec) {
  auto *p = GST_TENSOR_CROP(object)->priv;
  switch (id) {
    case PROP_LATENESS:
      g_value_set_int(value, p->lateness);
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_crop_finalize(GObject *object) {
  auto *self = GST_TENSOR_CROP(object);
  gst_object_unref(self->collect);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_crop_parent_class)->finalize(object);
}

static void gst_tensor_crop_class_init(GstTensorCropClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_crop_debug, "tensor_crop", 0, "tensor_crop element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_crop_set_property;
  gobject_class->get_property = gst_tensor_crop_get_property;
  gobject_class->finalize = gst_tensor_crop_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_LATENESS,
      g_param_spec_int("lateness", "Lateness",
                       "Largest time difference between raw and info buffers in ms (-1 = off)", -1,
                       G_MAXINT, -1, rw));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log per-frame details", TRUE, rw));
  gst_element_class_set_static_metadata(element_class, "TensorCrop", "Filter/Tensor",
                                        "Crops regions of a tensor frame", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &raw_template);
  gst_element_class_add_static_pad_template(element_class, &info_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->change_state = crop_change_state;
}

static void gst_tensor_crop_init(GstTensorCrop *self) {
  self->priv = new CropPriv();
  self->raw = gst_pad_new_from_static_template(&raw_template, "raw");
  self->info = gst_pad_new_from_static_template(&info_template, "info");
  gst_element_add_pad(GST_ELEMENT(self), self->raw);
  gst_element_add_pad(GST_ELEMENT(self), self->info);
  self->srcpad = gst_pad_new_from_static_template(&src_template, "src");
  gst_pad_use_fixed_caps(self->srcpad);
  gst_pad_set_event_function(self->srcpad, crop_src_event);
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
  self->collect = gst_collect_pads_new();
  gst_collect_pads_set_function(self->collect, crop_collected, self);
  gst_collect_pads_set_event_function(self->collect, crop_sink_event, self);
  self->raw_data = reinterpret_cast<CropPad *>(
      gst_collect_pads_add_pad(self->collect, self->raw, sizeof(CropPad), crop_pad_destroy, TRUE));
  self->raw_data->config = new nns::TensorsConfig();
  self->raw_data->has_caps = false;
  self->info_data = reinterpret_cast<CropPad *>(
      gst_collect_pads_add_pad(self->collect, self->info, sizeof(CropPad), crop_pad_destroy, TRUE));
  self->info_data->config = new nns::TensorsConfig();
  self->info_data->has_caps = false;
}

// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_converter
 *
 * Turns media into tensor frames (NNStreamer's tensor_converter): raw video becomes a
 * `C:W:H:N` uint8 tensor (uint16 for GRAY16, `W:H:3:N` for RGBP/BGRP), interleaved audio a
 * `channels:N` tensor of the sample type, utf8 text an `input-dim:N` uint8 tensor, an octet
 * stream the tensors of `input-dim`/`input-type` (or one flexible tensor when downstream wants
 * flexible), a flexible tensor stream static tensors. N is `frames-per-tensor`. Data is shared,
 * not copied, whenever the bytes are already laid out as the tensor (e.g. RGB with width % 4 ==
 * 0). `mode=custom-code:<name>` runs a callback registered with
 * nnstreamer_converter_custom_register(); other media types go to converter sub-plugins.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=224,height=224 !
 *       tensor_converter ! tensor_sink
 */
#include "gst/converter_state.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY(nns_tensor_converter_debug);
#define GST_CAT_DEFAULT nns_tensor_converter_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_CONVERTER (gst_tensor_converter_get_type())
G_DECLARE_FINAL_TYPE(GstTensorConverter, gst_tensor_converter, GST, TENSOR_CONVERTER, GstElement)
G_END_DECLS

namespace {

using nns::ErrorKind;
using nns::gst::ConverterSettings;
using nns::gst::ConverterState;
using nns::gst::MediaKind;

// The element's private part: properties apart from the streaming state.
struct ConverterPriv {
  ConverterSettings settings;  // guarded by the object lock
  ConverterState state;
};

enum {
  PROP_0,
  PROP_INPUT_DIM,
  PROP_INPUT_TYPE,
  PROP_FRAMES_PER_TENSOR,
  PROP_SET_TIMESTAMP,
  PROP_SUB_PLUGINS,
  PROP_SILENT,
  PROP_MODE
};

constexpr GParamFlags kRW = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);

}  // namespace

struct _GstTensorConverter {
  GstElement parent;
  GstPad *sinkpad;
  GstPad *srcpad;
  ConverterPriv *priv;
};

G_DEFINE_TYPE(GstTensorConverter, gst_tensor_converter, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_converter, "tensor_converter", GST_RANK_NONE,
                            GST_TYPE_TENSOR_CONVERTER)

namespace {

// Copies the properties under the object lock and parses them into the state.
void take_settings(GstTensorConverter *self) {
  ConverterSettings s;
  GST_OBJECT_LOCK(self);
  s = self->priv->settings;
  GST_OBJECT_UNLOCK(self);
  nns::gst::snapshot_settings(&self->priv->state, s);
}

GstFlowReturn chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_CONVERTER(parent);
  return nns::gst::guard(self, GST_FLOW_ERROR,
                         [&] { return nns::gst::process_buffer(&self->priv->state, buf); });
}

// ---- events and queries --------------------------------------------------------------------

gboolean sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_CONVERTER(parent);
  ConverterState *p = &self->priv->state;
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_CAPS: {
      GstCaps *caps = nullptr;
      gst_event_parse_caps(event, &caps);
      gboolean ok = nns::gst::guard(self, FALSE, [&]() -> gboolean {
        take_settings(self);  // properties may have changed since the element started
        nns::gst::configure(p, caps);
        return TRUE;
      });
      gst_event_unref(event);
      return ok;
    }
    case GST_EVENT_SEGMENT: {
      GstSegment seg;
      gst_event_copy_segment(event, &seg);
      if (seg.format != GST_FORMAT_TIME && seg.format != GST_FORMAT_BYTES) {
        NNS_POST_ERROR(self, ErrorKind::kStream,
                       std::string("segment format ") + gst_format_get_name(seg.format) +
                           " is not supported (expected time or bytes)");
        gst_event_unref(event);
        return FALSE;
      }
      p->segment = seg;
      if (seg.format == GST_FORMAT_TIME && p->caps_sent) {
        p->need_segment = false;
        return gst_pad_push_event(self->srcpad, event);
      }
      p->need_segment = true;  // pushed after the src caps, before the next buffer
      gst_event_unref(event);
      return TRUE;
    }
    case GST_EVENT_EOS:
      if (p->adapter && gst_adapter_available(p->adapter) > 0)
        GST_INFO_OBJECT(self, "dropping %" G_GSIZE_FORMAT " bytes: fewer than frames-per-tensor",
                        gst_adapter_available(p->adapter));
      if (p->need_segment && p->caps_sent) nns::gst::push_segment(p);
      break;
    case GST_EVENT_FLUSH_STOP:
      nns::gst::reset_stream(p);
      break;
    default:
      break;
  }
  return gst_pad_event_default(pad, parent, event);
}

GstCaps *sink_base_caps(GstTensorConverter *self) {
  GstCaps *caps = gst_pad_get_pad_template_caps(self->sinkpad);
  GstCaps *ext = nns::gst::ConverterRegistry::instance().all_caps();
  return gst_caps_merge(caps, ext);
}

bool in_custom_mode(GstTensorConverter *self) {
  GST_OBJECT_LOCK(self);
  bool custom_mode = !self->priv->settings.mode.empty();
  GST_OBJECT_UNLOCK(self);
  return custom_mode;
}

// The tensors downstream prefers: its first structure, with a list of equivalent dimension
// spellings (as tensor_filter and tensor_transform offer them) or of types reduced to its first
// entry. Other unfixed fields (a framerate range) stay as they are: they describe no tensor.
nns::TensorsConfig preferred_tensors(const GstCaps *peer) {
  nns::gst::StructurePtr s(gst_structure_copy(gst_caps_get_structure(peer, 0)));
  for (const char *field : {"dimensions", "dimension", "types", "type"}) {
    const GValue *v = gst_structure_get_value(s.get(), field);
    if (v && GST_VALUE_HOLDS_LIST(v) && gst_value_list_get_size(v) > 0) {
      GValue first = G_VALUE_INIT;
      g_value_init(&first, G_VALUE_TYPE(gst_value_list_get_value(v, 0)));
      g_value_copy(gst_value_list_get_value(v, 0), &first);
      gst_structure_take_value(s.get(), field, &first);
    }
  }
  return nns::gst::config_from_structure(s.get());
}

GstCaps *sink_query_caps(GstTensorConverter *self, GstCaps *filter) {
  // mode=custom-code/custom-script: the callback or script decides what it reads (e.g. a
  // Python script parsing other/flexbuf), so any input is offered.
  const bool custom_mode = in_custom_mode(self);
  GstCaps *caps = custom_mode ? gst_caps_new_any() : sink_base_caps(self);
  if (!custom_mode) {
    nns::gst::CapsPtr peer(gst_pad_peer_query_caps(self->srcpad, nullptr));
    if (peer && !gst_caps_is_any(peer.get()) && !gst_caps_is_empty(peer.get()) &&
        nns::gst::is_tensor_caps(peer.get())) {
      try {
        nns::TensorsConfig pc = preferred_tensors(peer.get());
        // What downstream wants first (upstream elements fixate to it, e.g. videoscale to a
        // model's 280x40), then everything else: a source already fixed on other media still
        // links, and the element that cannot take the result says why.
        GstCaps *narrowed = nns::gst::media_caps_for_tensor(pc, caps);
        caps = gst_caps_merge(narrowed, caps);
      } catch (const nns::Error &) {
      }
    }
  }
  if (filter) {
    GstCaps *x = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    caps = x;
  }
  return caps;
}

gboolean sink_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  auto *self = GST_TENSOR_CONVERTER(parent);
  switch (GST_QUERY_TYPE(query)) {
    case GST_QUERY_CAPS: {
      GstCaps *filter = nullptr;
      gst_query_parse_caps(query, &filter);
      GstCaps *caps = sink_query_caps(self, filter);
      gst_query_set_caps_result(query, caps);
      gst_caps_unref(caps);
      return TRUE;
    }
    case GST_QUERY_ACCEPT_CAPS: {
      GstCaps *caps = nullptr;
      gst_query_parse_accept_caps(query, &caps);
      gboolean ok = FALSE;
      if (gst_caps_is_fixed(caps)) {
        nns::gst::CapsPtr base(sink_base_caps(self));
        // Raw media outside the template (e.g. format=I420) is let through so the CAPS
        // event can post an error naming the field; caps queries still offer the template.
        MediaKind k = nns::gst::media_kind_of(gst_caps_get_structure(caps, 0));
        ok = in_custom_mode(self) || gst_caps_can_intersect(base.get(), caps) ||
             k == MediaKind::kVideo || k == MediaKind::kAudio || k == MediaKind::kText;
      }
      gst_query_set_accept_caps_result(query, ok);
      return TRUE;
    }
    default:
      return gst_pad_query_default(pad, parent, query);
  }
}

gboolean src_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  if (GST_QUERY_TYPE(query) != GST_QUERY_CAPS) return gst_pad_query_default(pad, parent, query);
  GstCaps *filter = nullptr;
  gst_query_parse_caps(query, &filter);
  GstCaps *caps = gst_pad_get_current_caps(pad);
  if (!caps) caps = gst_pad_get_pad_template_caps(pad);
  if (filter) {
    GstCaps *x = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    caps = x;
  }
  gst_query_set_caps_result(query, caps);
  gst_caps_unref(caps);
  return TRUE;
}

}  // namespace

// ---- GObject -------------------------------------------------------------------------------

static void gst_tensor_converter_set_property(GObject *object, guint id, const GValue *value,
                                              GParamSpec *pspec) {
  auto *self = GST_TENSOR_CONVERTER(object);
  ConverterSettings &s = self->priv->settings;
  GST_OBJECT_LOCK(self);
  switch (id) {
    case PROP_INPUT_DIM:
      s.input_dim = g_value_get_string(value) ? g_value_get_string(value) : "";
      break;
    case PROP_INPUT_TYPE:
      s.input_type = g_value_get_string(value) ? g_value_get_string(value) : "";
      break;
    case PROP_FRAMES_PER_TENSOR:
      s.frames_per_tensor = g_value_get_uint(value);
      break;
    case PROP_SET_TIMESTAMP:
      s.set_timestamp = g_value_get_boolean(value);
      break;
    case PROP_SILENT:
      s.silent = g_value_get_boolean(value);
      break;
    case PROP_MODE:
      s.mode = g_value_get_string(value) ? g_value_get_string(value) : "";
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
  GST_OBJECT_UNLOCK(self);
}

static void gst_tensor_converter_get_property(GObject *object, guint id, GValue *value,
                                              GParamSpec *pspec) {
  auto *self = GST_TENSOR_CONVERTER(object);
  if (id == PROP_SUB_PLUGINS) {
    std::string list;
    for (const auto &n : nns::gst::ConverterRegistry::instance().names())
      list += (list.empty() ? "" : ",") + n;
    g_value_set_string(value, list.c_str());
    return;
  }
  const ConverterSettings &s = self->priv->settings;
  GST_OBJECT_LOCK(self);
  switch (id) {
    case PROP_INPUT_DIM:
      g_value_set_string(value, s.input_dim.c_str());
      break;
    case PROP_INPUT_TYPE:
      g_value_set_string(value, s.input_type.c_str());
      break;
    case PROP_FRAMES_PER_TENSOR:
      g_value_set_uint(value, s.frames_per_tensor);
      break;
    case PROP_SET_TIMESTAMP:
      g_value_set_boolean(value, s.set_timestamp);
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, s.silent);
      break;
    case PROP_MODE:
      g_value_set_string(value, s.mode.c_str());
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
  GST_OBJECT_UNLOCK(self);
}

static GstStateChangeReturn gst_tensor_converter_change_state(GstElement *element,
                                                              GstStateChange transition) {
  auto *self = GST_TENSOR_CONVERTER(element);
  ConverterState *p = &self->priv->state;
  if (transition == GST_STATE_CHANGE_READY_TO_PAUSED) {
    gboolean ok = nns::gst::guard(self, FALSE, [&]() -> gboolean {
      take_settings(self);
      return TRUE;
    });
    if (!ok) return GST_STATE_CHANGE_FAILURE;
    nns::gst::reset_stream(p);
    p->configured = p->caps_sent = false;
  }
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_converter_parent_class)->change_state(element, transition);
  if (transition == GST_STATE_CHANGE_PAUSED_TO_READY) {
    nns::gst::reset_stream(p);
    nns::gst::close_external(p);
    p->configured = p->caps_sent = false;
  }
  return ret;
}

static void gst_tensor_converter_finalize(GObject *object) {
  auto *self = GST_TENSOR_CONVERTER(object);
  nns::gst::close_external(&self->priv->state);
  if (self->priv->state.adapter) g_object_unref(self->priv->state.adapter);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_converter_parent_class)->finalize(object);
}

static void gst_tensor_converter_class_init(GstTensorConverterClass *klass) {
  GST_DEBUG_CATEGORY_INIT(nns_tensor_converter_debug, "tensor_converter", 0,
                          "Converts media streams to tensor streams");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_converter_set_property;
  gobject_class->get_property = gst_tensor_converter_get_property;
  gobject_class->finalize = gst_tensor_converter_finalize;

  g_object_class_install_property(
      gobject_class, PROP_INPUT_DIM,
      g_param_spec_string("input-dim", "Input tensor dimension",
                          "Input tensor dimension from inner array", "", kRW));
  g_object_class_install_property(
      gobject_class, PROP_INPUT_TYPE,
      g_param_spec_string("input-type", "Input tensor type",
                          "Type of each element of the input tensor", "", kRW));
  g_object_class_install_property(
      gobject_class, PROP_FRAMES_PER_TENSOR,
      g_param_spec_uint("frames-per-tensor", "Frames per tensor",
                        "The number of frames in output tensor", 1, G_MAXUINT, 1, kRW));
  g_object_class_install_property(
      gobject_class, PROP_SET_TIMESTAMP,
      g_param_spec_boolean("set-timestamp", "Set timestamp",
                           "The flag to set timestamp when received a buffer with invalid "
                           "timestamp",
                           TRUE, kRW));
  g_object_class_install_property(
      gobject_class, PROP_SUB_PLUGINS,
      g_param_spec_string("sub-plugins", "Sub-plugins", "Registrable sub-plugins list", "",
                          static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Produce verbose output", TRUE, kRW));
  g_object_class_install_property(
      gobject_class, PROP_MODE,
      g_param_spec_string("mode", "Mode",
                          "Converter mode. e.g., mode=custom-code:<registered callback name> "
                          "or mode=custom-script:<script path>",
                          "", kRW));

  GstCaps *sink_caps = gst_caps_from_string(NNS_CONVERTER_MEDIA_CAPS_STR);
  sink_caps = gst_caps_merge(sink_caps, nns::gst::ConverterRegistry::instance().all_caps());
  gst_element_class_add_pad_template(
      element_class, gst_pad_template_new("sink", GST_PAD_SINK, GST_PAD_ALWAYS, sink_caps));
  gst_caps_unref(sink_caps);
  GstCaps *src_caps = gst_caps_from_string(NNS_TENSOR_CAPS_ANY_STR);
  gst_element_class_add_pad_template(
      element_class, gst_pad_template_new("src", GST_PAD_SRC, GST_PAD_ALWAYS, src_caps));
  gst_caps_unref(src_caps);

  gst_element_class_set_static_metadata(
      element_class, "TensorConverter", "Converter/Tensor",
      "Converts an audio, video, text, or arbitrary stream to a tensor stream of C-Array for "
      "neural network framework filters",
      "nnstreamer-cpp");
  element_class->change_state = gst_tensor_converter_change_state;
}

static void gst_tensor_converter_init(GstTensorConverter *self) {
  self->priv = new ConverterPriv();
  ConverterState &st = self->priv->state;
  st.element = GST_ELEMENT(self);
  st.adapter = gst_adapter_new();
  gst_segment_init(&st.segment, GST_FORMAT_TIME);
  auto *klass = GST_ELEMENT_GET_CLASS(self);
  self->sinkpad =
      gst_pad_new_from_template(gst_element_class_get_pad_template(klass, "sink"), "sink");
  gst_pad_set_event_function(self->sinkpad, GST_DEBUG_FUNCPTR(sink_event));
  gst_pad_set_query_function(self->sinkpad, GST_DEBUG_FUNCPTR(sink_query));
  gst_pad_set_chain_function(self->sinkpad, GST_DEBUG_FUNCPTR(chain));
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
  self->srcpad = gst_pad_new_from_template(gst_element_class_get_pad_template(klass, "src"), "src");
  gst_pad_set_query_function(self->srcpad, GST_DEBUG_FUNCPTR(src_query));
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
  st.srcpad = self->srcpad;
}

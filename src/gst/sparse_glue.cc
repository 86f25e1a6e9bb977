// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/sparse_glue.h"

#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/flow_util.h"

namespace nns::gst::sparse {

void class_init(GObjectClass *gobject_class, GstElementClass *element_class, const char *longname,
                const char *description, GstStaticPadTemplate *sink, GstStaticPadTemplate *src) {
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log per-buffer details", TRUE,
                           static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS)));
  gst_element_class_set_static_metadata(element_class, longname, "Filter/Tensor", description,
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, sink);
  gst_element_class_add_static_pad_template(element_class, src);
}

void set_silent(GObject *object, guint id, const GValue *value, GParamSpec *pspec,
                std::atomic<bool> &silent) {
  if (id == PROP_SILENT)
    silent = g_value_get_boolean(value);
  else
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

void get_silent(GObject *object, guint id, GValue *value, GParamSpec *pspec,
                const std::atomic<bool> &silent) {
  if (id == PROP_SILENT)
    g_value_set_boolean(value, silent);
  else
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

void add_pads(GstElement *element, GstStaticPadTemplate *sink, GstStaticPadTemplate *src,
              GstPadEventFunction event, GstPadChainFunction chain, bool proxy_allocation,
              GstPad **sinkpad, GstPad **srcpad) {
  *sinkpad = gst_pad_new_from_static_template(sink, "sink");
  gst_pad_set_event_function(*sinkpad, event);
  gst_pad_set_chain_function(*sinkpad, chain);
  if (proxy_allocation) GST_PAD_SET_PROXY_ALLOCATION(*sinkpad);
  gst_element_add_pad(element, *sinkpad);
  *srcpad = gst_pad_new_from_static_template(src, "src");
  gst_pad_use_fixed_caps(*srcpad);
  gst_element_add_pad(element, *srcpad);
}

gboolean sink_event(GstElement *element, GstPad *pad, GstEvent *event,
                    const std::function<void(GstCaps *)> &on_caps) {
  if (GST_EVENT_TYPE(event) != GST_EVENT_CAPS)
    return gst_pad_event_default(pad, GST_OBJECT(element), event);
  EventPtr owned(event);
  return guard(element, FALSE, [&]() -> gboolean {
    GstCaps *caps;
    gst_event_parse_caps(event, &caps);
    on_caps(caps);
    return TRUE;
  });
}

GstFlowReturn chain(GstElement *element, GstPad *srcpad, GstBuffer *in,
                    const std::function<void(GstBuffer *in, GstBuffer *out)> &convert) {
  BufferPtr owned(in);
  return guard(element, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    BufferPtr out(gst_buffer_new());
    convert(in, out.get());
    gst_buffer_copy_into(out.get(), in, GST_BUFFER_COPY_METADATA, 0, -1);
    return gst_pad_push(srcpad, out.release());
  });
}

void append_written(GstBuffer *out, std::size_t size, const std::function<void(uint8_t *)> &write) {
  GstMemory *mem = alloc_memory(size);
  {
    MemoryMap w(mem, GST_MAP_WRITE);
    write(w.data());
  }
  gst_buffer_append_memory(out, mem);
}

}  // namespace nns::gst::sparse

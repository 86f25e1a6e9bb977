// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/tensor_srcpads.h"

#include <string>

#include "gst/element_glue.h"
#include "gst/tensor_caps.h"

namespace nns::gst {

GstCaps *fixed_tensors_caps(const TensorsConfig &config) {
  return gst_caps_new_full(structure_from_config(config), nullptr);
}

SrcPads::SrcPads(GstElement *element, GstStaticPadTemplate *templ)
    : element_(element), templ_(templ), combiner_(gst_flow_combiner_new()) {}

SrcPads::~SrcPads() {
  // The element removes its pads in dispose; only the combiner is ours here.
  gst_flow_combiner_free(combiner_);
}

void SrcPads::remove_all() {
  gst_flow_combiner_clear(combiner_);
  for (GstPad *p : pads_) {
    gst_pad_set_active(p, FALSE);
    gst_element_remove_pad(element_, p);
  }
  pads_.clear();
}

void SrcPads::reset_flow() {
  gst_flow_combiner_reset(combiner_);
}

gboolean SrcPads::sink_event(GstPad *pad, GstEvent *event, const char *eos_error,
                             const std::function<void(GstCaps *)> &on_caps) {
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_CAPS: {
      GstCaps *caps = nullptr;
      gst_event_parse_caps(event, &caps);
      gboolean ok = guard(element_, FALSE, [&]() -> gboolean {
        on_caps(caps);
        return TRUE;
      });
      gst_event_unref(event);  // each src pad has its own caps
      return ok;
    }
    case GST_EVENT_EOS:
      if (pads_.empty()) {
        NNS_POST_ERROR(element_, ErrorKind::kStream, eos_error);
        gst_event_unref(event);
        return FALSE;
      }
      break;
    case GST_EVENT_FLUSH_STOP:
      reset_flow();
      break;
    default:
      break;
  }
  return gst_pad_event_default(pad, GST_OBJECT(element_), event);
}

GstStateChangeReturn SrcPads::change_state(GstElementClass *parent_class, GstStateChange transition,
                                           const std::function<void()> &on_start,
                                           const std::function<void()> &on_stop) {
  if (transition == GST_STATE_CHANGE_READY_TO_PAUSED) {
    bool ok = guard(element_, false, [&] {
      on_start();
      return true;
    });
    if (!ok) return GST_STATE_CHANGE_FAILURE;
  }
  GstStateChangeReturn ret = parent_class->change_state(element_, transition);
  if (transition == GST_STATE_CHANGE_PAUSED_TO_READY) {
    remove_all();
    if (on_stop) on_stop();
  }
  return ret;
}

void SrcPads::configure(GstPad *sinkpad, const std::vector<TensorsConfig> &configs) {
  if (configs.size() == pads_.size()) {
    for (std::size_t i = 0; i < pads_.size(); ++i) {
      GstCaps *caps = fixed_tensors_caps(configs[i]);
      gst_pad_push_event(pads_[i], gst_event_new_caps(caps));
      gst_caps_unref(caps);
    }
    return;
  }
  remove_all();
  guint group = 0;
  bool have_group = false;
  if (GstEvent *ss = gst_pad_get_sticky_event(sinkpad, GST_EVENT_STREAM_START, 0)) {
    have_group = gst_event_parse_group_id(ss, &group);
    gst_event_unref(ss);
  }
  if (!have_group) group = gst_util_group_id_next();
  GstEvent *segment = gst_pad_get_sticky_event(sinkpad, GST_EVENT_SEGMENT, 0);
  for (std::size_t i = 0; i < configs.size(); ++i) {
    std::string name = "src_" + std::to_string(i);
    GstPad *pad = gst_pad_new_from_static_template(templ_, name.c_str());
    gst_pad_use_fixed_caps(pad);
    gst_pad_set_active(pad, TRUE);
    gchar *sid = gst_pad_create_stream_id(pad, element_, name.c_str());
    GstEvent *ss = gst_event_new_stream_start(sid);
    g_free(sid);
    gst_event_set_group_id(ss, group);
    gst_pad_store_sticky_event(pad, ss);
    gst_event_unref(ss);
    GstCaps *caps = fixed_tensors_caps(configs[i]);
    GstEvent *ce = gst_event_new_caps(caps);
    gst_pad_store_sticky_event(pad, ce);
    gst_event_unref(ce);
    gst_caps_unref(caps);
    if (segment) gst_pad_store_sticky_event(pad, segment);
    pads_.push_back(pad);
    gst_flow_combiner_add_pad(combiner_, pad);
    gst_element_add_pad(element_, pad);
  }
  if (segment) gst_event_unref(segment);
  gst_element_no_more_pads(element_);
}

GstFlowReturn SrcPads::push(std::size_t i, GstBuffer *buf) {
  GstFlowReturn ret = gst_pad_push(pads_[i], buf);
  return gst_flow_combiner_update_pad_flow(combiner_, pads_[i], ret);
}

}  // namespace nns::gst

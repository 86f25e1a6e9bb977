// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/tensor_srcpads.h"

#include <string>

#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

namespace nns::gst {

GstCaps *fixed_tensors_caps(const TensorsConfig &config) {
  return gst_caps_new_full(structure_from_config(config), nullptr);
}

namespace {

// Our caps for `config` in the spelling the linked peer of `pad` takes (e.g. a capsfilter
// writing several tensors' fields with '.'); our own spelling when unlinked or refused.
GQuark offer_quark() {
  static const GQuark q = g_quark_from_static_string("nns-srcpad-offer");
  return q;
}

// What a pad offers: its config's caps with the equivalent spellings, so a peer written with
// '.' between tensors can link to it (the sticky caps are ours until the peer is known).
void set_offer(GstPad *pad, const TensorsConfig &config) {
  GstCaps *offer = fixed_tensors_caps(config);
  if (config.info.format == TensorFormat::kStatic) {
    CapsPtr variants(caps_from_config(config, true));
    gst_caps_unref(offer);
    offer = gst_caps_copy_nth(variants.get(), 0);  // other/tensors only, as always given
  }
  g_object_set_qdata_full(G_OBJECT(pad), offer_quark(), offer,
                          reinterpret_cast<GDestroyNotify>(gst_caps_unref));
}

gboolean offer_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  auto *offer = static_cast<GstCaps *>(g_object_get_qdata(G_OBJECT(pad), offer_quark()));
  if (GST_QUERY_TYPE(query) != GST_QUERY_CAPS || !offer)
    return gst_pad_query_default(pad, parent, query);
  GstCaps *filter = nullptr;
  gst_query_parse_caps(query, &filter);
  CapsPtr res(filter ? gst_caps_intersect_full(filter, offer, GST_CAPS_INTERSECT_FIRST)
                     : gst_caps_ref(offer));
  gst_query_set_caps_result(query, res.get());
  return TRUE;
}

GstCaps *caps_for_peer(GstPad *pad, const TensorsConfig &config) {
  GstCaps *plain = fixed_tensors_caps(config);
  if (config.info.format != TensorFormat::kStatic || !gst_pad_is_linked(pad)) return plain;
  // Only the other/tensors structure: these pads have always given other/tensors.
  CapsPtr variants(caps_from_config(config, true));
  CapsPtr mine(gst_caps_copy_nth(variants.get(), 0));
  CapsPtr peer(gst_pad_peer_query_caps(pad, mine.get()));
  if (!peer || gst_caps_is_empty(peer.get()) || gst_caps_can_intersect(peer.get(), plain))
    return plain;
  gst_caps_unref(plain);
  return gst_caps_fixate(peer.release());
}

}  // namespace

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
      set_offer(pads_[i], configs[i]);
      GstCaps *caps = caps_for_peer(pads_[i], configs[i]);
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
    set_offer(pad, configs[i]);
    gst_pad_set_query_function(pad, offer_query);
    gst_pad_set_active(pad, TRUE);
    gchar *sid = gst_pad_create_stream_id(pad, element_, name.c_str());
    GstEvent *ss = gst_event_new_stream_start(sid);
    g_free(sid);
    gst_event_set_group_id(ss, group);
    gst_pad_store_sticky_event(pad, ss);
    gst_event_unref(ss);
    CapsPtr caps(fixed_tensors_caps(configs[i]));
    GstEvent *ce = gst_event_new_caps(caps.get());
    gst_pad_store_sticky_event(pad, ce);
    gst_event_unref(ce);
    if (segment) gst_pad_store_sticky_event(pad, segment);
    pads_.push_back(pad);
    gst_flow_combiner_add_pad(combiner_, pad);
    gst_element_add_pad(element_, pad);
    // Linked now if the application did so on pad-added: follow the peer's spelling.
    if (gst_pad_is_linked(pad)) {
      CapsPtr peer_caps(caps_for_peer(pad, configs[i]));
      if (!gst_caps_is_equal(peer_caps.get(), caps.get())) {
        GstEvent *pe = gst_event_new_caps(peer_caps.get());
        gst_pad_store_sticky_event(pad, pe);
        gst_event_unref(pe);
      }
    }
  }
  if (segment) gst_event_unref(segment);
  gst_element_no_more_pads(element_);
}

GstFlowReturn SrcPads::push(std::size_t i, GstBuffer *buf) {
  GstFlowReturn ret = gst_pad_push(pads_[i], buf);
  return gst_flow_combiner_update_pad_flow(combiner_, pads_[i], ret);
}

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/flow_util.h"

#include "core/error.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

namespace nns::gst {

void set_src_caps(GstPad *src, const TensorsConfig &cfg, const std::string &what) {
  CapsPtr caps;
  if (cfg.info.format == TensorFormat::kStatic) {
    CapsPtr mine(caps_from_config(cfg, true));
    CapsPtr peer(gst_pad_peer_query_caps(src, nullptr));
    CapsPtr both(peer ? gst_caps_intersect_full(mine.get(), peer.get(), GST_CAPS_INTERSECT_FIRST)
                      : gst_caps_ref(mine.get()));
    if (gst_caps_is_empty(both.get())) {
      CapsPtr plain(caps_from_config(cfg, false));
      fail(ErrorKind::kNegotiation, what + " gives " + caps_to_string(plain.get()) +
                                        " but downstream accepts " + caps_to_string(peer.get()));
    }
    caps.reset(gst_caps_fixate(both.release()));
  } else {
    caps.reset(caps_for_format(cfg.info.format, cfg.rate_n, cfg.rate_d));
    caps.reset(gst_caps_fixate(caps.release()));
  }
  CapsPtr current(gst_pad_get_current_caps(src));
  if (current && gst_caps_is_equal(current.get(), caps.get())) return;
  if (!gst_pad_set_caps(src, caps.get()))
    fail(ErrorKind::kNegotiation,
         "downstream of " + what + " refused caps " + caps_to_string(caps.get()));
}

void start_src_pad(GstElement *element, GstPad *src, const std::string &suffix,
                   const TensorsConfig &cfg) {
  EventPtr ss(gst_pad_get_sticky_event(src, GST_EVENT_STREAM_START, 0));
  if (!ss) {
    GCharPtr name(gst_element_get_name(element));
    std::string id = std::string(name.get()) + "-" + suffix;
    GstEvent *ev = gst_event_new_stream_start(id.c_str());
    gst_event_set_group_id(ev, gst_util_group_id_next());
    gst_pad_push_event(src, ev);
  }
  set_src_caps(src, cfg, suffix);
  EventPtr seg(gst_pad_get_sticky_event(src, GST_EVENT_SEGMENT, 0));
  if (!seg) {
    GstSegment s;
    gst_segment_init(&s, GST_FORMAT_TIME);
    gst_pad_push_event(src, gst_event_new_segment(&s));
  }
}

TensorMaps::TensorMaps(GstBuffer *buf, std::size_t expected) {
  std::size_t n = buffer_tensor_count(buf);
  if (n != expected)
    fail(ErrorKind::kStream,
         "buffer has " + std::to_string(n) + " tensor(s), expected " + std::to_string(expected));
  mems_.reserve(n);
  maps_.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    GstMemory *m = buffer_get_tensor(buf, i);
    GstMapInfo info{};
    if (!m || !gst_memory_map(m, &info, GST_MAP_READ)) {
      if (m) gst_memory_unref(m);
      release();
      fail(ErrorKind::kStream, "cannot map tensor " + std::to_string(i));
    }
    mems_.push_back(m);
    maps_.push_back(info);
    ptrs_.push_back(info.data);
  }
}

TensorMaps::~TensorMaps() {
  release();
}

void TensorMaps::release() {
  for (std::size_t i = 0; i < mems_.size(); ++i) {
    gst_memory_unmap(mems_[i], &maps_[i]);
    gst_memory_unref(mems_[i]);
  }
  mems_.clear();
  maps_.clear();
  ptrs_.clear();
}

GstMemory *alloc_memory(std::size_t size) {
  return gst_allocator_alloc(nullptr, size, nullptr);
}

}  // namespace nns::gst

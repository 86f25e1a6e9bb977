// SPDX-License-Identifier: LGPL-2.1-only
// Small GStreamer helpers shared by the flow-control elements (tensor_if, tensor_crop,
// tensor_sparse_*, tensor_repo*, tensor_rate, tensor_debug, join).
#pragma once

#include <gst/gst.h>

#include <string>
#include <vector>

#include "core/tensor_info.h"
#include "gst/gst_ptr.h"

namespace nns::gst {

// Sets fixed caps for `cfg` on `src`: static configs are intersected with what the peer accepts
// (any dimension spelling) and fixated; flexible/sparse ones use the format-only caps. Throws
// nns::Error(kNegotiation) naming `what` (e.g. "src_0"), the offered and the accepted caps.
void set_src_caps(GstPad *src, const TensorsConfig &cfg, const std::string &what);

// Starts (or re-configures) a src pad in the order GStreamer requires: stream-start (id
// "<element>-<suffix>") unless present, the caps for `cfg` (set_src_caps, `suffix` names the
// pad in errors), then a TIME segment unless present.
void start_src_pad(GstElement *element, GstPad *src, const std::string &suffix,
                   const TensorsConfig &cfg);

// Read maps of every tensor memory of a buffer (tensors past 16 come out of the packed memory).
class TensorMaps {
 public:
  TensorMaps(GstBuffer *buf, std::size_t expected);  // throws kStream on count/map failure
  ~TensorMaps();
  TensorMaps(const TensorMaps &) = delete;
  TensorMaps &operator=(const TensorMaps &) = delete;
  std::size_t size() const { return maps_.size(); }
  const uint8_t *data(std::size_t i) const { return maps_[i].data; }
  std::size_t bytes(std::size_t i) const { return maps_[i].size; }
  const uint8_t *const *pointers() const { return ptrs_.data(); }

 private:
  void release();
  std::vector<GstMemory *> mems_;
  std::vector<GstMapInfo> maps_;
  std::vector<const uint8_t *> ptrs_;
};

// A new memory of `size` bytes.
GstMemory *alloc_memory(std::size_t size);

}  // namespace nns::gst

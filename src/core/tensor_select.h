// SPDX-License-Identifier: LGPL-2.1-only
// Option grammars and index math of tensor_demux and tensor_split (GStreamer-free).
//
// tensor_demux tensorpick: output pads separated by any of ",.;/"; inside one pad, tensor
//   indices separated by ':' or '+' ("0,1:2" = pad 0 gets tensor 0, pad 1 gets tensors 1, 2).
// tensor_split tensorseg: one dimension string per segment, separated by ",.;/"
//   ("1:100:100,2:100:100"). Segments are consecutive byte ranges of the input tensor.
// tensor_split tensorpick: segment indices separated by ",.;/"; picked segments leave on
//   src_0, src_1, ... in ascending index order.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string_view>
#include <vector>

#include "core/tensor_info.h"

namespace nns {

using PickGroups = std::vector<std::vector<uint32_t>>;

// Throws nns::Error(kSettings) naming tensorpick and the bad token. Empty input: no groups.
PickGroups parse_demux_tensorpick(std::string_view s);
std::string demux_tensorpick_to_string(const PickGroups &g);
// Throws nns::Error(kNegotiation) naming the group, the index and the tensor count.
void check_demux_tensorpick(const PickGroups &g, std::size_t num_tensors);
// Default (no tensorpick): one pad per tensor.
PickGroups default_demux_groups(std::size_t num_tensors);

std::vector<Dims> parse_tensorseg(std::string_view s);  // throws naming tensorseg
std::string tensorseg_to_string(const std::vector<Dims> &seg);
std::vector<uint32_t> parse_split_tensorpick(std::string_view s);  // throws naming tensorpick
std::string split_tensorpick_to_string(const std::vector<uint32_t> &pick);

// One output of tensor_split: a byte range of the input tensor.
struct Segment {
  uint32_t index = 0;      // position in tensorseg
  std::size_t offset = 0;  // bytes from the start of the input tensor
  std::size_t size = 0;
  TensorInfo info;
};
// Plans the outputs for an input tensor `in`. Throws nns::Error(kNegotiation) when a picked
// index is out of range, or when the segments need more bytes than the input has.
std::vector<Segment> plan_split(const TensorInfo &in, const std::vector<Dims> &seg,
                                const std::vector<uint32_t> &pick);

}  // namespace nns

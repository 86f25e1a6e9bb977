// SPDX-License-Identifier: LGPL-2.1-only
// Concatenation of tensors along one dimension (tensor_merge mode=linear, and the frame
// re-ordering of tensor_aggregator), and tensor_aggregator's frame arithmetic.
// Dimensions are innermost first; entries past a tensor's rank count as 1.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/tensor_info.h"

namespace nns {

// Output of concatenating `in` along `dim` (0..kRankLimit-1): same type, the other dims
// equal, dims[dim] summed. Throws nns::Error(kNegotiation) naming the disagreeing inputs
// (names[i], e.g. "sink_1") and both values.
TensorInfo concat_info(const std::vector<TensorInfo> &in, std::size_t dim,
                       const std::vector<std::string> &names);

// Copy plan, computed once at negotiation: for each of `outer` rounds, input k contributes
// `block[k]` contiguous bytes, appended in input order.
struct ConcatPlan {
  std::size_t outer = 1;
  std::vector<std::size_t> block;
  std::size_t total = 0;
};
ConcatPlan plan_concat(const std::vector<TensorInfo> &in, std::size_t dim);
// `src[k]` must hold outer*block[k] bytes; `dst` total bytes.
void run_concat(const ConcatPlan &plan, const uint8_t *const *src, uint8_t *dst);

// tensor_aggregator.
struct AggregatorConfig {
  uint32_t frames_in = 1;
  uint32_t frames_out = 1;
  uint32_t frames_flush = 0;  // 0: flush frames_out frames
  uint32_t frames_dim = kRankLimit - 1;
  bool concat = true;
};
struct AggregatorPlan {
  TensorInfo out;              // output tensor (frames_out frames)
  TensorInfo frame;            // one frame
  std::size_t in_size = 0;     // bytes per input buffer
  std::size_t frame_size = 0;  // bytes per frame
  std::size_t out_size = 0;    // bytes per output buffer
  std::size_t flush_size = 0;  // bytes dropped after each output
  bool reorder = false;        // frames must be interleaved along frames_dim
  ConcatPlan concat;           // used when reorder
};
// Throws nns::Error(kNegotiation) naming the property and the values that disagree.
AggregatorPlan plan_aggregator(const TensorInfo &in, const AggregatorConfig &cfg);

}  // namespace nns

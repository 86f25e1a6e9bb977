// SPDX-License-Identifier: LGPL-2.1-only
// The "sometimes" src pads of tensor_demux and tensor_split: src_0, src_1, ... created from
// a list of per-pad configs when the sink caps arrive, each with its own stream-start (same
// group id as the input), fixed caps and the input's segment; flow returns are combined
// (not-linked only when every pad is not linked).
#pragma once

#include <gst/base/gstflowcombiner.h>
#include <gst/gst.h>

#include <vector>

#include "core/tensor_info.h"

namespace nns::gst {

class SrcPads {
 public:
  SrcPads(GstElement *element, GstStaticPadTemplate *templ);
  ~SrcPads();
  SrcPads(const SrcPads &) = delete;
  SrcPads &operator=(const SrcPads &) = delete;

  // Makes the pads match `configs` (one pad per entry). Existing pads are kept and get new
  // caps when the count is unchanged; otherwise all pads are replaced. Emits no-more-pads.
  void configure(GstPad *sinkpad, const std::vector<TensorsConfig> &configs);
  void remove_all();
  std::size_t size() const { return pads_.size(); }
  // Pushes on pad `i` (taking `buf`); returns the combined flow of all pads.
  GstFlowReturn push(std::size_t i, GstBuffer *buf);
  void reset_flow();

 private:
  GstElement *element_;
  GstStaticPadTemplate *templ_;
  std::vector<GstPad *> pads_;
  GstFlowCombiner *combiner_;
};

// Fixed caps for one output pad: other/tensors (static or flexible).
GstCaps *fixed_tensors_caps(const TensorsConfig &config);

}  // namespace nns::gst

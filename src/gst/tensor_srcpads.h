// SPDX-License-Identifier: LGPL-2.1-only
// The "sometimes" src pads of tensor_demux and tensor_split: src_0, src_1, ... created from
// a list of per-pad configs when the sink caps arrive, each with its own stream-start (same
// group id as the input), fixed caps and the input's segment; flow returns are combined
// (not-linked only when every pad is not linked). sink_event() and change_state() hold the
// sink-event and state-change handling the two elements share.
#pragma once

#include <gst/base/gstflowcombiner.h>
#include <gst/gst.h>

#include <functional>
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

  // The element's sink-pad event handler. CAPS: `on_caps` runs inside guard() (an exception
  // becomes a posted error and FALSE) and the event is dropped, as each src pad sends its own
  // caps. EOS while no src pad exists: posts a kStream error with `eos_error` and fails.
  // FLUSH_STOP resets the combined flow. Everything else goes to the default handler.
  gboolean sink_event(GstPad *pad, GstEvent *event, const char *eos_error,
                      const std::function<void(GstCaps *)> &on_caps);
  // The element's change_state: on READY->PAUSED `on_start` (parse the settings) runs inside
  // guard() and a throw fails the transition; then the parent class's change_state; on
  // PAUSED->READY the pads are removed and `on_stop` (when set) runs.
  GstStateChangeReturn change_state(GstElementClass *parent_class, GstStateChange transition,
                                    const std::function<void()> &on_start,
                                    const std::function<void()> &on_stop = {});

 private:
  GstElement *element_;
  GstStaticPadTemplate *templ_;
  std::vector<GstPad *> pads_;
  GstFlowCombiner *combiner_;
};

// Fixed caps for one output pad: other/tensors (static or flexible).
GstCaps *fixed_tensors_caps(const TensorsConfig &config);

}  // namespace nns::gst

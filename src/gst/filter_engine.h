// SPDX-License-Identifier: LGPL-2.1-only
// The working part of tensor_filter, apart from the GObject shell: opening the back end,
// checking shapes, caps transformation, the per-buffer invoke and the statistics.
//
// Per buffer, the input memories are mapped and their pointers handed to the back end as they
// are (no copy); output memories are allocated with gst_allocator_alloc() and the back end
// writes straight into them. Copies happen only where the formats force them: a flexible
// output from an ALLOCATE_IN_INVOKE or invoke-dynamic back end (the 128-byte header must
// precede the data in the same memory), or a static input tensor passed through to a
// flexible output by output-combination.
#pragma once

#include <gst/base/gstbasetransform.h>
#include <gst/gst.h>

#include <array>
#include <atomic>
#include <memory>
#include <string>
#include <vector>

#include "core/filter_instance.h"
#include "core/meta_header.h"
#include "gst/filter_async.h"
#include "gst/filter_settings.h"

namespace nns::gst {

// Invoke statistics (latency=1, throughput=1, latency-report=true).
class FilterStats {
 public:
  void reset();
  // Records one invoke of `ns` nanoseconds; updates the published values.
  void record(int64_t ns, bool latency, bool throughput);
  int latency_us() const { return latency_us_.load(std::memory_order_relaxed); }
  int throughput() const { return throughput_.load(std::memory_order_relaxed); }
  int64_t total_invokes() const { return total_num_; }

 private:
  static constexpr std::size_t kRecent = 10;
  std::array<int64_t, kRecent> recent_{};
  std::size_t n_ = 0, pos_ = 0;
  int64_t sum_recent_ = 0;
  int64_t total_num_ = 0, total_ns_ = 0;
  std::atomic<int> latency_us_{0};
  std::atomic<int> throughput_{0};
};

class FilterEngine {
 public:
  explicit FilterEngine(GstBaseTransform *element) : element_(element) {}

  // Resolves the framework, opens (or shares) the model and checks the property shapes
  // against the model. Throws nns::Error naming the model, the framework and the cause.
  void open(const FilterSettings &settings);
  void close();
  bool is_open() const { return inst_ != nullptr; }
  // The settings the open instance was opened with.
  const FilterSettings &open_settings() const { return settings_; }
  // Posts the warnings of the last open() (properties the back end ignores). Kept apart so a
  // model opened for a caps query before start has them posted when the element starts.
  void post_open_warnings() const;
  std::shared_ptr<FilterInstance> instance() const { return inst_; }

  // Caps on the other pad for `caps` on pad `direction`; nullptr when unknown (the caller
  // then uses the template caps).
  GstCaps *transform_caps(GstPadDirection direction, GstCaps *caps);
  // Final negotiation. Throws nns::Error with both shapes when they do not agree.
  void configure(GstCaps *incaps, GstCaps *outcaps);
  bool configured() const { return configured_; }

  // One frame. Returns GST_BASE_TRANSFORM_FLOW_DROPPED when the back end drops it, and
  // always with invoke-async (the outputs go through the dispatcher).
  GstFlowReturn process(GstBuffer *inbuf, GstBuffer *outbuf);

  // invoke-async: whether the open back end has invoke_async, and the dispatcher that then
  // receives its outputs (nullptr: synchronous invoke).
  bool async_supported() const { return inst_ && inst_->supports_async(); }
  void set_async(std::shared_ptr<AsyncDispatcher> d) { async_ = std::move(d); }

  // is-updatable: load new model files into the running instance; re-checks the shapes.
  void reload(const std::vector<std::string> &models);

  // Shapes as known now (negotiated, else model/properties); empty when unknown.
  TensorsInfo current_input() const;
  TensorsInfo current_output() const;

  FilterStats &stats() { return stats_; }
  void set_profiling(bool latency, bool throughput, bool report) {
    prof_latency_ = latency;
    prof_throughput_ = throughput;
    prof_report_ = report;
  }
  // QoS throttling (tensor_rate throttle=true): the smallest delay asked for.
  void set_throttling_delay(GstClockTimeDiff diff);
  // True when `inbuf` comes too soon after the last processed frame; sends QoS OVERFLOW
  // upstream. Streaming thread, without the engine lock (it pushes an event upstream).
  bool throttled(GstBuffer *inbuf);

 private:
  struct OutTensor {
    GstMemory *mem = nullptr;
    GstMapInfo map{};
    bool mapped = false;
  };
  struct InTensor {
    GstMemory *mem = nullptr;  // borrowed (peeked) or owned (packed sub-memory)
    bool owned = false;
    GstMapInfo map{};
    bool mapped = false;
    MetaHeader header;  // flexible input only
  };

  std::string where() const;  // "framework 'x', model 'y'"
  void open_model(const FilterSettings &settings);
  void check_model_shapes();
  // A batching source upstream (tensor_query_serversrc max-batch > 1) whose batch the model
  // cannot take: throws the refusal naming max-batch, the model's inputs, `want` (the batched
  // input, `what`: "input=" or "the stream") and `cause` (the back end's or the shape check's
  // message). Returns when there is no batching source, when `want` differs from the model
  // beyond the batch, or when the model does not open at its own shapes either (`cause` then
  // stands alone). filter_engine_batch.cc.
  void refuse_batch(const FilterSettings &settings, const TensorsInfo &want,
                    const std::string &what, const std::string &cause);
  void release_inputs(std::size_t n);
  void release_outputs(bool free_mems);
  GstMemory *pass_input(std::size_t i);
  void track_latency();
  // One measured invoke: the statistics of the profiling properties and the nnsprofile tracer.
  void record_invoke(int64_t dur_ns);
  void describe_input(nns_tensors_desc &d, std::size_t nin) const;

  GstBaseTransform *element_;
  std::shared_ptr<FilterInstance> inst_;
  FilterSettings settings_;
  std::vector<std::string> open_warnings_;
  Combination combi_;
  bool invoke_dynamic_ = false;
  bool allocate_in_invoke_ = false;

  // From the model and the properties (after open()).
  TensorsInfo eff_in_, eff_out_;
  bool eff_in_known_ = false, eff_out_known_ = false;
  bool model_in_known_ = false, model_out_known_ = false;
  std::string in_source_, out_source_;

  // Negotiated.
  bool configured_ = false;
  bool in_flexible_ = false, out_flexible_ = false;
  TensorsInfo frame_in_;   // input caps (static)
  TensorsInfo model_in_;   // what invoke gets
  TensorsInfo model_out_;  // what invoke returns
  TensorsInfo frame_out_;  // output caps
  std::vector<std::array<uint8_t, kMetaHeaderSize>> out_headers_;

  // Per-buffer scratch, sized at configure().
  std::vector<InTensor> in_;
  std::vector<GstTensorMemory> in_tm_, invoke_in_, out_tm_;
  std::vector<OutTensor> out_;
  std::vector<GstMemory *> outs_;
  std::unique_ptr<nns_tensors_desc> dyn_in_, dyn_out_;
  std::shared_ptr<AsyncDispatcher> async_;

  FilterStats stats_;
  std::atomic<bool> prof_latency_{false}, prof_throughput_{false}, prof_report_{false};
  int64_t last_posted_ns_ = 0;
  std::atomic<int64_t> reported_ns_{0};

  // QoS
  std::atomic<GstClockTimeDiff> throttling_delay_{0};
  GstClockTime prev_ts_ = GST_CLOCK_TIME_NONE;
  GstClockTimeDiff throttling_accum_ = 0;

 public:
  // latency-report: the latency added to LATENCY query answers (ns).
  std::atomic<int64_t> &reported_ns() { return reported_ns_; }
};

}  // namespace nns::gst

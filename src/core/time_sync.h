// SPDX-License-Identifier: LGPL-2.1-only
// Time-synchronisation policies of tensor_mux / tensor_merge (GStreamer-free).
//
// NNStreamer's `sync-mode` values and their rules, decided on PTS only:
//  - nosync:  every input gives its next buffer; output PTS = latest PTS seen.
//  - slowest: the base time is the largest head PTS (the slowest stream's); inputs drop
//             buffers older than it, but keep the previous one when it is nearer to the base.
//  - basepad: the base time is the head PTS of pad `sink_id`; another pad's new buffer is
//             used only when within `duration` (capped by the base pad's own frame gap).
//  - refresh: an output whenever any pad gets a buffer, re-using the last buffer of the
//             others; every pad needs one buffer before the first output.
// The policy sees the pads through SyncInputs: each pad has an optional queued "head" buffer
// and an optional "last" (the buffer currently chosen for output). Outputs are built from the
// "last" buffers.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>

namespace nns {

enum class SyncMode { kNoSync = 0, kSlowest, kBasePad, kRefresh };

std::optional<SyncMode> sync_mode_from_name(std::string_view s);
std::string_view sync_mode_name(SyncMode m);

// sync-option. Only basepad uses it: "<sink_id>:<duration_ns>", both optional
// (defaults 0 and G_MAXINT ns, as upstream).
struct SyncOption {
  uint32_t sink_id = 0;
  uint64_t duration = 2147483647;
};
// Throws nns::Error(kSettings) naming sync-option and the bad token.
SyncOption parse_sync_option(SyncMode mode, std::string_view s);

constexpr uint64_t kNoTime = UINT64_MAX;  // GST_CLOCK_TIME_NONE

// How the policy sees the sink pads (in pad order).
class SyncInputs {
 public:
  virtual ~SyncInputs() = default;
  virtual std::size_t count() const = 0;
  // PTS of the queued buffer, or nullopt when the pad has none (EOS, or not arrived).
  virtual std::optional<uint64_t> head_pts(std::size_t i) = 0;
  // PTS of the buffer currently chosen for the pad, or nullopt when there is none yet.
  virtual std::optional<uint64_t> last_pts(std::size_t i) = 0;
  // Pops the queued buffer and makes it the pad's chosen buffer.
  virtual void take_head(std::size_t i) = 0;
  // The queued buffer of pad `i` decides the output time (copy its metadata).
  virtual void set_time_source(std::size_t /*i*/) {}
};

enum class SyncResult {
  kOutput,    // every pad has a chosen buffer: build the output from them, PTS = time()
  kNeedData,  // a stale buffer was dropped (or a pad has no buffer yet): wait for more
  kEos,       // the stream ended
};

class TimeSync {
 public:
  TimeSync() = default;
  TimeSync(SyncMode mode, SyncOption option) : mode_(mode), option_(option) {}

  SyncMode mode() const { return mode_; }
  const SyncOption &option() const { return option_; }
  void reset() {
    current_ = 0;
    need_time_ = true;
  }

  // One decision. nosync/slowest/basepad: call when every pad has a head or is EOS.
  // refresh: call whenever a pad has a new head (heads are then taken as they come).
  SyncResult step(SyncInputs &in);
  // Output PTS of the last kOutput.
  uint64_t time() const { return current_; }

 private:
  bool pick_time(SyncInputs &in);  // false: end of stream
  SyncMode mode_ = SyncMode::kSlowest;
  SyncOption option_;
  uint64_t current_ = 0;
  bool need_time_ = true;
};

}  // namespace nns

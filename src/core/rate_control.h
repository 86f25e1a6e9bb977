// SPDX-License-Identifier: LGPL-2.1-only
// Frame-rate adjustment of tensor_rate (GStreamer-free): like videorate, each input frame is
// compared with the previous one and the previous frame is output zero, one or several times,
// so output frames sit on a regular grid of the target rate. The caller keeps the previous
// buffer; this class keeps the timing and the in/out/duplicate/drop counters.
// Times are nanoseconds; kNone marks an unset time.
#pragma once

#include <cstdint>
#include <limits>

namespace nns {

class RateAdjuster {
 public:
  static constexpr uint64_t kNone = std::numeric_limits<uint64_t>::max();

  struct Counters {
    uint64_t in = 0, out = 0, duplicate = 0, drop = 0;
  };

  // What happened to an input frame.
  struct Result {
    bool discard_new = false;   // older than the previous frame: the new frame is dropped
    bool dropped_prev = false;  // the previous frame was never output (send QoS upstream)
    bool store_new = false;     // the new frame becomes the previous frame
  };

  // Forgets frames, timing and counters (start, stop, flush).
  void reset();
  // Output rate from the negotiated caps; num 0 means "use buffer durations".
  void set_output_rate(int num, int den);
  // A new segment (time format) with its base and start.
  void new_segment(uint64_t base, uint64_t start, uint64_t stop);

  // One input frame with stream time `ts` and `duration` (kNone if unknown). For every output
  // of the previous frame, calls emit(pts, duration, is_duplicate), which returns false to stop
  // (a flow error downstream). Returns false when an emit failed.
  template <typename Emit>
  bool on_frame(uint64_t ts, uint64_t duration, Emit &&emit, Result *r);
  // End of stream or segment: outputs the previous frame once (or up to the segment stop).
  template <typename Emit>
  bool drain(Emit &&emit);

  // Passthrough (same rate in and out): only counts.
  void count_passthrough() {
    ++c_.in;
    ++c_.out;
  }

  const Counters &counters() const { return c_; }
  bool has_prev() const { return has_prev_; }
  // Interval of one output frame (0 when the output rate is variable).
  uint64_t frame_interval() const;
  // Delay upstream's QoS throttle event carries: 0.999 of one output interval (upstream's ratio).
  int64_t throttle_delay() const;
  void forget_prev() { has_prev_ = false; }

 private:
  uint64_t scaled(uint64_t frames) const;
  template <typename Emit>
  bool emit_prev(bool dup, Emit &&emit);

  int to_n_ = 0, to_d_ = 1;
  uint64_t seg_base_ = 0, seg_start_ = 0, seg_stop_ = kNone;
  uint64_t base_ts_ = 0, next_ts_ = kNone, out_frames_ = 0;
  bool has_prev_ = false;
  uint64_t prev_time_ = 0, prev_dur_ = kNone;
  Counters c_;
};

template <typename Emit>
bool RateAdjuster::emit_prev(bool dup, Emit &&emit) {
  uint64_t push_ts = next_ts_;
  uint64_t dur;
  ++c_.out;
  ++out_frames_;
  if (to_n_ > 0) {
    next_ts_ = seg_base_ + seg_start_ + base_ts_ + scaled(out_frames_);
    dur = next_ts_ - push_ts;
  } else {
    dur = prev_dur_ == kNone ? 0 : prev_dur_;
    next_ts_ = push_ts + dur;
  }
  return emit(push_ts - seg_base_, dur, dup);
}

template <typename Emit>
bool RateAdjuster::on_frame(uint64_t ts, uint64_t duration, Emit &&emit, Result *r) {
  *r = Result{};
  ++c_.in;
  const uint64_t intime = ts + seg_base_;
  if (!has_prev_) {
    has_prev_ = true;
    prev_time_ = intime;
    prev_dur_ = duration;
    r->store_new = true;
    if (next_ts_ == kNone) {
      next_ts_ = intime;
      base_ts_ = ts - seg_start_;
      out_frames_ = 0;
    }
    return true;
  }
  if (intime < prev_time_) {
    ++c_.drop;
    r->discard_new = true;
    return true;
  }
  if (prev_dur_ == kNone) prev_dur_ = intime - prev_time_;
  unsigned count = 0;
  uint64_t d1, d2;
  do {
    d1 = prev_time_ > next_ts_ ? prev_time_ - next_ts_ : next_ts_ - prev_time_;
    d2 = intime > next_ts_ ? intime - next_ts_ : next_ts_ - intime;
    if (d1 <= d2) {
      ++count;
      if (!emit_prev(count > 1, emit)) return false;
    }
  } while (d1 < d2);
  if (count > 1) {
    c_.duplicate += count - 1;
  } else if (count == 0) {
    ++c_.drop;
    r->dropped_prev = true;
  }
  prev_time_ = intime;
  prev_dur_ = duration;
  r->store_new = true;
  return true;
}

template <typename Emit>
bool RateAdjuster::drain(Emit &&emit) {
  if (!has_prev_) return true;
  unsigned count = 0;
  constexpr unsigned kLimit = 25;  // never loop wildly on odd segments
  do {
    if (!emit_prev(count > 0, emit)) return false;
    ++count;
  } while (seg_stop_ != kNone && next_ts_ != kNone && next_ts_ - seg_base_ < seg_stop_ &&
           count <= kLimit && to_n_ > 0);
  if (count > 1) c_.duplicate += count - 1;
  has_prev_ = false;
  return true;
}

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
#include "core/rate_control.h"

namespace nns {

void RateAdjuster::reset() {
  c_ = Counters{};
  base_ts_ = 0;
  next_ts_ = kNone;
  out_frames_ = 0;
  has_prev_ = false;
  prev_time_ = 0;
  prev_dur_ = kNone;
  seg_base_ = seg_start_ = 0;
  seg_stop_ = kNone;
}

uint64_t RateAdjuster::scaled(uint64_t frames) const {
  if (to_n_ <= 0) return 0;
  // frames * to_d * 1e9 / to_n without overflow for realistic values
  unsigned __int128 v =
      static_cast<unsigned __int128>(frames) * static_cast<uint64_t>(to_d_) * 1000000000ull;
  return static_cast<uint64_t>(v / static_cast<uint64_t>(to_n_));
}

void RateAdjuster::set_output_rate(int num, int den) {
  // Keep the grid continuous across a rate change (frames already output stay where they are).
  if (to_n_ > 0) base_ts_ += scaled(out_frames_);
  out_frames_ = 0;
  to_n_ = num;
  to_d_ = den > 0 ? den : 1;
  has_prev_ = false;  // caps changed: the stored frame may not match them
}

void RateAdjuster::new_segment(uint64_t base, uint64_t start, uint64_t stop) {
  seg_base_ = base;
  seg_start_ = start;
  seg_stop_ = stop;
  base_ts_ = 0;
  out_frames_ = 0;
  next_ts_ = kNone;
}

uint64_t RateAdjuster::frame_interval() const {
  return scaled(1);
}

int64_t RateAdjuster::throttle_delay() const {
  return static_cast<int64_t>(static_cast<double>(scaled(1)) * 0.999);
}

}  // namespace nns

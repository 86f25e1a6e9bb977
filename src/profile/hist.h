// SPDX-License-Identifier: LGPL-2.1-only
// Log-scale histogram of durations for the nnsprofile tracer: four buckets per power of two
// from 64 ns up (bucket k covers [lower(k), lower(k + 1))), so a bucket's width is at most 25 %
// of its lower bound. Adding a sample is one relaxed atomic increment (no lock, no allocation).
// GStreamer-free.
#pragma once

#include <array>
#include <atomic>
#include <bit>
#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace nns::profile {

constexpr int kHistBuckets = 128;
constexpr int kHistMinShift = 6;  // 64 ns: everything below lands in bucket 0

// Bucket of a duration in ns (negative durations count as 0).
constexpr int hist_bucket(int64_t ns) {
  if (ns < (int64_t{1} << kHistMinShift)) return 0;
  const auto v = static_cast<uint64_t>(ns);
  const int msb = 63 - std::countl_zero(v);
  const int sub = static_cast<int>((v >> (msb - 2)) & 3u);
  const int k = (msb - kHistMinShift) * 4 + sub;
  return k >= kHistBuckets ? kHistBuckets - 1 : k;
}

// Lower bound (ns) of bucket k; bucket 0 starts at 0.
constexpr int64_t hist_lower(int k) {
  if (k <= 0) return 0;
  const int msb = k / 4 + kHistMinShift;
  const int sub = k % 4;
  return static_cast<int64_t>(4 + sub) << (msb - 2);
}

class Hist {
 public:
  void add(int64_t ns) { b_[hist_bucket(ns)].fetch_add(1, std::memory_order_relaxed); }
  // Non-empty buckets as (lower bound ns, count), in increasing order.
  std::vector<std::pair<int64_t, uint64_t>> nonzero() const {
    std::vector<std::pair<int64_t, uint64_t>> out;
    for (int k = 0; k < kHistBuckets; ++k) {
      uint32_t c = b_[static_cast<std::size_t>(k)].load(std::memory_order_relaxed);
      if (c) out.emplace_back(hist_lower(k), c);
    }
    return out;
  }

 private:
  std::array<std::atomic<uint32_t>, kHistBuckets> b_{};
};

// Quantile q (0..1) of a histogram given as (lower bound, count) pairs: the midpoint of the
// bucket holding it (the next bucket's lower bound is 1.25 x this one's at most). -1 when empty.
inline int64_t hist_quantile(const std::vector<std::pair<int64_t, uint64_t>> &h, double q) {
  uint64_t total = 0;
  for (const auto &b : h) total += b.second;
  if (total == 0) return -1;
  const double want = q * static_cast<double>(total);
  uint64_t seen = 0;
  for (const auto &b : h) {
    seen += b.second;
    if (static_cast<double>(seen) >= want) {
      int k = hist_bucket(b.first);
      return (b.first + hist_lower(k + 1)) / 2;
    }
  }
  return h.back().first;
}

// Keeps `slot` at the maximum of itself and v.
inline void atomic_max(std::atomic<int64_t> &slot, int64_t v) {
  int64_t cur = slot.load(std::memory_order_relaxed);
  while (v > cur && !slot.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}
inline void atomic_min(std::atomic<int64_t> &slot, int64_t v) {
  int64_t cur = slot.load(std::memory_order_relaxed);
  while (v < cur && !slot.compare_exchange_weak(cur, v, std::memory_order_relaxed)) {
  }
}

}  // namespace nns::profile

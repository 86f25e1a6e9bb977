// SPDX-License-Identifier: LGPL-2.1-only
// RateAdjuster: down/up conversion counts and output timestamps, late frames, drain, rate
// changes and the QoS throttle delay.
#include "core/rate_control.h"

#include <gtest/gtest.h>

#include <vector>

namespace nns {
namespace {

constexpr uint64_t kMs = 1000000;

struct Out {
  uint64_t pts, dur;
  bool dup;
  int src;  // which input frame was output
};

// Feeds `n` frames at `in_fps`, converting to `out_fps`; returns the outputs (with drain).
std::vector<Out> run(int n, int in_fps, int out_fps, RateAdjuster *r) {
  r->reset();
  r->set_output_rate(out_fps, 1);
  r->new_segment(0, 0, RateAdjuster::kNone);
  std::vector<Out> out;
  int prev = -1;
  for (int i = 0; i < n; ++i) {
    uint64_t ts = uint64_t(i) * 1000000000ull / in_fps;
    RateAdjuster::Result res;
    EXPECT_TRUE(r->on_frame(
        ts, 1000000000ull / in_fps,
        [&](uint64_t pts, uint64_t dur, bool dup) {
          out.push_back({pts, dur, dup, prev});
          return true;
        },
        &res));
    if (res.store_new) prev = i;
  }
  r->drain([&](uint64_t pts, uint64_t dur, bool dup) {
    out.push_back({pts, dur, dup, prev});
    return true;
  });
  return out;
}

TEST(RateAdjuster, DownConvert30To10) {
  RateAdjuster r;
  auto out = run(30, 30, 10, &r);
  // Grid points 0..900 ms take the nearest input frame; EOS outputs the last frame once more
  // at 1000 ms (videorate's behaviour, and upstream tensor_rate's).
  ASSERT_EQ(out.size(), 11u);
  for (std::size_t k = 0; k < out.size(); ++k) {
    EXPECT_EQ(out[k].pts, k * 100 * kMs);
    EXPECT_EQ(out[k].dur, 100 * kMs);
    EXPECT_FALSE(out[k].dup);
    EXPECT_EQ(out[k].src, k < 10 ? int(3 * k) : 29);
  }
  EXPECT_EQ(r.counters().in, 30u);
  EXPECT_EQ(r.counters().out, 11u);
  EXPECT_EQ(r.counters().drop, 19u);
  EXPECT_EQ(r.counters().duplicate, 0u);
}

TEST(RateAdjuster, UpConvert10To30) {
  RateAdjuster r;
  auto out = run(10, 10, 30, &r);
  // Grid points 0..833 ms come from frames 0..8 (three each); EOS outputs frame 9 once at
  // 866 ms.
  EXPECT_EQ(r.counters().in, 10u);
  EXPECT_EQ(r.counters().out, out.size());
  EXPECT_EQ(r.counters().drop, 0u);
  EXPECT_EQ(r.counters().duplicate, r.counters().out - 10);
  ASSERT_EQ(out.size(), 27u);
  EXPECT_EQ(out[26].src, 9);
  for (std::size_t k = 0; k < out.size(); ++k) EXPECT_EQ(out[k].pts, k * 1000000000ull / 30) << k;
  // frame 0 covers 0, 33 ms (nearest to frame 0), frame 1 covers 66..133 ms, ...
  EXPECT_EQ(out[0].src, 0);
  EXPECT_EQ(out[1].src, 0);
  EXPECT_TRUE(out[1].dup);
  EXPECT_EQ(out[2].src, 1);
}

TEST(RateAdjuster, SameRateKeepsEveryFrame) {
  RateAdjuster r;
  auto out = run(12, 15, 15, &r);
  ASSERT_EQ(out.size(), 12u);
  for (std::size_t k = 0; k < out.size(); ++k) EXPECT_EQ(out[k].src, int(k));
  EXPECT_EQ(r.counters().drop + r.counters().duplicate, 0u);
}

TEST(RateAdjuster, LateFrameIsDiscardedAndDropReported) {
  RateAdjuster r;
  r.reset();
  r.set_output_rate(10, 1);
  r.new_segment(0, 0, RateAdjuster::kNone);
  RateAdjuster::Result res;
  auto none = [](uint64_t, uint64_t, bool) { return true; };
  r.on_frame(500 * kMs, RateAdjuster::kNone, none, &res);
  EXPECT_TRUE(res.store_new);
  r.on_frame(400 * kMs, RateAdjuster::kNone, none, &res);
  EXPECT_TRUE(res.discard_new);
  EXPECT_EQ(r.counters().drop, 1u);
  // 530 ms: frame at 500 is nearest to the 500 ms grid point -> output
  int emitted = 0;
  r.on_frame(
      530 * kMs, RateAdjuster::kNone,
      [&](uint64_t pts, uint64_t, bool) {
        EXPECT_EQ(pts, 500 * kMs);
        ++emitted;
        return true;
      },
      &res);
  EXPECT_EQ(emitted, 1);
  // 560 ms: 530 is farther from the 600 ms point than 560 -> 530 dropped, QoS wanted
  r.on_frame(560 * kMs, RateAdjuster::kNone, none, &res);
  EXPECT_TRUE(res.dropped_prev);
  EXPECT_EQ(r.throttle_delay(), int64_t(99.9 * kMs));
}

TEST(RateAdjuster, EmitFailureStops) {
  RateAdjuster r;
  r.reset();
  r.set_output_rate(10, 1);
  r.new_segment(0, 0, RateAdjuster::kNone);
  RateAdjuster::Result res;
  auto fail = [](uint64_t, uint64_t, bool) { return false; };
  EXPECT_TRUE(r.on_frame(0, RateAdjuster::kNone, fail, &res));
  EXPECT_FALSE(r.on_frame(100 * kMs, RateAdjuster::kNone, fail, &res));
}

TEST(RateAdjuster, SegmentBaseIsRemovedFromOutput) {
  RateAdjuster r;
  r.reset();
  r.set_output_rate(10, 1);
  r.new_segment(5000 * kMs, 0, RateAdjuster::kNone);
  RateAdjuster::Result res;
  std::vector<uint64_t> pts;
  auto rec = [&](uint64_t p, uint64_t, bool) {
    pts.push_back(p);
    return true;
  };
  r.on_frame(0, RateAdjuster::kNone, rec, &res);
  r.on_frame(100 * kMs, RateAdjuster::kNone, rec, &res);
  r.drain(rec);
  EXPECT_EQ(pts, (std::vector<uint64_t>{0, 100 * kMs}));
}

}  // namespace
}  // namespace nns

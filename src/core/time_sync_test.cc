// SPDX-License-Identifier: LGPL-2.1-only
// Sync policies against the tables of NNStreamer's synchronization-policies-at-mux-merge.md
// (pads at 30, 20 and 10 fps), simulated the way an aggregator calls them: each pad holds at
// most one queued buffer, refilled from its stream after it is taken.
#include "core/time_sync.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <deque>

#include "core/error.h"

namespace nns {
namespace {

struct Out {
  uint64_t pts;
  std::vector<uint64_t> used;
  bool operator==(const Out &o) const { return pts == o.pts && used == o.used; }
};

std::ostream &operator<<(std::ostream &os, const Out &o) {
  os << "@" << o.pts << " (";
  for (auto u : o.used) os << u << " ";
  return os << ")";
}

class FakePads : public SyncInputs {
 public:
  explicit FakePads(std::vector<std::deque<uint64_t>> streams)
      : streams_(std::move(streams)), last_(streams_.size()) {}
  std::size_t count() const override { return streams_.size(); }
  std::optional<uint64_t> head_pts(std::size_t i) override {
    if (streams_[i].empty()) return std::nullopt;
    return streams_[i].front();
  }
  std::optional<uint64_t> last_pts(std::size_t i) override { return last_[i]; }
  void take_head(std::size_t i) override {
    last_[i] = streams_[i].front();
    streams_[i].pop_front();
  }
  void set_time_source(std::size_t i) override { source_ = i; }
  std::vector<uint64_t> used() const {
    std::vector<uint64_t> u;
    for (auto &l : last_) u.push_back(l.value_or(kNoTime));
    return u;
  }
  std::vector<std::deque<uint64_t>> streams_;
  std::vector<std::optional<uint64_t>> last_;
  std::size_t source_ = 99;
};

std::deque<uint64_t> stream(uint64_t step, std::size_t n) {
  std::deque<uint64_t> d;
  for (std::size_t i = 0; i < n; ++i) d.push_back(i * step);
  return d;
}

std::vector<Out> run(TimeSync sync, FakePads &pads, std::size_t max_out = 100) {
  std::vector<Out> out;
  for (int guard = 0; guard < 10000 && out.size() < max_out; ++guard) {
    SyncResult r = sync.step(pads);
    if (r == SyncResult::kEos) break;
    if (r == SyncResult::kOutput) {
      out.push_back({sync.time(), pads.used()});
      if (sync.mode() == SyncMode::kNoSync)
        for (auto &l : pads.last_) l.reset();
    }
  }
  return out;
}

constexpr uint64_t k30 = 33333333, k20 = 50000000, k10 = 100000000;

TEST(TimeSync, ModeNames) {
  EXPECT_EQ(sync_mode_from_name("nosync"), SyncMode::kNoSync);
  EXPECT_EQ(sync_mode_from_name("slowest"), SyncMode::kSlowest);
  EXPECT_EQ(sync_mode_from_name(" basepad "), SyncMode::kBasePad);
  EXPECT_EQ(sync_mode_from_name("refresh"), SyncMode::kRefresh);
  EXPECT_FALSE(sync_mode_from_name("fastest"));
  EXPECT_EQ(sync_mode_name(SyncMode::kRefresh), "refresh");
}

TEST(TimeSync, BasepadOption) {
  auto o = parse_sync_option(SyncMode::kBasePad, "1:33333333");
  EXPECT_EQ(o.sink_id, 1u);
  EXPECT_EQ(o.duration, 33333333u);
  o = parse_sync_option(SyncMode::kBasePad, "2");
  EXPECT_EQ(o.sink_id, 2u);
  EXPECT_EQ(o.duration, 2147483647u);
  o = parse_sync_option(SyncMode::kBasePad, "");
  EXPECT_EQ(o.sink_id, 0u);
  // Other modes ignore the option.
  EXPECT_NO_THROW(parse_sync_option(SyncMode::kSlowest, "garbage"));
  try {
    parse_sync_option(SyncMode::kBasePad, "x:10");
    FAIL();
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("sync-option"), std::string::npos);
    EXPECT_NE(std::string(e.what()).find("'x'"), std::string::npos);
  }
  EXPECT_THROW(parse_sync_option(SyncMode::kBasePad, "1:2:3"), Error);
  EXPECT_THROW(parse_sync_option(SyncMode::kBasePad, "0:-5"), Error);
}

TEST(TimeSync, NoSyncTakesOneFromEachPad) {
  FakePads pads({stream(k30, 4), stream(k20, 4), stream(k10, 4)});
  auto out = run(TimeSync(SyncMode::kNoSync, {}), pads);
  ASSERT_EQ(out.size(), 4u);
  EXPECT_EQ(out[0], (Out{0, {0, 0, 0}}));
  EXPECT_EQ(out[1], (Out{k10, {k30, k20, k10}}));
  EXPECT_EQ(out[3], (Out{3 * k10, {3 * k30, 3 * k20, 3 * k10}}));
}

TEST(TimeSync, SlowestFollowsTheSlowestPad) {
  FakePads pads({stream(k30, 10), stream(k20, 7), stream(k10, 4)});
  auto out = run(TimeSync(SyncMode::kSlowest, {}), pads);
  ASSERT_GE(out.size(), 3u);
  EXPECT_EQ(out[0], (Out{0, {0, 0, 0}}));
  // 99999999 is kept although older than 100000000: it is nearer than 133333332.
  EXPECT_EQ(out[1], (Out{k10, {3 * k30, 2 * k20, k10}}));
  EXPECT_EQ(out[2], (Out{2 * k10, {6 * k30, 4 * k20, 2 * k10}}));
  // The 30 fps pad runs out after 9 frames (299999997): the next base is 300000000.
  EXPECT_EQ(out[3], (Out{3 * k10, {9 * k30, 6 * k20, 3 * k10}}));
  EXPECT_EQ(out.size(), 4u);
}

TEST(TimeSync, BasepadUsesBufferWithinDuration) {
  FakePads pads({stream(k30, 10), stream(k20, 7), stream(k10, 4)});
  auto out = run(TimeSync(SyncMode::kBasePad, {0, 33333333}), pads);
  // Table of the upstream document (its srcpad2 column is the 10 fps stream).
  std::vector<Out> want = {
      {0, {0, 0, 0}},
      {k30, {k30, k20, 0}},
      {2 * k30, {2 * k30, k20, 0}},
      {3 * k30, {3 * k30, 2 * k20, k10}},
      {4 * k30, {4 * k30, 3 * k20, k10}},
      {5 * k30, {5 * k30, 3 * k20, k10}},
      {6 * k30, {6 * k30, 4 * k20, 2 * k10}},
  };
  ASSERT_GE(out.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) EXPECT_EQ(out[i], want[i]) << "output " << i;
  EXPECT_EQ(pads.source_, 0u);
}

TEST(TimeSync, BasepadOnAnotherPad) {
  FakePads pads({stream(k30, 10), stream(k20, 7), stream(k10, 4)});
  auto out = run(TimeSync(SyncMode::kBasePad, {2, 1000000000}), pads);
  ASSERT_GE(out.size(), 3u);
  EXPECT_EQ(out[1].pts, k10);
  EXPECT_EQ(out[2].pts, 2 * k10);
  EXPECT_EQ(pads.source_, 2u);
}

TEST(TimeSync, EosWhenAnyPadEnds) {
  FakePads pads({stream(k30, 2), stream(k30, 10)});
  auto out = run(TimeSync(SyncMode::kNoSync, {}), pads);
  EXPECT_EQ(out.size(), 2u);
  FakePads pads2({stream(k30, 2), stream(k30, 10)});
  EXPECT_EQ(run(TimeSync(SyncMode::kSlowest, {}), pads2).size(), 2u);
}

// refresh: buffers arrive one at a time (in PTS order); each arrival is one step.
TEST(TimeSync, RefreshOutputsOnEveryArrival) {
  TimeSync sync(SyncMode::kRefresh, {});
  FakePads pads({{}, {}, {}});
  struct Arrival {
    std::size_t pad;
    uint64_t pts;
  };
  // The table of the upstream document: values are pad/arrival numbers, PTS grow.
  std::vector<Arrival> arrivals = {{0, 0},  {1, 0},  {2, 0},  {1, 10},
                                   {2, 20}, {2, 30}, {0, 40}, {2, 50}};
  std::vector<Out> out;
  for (auto a : arrivals) {
    pads.streams_[a.pad].push_back(a.pts);
    if (sync.step(pads) == SyncResult::kOutput) out.push_back({sync.time(), pads.used()});
  }
  std::vector<Out> want = {
      {0, {0, 0, 0}},    {10, {0, 10, 0}},   {20, {0, 10, 20}},
      {30, {0, 10, 30}}, {40, {40, 10, 30}}, {50, {40, 10, 50}},
  };
  EXPECT_EQ(out, want);
  // Ends only when every pad is empty.
  EXPECT_EQ(sync.step(pads), SyncResult::kEos);
}

TEST(TimeSync, RefreshFirstOutputKeepsFirstTime) {
  // As upstream: the time is picked when an attempt starts and kept until an output.
  TimeSync sync(SyncMode::kRefresh, {});
  FakePads pads({{}, {}});
  pads.streams_[0].push_back(5);
  EXPECT_EQ(sync.step(pads), SyncResult::kNeedData);
  pads.streams_[0].push_back(7);
  EXPECT_EQ(sync.step(pads), SyncResult::kNeedData);
  pads.streams_[1].push_back(9);
  EXPECT_EQ(sync.step(pads), SyncResult::kOutput);
  EXPECT_EQ(sync.time(), 5u);
  EXPECT_EQ(pads.used(), (std::vector<uint64_t>{7, 9}));
}

TEST(TimeSync, RefreshKeepsEarlyArrivalsOfLaterPads) {
  TimeSync sync(SyncMode::kRefresh, {});
  FakePads pads({{}, {}});
  pads.streams_[1].push_back(3);
  EXPECT_EQ(sync.step(pads), SyncResult::kNeedData);
  EXPECT_TRUE(pads.streams_[1].empty()) << "the buffer of pad 1 is kept as its last";
  pads.streams_[0].push_back(4);
  EXPECT_EQ(sync.step(pads), SyncResult::kOutput);
  EXPECT_EQ(pads.used(), (std::vector<uint64_t>{4, 3}));
}

// A pad that ended without any data: once the other pad ended too the stream ends (a step
// that neither outputs nor consumes would be called again forever).
TEST(TimeSync, RefreshEndsWhenAPadEndedWithoutData) {
  TimeSync sync(SyncMode::kRefresh, {});
  FakePads pads({{}, {}});
  pads.streams_[0].push_back(5);
  EXPECT_EQ(sync.step(pads), SyncResult::kNeedData);
  pads.streams_[0].push_back(7);
  EXPECT_EQ(sync.step(pads), SyncResult::kNeedData);
  EXPECT_EQ(sync.step(pads), SyncResult::kEos);  // both empty: pad 1 never had data
}

TEST(TimeSync, ResetRestartsTime) {
  TimeSync sync(SyncMode::kNoSync, {});
  FakePads pads({stream(k30, 3)});
  run(sync, pads);
  sync.reset();
  EXPECT_EQ(sync.time(), 0u);
}

}  // namespace
}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_aggregator: aggregation, sliding window (frames-flush), dis-aggregation
// (frames-in), concat re-ordering along frames-dim, output caps and PTS, bad settings.
#include <gtest/gtest.h>

#include <numeric>

#include "elements/cycle_check.h"
#include "elements/stream_util.h"
#include "gst/tensor_caps.h"

namespace nns::test {
namespace {

struct AggOut {
  std::vector<std::vector<uint8_t>> data;
  std::vector<GstClockTime> pts;
  std::string out_info;
  RunResult result;
};

// Pushes `frames` buffers (each `frame` bytes: frame index * 10 + byte index) at 10 fps.
AggOut run_agg(const std::string &in_dims, std::size_t bytes, int buffers,
               const std::string &props) {
  std::string caps = "other/tensor,dimension=(string)" + in_dims + ",type=uint8,framerate=10/1";
  Pipe p(appsrc("in", caps) + "! tensor_aggregator name=a " + props +
         " ! appsink name=out sync=false");
  p.collect("out");
  for (int b = 0; b < buffers; ++b) {
    std::vector<uint8_t> v(bytes);
    for (std::size_t i = 0; i < bytes; ++i) v[i] = static_cast<uint8_t>(b * 10 + i);
    p.push("in", make_buffer({v}, b * 100000000ull, 100000000ull));
  }
  p.eos("in");
  AggOut o;
  GstPad *src = gst_element_get_static_pad(p.get("a"), "src");
  o.result = p.run();
  for (GstBuffer *b : p.out()) {
    o.data.push_back(tensor_bytes(b, 0));
    o.pts.push_back(GST_BUFFER_PTS(b));
  }
  gst_object_unref(src);
  return o;
}

std::string out_caps_info(const std::string &in_dims, const std::string &props) {
  std::string caps = "other/tensor,dimension=(string)" + in_dims + ",type=uint8,framerate=10/1";
  Pipe p(appsrc("in", caps) + "! tensor_aggregator name=a " + props + " ! fakesink");
  GstCaps *c = gst_caps_from_string(caps.c_str());
  GstPad *sink = gst_element_get_static_pad(p.get("a"), "sink");
  gst_element_set_state(p.pipeline(), GST_STATE_PAUSED);
  gst_pad_send_event(sink, gst_event_new_stream_start("x"));
  gst_pad_send_event(sink, gst_event_new_caps(c));
  GstPad *src = gst_element_get_static_pad(p.get("a"), "src");
  GstCaps *oc = gst_pad_get_current_caps(src);
  std::string s = oc ? nns::gst::config_from_caps(oc).info.to_string() : "(none)";
  if (oc) gst_caps_unref(oc);
  gst_caps_unref(c);
  gst_object_unref(src);
  gst_object_unref(sink);
  return s;
}

TEST(TensorAggregator, PropertyDefaults) {
  GstElement *a = gst_element_factory_make("tensor_aggregator", nullptr);
  guint fin, fout, fflush, fdim;
  gboolean concat, silent;
  g_object_get(a, "frames-in", &fin, "frames-out", &fout, "frames-flush", &fflush, "frames-dim",
               &fdim, "concat", &concat, "silent", &silent, nullptr);
  EXPECT_EQ(fin, 1u);
  EXPECT_EQ(fout, 1u);
  EXPECT_EQ(fflush, 0u);
  EXPECT_EQ(fdim, 15u);
  EXPECT_TRUE(concat);
  EXPECT_TRUE(silent);
  gst_object_unref(a);
}

TEST(TensorAggregator, AggregatesFramesOutWithOldestPts) {
  auto o = run_agg("2:1", 2, 6, "frames-out=3 frames-dim=1");
  ASSERT_TRUE(o.result.eos) << o.result.error_text;
  ASSERT_EQ(o.data.size(), 2u);
  EXPECT_EQ(o.data[0], (std::vector<uint8_t>{0, 1, 10, 11, 20, 21}));
  EXPECT_EQ(o.data[1], (std::vector<uint8_t>{30, 31, 40, 41, 50, 51}));
  EXPECT_EQ(o.pts, (std::vector<GstClockTime>{0, 300000000}));
  EXPECT_EQ(out_caps_info("2:1", "frames-out=3 frames-dim=1"), "1 tensor(s): [0] uint8 2:3");
}

TEST(TensorAggregator, SlidingWindowWithFramesFlush) {
  auto o = run_agg("1", 1, 5, "frames-out=3 frames-flush=1 frames-dim=1");
  ASSERT_TRUE(o.result.eos) << o.result.error_text;
  ASSERT_EQ(o.data.size(), 3u);
  EXPECT_EQ(o.data[0], (std::vector<uint8_t>{0, 10, 20}));
  EXPECT_EQ(o.data[1], (std::vector<uint8_t>{10, 20, 30}));
  EXPECT_EQ(o.data[2], (std::vector<uint8_t>{20, 30, 40}));
  EXPECT_EQ(o.pts, (std::vector<GstClockTime>{0, 100000000, 200000000}));
}

TEST(TensorAggregator, UpstreamDocExampleInThreeOutFourFlushTwo) {
  // frames-in=3, frames-out=4, frames-flush=2 on 4 buffers of 3 frames: 5 outputs.
  auto o = run_agg("3", 3, 4, "frames-in=3 frames-out=4 frames-flush=2 frames-dim=0");
  ASSERT_TRUE(o.result.eos) << o.result.error_text;
  ASSERT_EQ(o.data.size(), 5u);
  EXPECT_EQ(o.data[0], (std::vector<uint8_t>{0, 1, 2, 10}));
  EXPECT_EQ(o.data[1], (std::vector<uint8_t>{2, 10, 11, 12}));
  EXPECT_EQ(o.data[4], (std::vector<uint8_t>{22, 30, 31, 32}));
  EXPECT_EQ(out_caps_info("3", "frames-in=3 frames-out=4 frames-dim=0"),
            "1 tensor(s): [0] uint8 4");
}

TEST(TensorAggregator, DisaggregatesWithFramePts) {
  auto o = run_agg("2:4", 8, 2, "frames-in=4 frames-out=1 frames-dim=1");
  ASSERT_TRUE(o.result.eos) << o.result.error_text;
  ASSERT_EQ(o.data.size(), 8u);
  EXPECT_EQ(o.data[1], (std::vector<uint8_t>{2, 3}));
  EXPECT_EQ(o.data[5], (std::vector<uint8_t>{12, 13}));
  // Frames within a buffer are spaced by the caps rate (10/1), as upstream computes it.
  EXPECT_EQ(o.pts[0], 0u);
  EXPECT_EQ(o.pts[1], 100000000u);
  EXPECT_EQ(o.pts[4], 100000000u);
  EXPECT_EQ(out_caps_info("2:4", "frames-in=4 frames-out=1 frames-dim=1"),
            "1 tensor(s): [0] uint8 2:1");
}

TEST(TensorAggregator, ConcatReordersAlongFramesDim) {
  // Two frames of 3:4:2 (24 bytes each); frames-dim=1 interleaves the rows of the frames.
  auto o = run_agg("3:4:2", 24, 2, "frames-out=2 frames-dim=1");
  ASSERT_TRUE(o.result.eos) << o.result.error_text;
  ASSERT_EQ(o.data.size(), 1u);
  std::vector<uint8_t> want;
  for (int half = 0; half < 2; ++half)
    for (int f = 0; f < 2; ++f)
      for (int i = 0; i < 12; ++i) want.push_back(static_cast<uint8_t>(f * 10 + half * 12 + i));
  EXPECT_EQ(o.data[0], want);
  EXPECT_EQ(out_caps_info("3:4:2", "frames-out=2 frames-dim=1"), "1 tensor(s): [0] uint8 3:8:2");
  // concat=false keeps the frames one after the other.
  auto n = run_agg("3:4:2", 24, 2, "frames-out=2 frames-dim=1 concat=false");
  ASSERT_EQ(n.data.size(), 1u);
  std::vector<uint8_t> seq;
  for (int f = 0; f < 2; ++f)
    for (int i = 0; i < 24; ++i) seq.push_back(static_cast<uint8_t>(f * 10 + i));
  EXPECT_EQ(n.data[0], seq);
}

TEST(TensorAggregator, DefaultFramesDimExtendsTheRank) {
  EXPECT_EQ(out_caps_info("3:4", "frames-out=2"),
            "1 tensor(s): [0] uint8 3:4:1:1:1:1:1:1:1:1:1:1:1:1:1:2");
}

TEST(TensorAggregator, SameFramesInAndOutPassesBuffers) {
  auto o = run_agg("2", 2, 3, "");
  ASSERT_EQ(o.data.size(), 3u);
  EXPECT_EQ(o.data[2], (std::vector<uint8_t>{20, 21}));
}

TEST(TensorAggregator, FramesInNotDividingIsABusError) {
  auto o = run_agg("2:3", 6, 1, "frames-in=2 frames-dim=1");
  ASSERT_TRUE(o.result.error);
  EXPECT_NE(o.result.error_text.find("a: frames-dim=1: dimension 1 of the input 2:3 is 3, not a "
                                     "multiple of frames-in=2"),
            std::string::npos)
      << o.result.error_text;
}

TEST(TensorAggregator, FramesFlushTooLargeIsABusError) {
  auto o = run_agg("1", 1, 1, "frames-in=1 frames-out=2 frames-flush=3 frames-dim=0");
  ASSERT_TRUE(o.result.error);
  EXPECT_NE(o.result.error_text.find("a: frames-flush=3 is more than the 2 frames held"),
            std::string::npos)
      << o.result.error_text;
}

TEST(TensorAggregator, WrongBufferSizeIsABusError) {
  auto o = run_agg("4", 3, 1, "frames-out=2 frames-dim=1");
  ASSERT_TRUE(o.result.error);
  EXPECT_NE(o.result.error_text.find("a: buffer has 3 bytes, expected 4"), std::string::npos)
      << o.result.error_text;
}

// 100 cycles of a sliding window (frames-out=3, frames-flush=1): a third stop with frames held
// in the adapter and no output yet, a third after two outputs, a third after EOS. Nothing may
// be left alive after any of them.
TEST(TensorAggregator, HundredPlayingNullCyclesNoHangNoLeak) {
  Pipe q(appsrc("in", "other/tensor,dimension=(string)2,type=uint8,framerate=10/1") +
         "! tensor_aggregator frames-out=3 frames-flush=1 frames-dim=1 ! fakesink name=out");
  state_cycles(q.pipeline(), 100, [&](int i, LiveObjects &live) {
    std::size_t before = live.delivered("out");
    q.push("in", make_buffer({{1, 2}}, 0));
    q.push("in", make_buffer({{3, 4}}, 100000000));
    if (i % 3 == 0) return;  // 2 frames held, none out
    q.push("in", make_buffer({{5, 6}}, 200000000));
    q.push("in", make_buffer({{7, 8}}, 300000000));
    if (i % 3 == 2) {
      q.eos("in");
      std::string err;
      EXPECT_TRUE(wait_eos(q.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
    }
    EXPECT_TRUE(live.wait_delivered("out", before + 2)) << "cycle " << i;
  });
}

}  // namespace
}  // namespace nns::test

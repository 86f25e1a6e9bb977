// SPDX-License-Identifier: LGPL-2.1-only
// tensor_merge: linear concatenation along every dimension (golden bytes), sync modes with
// different rates, caps, bad input.
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include "elements/cycle_check.h"
#include "elements/stream_util.h"
#include "gst/tensor_caps.h"

namespace nns::test {
namespace {

// 2:2:2 uint8 tensor with bytes base + (y*4 + x*2 + c).
std::vector<uint8_t> cube(uint8_t base) {
  std::vector<uint8_t> v(8);
  for (int i = 0; i < 8; ++i) v[i] = base + i;
  return v;
}

const char *kCube =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)2:2:2,"
    "types=uint8,framerate=30/1";

struct Merged {
  std::vector<uint8_t> bytes;
  std::string dims;
};

Merged merge_two(const char *option) {
  GstElement *m = gst_element_factory_make("tensor_merge", nullptr);
  g_object_set(m, "option", option, nullptr);
  HarnessPtr h0(gst_harness_new_with_element(m, "sink_0", "src"));
  HarnessPtr h1(gst_harness_new_with_element(m, "sink_1", nullptr));
  gst_object_unref(m);
  gst_harness_set_src_caps_str(h0.get(), kCube);
  gst_harness_set_src_caps_str(h1.get(), kCube);
  EXPECT_EQ(gst_harness_push(h0.get(), make_buffer({cube(0)}, 0)), GST_FLOW_OK);
  EXPECT_EQ(gst_harness_push(h1.get(), make_buffer({cube(100)}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h0.get());
  Merged r;
  if (!out) return r;
  r.bytes = tensor_bytes(out, 0);
  gst_buffer_unref(out);
  GstCaps *caps = gst_pad_get_current_caps(h0->sinkpad);
  r.dims = nns::gst::config_from_caps(caps).info.dims_string();
  gst_caps_unref(caps);
  return r;
}

TEST(TensorMerge, PropertyDefaults) {
  GstElement *m = gst_element_factory_make("tensor_merge", nullptr);
  gchar *mode = nullptr, *option = nullptr, *sync = nullptr;
  g_object_get(m, "mode", &mode, "option", &option, "sync-mode", &sync, nullptr);
  EXPECT_STREQ(mode, "linear");
  EXPECT_EQ(option, nullptr);
  EXPECT_STREQ(sync, "nosync");
  g_free(mode);
  g_free(sync);
  gst_object_unref(m);
}

TEST(TensorMerge, LinearAlongEachDimension) {
  auto r0 = merge_two("0");
  EXPECT_EQ(r0.dims, "4:2:2");
  EXPECT_EQ(r0.bytes,
            (std::vector<uint8_t>{0, 1, 100, 101, 2, 3, 102, 103, 4, 5, 104, 105, 6, 7, 106, 107}));
  auto r1 = merge_two("1");
  EXPECT_EQ(r1.dims, "2:4:2");
  EXPECT_EQ(r1.bytes,
            (std::vector<uint8_t>{0, 1, 2, 3, 100, 101, 102, 103, 4, 5, 6, 7, 104, 105, 106, 107}));
  std::vector<uint8_t> append = cube(0);
  auto c = cube(100);
  append.insert(append.end(), c.begin(), c.end());
  auto r2 = merge_two("2");
  EXPECT_EQ(r2.dims, "2:2:4");
  EXPECT_EQ(r2.bytes, append);
  auto r3 = merge_two("3");
  EXPECT_EQ(r3.dims, "2:2:2:2");
  EXPECT_EQ(r3.bytes, append);
}

TEST(TensorMerge, UnsetOptionMergesAlongDimensionZero) {
  auto r = merge_two("");
  EXPECT_EQ(r.dims, "4:2:2");
}

TEST(TensorMerge, DifferentSizesAlongTheMergedDim) {
  GstElement *m = gst_element_factory_make("tensor_merge", nullptr);
  g_object_set(m, "option", "1", nullptr);
  HarnessPtr h0(gst_harness_new_with_element(m, "sink_0", "src"));
  HarnessPtr h1(gst_harness_new_with_element(m, "sink_1", nullptr));
  gst_object_unref(m);
  gst_harness_set_src_caps_str(h0.get(),
                               "other/tensor,dimension=(string)3:2,type=float32,"
                               "framerate=30/1");
  gst_harness_set_src_caps_str(h1.get(),
                               "other/tensor,dimension=(string)3:1,type=float32,"
                               "framerate=10/1");
  std::vector<uint8_t> a(24, 1), b(12, 2);
  ASSERT_EQ(gst_harness_push(h0.get(), make_buffer({a}, 0)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(h1.get(), make_buffer({b}, 7)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h0.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_get_size(out), 36u);
  EXPECT_EQ(GST_BUFFER_PTS(out), 7u);
  gst_buffer_unref(out);
  GstCaps *caps = gst_pad_get_current_caps(h0->sinkpad);
  auto c = nns::gst::config_from_caps(caps);
  EXPECT_EQ(c.info.to_string(), "1 tensor(s): [0] float32 3:3");
  EXPECT_EQ(c.rate_n, 10);
  gst_caps_unref(caps);
}

// Two streams at 30 and 10 fps; tensor bytes carry the frame index.
std::vector<std::pair<GstClockTime, std::vector<uint8_t>>> run_rates(const std::string &props) {
  const char *caps30 = "other/tensor,dimension=(string)1,type=uint8,framerate=30/1";
  const char *caps10 = "other/tensor,dimension=(string)1,type=uint8,framerate=10/1";
  Pipe p(appsrc("a0", caps30) + "! m.sink_0 " + appsrc("a1", caps10) +
         "! m.sink_1 tensor_merge name=m " + props + " ! appsink name=out sync=false");
  p.collect("out");
  for (int i = 0; i < 9; ++i) p.push("a0", make_buffer({{uint8_t(i)}}, i * 33333333));
  for (int i = 0; i < 3; ++i) p.push("a1", make_buffer({{uint8_t(i)}}, i * 100000000));
  p.eos("a0");
  p.eos("a1");
  auto r = p.run();
  EXPECT_TRUE(r.eos) << r.error_text;
  std::vector<std::pair<GstClockTime, std::vector<uint8_t>>> out;
  for (GstBuffer *b : p.out()) out.push_back({GST_BUFFER_PTS(b), tensor_bytes(b, 0)});
  return out;
}

using Merged2 = std::vector<std::pair<GstClockTime, std::vector<uint8_t>>>;
constexpr GstClockTime k30 = 33333333, k10 = 100000000;

// nosync: one buffer of each pad per output, PTS the latest; ends when sink_1 (3 frames) ends.
TEST(TensorMerge, NoSyncIsDefault) {
  Merged2 want = {{0, {0, 0}}, {k10, {1, 1}}, {2 * k10, {2, 2}}};
  EXPECT_EQ(run_rates(""), want);
}

// slowest: the base time is sink_1's; sink_0 gives its frame nearest to it.
TEST(TensorMerge, Slowest) {
  Merged2 want = {{0, {0, 0}}, {k10, {3, 1}}, {2 * k10, {6, 2}}};
  EXPECT_EQ(run_rates("sync-mode=slowest"), want);
}

// basepad sink_0, duration 1/30 s: sink_1's next frame is taken within 33333332 ns of the base
// time; the stream ends when sink_1 has no more buffer when a time is picked (after 200 ms).
TEST(TensorMerge, Basepad) {
  Merged2 want = {{0, {0, 0}},       {k30, {1, 0}},     {2 * k30, {2, 0}}, {3 * k30, {3, 1}},
                  {4 * k30, {4, 1}}, {5 * k30, {5, 1}}, {6 * k30, {6, 2}}};
  EXPECT_EQ(run_rates("sync-mode=basepad sync-option=0:33333333"), want);
}

const char *kOne = "other/tensor,dimension=(string)1,type=uint8,framerate=30/1";

// Two GstHarness pads on one tensor_merge (pushes are synchronous: arrival order is exact).
struct MergeHarness {
  explicit MergeHarness(const char *sync_mode) {
    GstElement *m = gst_element_factory_make("tensor_merge", nullptr);
    g_object_set(m, "sync-mode", sync_mode, nullptr);
    h0.reset(gst_harness_new_with_element(m, "sink_0", "src"));
    h1.reset(gst_harness_new_with_element(m, "sink_1", nullptr));
    gst_object_unref(m);
    gst_harness_set_src_caps_str(h0.get(), kOne);
    gst_harness_set_src_caps_str(h1.get(), kOne);
  }
  GstHarness *pad(int i) { return i ? h1.get() : h0.get(); }
  // The next output (PTS, bytes), or PTS GST_CLOCK_TIME_NONE when there is none queued.
  std::pair<GstClockTime, std::vector<uint8_t>> pull() {
    if (gst_harness_buffers_in_queue(h0.get()) == 0) return {GST_CLOCK_TIME_NONE, {}};
    GstBuffer *out = gst_harness_pull(h0.get());
    std::pair<GstClockTime, std::vector<uint8_t>> r{GST_BUFFER_PTS(out), tensor_bytes(out, 0)};
    gst_buffer_unref(out);
    return r;
  }
  std::string dims() {
    GstCaps *caps = gst_pad_get_current_caps(h0->sinkpad);
    std::string d = nns::gst::config_from_caps(caps).info.dims_string();
    gst_caps_unref(caps);
    return d;
  }
  HarnessPtr h0, h1;
};

// refresh: an output for every arrival once both pads had one, re-using the other pad's last
// buffer; after EOS on one pad the other still refreshes the output; EOS once both ended.
TEST(TensorMerge, RefreshOutputsOnEveryArrivalAndOutlivesOnePad) {
  MergeHarness m("refresh");
  struct Arrival {
    int pad;
    GstClockTime pts;
    uint8_t value;
  };
  std::vector<Arrival> arrivals = {{0, 0, 10},  {1, 0, 20},  {0, 10, 11},
                                   {0, 20, 12}, {1, 30, 21}, {0, 40, 13}};
  Merged2 got;
  for (auto a : arrivals) {
    ASSERT_EQ(gst_harness_push(m.pad(a.pad), make_buffer({{a.value}}, a.pts)), GST_FLOW_OK);
    for (auto o = m.pull(); o.first != GST_CLOCK_TIME_NONE; o = m.pull()) got.push_back(o);
  }
  Merged2 want = {{0, {10, 20}}, {10, {11, 20}}, {20, {12, 20}}, {30, {12, 21}}, {40, {13, 21}}};
  EXPECT_EQ(got, want);
  EXPECT_EQ(m.dims(), "2");
  ASSERT_TRUE(gst_harness_push_event(m.pad(1), gst_event_new_eos()));
  ASSERT_EQ(gst_harness_push(m.pad(0), make_buffer({{14}}, 50)), GST_FLOW_OK);
  EXPECT_EQ(m.pull(), (std::pair<GstClockTime, std::vector<uint8_t>>{50, {14, 21}}));
  ASSERT_TRUE(gst_harness_push_event(m.pad(0), gst_event_new_eos()));
  bool eos = false;
  while (GstEvent *ev = gst_harness_try_pull_event(m.h0.get())) {
    eos = eos || GST_EVENT_TYPE(ev) == GST_EVENT_EOS;
    gst_event_unref(ev);
  }
  EXPECT_TRUE(eos);
  EXPECT_EQ(m.pull().first, GST_CLOCK_TIME_NONE);
}

// nosync: EOS on sink_0 after 3 frames ends the stream while sink_1 still has 47 to give.
TEST(TensorMerge, EosOnOnePadEndsTheStream) {
  Pipe p(appsrc("a0", kOne) + "! m.sink_0 " + appsrc("a1", kOne) +
         "! m.sink_1 tensor_merge name=m ! appsink name=out sync=false");
  p.collect("out");
  for (int i = 0; i < 3; ++i) p.push("a0", make_buffer({{uint8_t(i)}}, i * k30));
  p.eos("a0");
  for (int i = 0; i < 50; ++i) p.push("a1", make_buffer({{uint8_t(100 + i)}}, i * k30));
  p.eos("a1");
  auto r = p.run(10);
  ASSERT_TRUE(r.eos) << (r.timed_out ? "timed out" : r.error_text);
  Merged2 got;
  for (GstBuffer *b : p.out()) got.push_back({GST_BUFFER_PTS(b), tensor_bytes(b, 0)});
  Merged2 want = {{0, {0, 100}}, {k30, {1, 101}}, {2 * k30, {2, 102}}};
  EXPECT_EQ(got, want);
}

// Releasing sink_1 while PLAYING: sink_0 alone makes the output, renegotiated to 1 element.
TEST(TensorMerge, ReleasePadWhilePlaying) {
  MergeHarness m("nosync");
  ASSERT_EQ(gst_harness_push(m.pad(1), make_buffer({{20}}, 0)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(m.pad(0), make_buffer({{10}}, 0)), GST_FLOW_OK);
  EXPECT_EQ(m.pull(), (std::pair<GstClockTime, std::vector<uint8_t>>{0, {10, 20}}));
  EXPECT_EQ(m.dims(), "2");
  // sink_1 gets a buffer that is never used, then goes away.
  ASSERT_EQ(gst_harness_push(m.pad(1), make_buffer({{21}}, k30)), GST_FLOW_OK);
  gst_harness_teardown(m.h1.release());
  EXPECT_EQ(m.pull().first, GST_CLOCK_TIME_NONE);
  ASSERT_EQ(gst_harness_push(m.pad(0), make_buffer({{11}}, k30)), GST_FLOW_OK);
  EXPECT_EQ(m.pull(), (std::pair<GstClockTime, std::vector<uint8_t>>{k30, {11}}));
  EXPECT_EQ(m.dims(), "1");
}

std::string two_pad_pipeline(const std::string &caps0, const std::string &caps1,
                             const std::string &props) {
  return appsrc("a0", caps0) + "! m.sink_0 " + appsrc("a1", caps1) +
         "! m.sink_1 tensor_merge name=m " + props + " ! fakesink";
}

RunResult run_two(const std::string &caps0, const std::string &caps1, const std::string &props,
                  std::size_t size0, std::size_t size1) {
  Pipe p(two_pad_pipeline(caps0, caps1, props));
  p.push("a0", make_buffer({std::vector<uint8_t>(size0)}, 0));
  p.push("a1", make_buffer({std::vector<uint8_t>(size1)}, 0));
  p.eos("a0");
  p.eos("a1");
  return p.run();
}

TEST(TensorMerge, DifferentTypesIsABusError) {
  auto r = run_two("other/tensor,dimension=(string)4,type=uint8,framerate=30/1",
                   "other/tensor,dimension=(string)4,type=int8,framerate=30/1", "option=0", 4, 4);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("m: option=0: sink_1 has type int8 but sink_0 has uint8"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorMerge, IncompatibleDimsIsABusError) {
  auto r =
      run_two("other/tensor,dimension=(string)3:4,type=uint8,framerate=30/1",
              "other/tensor,dimension=(string)3:5,type=uint8,framerate=30/1", "option=0", 12, 15);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("sink_1 has dimensions 3:5 but sink_0 has 3:4: dimension 1 "
                              "differs (5 vs 4)"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorMerge, BadModeAndOption) {
  auto r = run_pipeline(appsrc("a0", kCube) +
                        "! m.sink_0 tensor_merge name=m mode=tiled ! "
                        "fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("m: mode='tiled' is not supported (the only mode is linear)"),
            std::string::npos)
      << r.error_text;
  r = run_pipeline(appsrc("a0", kCube) + "! m.sink_0 tensor_merge name=m option=16 ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("m: option='16' must be a dimension index 0..15"), std::string::npos)
      << r.error_text;
}

TEST(TensorMerge, WrongBufferSizeIsABusError) {
  auto r = run_two(kCube, kCube, "", 8, 6);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("m: sink_1: buffer has 6 bytes, expected 8 for uint8 2:2:2"),
            std::string::npos)
      << r.error_text;
}

// 100 PLAYING<->NULL cycles per sync mode: a third stop after two outputs, a third while the
// merge waits for sink_1, a third after EOS on sink_1 ended the stream (refresh: both pads
// end). No hang, nothing left alive after any cycle.
TEST(TensorMerge, HundredPlayingNullCyclesNoHangNoLeak) {
  for (std::string mode : {"nosync", "slowest", "basepad", "refresh"}) {
    SCOPED_TRACE(mode);
    Pipe q(appsrc("a0", kCube) + "! m.sink_0 " + appsrc("a1", kCube) +
           "! m.sink_1 tensor_merge name=m sync-mode=" + mode + " ! fakesink name=out");
    state_cycles(q.pipeline(), 100, [&](int i, LiveObjects &live) {
      std::size_t before = live.delivered("out");
      q.push("a0", make_buffer({cube(0)}, 0));
      q.push("a0", make_buffer({cube(10)}, k30));
      if (i % 3 == 0) {
        q.push("a1", make_buffer({cube(100)}, 0));
        q.push("a1", make_buffer({cube(110)}, k30));
        EXPECT_TRUE(live.wait_delivered("out", before + 2)) << "cycle " << i;
      } else if (i % 3 == 2) {
        q.eos("a1");
        if (mode == "refresh") q.eos("a0");
        std::string err;
        EXPECT_TRUE(wait_eos(q.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
      }
    });
  }
}

}  // namespace
}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_merge: linear concatenation along every dimension (golden bytes), sync modes with
// different rates, caps, bad input.
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

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

TEST(TensorMerge, NoSyncIsDefault) {
  auto o = run_rates("");
  ASSERT_EQ(o.size(), 3u);
  EXPECT_EQ(o[1].first, 100000000u);
  EXPECT_EQ(o[1].second, (std::vector<uint8_t>{1, 1}));
  EXPECT_EQ(o[2].second, (std::vector<uint8_t>{2, 2}));
}

TEST(TensorMerge, Slowest) {
  auto o = run_rates("sync-mode=slowest");
  ASSERT_EQ(o.size(), 3u);
  EXPECT_EQ(o[1].first, 100000000u);
  EXPECT_EQ(o[1].second, (std::vector<uint8_t>{3, 1}));
  EXPECT_EQ(o[2].second, (std::vector<uint8_t>{6, 2}));
}

TEST(TensorMerge, Basepad) {
  auto o = run_rates("sync-mode=basepad sync-option=0:33333333");
  ASSERT_GE(o.size(), 4u);
  EXPECT_EQ(o[1].first, 33333333u);
  EXPECT_EQ(o[1].second, (std::vector<uint8_t>{1, 0}));
  EXPECT_EQ(o[3].second, (std::vector<uint8_t>{3, 1}));
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

TEST(TensorMerge, HundredStateCycles) {
  Pipe q(two_pad_pipeline(kCube, kCube, ""));
  for (int i = 0; i < 100; ++i) {
    ASSERT_NE(gst_element_set_state(q.pipeline(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
    q.push("a0", make_buffer({cube(0)}, 0));
    if (i % 2 == 0) {
      q.push("a1", make_buffer({cube(0)}, 0));
      ASSERT_EQ(gst_element_get_state(q.pipeline(), nullptr, nullptr, 5 * GST_SECOND),
                GST_STATE_CHANGE_SUCCESS)
          << "cycle " << i;
    }
    ASSERT_EQ(gst_element_set_state(q.pipeline(), GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS);
  }
}

}  // namespace
}  // namespace nns::test

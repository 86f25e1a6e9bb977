// SPDX-License-Identifier: LGPL-2.1-only
// tensor_if driven from appsrc, as NNStreamer's tests/nnstreamer_if tensorIfAppsrc.action0/1
// check it: A_VALUE with PASSTHROUGH/SKIP on the legacy other/tensor caps, and
// TENSOR_AVERAGE_VALUE with TENSORPICK to two source pads; `supplied-value` changed between
// buffers while PLAYING.
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "gst/gst_ptr.h"
#include "support/harness.h"

namespace {

// Two int32 frames of 3:4:2:2 (48 values each), as upstream's test data.
std::vector<int32_t> frame(int f) {
  std::vector<int32_t> v;
  for (int half = 0; half < 2; ++half)
    for (int i = 1; i <= 24; ++i) v.push_back((f + 1) * 1000 + (half + 1) * 100 + i);
  return v;
}

struct Sink {
  std::atomic<int> received{0};
  std::atomic<int> bad{0};
  std::atomic<int> expect{0};  // which frame the next buffer must hold; 100 = none allowed
};

void on_data(GstElement *, GstBuffer *buf, gpointer user) {
  auto *s = static_cast<Sink *>(user);
  ++s->received;
  const int idx = s->expect;
  if (idx == 100 || gst_buffer_n_memory(buf) < 1) {
    ++s->bad;
    return;
  }
  std::vector<int32_t> got(48);
  GstMemory *m = gst_buffer_peek_memory(buf, 0);
  GstMapInfo map;
  if (!gst_memory_map(m, &map, GST_MAP_READ) || map.size != 192) {
    ++s->bad;
    return;
  }
  std::memcpy(got.data(), map.data, 192);
  gst_memory_unmap(m, &map);
  if (got != frame(idx)) ++s->bad;
}

GstBuffer *buffer_of(std::initializer_list<int> frames) {
  GstBuffer *b = gst_buffer_new();
  for (int f : frames) {
    auto v = frame(f);
    GstMemory *m = gst_allocator_alloc(nullptr, 192, nullptr);
    GstMapInfo map;
    gst_memory_map(m, &map, GST_MAP_WRITE);
    std::memcpy(map.data, v.data(), 192);
    gst_memory_unmap(m, &map);
    gst_buffer_append_memory(b, m);
  }
  return b;
}

bool wait_for(const std::atomic<int> &n, int value) {
  for (int i = 0; i < 500 && n < value; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  return n >= value;
}

class TensorIfAppsrc : public ::testing::Test {
 protected:
  void start(const std::string &desc) {
    GError *err = nullptr;
    pipeline = gst_parse_launch(desc.c_str(), &err);
    ASSERT_TRUE(pipeline) << (err ? err->message : "");
    src = gst_bin_get_by_name(GST_BIN(pipeline), "appsrc");
    tif = gst_bin_get_by_name(GST_BIN(pipeline), "tif");
    ASSERT_NE(gst_element_set_state(pipeline, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  }
  void connect(const char *name, Sink *s) {
    GstElement *e = gst_bin_get_by_name(GST_BIN(pipeline), name);
    ASSERT_TRUE(e);
    g_signal_connect(e, "new-data", G_CALLBACK(on_data), s);
    gst_object_unref(e);
  }
  nns::test::RunResult finish() {
    gst_app_src_end_of_stream(GST_APP_SRC(src));
    return nns::test::run_pipeline(pipeline);
  }
  void TearDown() override {
    if (src) gst_object_unref(src);
    if (tif) gst_object_unref(tif);
    if (pipeline) {
      gst_element_set_state(pipeline, GST_STATE_NULL);
      gst_object_unref(pipeline);
    }
  }
  GstElement *pipeline = nullptr, *src = nullptr, *tif = nullptr;
};

TEST_F(TensorIfAppsrc, PassthroughThenSkip) {
  Sink sink;
  ASSERT_NO_FATAL_FAILURE(
      start("appsrc name=appsrc ! other/tensor,dimension=(string)3:4:2:2,type=(string)int32,"
            "framerate=(fraction)0/1 ! tensor_if name=tif compared-value=A_VALUE "
            "compared-value-option=1:1:1:1,0 supplied-value=1217 operator=EQ then=PASSTHROUGH "
            "else=SKIP ! other/tensors,num_tensors=1,dimensions=(string)3:4:2:2,"
            "types=(string)int32,framerate=(fraction)0/1 ! tensor_sink name=sinkx async=false"));
  connect("sinkx", &sink);
  sink.expect = 0;
  ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), buffer_of({0})), GST_FLOW_OK);
  ASSERT_TRUE(wait_for(sink.received, 1));
  // The value at 1:1:1:1 is 1217: with 2000 the condition fails and the frame is skipped.
  g_object_set(tif, "supplied-value", "2000", nullptr);
  sink.expect = 100;
  ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), buffer_of({0})), GST_FLOW_OK);
  GstElement *s = gst_bin_get_by_name(GST_BIN(pipeline), "sinkx");
  GstPad *pad = gst_element_get_static_pad(s, "sink");
  nns::gst::CapsPtr caps(gst_pad_get_current_caps(pad));
  ASSERT_TRUE(caps);
  EXPECT_STREQ(gst_structure_get_name(gst_caps_get_structure(caps.get(), 0)), "other/tensors");
  gst_object_unref(pad);
  gst_object_unref(s);
  auto r = finish();
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(sink.received, 1);
  EXPECT_EQ(sink.bad, 0);
}

TEST_F(TensorIfAppsrc, TensorPickToTwoPads) {
  Sink yes, no;
  ASSERT_NO_FATAL_FAILURE(
      start("appsrc name=appsrc ! other/tensors,num_tensors=2,dimensions=(string)3:4:2:2.3:4:2:2,"
            "types=(string)int32.int32,framerate=(fraction)0/1 ! tensor_if name=tif "
            "compared-value=TENSOR_AVERAGE_VALUE compared-value-option=0 supplied-value=1162.5 "
            "operator=EQ then=TENSORPICK then-option=0 else=TENSORPICK else-option=1 "
            "tif.src_0 ! queue ! tensor_sink name=sink_true async=false "
            "tif.src_1 ! queue ! tensor_sink name=sink_false async=false"));
  connect("sink_true", &yes);
  connect("sink_false", &no);
  yes.expect = 0;
  no.expect = 100;
  // The average of tensor 0 is 1162.5: tensor 0 leaves on src_0.
  ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), buffer_of({0, 1})), GST_FLOW_OK);
  ASSERT_TRUE(wait_for(yes.received, 1));
  g_object_set(tif, "supplied-value", "2000", nullptr);
  yes.expect = 100;
  no.expect = 1;
  ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), buffer_of({0, 1})), GST_FLOW_OK);
  auto r = finish();
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(yes.received, 1);
  EXPECT_EQ(no.received, 1);
  EXPECT_EQ(yes.bad + no.bad, 0);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// More than 16 tensors in one buffer (NNStreamer's "extra tensors", NNS_TENSOR_SIZE_EXTRA_LIMIT)
// through tensor_sink, tensor_mux and tensor_demux, as NNStreamer's tests/nnstreamer_sink
// extraTensors.* check: a buffer built by hand from appsrc, a 20-pad mux, 16 x 16 = 256 tensors
// and a demux of 20 tensors.
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "gst/tensor_buffer.h"
#include "support/harness.h"

namespace {

struct Received {
  std::atomic<int> buffers{0};
  std::atomic<int> bad{0};
  std::atomic<std::size_t> tensors{0};
  int expected_value = 16;  // uint8 per tensor; -1: int32 tensor i holds i
};

void check_tensors(GstElement *, GstBuffer *buffer, gpointer user_data) {
  auto *r = static_cast<Received *>(user_data);
  ++r->buffers;
  const std::size_t n = nns::gst::buffer_tensor_count(buffer);
  r->tensors = n;
  if (gst_buffer_n_memory(buffer) > 16) ++r->bad;
  for (std::size_t i = 0; i < n; ++i) {
    GstMemory *m = nns::gst::buffer_get_tensor(buffer, i);
    if (!m) {
      ++r->bad;
      continue;
    }
    GstMapInfo map;
    if (gst_memory_map(m, &map, GST_MAP_READ)) {
      bool ok;
      if (r->expected_value < 0)
        ok = map.size == 4 && *reinterpret_cast<const int32_t *>(map.data) == int32_t(i);
      else
        ok = map.size == 1 && map.data[0] == r->expected_value;
      if (!ok) ++r->bad;
      gst_memory_unmap(m, &map);
    } else {
      ++r->bad;
    }
    gst_memory_unref(m);
  }
}

std::string tee_into(const std::string &tee, const std::string &mux, int n) {
  std::string s;
  for (int i = 0; i < n; ++i) s += tee + ". ! queue ! " + mux + ".sink_" + std::to_string(i) + " ";
  return s;
}

const char *kOnePixel =
    "videotestsrc pattern=black num-buffers=%d ! "
    "video/x-raw,format=GRAY8,width=1,height=1,framerate=30/1 ! "
    "tensor_converter ! other/tensors,format=static,num_tensors=1,types=(string)uint8,"
    "dimensions=(string)1:1 ! tee name=t ";

std::string one_pixel(int buffers) {
  char buf[512];
  std::snprintf(buf, sizeof buf, kOnePixel, buffers);
  return buf;
}

GstElement *parse(const std::string &desc) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  EXPECT_EQ(err, nullptr) << (err ? err->message : "");
  if (err) g_error_free(err);
  return p;
}

void connect(GstElement *pipeline, const char *sink, Received *r) {
  GstElement *s = gst_bin_get_by_name(GST_BIN(pipeline), sink);
  ASSERT_TRUE(s);
  g_signal_connect(s, "new-data", G_CALLBACK(check_tensors), r);
  gst_object_unref(s);
}

TEST(ExtraTensors, ManualBufferFromAppsrc) {
  // 20 int32 tensors; as upstream's test, the caps give only the first two dimensions/types.
  GstElement *p = parse(
      "appsrc name=src caps=other/tensors,num_tensors=20,format=static,"
      "dimensions=(string)1:1.1:1,types=(string)int32.int32,framerate=(fraction)0/1 ! "
      "tensor_sink name=sinkx async=false");
  ASSERT_TRUE(p);
  Received r;
  r.expected_value = -1;
  connect(p, "sinkx", &r);
  GstBuffer *buf = gst_buffer_new();
  nns::TensorInfo info{"", nns::TensorType::kInt32, nns::Dims{}};
  info.dims[0] = info.dims[1] = info.dims[2] = info.dims[3] = 1;
  for (int32_t i = 0; i < 20; ++i) {
    GstMemory *m = gst_allocator_alloc(nullptr, 4, nullptr);
    GstMapInfo map;
    ASSERT_TRUE(gst_memory_map(m, &map, GST_MAP_WRITE));
    std::memcpy(map.data, &i, 4);
    gst_memory_unmap(m, &map);
    nns::gst::buffer_append_tensor(buf, m, info);
  }
  EXPECT_EQ(gst_buffer_n_memory(buf), 16u);  // 15 + the packed extra memory, as upstream
  EXPECT_EQ(nns::gst::buffer_tensor_count(buf), 20u);
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src");
  ASSERT_NE(gst_element_set_state(p, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  EXPECT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), gst_buffer_copy(buf)), GST_FLOW_OK);
  EXPECT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), buf), GST_FLOW_OK);
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  gst_object_unref(src);
  auto res = nns::test::run_pipeline(p);
  EXPECT_TRUE(res.eos) << res.error_text;
  EXPECT_EQ(r.buffers, 2);
  EXPECT_EQ(r.tensors, 20u);
  EXPECT_EQ(r.bad, 0);
  gst_object_unref(p);
}

TEST(ExtraTensors, MuxOf20Pads) {
  GstElement *p = parse(one_pixel(5) + tee_into("t", "mux", 20) +
                        "tensor_mux name=mux ! tensor_sink name=sinkx async=false");
  ASSERT_TRUE(p);
  Received r;
  connect(p, "sinkx", &r);
  auto res = nns::test::run_pipeline(p);
  EXPECT_TRUE(res.eos) << res.error_text;
  EXPECT_EQ(r.buffers, 5);
  EXPECT_EQ(r.tensors, 20u);
  EXPECT_EQ(r.bad, 0);
  gst_object_unref(p);
}

TEST(ExtraTensors, MuxOf256Tensors) {
  GstElement *p = parse(one_pixel(1) + tee_into("t", "mux", 16) +
                        "tensor_mux name=mux ! tee name=t16 " + tee_into("t16", "mux256", 16) +
                        "tensor_mux name=mux256 ! tensor_sink name=sinkx async=false");
  ASSERT_TRUE(p);
  Received r;
  connect(p, "sinkx", &r);
  auto res = nns::test::run_pipeline(p);
  EXPECT_TRUE(res.eos) << res.error_text;
  EXPECT_EQ(r.buffers, 1);
  EXPECT_EQ(r.tensors, 256u);
  EXPECT_EQ(r.bad, 0);
  gst_object_unref(p);
}

TEST(ExtraTensors, DemuxOf20Tensors) {
  GstElement *p = parse(one_pixel(5) + tee_into("t", "mux", 20) +
                        "tensor_mux name=mux ! tensor_demux name=demux "
                        "demux.src_0 ! queue ! tensor_sink name=sink0 async=false "
                        "demux.src_15 ! queue ! tensor_sink name=sink15 async=false "
                        "demux.src_19 ! queue ! tensor_sink name=sink19 async=false");
  ASSERT_TRUE(p);
  Received r0, r15, r19;
  connect(p, "sink0", &r0);
  connect(p, "sink15", &r15);
  connect(p, "sink19", &r19);
  auto res = nns::test::run_pipeline(p);
  EXPECT_TRUE(res.eos) << res.error_text;
  for (Received *r : {&r0, &r15, &r19}) {
    EXPECT_EQ(r->buffers, 5);
    EXPECT_EQ(r->tensors, 1u);
    EXPECT_EQ(r->bad, 0);
  }
  gst_object_unref(p);
}

}  // namespace

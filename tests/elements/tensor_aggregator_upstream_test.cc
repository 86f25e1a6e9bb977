// SPDX-License-Identifier: LGPL-2.1-only
// tensor_aggregator with several clients, as NNStreamer's tests/nnstreamer_plugins
// testTensorAggregator.multiClients checks it: buffers carrying different GstMetaQuery client
// ids are aggregated apart, and each output carries its client's id.
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "gst/edge_glue.h"
#include "support/harness.h"

namespace {

using nns::test::HarnessPtr;

GstBuffer *client_buffer(int32_t value, int64_t client) {
  const int32_t data[4] = {value, value, value, value};
  GstBuffer *b = gst_buffer_new_allocate(nullptr, sizeof data, nullptr);
  gst_buffer_fill(b, 0, data, sizeof data);
  if (client >= 0) nns::gst::buffer_add_meta_query(b, client);
  return b;
}

// Checks `out` holds 5 int32 values `value` and the client id `client`.
void expect_output(GstBuffer *out, int32_t value, int64_t client) {
  ASSERT_TRUE(out);
  const GstMetaQuery *meta = nns::gst::buffer_get_meta_query(out);
  ASSERT_TRUE(meta);
  EXPECT_EQ(meta->client_id, client);
  std::vector<int32_t> v(gst_buffer_get_size(out) / sizeof(int32_t));
  ASSERT_EQ(v.size(), 5u);
  gst_buffer_extract(out, 0, v.data(), v.size() * sizeof(int32_t));
  for (int32_t x : v) EXPECT_EQ(x, value);
}

TEST(TensorAggregatorUpstream, MultiClients) {
  HarnessPtr h(gst_harness_new("tensor_aggregator"));
  // 4 frames in, 5 frames out, along dimension 0.
  g_object_set(h->element, "frames-in", 4, "frames-out", 5, "frames-dim", 0, nullptr);
  gst_harness_set_src_caps_str(h.get(),
                               "other/tensors,format=static,num_tensors=1,types=(string)int32,"
                               "dimensions=(string)4,framerate=(fraction)0/1");
  const int64_t c1 = 0xBADC0FEE, c2 = 0xBADF00D;
  // 1 > 2 > 1: 12 frames, but client 1 alone has the 5 an output needs.
  EXPECT_EQ(gst_harness_push(h.get(), client_buffer(1, c1)), GST_FLOW_OK);
  EXPECT_EQ(gst_harness_push(h.get(), client_buffer(2, c2)), GST_FLOW_OK);
  EXPECT_EQ(gst_harness_push(h.get(), client_buffer(1, c1)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_buffers_in_queue(h.get()), 1u);
  GstBuffer *out = gst_harness_pull(h.get());
  expect_output(out, 1, c1);
  gst_buffer_unref(out);
  // Client 2 again: its own output.
  EXPECT_EQ(gst_harness_push(h.get(), client_buffer(2, c2)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_buffers_in_queue(h.get()), 1u);
  out = gst_harness_pull(h.get());
  expect_output(out, 2, c2);
  gst_buffer_unref(out);
  EXPECT_EQ(gst_harness_buffers_received(h.get()), 2u);
}

TEST(TensorAggregatorUpstream, BuffersWithoutClientShareOneAdapter) {
  HarnessPtr h(gst_harness_new("tensor_aggregator"));
  g_object_set(h->element, "frames-in", 4, "frames-out", 5, "frames-dim", 0, nullptr);
  gst_harness_set_src_caps_str(h.get(),
                               "other/tensors,format=static,num_tensors=1,types=(string)int32,"
                               "dimensions=(string)4,framerate=(fraction)0/1");
  EXPECT_EQ(gst_harness_push(h.get(), client_buffer(3, -1)), GST_FLOW_OK);
  EXPECT_EQ(gst_harness_push(h.get(), client_buffer(3, -1)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_buffers_in_queue(h.get()), 1u);
  GstBuffer *out = gst_harness_pull(h.get());
  EXPECT_EQ(gst_buffer_get_size(out), 5 * sizeof(int32_t));
  EXPECT_FALSE(nns::gst::buffer_get_meta_query(out));
  gst_buffer_unref(out);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// Static stays static (as NNStreamer): where every input is static, tensor_mux, tensor_converter
// fed a flexible stream, and a static -> flexible -> static round trip produce static caps and
// buffers without the 128-byte flexible header, even when downstream (tensor_sink, fakesink)
// would also take flexible tensors.
#include <gst/app/gstappsink.h>
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "core/meta_header.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

namespace {

struct Got {
  std::string caps;
  std::vector<std::vector<gsize>> sizes;  // per buffer, per memory
  bool eos = false;
  std::string error;
};

// Runs `desc` (ending in "appsink name=out") to EOS and records the sink's caps and sizes.
Got run(const std::string &desc) {
  Got g;
  GError *err = nullptr;
  nns::gst::ElementPtr pipe(gst_parse_launch(desc.c_str(), &err));
  if (err) {
    g.error = err->message;
    g_error_free(err);
    return g;
  }
  GstElement *sink = gst_bin_get_by_name(GST_BIN(pipe.get()), "out");
  g_object_set(sink, "sync", FALSE, "emit-signals", FALSE, nullptr);
  gst_element_set_state(pipe.get(), GST_STATE_PLAYING);
  while (GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 5 * GST_SECOND)) {
    if (g.caps.empty()) g.caps = nns::gst::caps_to_string(gst_sample_get_caps(s));
    GstBuffer *b = gst_sample_get_buffer(s);
    std::vector<gsize> m;
    for (guint i = 0; i < gst_buffer_n_memory(b); ++i)
      m.push_back(gst_memory_get_sizes(gst_buffer_peek_memory(b, i), nullptr, nullptr));
    g.sizes.push_back(m);
    gst_sample_unref(s);
  }
  g.eos = gst_app_sink_is_eos(GST_APP_SINK(sink));
  GstBus *bus = gst_element_get_bus(pipe.get());
  if (GstMessage *msg = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR)) {
    GError *e = nullptr;
    gst_message_parse_error(msg, &e, nullptr);
    g.error = e->message;
    g_error_free(e);
    gst_message_unref(msg);
  }
  gst_object_unref(bus);
  gst_object_unref(sink);
  gst_element_set_state(pipe.get(), GST_STATE_NULL);
  return g;
}

// 1:10:4:1 uint8: 40 bytes per frame.
const std::string kSrc =
    "videotestsrc num-buffers=2 ! video/x-raw,format=GRAY8,width=10,height=4,framerate=30/1 ! "
    "tensor_converter";

void expect_static(const Got &g, std::size_t tensors) {
  ASSERT_TRUE(g.eos) << g.error;
  EXPECT_NE(g.caps.find("format=(string)static"), std::string::npos) << g.caps;
  ASSERT_EQ(g.sizes.size(), 2u);
  for (const auto &b : g.sizes) {
    ASSERT_EQ(b.size(), tensors);
    for (gsize s : b) EXPECT_EQ(s, 40u);  // no 128-byte header
  }
}

}  // namespace

TEST(StaticStaysStatic, MuxOfStaticInputs) {
  expect_static(run("tensor_mux name=mux ! appsink name=out " + kSrc + " ! mux.sink_0 " + kSrc +
                    " ! mux.sink_1"),
                2);
}

TEST(StaticStaysStatic, ConverterFromFlexible) {
  expect_static(
      run(kSrc + " ! other/tensors,format=flexible ! tensor_converter ! appsink name=out"), 1);
}

// static -> flexible -> static, then muxed with a static stream: still static.
TEST(StaticStaysStatic, RoundTripThroughFlexibleIntoMux) {
  expect_static(run("tensor_mux name=mux ! appsink name=out " + kSrc +
                    " ! other/tensors,format=flexible ! tensor_converter ! mux.sink_0 " + kSrc +
                    " ! mux.sink_1"),
                2);
}

// Downstream that takes only flexible tensors still gets them, untouched (header kept).
TEST(StaticStaysStatic, FlexibleOnlyDownstreamKeepsFlexible) {
  Got g =
      run(kSrc +
          " ! other/tensors,format=flexible ! tensor_converter ! other/tensors,format=flexible ! "
          "appsink name=out");
  ASSERT_TRUE(g.eos) << g.error;
  EXPECT_NE(g.caps.find("format=(string)flexible"), std::string::npos) << g.caps;
  ASSERT_EQ(g.sizes.size(), 2u);
  EXPECT_EQ(g.sizes[0], std::vector<gsize>{40 + nns::kMetaHeaderSize});
}

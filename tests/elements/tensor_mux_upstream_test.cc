// SPDX-License-Identifier: LGPL-2.1-only
// tensor_mux sync-mode=refresh as NNStreamer's tests/nnstreamer_sink muxRefreshMode checks it:
// appsrc (5 timestamped frames of 10 bytes, other/tensor 0/1) and a 160x120 RGB video into a
// refresh mux: more outputs than appsrc frames, two memories of 10 and 57600 bytes each, valid
// timestamps, output caps with the two tensors and framerate 0/1.
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

namespace {

struct Seen {
  std::atomic<int> buffers{0};
  std::atomic<int> bad_layout{0};
  std::atomic<int> bad_time{0};
};

void on_data(GstElement *, GstBuffer *b, gpointer user) {
  auto *s = static_cast<Seen *>(user);
  ++s->buffers;
  if (nns::gst::buffer_tensor_count(b) != 2 || gst_buffer_get_size(b) != 3u * 160 * 120 + 10)
    ++s->bad_layout;
  if (!GST_BUFFER_PTS_IS_VALID(b)) ++s->bad_time;
}

TEST(TensorMuxUpstream, RefreshModeOutputsOnEveryArrival) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(
      "tensor_mux name=mux sync-mode=refresh ! tensor_sink name=test_sink "
      "appsrc name=appsrc format=time ! other/tensor,type=(string)uint8,"
      "dimension=(string)10:1:1:1,framerate=(fraction)0/1 ! mux.sink_0 "
      "videotestsrc is-live=true num-buffers=10 ! video/x-raw,width=160,height=120,format=RGB,"
      "framerate=(fraction)30/1 ! tensor_converter ! mux.sink_1",
      &err);
  // A live video (as upstream's endless one paced by its sink): its frames come after appsrc's
  // first buffer, so each of them refreshes the output.
  ASSERT_TRUE(p) << (err ? err->message : "");
  Seen seen;
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "test_sink");
  g_signal_connect(sink, "new-data", G_CALLBACK(on_data), &seen);
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "appsrc");
  for (int i = 0; i < 5; ++i) {
    GstBuffer *b = gst_buffer_new_allocate(nullptr, 10, nullptr);
    char text[10] = {0};
    text[0] = static_cast<char>('0' + i);  // the frame number as text, as upstream's test fills it
    gst_buffer_fill(b, 0, text, 10);
    GST_BUFFER_PTS(b) = i * 100 * GST_MSECOND;
    GST_BUFFER_DURATION(b) = 100 * GST_MSECOND;
    ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), b), GST_FLOW_OK);
  }
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  gst_object_unref(src);
  auto r = nns::test::run_pipeline(p);
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_GT(seen.buffers, 5);
  EXPECT_EQ(seen.bad_layout, 0);
  EXPECT_EQ(seen.bad_time, 0);
  gst_object_unref(sink);
  gst_object_unref(p);
}

TEST(TensorMuxUpstream, RefreshModeOutputCaps) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(
      "tensor_mux name=mux sync-mode=refresh ! fakesink name=out "
      "appsrc name=appsrc format=time ! other/tensor,type=(string)uint8,"
      "dimension=(string)10:1:1:1,framerate=(fraction)0/1 ! mux.sink_0 "
      "videotestsrc num-buffers=3 ! video/x-raw,width=160,height=120,format=RGB,"
      "framerate=(fraction)30/1 ! tensor_converter ! mux.sink_1",
      &err);
  ASSERT_TRUE(p) << (err ? err->message : "");
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "appsrc");
  GstBuffer *b = gst_buffer_new_allocate(nullptr, 10, nullptr);
  gst_buffer_memset(b, 0, 1, 10);
  GST_BUFFER_PTS(b) = 0;
  ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), b), GST_FLOW_OK);
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  gst_object_unref(src);
  // Keep the caps seen by the sink.
  GstElement *out = gst_bin_get_by_name(GST_BIN(p), "out");
  GstPad *pad = gst_element_get_static_pad(out, "sink");
  static nns::gst::CapsPtr seen;
  seen.reset();
  gst_pad_add_probe(
      pad, GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM,
      +[](GstPad *, GstPadProbeInfo *info, gpointer) -> GstPadProbeReturn {
        GstEvent *ev = GST_PAD_PROBE_INFO_EVENT(info);
        if (GST_EVENT_TYPE(ev) == GST_EVENT_CAPS) {
          GstCaps *c = nullptr;
          gst_event_parse_caps(ev, &c);
          seen.reset(gst_caps_ref(c));
        }
        return GST_PAD_PROBE_OK;
      },
      nullptr, nullptr);
  gst_object_unref(pad);
  gst_object_unref(out);
  auto r = nns::test::run_pipeline(p);
  EXPECT_TRUE(r.eos) << r.error_text;
  ASSERT_TRUE(seen);
  nns::TensorsConfig cfg = nns::gst::config_from_caps(seen.get());
  ASSERT_EQ(cfg.info.size(), 2u);
  EXPECT_EQ(cfg.info[0].type, nns::TensorType::kUInt8);
  EXPECT_EQ(cfg.info[0].dims[0], 10u);
  EXPECT_EQ(cfg.info[1].dims[0], 3u);
  EXPECT_EQ(cfg.info[1].dims[1], 160u);
  EXPECT_EQ(cfg.info[1].dims[2], 120u);
  EXPECT_EQ(cfg.rate_n, 0);
  EXPECT_EQ(cfg.rate_d, 1);
  seen.reset();
  gst_object_unref(p);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_split: byte-range segments, tensorpick, caps per pad, zero-copy (shared regions),
// bad options.
#include <gtest/gtest.h>

#include <numeric>

#include "elements/cycle_check.h"
#include "elements/stream_util.h"
#include "gst/tensor_caps.h"

namespace nns::test {
namespace {

const char *kRgb = "other/tensor,dimension=(string)3:4:4,type=uint8,framerate=30/1";

GstBuffer *ramp(GstClockTime pts) {
  std::vector<uint8_t> v(48);
  std::iota(v.begin(), v.end(), 0);
  return make_buffer({v}, pts);
}

std::vector<uint8_t> range(uint8_t from, uint8_t count) {
  std::vector<uint8_t> v(count);
  std::iota(v.begin(), v.end(), from);
  return v;
}

std::string pad_dims(GstElement *e, const char *pad) {
  GstPad *p = gst_element_get_static_pad(e, pad);
  if (!p) return "(no pad)";
  GstCaps *caps = gst_pad_get_current_caps(p);
  std::string s = caps ? nns::gst::config_from_caps(caps).info.to_string() : "(no caps)";
  if (caps) gst_caps_unref(caps);
  gst_object_unref(p);
  return s;
}

TEST(TensorSplit, SegmentsAreConsecutiveByteRanges) {
  Pipe p(appsrc("in", kRgb) +
         "! tensor_split name=s tensorseg=1:4:4,2:4:4 "
         "s.src_0 ! queue ! appsink name=o0 sync=false "
         "s.src_1 ! queue ! appsink name=o1 sync=false");
  p.collect("o0");
  p.collect("o1");
  GstBuffer *in = ramp(5);
  GstMapInfo map;
  gst_buffer_map(in, &map, GST_MAP_READ);
  const guint8 *base = map.data;
  gst_buffer_unmap(in, &map);
  gst_buffer_ref(in);
  p.push("in", in);
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out("o0").size(), 1u);
  ASSERT_EQ(p.out("o1").size(), 1u);
  EXPECT_EQ(tensor_bytes(p.out("o0")[0], 0), range(0, 16));
  EXPECT_EQ(tensor_bytes(p.out("o1")[0], 0), range(16, 32));
  EXPECT_EQ(GST_BUFFER_PTS(p.out("o1")[0]), 5u);
  // Zero-copy: the segments are regions of the input memory.
  GstMemory *m = gst_buffer_peek_memory(p.out("o1")[0], 0);
  gst_memory_map(m, &map, GST_MAP_READ);
  EXPECT_EQ(map.data, base + 16);
  gst_memory_unmap(m, &map);
  EXPECT_EQ(m->parent, gst_buffer_peek_memory(in, 0));
  gst_buffer_unref(in);
}

TEST(TensorSplit, TensorpickKeepsAscendingOrderAndOwnDims) {
  Pipe p(appsrc("in", kRgb) +
         "! tensor_split name=s tensorseg=1:4:4,1:4:4,1:4:4 tensorpick=2,0 "
         "s.src_0 ! queue ! appsink name=o0 sync=false "
         "s.src_1 ! queue ! appsink name=o1 sync=false");
  p.collect("o0");
  p.collect("o1");
  ASSERT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_PAUSED), GST_STATE_CHANGE_ASYNC);
  p.push("in", ramp(0));
  ASSERT_EQ(gst_element_get_state(p.pipeline(), nullptr, nullptr, 5 * GST_SECOND),
            GST_STATE_CHANGE_SUCCESS);
  EXPECT_EQ(pad_dims(p.get("s"), "src_1"), "1 tensor(s): [0] uint8 1:4:4");
  EXPECT_EQ(pad_dims(p.get("s"), "src_2"), "(no pad)");
  p.eos("in");
  ASSERT_TRUE(p.run().eos);
  EXPECT_EQ(tensor_bytes(p.out("o0")[0], 0), range(0, 16));
  EXPECT_EQ(tensor_bytes(p.out("o1")[0], 0), range(32, 16));
}

TEST(TensorSplit, SegmentDimsAndTypeOnCaps) {
  Pipe p(appsrc("in", "other/tensor,dimension=(string)6,type=float32,framerate=10/1") +
         "! tensor_split name=s tensorseg=2,4 s.src_0 ! queue ! appsink name=o0 sync=false "
         "s.src_1 ! queue ! appsink name=o1 sync=false");
  p.collect("o0");
  p.collect("o1");
  ASSERT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_PAUSED), GST_STATE_CHANGE_ASYNC);
  p.push("in", make_buffer({std::vector<uint8_t>(24, 1)}, 0));
  ASSERT_EQ(gst_element_get_state(p.pipeline(), nullptr, nullptr, 5 * GST_SECOND),
            GST_STATE_CHANGE_SUCCESS);
  EXPECT_EQ(pad_dims(p.get("s"), "src_0"), "1 tensor(s): [0] float32 2");
  EXPECT_EQ(pad_dims(p.get("s"), "src_1"), "1 tensor(s): [0] float32 4");
  p.eos("in");
  ASSERT_TRUE(p.run().eos);
  EXPECT_EQ(gst_buffer_get_size(p.out("o1")[0]), 16u);
}

TEST(TensorSplit, TensorsegTooLargeIsABusError) {
  Pipe p(appsrc("in", kRgb) + "! tensor_split name=s tensorseg=2:4:4,2:4:4 s.src_0 ! fakesink");
  p.push("in", ramp(0));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("s: tensorseg='2:4:4,2:4:4' needs 64 bytes of uint8 but the input "
                              "tensor uint8 3:4:4 has 48 bytes"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorSplit, TensorpickOutOfRangeIsABusError) {
  Pipe p(appsrc("in", kRgb) +
         "! tensor_split name=s tensorseg=1:4:4,2:4:4 tensorpick=0,2 s.src_0 ! fakesink");
  p.push("in", ramp(0));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("s: tensorpick='0,2' picks segment 2 but tensorseg has only 2 "
                              "segment(s)"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorSplit, MissingOrBadTensorsegIsABusError) {
  auto r = run_pipeline(appsrc("in", kRgb) + "! tensor_split name=s ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("s: tensorseg is not set"), std::string::npos) << r.error_text;
  r = run_pipeline(appsrc("in", kRgb) + "! tensor_split name=s tensorseg=1:a ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("s: tensorseg='1:a'"), std::string::npos) << r.error_text;
}

TEST(TensorSplit, WrongBufferSizeIsABusError) {
  Pipe p(appsrc("in", kRgb) + "! tensor_split name=s tensorseg=1:4:4,2:4:4 s.src_0 ! fakesink");
  p.push("in", make_buffer({std::vector<uint8_t>(40)}, 0));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("s: buffer has 40 bytes, expected 48 for uint8 3:4:4"),
            std::string::npos)
      << r.error_text;
}

// Src pads come and go with the state, so they are linked on pad-added. Odd cycles end with
// EOS, even ones stop while data flows; nothing may be left alive after any of them.
TEST(TensorSplit, HundredPlayingNullCyclesNoHangNoLeak) {
  Pipe q(appsrc("in", kRgb) +
         "! tensor_split name=s tensorseg=1:4:4,2:4:4 queue name=q0 ! "
         "fakesink name=f0 queue name=q1 ! fakesink name=f1");
  g_signal_connect(q.get("s"), "pad-added",
                   G_CALLBACK(+[](GstElement *, GstPad *pad, gpointer bin) {
                     std::string qn = "q" + std::string(GST_PAD_NAME(pad)).substr(4);
                     GstElement *qe = gst_bin_get_by_name(GST_BIN(bin), qn.c_str());
                     GstPad *sink = gst_element_get_static_pad(qe, "sink");
                     gst_pad_link(pad, sink);
                     gst_object_unref(sink);
                     gst_object_unref(qe);
                   }),
                   q.pipeline());
  state_cycles(q.pipeline(), 100, [&](int i, LiveObjects &live) {
    std::size_t before = live.delivered("f1");
    q.push("in", ramp(0));
    q.push("in", ramp(1));
    if (i % 2) {
      q.eos("in");
      std::string err;
      EXPECT_TRUE(wait_eos(q.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
    }
    for (const char *f : {"f0", "f1"})
      EXPECT_TRUE(live.wait_delivered(f, before + 2)) << f << " cycle " << i;
  });
}

}  // namespace
}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// join: first-come forwarding from N request pads, EOS once all linked pads ended, different
// caps on the sink pads refused (as upstream), read-only properties, pad release.
#include <gtest/gtest.h>

#include "elements/cycle_check.h"
#include "elements/flow_harness.h"

namespace {

using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::Frame;
using nns::test::static_caps;

TEST(Join, ForwardsEveryBufferFromEveryPadAndEndsAfterAll) {
  AppPipeline p(
      "appsrc name=a ! join.sink_0 appsrc name=b ! join.sink_1 "
      "join name=join ! appsink name=out");
  p.set_caps("a", static_caps("2", "uint8"));
  p.set_caps("b", static_caps("2", "uint8"));
  for (int i = 0; i < 4; ++i)
    p.push("a", Frame({Bytes{0, static_cast<uint8_t>(i)}}, i * GST_MSECOND));
  for (int i = 0; i < 3; ++i)
    p.push("b", Frame({Bytes{1, static_cast<uint8_t>(i)}}, i * GST_MSECOND));
  p.eos("a");
  p.eos("b");
  auto r = p.run(10);
  ASSERT_TRUE(r.eos) << r.error_text;
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 7u);
  int from_a = 0, from_b = 0, next_a = 0, next_b = 0;
  for (const auto &f : out) {
    if (f.mems[0][0] == 0) {
      EXPECT_EQ(f.mems[0][1], next_a++);  // per-pad order kept
      ++from_a;
    } else {
      EXPECT_EQ(f.mems[0][1], next_b++);
      ++from_b;
    }
  }
  EXPECT_EQ(from_a, 4);
  EXPECT_EQ(from_b, 3);
  GstElement *join = p.get("join");
  guint n = 0;
  GstPad *active = nullptr;
  g_object_get(join, "n-pads", &n, "active-pad", &active, nullptr);
  EXPECT_EQ(n, 2u);
  ASSERT_NE(active, nullptr);
  EXPECT_TRUE(g_str_has_prefix(GST_PAD_NAME(active), "sink_"));
  gst_object_unref(active);
  gst_object_unref(join);
}

// As upstream's join: sink pads must carry the same caps. The second pad's different caps are
// refused (not-negotiated for its branch) with a bus error naming both pads and both caps.
TEST(Join, SinkPadsWithDifferentCapsFailNegotiation) {
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=160,height=120 ! "
      "tensor_converter ! join.sink_0 "
      "videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=480,height=240 ! "
      "tensor_converter ! join.sink_1 join name=join ! fakesink",
      10);
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_NE(r.error_text.find("the caps of every sink pad must be the same"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("3:160:120:1"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("3:480:240:1"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("sink_0"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("sink_1"), std::string::npos) << r.error_text;
}

// textoverlay first sends video/x-raw(meta:GstVideoOverlayComposition), then (downstream taking
// no overlay meta) the same caps without the feature. As upstream, join lets the active pad
// renegotiate and does not count a caps feature as a difference (NNStreamer's early-exit
// examples use this pattern).
TEST(Join, TextoverlayTransientCapsAreNotAClash) {
  GstElementFactory *f = gst_element_factory_find("textoverlay");
  if (!f) GTEST_SKIP() << "textoverlay missing (Debian gstreamer1.0-x)";
  gst_object_unref(f);
  for (int round = 0; round < 5; ++round) {
    SCOPED_TRACE(round);
    auto r = nns::test::run_pipeline(
        "videotestsrc num-buffers=5 ! textoverlay text=hi ! join.sink_0 "
        "videotestsrc num-buffers=5 ! join.sink_1 join name=join ! fakesink",
        20);
    EXPECT_TRUE(r.eos) << (r.timed_out ? "timed out" : r.error_text);
  }
}

TEST(Join, UnlinkedAndReleasedPadsDoNotHoldEos) {
  AppPipeline p("appsrc name=a ! join.sink_0 join name=join ! appsink name=out");
  p.set_caps("a", static_caps("2", "uint8"));
  GstElement *join = p.get("join");
  GstPad *extra = gst_element_request_pad_simple(join, "sink_%u");
  ASSERT_NE(extra, nullptr);
  EXPECT_STREQ(GST_PAD_NAME(extra), "sink_1");
  guint n = 0;
  g_object_get(join, "n-pads", &n, nullptr);
  EXPECT_EQ(n, 2u);
  p.push("a", Frame({Bytes{1, 2}}, 0));
  p.eos("a");
  auto r = p.run(10);
  EXPECT_TRUE(r.eos) << r.error_text << (r.timed_out ? " timed out" : "");
  gst_element_release_request_pad(join, extra);
  g_object_get(join, "n-pads", &n, nullptr);
  EXPECT_EQ(n, 1u);
  gst_object_unref(extra);
  gst_object_unref(join);
}

// sink_1's upstream never ends; releasing sink_1 while PLAYING lets sink_0's EOS through.
TEST(Join, ReleasingAPadWhilePlayingLetsEosThrough) {
  AppPipeline p(
      "appsrc name=a ! join.sink_0 appsrc name=b ! join.sink_1 "
      "join name=join ! appsink name=out");
  p.set_caps("a", static_caps("2", "uint8"));
  p.set_caps("b", static_caps("2", "uint8"));
  p.push("b", Frame({Bytes{1, 0}}, 0));
  p.push("a", Frame({Bytes{0, 0}}, 0));
  p.push("a", Frame({Bytes{0, 1}}, GST_MSECOND));
  p.eos("a");
  ASSERT_NE(gst_element_set_state(p.pipeline(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  for (int k = 0; k < 5000 && p.frames("out").size() < 3; ++k) g_usleep(1000);
  ASSERT_EQ(p.frames("out").size(), 3u);
  GstBus *bus = gst_element_get_bus(p.pipeline());
  GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_EOS);
  EXPECT_EQ(m, nullptr) << "EOS while sink_1 is linked and not ended";
  if (m) gst_message_unref(m);
  gst_object_unref(bus);
  GstElement *join = p.get("join");
  GstPad *pad = gst_element_get_static_pad(join, "sink_1");
  ASSERT_NE(pad, nullptr);
  gst_element_release_request_pad(join, pad);
  gst_object_unref(pad);
  guint n = 0;
  g_object_get(join, "n-pads", &n, nullptr);
  EXPECT_EQ(n, 1u);
  gst_object_unref(join);
  auto r = p.run(10);
  EXPECT_TRUE(r.eos) << r.error_text << (r.timed_out ? " timed out" : "");
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 3u);
  int a = 0;
  for (const auto &f : out) {
    if (f.mems[0][0] == 0)
      EXPECT_EQ(f.mems[0], (Bytes{0, static_cast<uint8_t>(a++)}));
    else
      EXPECT_EQ(f.mems[0], (Bytes{1, 0}));
  }
  EXPECT_EQ(a, 2);
}

// 100 PLAYING<->NULL cycles: both pads feed; sink_0 ends while sink_1 feeds (no EOS yet);
// both end (EOS). No hang, nothing left alive.
TEST(Join, HundredPlayingNullCyclesNoHangNoLeak) {
  AppPipeline p(
      "appsrc name=a ! join.sink_0 appsrc name=b ! join.sink_1 "
      "join name=join ! fakesink name=out");
  p.set_caps("a", static_caps("2", "uint8"));
  p.set_caps("b", static_caps("2", "uint8"));
  nns::test::state_cycles(p.pipeline(), 100, [&](int i, nns::test::LiveObjects &live) {
    std::size_t before = live.delivered("out");
    p.push("b", Frame({Bytes{1, 0}}, 0));
    if (i % 3 == 1)
      p.eos("a");
    else
      p.push("a", Frame({Bytes{0, 0}}, 0));
    p.push("b", Frame({Bytes{1, 1}}, GST_MSECOND));
    std::size_t want = before + (i % 3 == 1 ? 2 : 3);
    if (i % 3 == 2) {
      p.eos("a");
      p.eos("b");
      std::string err;
      EXPECT_TRUE(nns::test::wait_eos(p.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
    }
    EXPECT_TRUE(live.wait_delivered("out", want)) << "cycle " << i;
  });
}

TEST(Join, VideoSourcesThroughGstLaunch) {
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=5 ! video/x-raw,format=RGB,width=8,height=8 ! join.sink_0 "
      "videotestsrc num-buffers=7 pattern=ball ! video/x-raw,format=RGB,width=8,height=8 ! "
      "join.sink_1 join name=join ! tensor_converter ! fakesink",
      10);
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(Join, PadTemplatesAsUpstream) {
  GstElement *e = gst_element_factory_make("join", nullptr);
  ASSERT_NE(e, nullptr);
  GstPadTemplate *t = gst_element_class_get_pad_template(GST_ELEMENT_GET_CLASS(e), "sink_%u");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(GST_PAD_TEMPLATE_PRESENCE(t), GST_PAD_REQUEST);
  GParamSpec *ps = g_object_class_find_property(G_OBJECT_GET_CLASS(e), "active-pad");
  ASSERT_NE(ps, nullptr);
  EXPECT_FALSE(ps->flags & G_PARAM_WRITABLE);
  gst_object_unref(e);
}

}  // namespace

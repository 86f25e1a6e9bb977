// SPDX-License-Identifier: LGPL-2.1-only
// tensor_reposink / tensor_reposrc: a pipeline cycle through the repository, a recurrence
// driven step by step through the application, EOS propagation without deadlock, caps checks
// (bus errors naming both caps), 100 PLAYING<->NULL cycles without leaks or hangs, and
// property compatibility.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <cmath>
#include <thread>

#include "elements/flow_harness.h"
#include "support/deadline.h"
#include "gst/tensor_repo.h"

namespace {

using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::finish_within;
using nns::test::Frame;

const char *kF4Caps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=(string)float32,"
    "framerate=(fraction)0/1";

std::string repo_src(int slot, const std::string &caps, const std::string &extra = "") {
  return "tensor_reposrc name=rsrc slot-index=" + std::to_string(slot) + " caps=\"" + caps + "\" " +
         extra;
}

TEST(TensorRepo, SelfLoopCirculatesTheZeroFrameAndEnds) {
  AppPipeline p(repo_src(11, kF4Caps, "num-buffers=6") +
                " ! tee name=t t. ! queue ! tensor_reposink slot-index=11 "
                "t. ! queue ! appsink name=out");
  auto r = p.run(10);
  ASSERT_TRUE(r.eos) << r.error_text << (r.timed_out ? " (timed out)" : "");
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 6u);
  for (const auto &f : out) EXPECT_EQ(f.mems, std::vector<Bytes>{Bytes(16, 0)});
  EXPECT_NE(out[0].caps.find("dimensions=(string)4"), std::string::npos) << out[0].caps;
}

// h_{t+1} = tanh(0.5 * h_t + x_t) per element, with x_t = (t+1) * {0.1, -0.2, 0.3, 0.05}.
std::vector<float> step(const std::vector<float> &h, int t) {
  const float x[4] = {0.1f, -0.2f, 0.3f, 0.05f};
  std::vector<float> n(4);
  for (int i = 0; i < 4; ++i) n[i] = std::tanh(0.5f * h[i] + (t + 1) * x[i]);
  return n;
}

TEST(TensorRepo, RecurrenceThroughTheApplicationMatchesReference) {
  // The application is the cell: it reads h_t from the source side and writes h_{t+1} into
  // the sink side of the same slot.
  GError *err = nullptr;
  std::string desc = "appsrc name=in format=time ! tensor_reposink slot-index=21 " +
                     repo_src(21, kF4Caps) + " ! appsink name=state sync=false";
  GstElement *pipe = gst_parse_launch(desc.c_str(), &err);
  ASSERT_EQ(err, nullptr) << err->message;
  GstElement *in = gst_bin_get_by_name(GST_BIN(pipe), "in");
  GstElement *st = gst_bin_get_by_name(GST_BIN(pipe), "state");
  GstCaps *caps = gst_caps_from_string(kF4Caps);
  g_object_set(in, "caps", caps, nullptr);
  gst_caps_unref(caps);
  ASSERT_NE(gst_element_set_state(pipe, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  std::vector<float> ref(4, 0.0f);
  const int steps = 20;
  finish_within(30, "the recurrence", [&] {
    for (int t = 0; t <= steps; ++t) {
      GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(st), 5 * GST_SECOND);
      ASSERT_NE(s, nullptr) << "no state at step " << t;
      auto f = nns::test::frame_of(gst_sample_get_buffer(s));
      gst_sample_unref(s);
      auto h = nns::test::values_of<float>(f.mems.at(0));
      ASSERT_EQ(h.size(), 4u);
      for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(h[i], ref[i]) << "step " << t << " elem " << i;
      if (t == steps) break;
      ref = step(ref, t);
      std::vector<float> next = step(h, t);
      Frame nf({nns::test::bytes_of(next)}, static_cast<GstClockTime>(t) * GST_MSECOND);
      EXPECT_EQ(gst_app_src_push_buffer(GST_APP_SRC(in), nns::test::make_buffer(nf)), GST_FLOW_OK);
    }
    // EOS on the writer side ends the reader side.
    gst_app_src_end_of_stream(GST_APP_SRC(in));
    GstMessage *m = gst_bus_timed_pop_filtered(
        GST_ELEMENT_BUS(pipe), 5 * GST_SECOND,
        static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    ASSERT_NE(m, nullptr) << "no EOS";
    EXPECT_EQ(GST_MESSAGE_TYPE(m), GST_MESSAGE_EOS);
    gst_message_unref(m);
  });
  finish_within(30, "setting the pipeline to NULL",
                [&] { gst_element_set_state(pipe, GST_STATE_NULL); });
  gst_object_unref(in);
  gst_object_unref(st);
  gst_object_unref(pipe);
}

TEST(TensorRepo, SinkCapsThatDisagreeWithCapsPropertyAreABusError) {
  AppPipeline p("appsrc name=in ! tensor_reposink slot-index=31 " +
                repo_src(31,
                         "other/tensors,format=static,num_tensors=1,dimensions=(string)5,"
                         "types=(string)float32,framerate=(fraction)0/1") +
                " ! fakesink");
  p.set_caps("in", kF4Caps);
  for (int i = 0; i < 3; ++i) p.push("in", Frame({Bytes(16, 1)}, i * GST_MSECOND));
  p.eos("in");
  auto r = p.run(10);
  ASSERT_TRUE(r.error) << (r.timed_out ? "timed out" : "eos");
  EXPECT_NE(r.error_text.find("rsrc: slot 31: caps property"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("(float32 5) disagrees with the caps tensor_reposink stored"),
            std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("(float32 4)"), std::string::npos) << r.error_text;
}

// Matching caps, but the buffers in the slot are not what they describe (12 bytes for float32 4):
// a bus error naming the caps property and what arrived, not buffers pushed under wrong caps.
TEST(TensorRepo, TensorsThatDisagreeWithCapsPropertyAreABusError) {
  AppPipeline p("appsrc name=in ! tensor_reposink slot-index=32 " + repo_src(32, kF4Caps) +
                " ! fakesink");
  p.set_caps("in", kF4Caps);
  for (int i = 0; i < 3; ++i) p.push("in", Frame({Bytes(12, 1)}, i * GST_MSECOND));
  p.eos("in");
  auto r = p.run(10);
  ASSERT_TRUE(r.error) << (r.timed_out ? "timed out" : "eos");
  EXPECT_NE(r.error_text.find("rsrc: slot 32: the tensors that arrived do not match the caps "
                              "property"),
            std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("(float32 4)"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("tensor 0 has 12 bytes, expected 16"), std::string::npos)
      << r.error_text;
}

TEST(TensorRepo, MissingOrBadCapsPropertyIsABusError) {
  auto r = nns::test::run_pipeline("tensor_reposrc name=rsrc ! fakesink", 10);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("rsrc: the caps property is required"), std::string::npos)
      << r.error_text;
  r = nns::test::run_pipeline(
      "tensor_reposrc name=rsrc caps=\"other/tensors,format=static\" ! fakesink", 10);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("must give format=static with the dimensions and types"),
            std::string::npos)
      << r.error_text;
}

std::atomic<int> g_alive{0};
void buffer_gone(gpointer, GstMiniObject *) {
  --g_alive;
}

GstPadProbeReturn track_buffer(GstPad *, GstPadProbeInfo *info, gpointer) {
  GstBuffer *b = GST_PAD_PROBE_INFO_BUFFER(info);
  ++g_alive;
  gst_mini_object_weak_ref(GST_MINI_OBJECT(b), buffer_gone, nullptr);
  return GST_PAD_PROBE_OK;
}

TEST(TensorRepo, HundredPlayingNullCyclesNoHangNoLeak) {
  // A free-running cycle (no num-buffers): every stop happens while both sides may be waiting.
  std::string desc = repo_src(41, kF4Caps) +
                     " ! tee name=t t. ! queue ! tensor_reposink slot-index=41 "
                     "t. ! queue ! fakesink name=out sync=false";
  GError *err = nullptr;
  GstElement *pipe = gst_parse_launch(desc.c_str(), &err);
  ASSERT_EQ(err, nullptr);
  GstElement *rsrc = gst_bin_get_by_name(GST_BIN(pipe), "rsrc");
  GstPad *pad = gst_element_get_static_pad(rsrc, "src");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, track_buffer, nullptr, nullptr);
  GstElement *out = gst_bin_get_by_name(GST_BIN(pipe), "out");
  std::atomic<int> handoffs{0};
  g_object_set(out, "signal-handoffs", TRUE, nullptr);
  g_signal_connect(out, "handoff", G_CALLBACK(+[](GstElement *, GstBuffer *, GstPad *, gpointer c) {
                     ++*static_cast<std::atomic<int> *>(c);
                   }),
                   &handoffs);
  for (int i = 0; i < 100; ++i) {
    int before = handoffs;
    finish_within(30, "PLAYING<->NULL cycle " + std::to_string(i), [&] {
      gst_element_set_state(pipe, GST_STATE_PLAYING);
      // Up to 5 s (a deadline, not a count of 1 ms sleeps that a loaded machine stretches).
      const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(5);
      while (handoffs < before + 2 && std::chrono::steady_clock::now() < end)
        std::this_thread::sleep_for(std::chrono::milliseconds(1));
      gst_element_set_state(pipe, GST_STATE_NULL);
    });
    EXPECT_GE(handoffs, before + 2) << "cycle " << i << " did not circulate";
  }
  EXPECT_FALSE(nns::gst::TensorRepo::instance().has_buffer(41));
  gst_object_unref(pad);
  gst_object_unref(rsrc);
  gst_object_unref(out);
  gst_object_unref(pipe);
  EXPECT_EQ(g_alive.load(), 0) << "buffers still alive after 100 cycles";
}

TEST(TensorRepo, StopWhileWriterWaitsDoesNotHang) {
  // The writer blocks (nobody reads slot 51); going to NULL must wake it. The buffers are queued
  // before PLAYING, so the first can reach the sink while it goes PAUSED->PLAYING (the
  // streaming thread then commits PLAYING itself and renders the second one at once): the state
  // change must not wait for the writer either.
  AppPipeline p("appsrc name=in ! tensor_reposink slot-index=51");
  p.set_caps("in", kF4Caps);
  for (int i = 0; i < 5; ++i) p.push("in", Frame({Bytes(16, 1)}, i * GST_MSECOND));
  finish_within(30, "NULL->PLAYING with a writer that fills slot 51", [&] {
    EXPECT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_PLAYING), GST_STATE_CHANGE_SUCCESS);
    for (int k = 0; k < 5000 && !nns::gst::TensorRepo::instance().has_buffer(51); ++k)
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
  });
  EXPECT_TRUE(nns::gst::TensorRepo::instance().has_buffer(51));
  finish_within(30, "PLAYING->NULL with the writer waiting",
                [&] { gst_element_set_state(p.pipeline(), GST_STATE_NULL); });
}

TEST(TensorRepo, PropertiesAsUpstream) {
  GstElement *src = gst_element_factory_make("tensor_reposrc", nullptr);
  GstElement *sink = gst_element_factory_make("tensor_reposink", nullptr);
  ASSERT_TRUE(src && sink);
  guint slot = 0;
  g_object_get(src, "slot-index", &slot, nullptr);
  EXPECT_EQ(slot, G_MAXUINT);  // upstream's "unset"
  g_object_get(sink, "slot-index", &slot, nullptr);
  EXPECT_EQ(slot, 0u);
  // As upstream's GParamSpec: range 0..G_MAXUINT-1, declared default 0; the instance reads
  // G_MAXUINT until set, which is what gst-inspect prints as the default (it shows the value
  // read from a new element).
  auto *ps = G_PARAM_SPEC_UINT(g_object_class_find_property(G_OBJECT_GET_CLASS(src), "slot-index"));
  EXPECT_EQ(ps->maximum, G_MAXUINT - 1);
  EXPECT_EQ(ps->default_value, 0u);
  auto *pk =
      G_PARAM_SPEC_UINT(g_object_class_find_property(G_OBJECT_GET_CLASS(sink), "slot-index"));
  EXPECT_EQ(pk->maximum, G_MAXUINT);
  EXPECT_EQ(pk->default_value, 0u);
  auto *rate =
      G_PARAM_SPEC_UINT(g_object_class_find_property(G_OBJECT_GET_CLASS(sink), "signal-rate"));
  EXPECT_EQ(rate->maximum, 500u);
  gboolean sync = TRUE, async = TRUE, qos = FALSE;
  g_object_get(sink, "sync", &sync, "async", &async, "qos", &qos, nullptr);
  EXPECT_FALSE(sync);
  EXPECT_FALSE(async);
  EXPECT_TRUE(qos);
  GParamSpec *caps = g_object_class_find_property(G_OBJECT_GET_CLASS(src), "caps");
  ASSERT_NE(caps, nullptr);
  EXPECT_EQ(caps->value_type, GST_TYPE_CAPS);
  gst_object_unref(src);
  gst_object_unref(sink);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_rate: down/up conversion (frames, timestamps, counters, GAP flags), passthrough,
// throttle QoS events upstream (type, diff, count), properties and bus errors.
#include <gtest/gtest.h>

#include <atomic>
#include <cstring>
#include <mutex>

#include "elements/cycle_check.h"
#include "elements/flow_harness.h"
#include "gst/tensor_caps.h"
#include "tensor_filter_custom_easy.h"

namespace {

using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::Frame;
using nns::test::static_caps;

struct Qos {
  GstQOSType type;
  double proportion;
  GstClockTimeDiff diff;
  GstClockTime ts;
};

struct RateRun {
  nns::test::RunResult r;
  std::vector<Frame> out;
  guint64 in = 0, outc = 0, dup = 0, drop = 0;
  std::vector<Qos> qos;
};

GstPadProbeReturn catch_qos(GstPad *, GstPadProbeInfo *info, gpointer user) {
  GstEvent *ev = GST_PAD_PROBE_INFO_EVENT(info);
  if (GST_EVENT_TYPE(ev) == GST_EVENT_QOS) {
    Qos q;
    gst_event_parse_qos(ev, &q.type, &q.proportion, &q.diff, &q.ts);
    static std::mutex m;
    std::lock_guard<std::mutex> l(m);
    static_cast<std::vector<Qos> *>(user)->push_back(q);
  }
  return GST_PAD_PROBE_OK;
}

// `n` frames at `fps` (frame i holds byte i) through tensor_rate `props`.
RateRun run_rate(int n, int fps, const std::string &props) {
  AppPipeline p("appsrc name=src ! tensor_rate name=rate " + props + " ! appsink name=out");
  RateRun rr;
  p.set_caps("src", static_caps("2", "uint8", std::to_string(fps) + "/1"));
  GstElement *src = p.get("src");
  GstPad *pad = gst_element_get_static_pad(src, "src");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_EVENT_UPSTREAM, catch_qos, &rr.qos, nullptr);
  for (int i = 0; i < n; ++i)
    p.push("src",
           Frame({Bytes{static_cast<uint8_t>(i), 7}}, gst_util_uint64_scale(i, GST_SECOND, fps),
                 gst_util_uint64_scale(1, GST_SECOND, fps)));
  p.eos("src");
  rr.r = p.run(10);
  rr.out = p.frames("out");
  GstElement *rate = p.get("rate");
  g_object_get(rate, "in", &rr.in, "out", &rr.outc, "duplicate", &rr.dup, "drop", &rr.drop,
               nullptr);
  gst_object_unref(rate);
  gst_object_unref(pad);
  gst_object_unref(src);
  return rr;
}

TEST(TensorRate, DownConvert30To10) {
  auto rr = run_rate(30, 30, "framerate=10/1");
  ASSERT_TRUE(rr.r.eos) << rr.r.error_text;
  ASSERT_EQ(rr.out.size(), 11u);
  for (std::size_t k = 0; k < rr.out.size(); ++k) {
    EXPECT_EQ(rr.out[k].pts, k * 100 * GST_MSECOND) << k;
    EXPECT_EQ(rr.out[k].duration, 100 * GST_MSECOND) << k;
    EXPECT_EQ(rr.out[k].mems[0][0], k < 10 ? 3 * k : 29) << k;
    EXPECT_FALSE(rr.out[k].gap);
  }
  EXPECT_NE(rr.out[0].caps.find("framerate=(fraction)10/1"), std::string::npos) << rr.out[0].caps;
  EXPECT_EQ(rr.in, 30u);
  EXPECT_EQ(rr.outc, 11u);
  EXPECT_EQ(rr.drop, 19u);
  EXPECT_EQ(rr.dup, 0u);
  // one THROTTLE QoS per dropped frame, diff = 0.999 x 100 ms
  ASSERT_EQ(rr.qos.size(), 19u);
  for (const auto &q : rr.qos) {
    EXPECT_EQ(q.type, GST_QOS_TYPE_THROTTLE);
    EXPECT_EQ(q.diff, GstClockTimeDiff(99900000));
    EXPECT_TRUE(GST_CLOCK_TIME_IS_VALID(q.ts));
  }
}

TEST(TensorRate, UpConvert10To30MarksDuplicates) {
  auto rr = run_rate(10, 10, "framerate=30/1");
  ASSERT_TRUE(rr.r.eos) << rr.r.error_text;
  ASSERT_EQ(rr.out.size(), 27u);
  EXPECT_EQ(rr.dup, 17u);
  EXPECT_EQ(rr.drop, 0u);
  EXPECT_EQ(rr.in, 10u);
  EXPECT_EQ(rr.outc, 27u);
  int gaps = 0;
  for (std::size_t k = 0; k < rr.out.size(); ++k) {
    EXPECT_EQ(rr.out[k].pts, gst_util_uint64_scale(k, GST_SECOND, 30)) << k;
    gaps += rr.out[k].gap;
  }
  EXPECT_EQ(gaps, 17);
  EXPECT_EQ(rr.out[0].mems[0][0], 0);
  EXPECT_EQ(rr.out[1].mems[0][0], 0);
  EXPECT_TRUE(rr.out[1].gap);
  EXPECT_EQ(rr.out[2].mems[0][0], 1);
  EXPECT_TRUE(rr.qos.empty());  // nothing dropped
}

TEST(TensorRate, WithoutFramerateItPassesThroughAndThrottlesOnce) {
  auto rr = run_rate(12, 15, "");
  ASSERT_TRUE(rr.r.eos) << rr.r.error_text;
  ASSERT_EQ(rr.out.size(), 12u);
  for (int i = 0; i < 12; ++i) EXPECT_EQ(rr.out[i].mems[0][0], i);
  EXPECT_EQ(rr.in, 12u);
  EXPECT_EQ(rr.outc, 12u);
  ASSERT_EQ(rr.qos.size(), 1u);
  EXPECT_EQ(rr.qos[0].diff, GstClockTimeDiff(gst_util_uint64_scale(1, GST_SECOND, 15) * 0.999));
}

TEST(TensorRate, ThrottleFalseSendsNoQos) {
  auto rr = run_rate(30, 30, "framerate=10/1 throttle=false");
  ASSERT_TRUE(rr.r.eos) << rr.r.error_text;
  EXPECT_EQ(rr.out.size(), 11u);
  EXPECT_TRUE(rr.qos.empty());
}

TEST(TensorRate, VideoPipeline) {
  AppPipeline p(
      "videotestsrc num-buffers=30 ! video/x-raw,format=GRAY8,width=4,height=4,framerate=30/1 "
      "! tensor_converter ! tensor_rate framerate=5/1 ! appsink name=out");
  auto r = p.run(10);
  ASSERT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(p.frames("out").size(), 6u);
}

TEST(TensorRate, BadFramerateAndVariableInputAreBusErrors) {
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=3 ! video/x-raw,format=GRAY8,width=4,height=4 ! "
      "tensor_converter ! tensor_rate name=rate framerate=ten ! fakesink",
      10);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("rate: framerate 'ten' was refused: it must be N/D"),
            std::string::npos)
      << r.error_text;
  AppPipeline p("appsrc name=src ! tensor_rate name=rate framerate=10/1 ! appsink name=out");
  p.set_caps("src", static_caps("2", "uint8", "0/1"));
  p.push("src", Frame({Bytes{1, 2}}, 0));
  p.eos("src");
  r = p.run(10);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("needs an input with a known rate"), std::string::npos)
      << r.error_text;
}

std::atomic<int> g_invocations{0};
int count_copy(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
               GstTensorMemory *out) {
  ++g_invocations;
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
}

// tensor_filter honours the THROTTLE QoS: with throttle=true it skips the frames tensor_rate
// would drop (30 fps in, 10 fps out), with throttle=false it runs on every frame.
// Deterministic: appsrc, filter and tensor_rate run in one streaming thread (no queue), so the
// QoS event reaches the filter before its next frame, and the filter's skipping depends only on
// PTS (its latency property is off, so the measured invoke time plays no part). Frame k has
// PTS k/30 s. The filter runs f0, f1, f2 unthrottled; tensor_rate drops f1 when f2 arrives
// (f2 is nearer the 100 ms slot) and sends THROTTLE with diff 99.9 ms. From then on the filter
// runs a frame when at least 99.9 ms of PTS passed since the last one it ran: f3 (its first
// frame with a delay set), f6, f9, ..., f27. 4 + 8 = 12 invocations; tensor_rate outputs frames
// 0, 3, ..., 27 at 0, 100, ..., 900 ms (f27 at EOS), 10 buffers.
TEST(TensorRate, ThrottleMakesAnUpstreamFilterSkipFrames) {
  GstTensorsInfo info{};
  info.num_tensors = 1;
  info.info[0].type = _NNS_UINT8;
  info.info[0].dimension[0] = 2;
  info.format = _NNS_TENSOR_FORMAT_STATIC;
  ASSERT_EQ(NNS_custom_easy_register("flow_rate_count", count_copy, nullptr, &info, &info), 0);
  for (bool throttle : {true, false}) {
    g_invocations = 0;
    AppPipeline p(
        "appsrc name=src ! tensor_filter framework=custom-easy model=flow_rate_count ! "
        "tensor_rate framerate=10/1 throttle=" +
        std::string(throttle ? "true" : "false") + " ! appsink name=out");
    p.set_caps("src", static_caps("2", "uint8", "30/1"));
    for (int i = 0; i < 30; ++i)
      p.push("src",
             Frame({Bytes{static_cast<uint8_t>(i), 0}}, gst_util_uint64_scale(i, GST_SECOND, 30),
                   gst_util_uint64_scale(1, GST_SECOND, 30)));
    p.eos("src");
    auto r = p.run(10);
    ASSERT_TRUE(r.eos) << r.error_text;
    auto out = p.frames("out");
    // Without throttling: 30 invocations and frames 0, 3, ..., 27, then 29 at 1.0 s (EOS).
    EXPECT_EQ(g_invocations.load(), throttle ? 12 : 30);
    ASSERT_EQ(out.size(), throttle ? 10u : 11u);
    for (std::size_t k = 0; k < out.size(); ++k) {
      uint8_t frame = k < 10 ? static_cast<uint8_t>(3 * k) : 29;
      EXPECT_EQ(out[k].mems, std::vector<Bytes>{(Bytes{frame, 0})}) << k;
      EXPECT_EQ(out[k].pts, k * 100 * GST_MSECOND) << k;
    }
  }
  EXPECT_EQ(NNS_custom_easy_unregister("flow_rate_count"), 0);
}

// 100 PLAYING<->NULL cycles of a 30 -> 10 fps conversion (throttle QoS going upstream): 7
// frames give at least the outputs at 0 and 100 ms; odd cycles end with EOS. No hang, nothing
// (buffers, events either way) left alive.
TEST(TensorRate, HundredPlayingNullCyclesNoHangNoLeak) {
  AppPipeline p("appsrc name=src ! tensor_rate name=rate framerate=10/1 ! fakesink name=out");
  p.set_caps("src", static_caps("2", "uint8", "30/1"));
  nns::test::state_cycles(p.pipeline(), 100, [&](int i, nns::test::LiveObjects &live) {
    std::size_t before = live.delivered("out");
    for (int k = 0; k < 7; ++k)
      p.push("src",
             Frame({Bytes{static_cast<uint8_t>(k), 7}}, gst_util_uint64_scale(k, GST_SECOND, 30),
                   gst_util_uint64_scale(1, GST_SECOND, 30)));
    if (i % 2) {
      p.eos("src");
      std::string err;
      EXPECT_TRUE(nns::test::wait_eos(p.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
      EXPECT_TRUE(live.wait_delivered("out", before + 3)) << "cycle " << i;
    } else {
      EXPECT_TRUE(live.wait_delivered("out", before + 2)) << "cycle " << i;
    }
  });
}

TEST(TensorRate, PropertiesAsUpstream) {
  GstElement *e = gst_element_factory_make("tensor_rate", nullptr);
  ASSERT_NE(e, nullptr);
  gboolean throttle = FALSE, silent = FALSE;
  gchar *fr = nullptr;
  g_object_get(e, "throttle", &throttle, "silent", &silent, "framerate", &fr, nullptr);
  EXPECT_TRUE(throttle);
  EXPECT_TRUE(silent);
  EXPECT_STREQ(fr, "");
  g_free(fr);
  g_object_set(e, "framerate", "10/1", nullptr);
  g_object_get(e, "framerate", &fr, nullptr);
  EXPECT_STREQ(fr, "10/1");
  g_free(fr);
  for (const char *ro : {"in", "out", "duplicate", "drop"}) {
    GParamSpec *ps = g_object_class_find_property(G_OBJECT_GET_CLASS(e), ro);
    ASSERT_NE(ps, nullptr) << ro;
    EXPECT_EQ(ps->value_type, G_TYPE_UINT64);
    EXPECT_FALSE(ps->flags & G_PARAM_WRITABLE) << ro;
  }
  gst_object_unref(e);
}

}  // namespace

GstPadProbeReturn record_caps(GstPad *, GstPadProbeInfo *info, gpointer user) {
  GstEvent *ev = GST_PAD_PROBE_INFO_EVENT(info);
  if (GST_EVENT_TYPE(ev) == GST_EVENT_CAPS) {
    GstCaps *caps;
    gst_event_parse_caps(ev, &caps);
    *static_cast<std::string *>(user) = nns::gst::caps_to_string(caps);
  }
  return GST_PAD_PROBE_OK;
}

// Records the caps that `element`'s src pad sends into `*out`.
void watch_caps(AppPipeline &p, const char *element, std::string *out) {
  GstElement *e = p.get(element);
  GstPad *pad = gst_element_get_static_pad(e, "src");
  gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM, record_caps, out, nullptr);
  gst_object_unref(pad);
  gst_object_unref(e);
}

int pass_copy(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
              GstTensorMemory *out) {
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
}

// tensor_rate converts any input rate, so its sink side must not push its target rate upstream:
// the chain above it keeps the source's 30/1 and tensor_rate alone turns it into 10/1.
TEST(TensorRate, UpstreamKeepsItsOwnFramerate) {
  GstTensorsInfo info{};
  info.num_tensors = 1;
  info.info[0].type = _NNS_UINT8;
  info.info[0].dimension[0] = 1;
  info.info[0].dimension[1] = 4;
  info.info[0].dimension[2] = 4;
  info.info[0].dimension[3] = 1;
  info.format = _NNS_TENSOR_FORMAT_STATIC;
  ASSERT_EQ(NNS_custom_easy_register("rate_pass", pass_copy, nullptr, &info, &info), 0);
  for (const char *mid : {"tensor_filter name=mid framework=custom-easy model=rate_pass",
                          "tensor_transform name=mid mode=typecast option=uint8"}) {
    SCOPED_TRACE(mid);
    AppPipeline p(
        "videotestsrc num-buffers=30 ! video/x-raw,format=GRAY8,width=4,height=4,framerate=30/1 "
        "! tensor_converter name=conv ! " +
        std::string(mid) + " ! tensor_rate name=rate framerate=10/1 throttle=false ! " +
        "appsink name=out");
    std::string conv, m, rate;
    watch_caps(p, "conv", &conv);
    watch_caps(p, "mid", &m);
    watch_caps(p, "rate", &rate);
    auto r = p.run(10);
    ASSERT_TRUE(r.eos) << r.error_text;
    EXPECT_NE(conv.find("framerate=(fraction)30/1"), std::string::npos) << conv;
    EXPECT_NE(m.find("framerate=(fraction)30/1"), std::string::npos) << m;
    EXPECT_NE(rate.find("framerate=(fraction)10/1"), std::string::npos) << rate;
    EXPECT_EQ(p.frames("out").size(), 11u);  // 0.0 s .. 1.0 s as DownConvert30To10
  }
  EXPECT_EQ(NNS_custom_easy_unregister("rate_pass"), 0);
}

// NNStreamer's setPropertyInvalidFramerate_n: a malformed framerate is refused when set and the
// previous value reads back; starting then fails naming the refused text and the kept value.
TEST(TensorRate, InvalidFramerateIsRefusedWhenSet) {
  GstElement *rate = gst_element_factory_make("tensor_rate", "rate");
  ASSERT_TRUE(rate);
  auto framerate = [&] {
    gchar *s = nullptr;
    g_object_get(rate, "framerate", &s, nullptr);
    std::string out = s ? s : "<NULL>";
    g_free(s);
    return out;
  };
  EXPECT_EQ(framerate(), "");
  g_object_set(rate, "framerate", "30/1", nullptr);
  for (const char *bad : {"ASDF", "10/0", "-1/1", "10/1/2"}) {
    g_object_set(rate, "framerate", bad, nullptr);
    EXPECT_EQ(framerate(), "30/1") << bad;
  }
  g_object_set(rate, "framerate", "15/1", nullptr);
  EXPECT_EQ(framerate(), "15/1");
  gst_object_unref(rate);

  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=3 ! video/x-raw,format=GRAY8,width=4,height=4,framerate=30/1 ! "
      "tensor_converter ! tensor_rate name=rate framerate=30/1 framerate=10/0 ! fakesink",
      10);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("rate: framerate '10/0' was refused"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("kept '30/1'"), std::string::npos) << r.error_text;
}

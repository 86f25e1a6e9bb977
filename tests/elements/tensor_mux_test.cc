// SPDX-License-Identifier: LGPL-2.1-only
// tensor_mux: sync policies with streams of different rates (appsrc with explicit PTS),
// caps, zero-copy, flexible output, bad input, EOS/pad release/state cycles.
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include "core/meta_header.h"
#include "elements/cycle_check.h"
#include "elements/stream_util.h"
#include "gst/tensor_caps.h"

namespace nns::test {
namespace {

constexpr GstClockTime k30 = 33333333, k20 = 50000000, k10 = 100000000;
const char *kCaps = "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8";

std::string caps_rate(int fps) {
  return std::string(kCaps) + ",framerate=" + std::to_string(fps) + "/1";
}

// Three inputs at 30, 20 and 10 fps; tensor bytes are {pad, frame, 0, 0}.
std::string three_pads(const std::string &mux_props) {
  return appsrc("a0", caps_rate(30)) + "! mux.sink_0 " + appsrc("a1", caps_rate(20)) +
         "! mux.sink_1 " + appsrc("a2", caps_rate(10)) + "! mux.sink_2 tensor_mux name=mux " +
         mux_props + " ! appsink name=out sync=false";
}

void feed(Pipe &p, const char *src, uint8_t pad, GstClockTime step, int n) {
  for (int i = 0; i < n; ++i)
    p.push(src, make_buffer({{pad, static_cast<uint8_t>(i), 0, 0}}, i * step));
  p.eos(src);
}

struct Frame {
  GstClockTime pts;
  std::vector<int> frames;  // frame index taken from each pad
  bool operator==(const Frame &o) const { return pts == o.pts && frames == o.frames; }
};
std::ostream &operator<<(std::ostream &os, const Frame &f) {
  os << "@" << f.pts << " [";
  for (int i : f.frames) os << i << " ";
  return os << "]";
}

// A tensor_mux with `mode` set before the harness starts it.
GstHarness *mux_harness(const char *mode, const char *props_extra = nullptr) {
  GstElement *mux = gst_element_factory_make("tensor_mux", nullptr);
  g_object_set(mux, "sync-mode", mode, nullptr);
  if (props_extra) g_object_set(mux, "sync-option", props_extra, nullptr);
  GstHarness *h = gst_harness_new_with_element(mux, "sink_0", "src");
  gst_object_unref(mux);
  return h;
}

std::vector<Frame> frames_of(Pipe &p) {
  std::vector<Frame> v;
  for (GstBuffer *b : p.out()) {
    Frame f{GST_BUFFER_PTS(b), {}};
    for (guint m = 0; m < gst_buffer_n_memory(b); ++m) {
      auto bytes = tensor_bytes(b, m);
      EXPECT_EQ(bytes.size(), 4u);
      if (bytes.size() != 4) continue;
      EXPECT_EQ(bytes[0], m) << "tensor order follows pad order";
      EXPECT_EQ(bytes[2] | bytes[3], 0);
      f.frames.push_back(bytes[1]);
    }
    v.push_back(f);
  }
  return v;
}

std::vector<Frame> run_three(const std::string &props, int n30, int n20, int n10) {
  Pipe p(three_pads(props));
  p.collect("out");
  feed(p, "a0", 0, k30, n30);
  feed(p, "a1", 1, k20, n20);
  feed(p, "a2", 2, k10, n10);
  auto r = p.run();
  EXPECT_TRUE(r.eos) << r.error_text;
  return frames_of(p);
}

TEST(TensorMux, PropertyDefaults) {
  GstElement *mux = gst_element_factory_make("tensor_mux", nullptr);
  ASSERT_NE(mux, nullptr);
  gchar *mode = nullptr, *option = nullptr;
  gboolean silent = FALSE;
  g_object_get(mux, "sync-mode", &mode, "sync-option", &option, "silent", &silent, nullptr);
  EXPECT_STREQ(mode, "slowest");
  EXPECT_EQ(option, nullptr);
  EXPECT_TRUE(silent);
  g_free(mode);
  g_object_set(mux, "sync-mode", "refresh", "sync-option", "1:2", nullptr);
  g_object_get(mux, "sync-mode", &mode, "sync-option", &option, nullptr);
  EXPECT_STREQ(mode, "refresh");
  EXPECT_STREQ(option, "1:2");
  g_free(mode);
  g_free(option);
  gst_object_unref(mux);
}

TEST(TensorMux, NoSyncTakesOneBufferPerPad) {
  auto f = run_three("sync-mode=nosync", 4, 4, 4);
  std::vector<Frame> want = {
      {0, {0, 0, 0}}, {k10, {1, 1, 1}}, {2 * k10, {2, 2, 2}}, {3 * k10, {3, 3, 3}}};
  EXPECT_EQ(f, want);
}

TEST(TensorMux, SlowestIsDefault) {
  auto f = run_three("", 10, 7, 4);
  // Base times are the 10 fps pad's; the others give the frame nearest to it.
  std::vector<Frame> want = {
      {0, {0, 0, 0}}, {k10, {3, 2, 1}}, {2 * k10, {6, 4, 2}}, {3 * k10, {9, 6, 3}}};
  EXPECT_EQ(f, want);
}

// Base pad sink_0 (30 fps), duration 1/30 s: another pad's next buffer is taken when it is
// within min(duration, base gap - 1 ns) = 33333332 ns of the base time. The stream ends when
// the base pad has no more buffers: one output per base frame.
TEST(TensorMux, Basepad) {
  auto f = run_three("sync-mode=basepad sync-option=0:33333333", 10, 7, 4);
  std::vector<Frame> want = {{0, {0, 0, 0}},       {k30, {1, 1, 0}},     {2 * k30, {2, 1, 0}},
                             {3 * k30, {3, 2, 1}}, {4 * k30, {4, 3, 1}}, {5 * k30, {5, 3, 1}},
                             {6 * k30, {6, 4, 2}}, {7 * k30, {7, 5, 2}}, {8 * k30, {8, 5, 2}},
                             {9 * k30, {9, 6, 3}}};
  EXPECT_EQ(f, want);
}

// Base pad sink_2 (10 fps) with the default duration (G_MAXINT ns): the tolerance is the base
// pad's own gap minus 1 ns (99999999). As upstream, a pad's buffers older than the base time
// are dropped one policy pass at a time, and each later pass also takes that pad's next buffer
// while it is within the tolerance: at 100 ms sink_0 ends on frame 5 (166.7 ms), not 3.
// The stream ends when the base pad's 4 frames are used.
TEST(TensorMux, BasepadSecondPadDefaultDuration) {
  auto f = run_three("sync-mode=basepad sync-option=2", 10, 7, 4);
  std::vector<Frame> want = {
      {0, {0, 0, 0}}, {k10, {5, 2, 1}}, {2 * k10, {8, 4, 2}}, {3 * k10, {9, 6, 3}}};
  EXPECT_EQ(f, want);
}

TEST(TensorMux, OutputCapsAndMetadata) {
  Pipe p(appsrc("a0",
                "other/tensors,format=static,num_tensors=2,dimensions=4.2:2,"
                "types=uint8.float32,framerate=30/1") +
         "! mux.sink_0 " + appsrc("a1", caps_rate(10)) +
         "! mux.sink_1 tensor_mux name=mux sync-mode=nosync ! appsink name=out sync=false");
  p.collect("out");
  p.push("a0", make_buffer({{1, 2, 3, 4}, std::vector<uint8_t>(16, 7)}, 0, 5));
  p.push("a1", make_buffer({{9, 9, 9, 9}}, 40, 100));
  p.eos("a0");
  p.eos("a1");
  GstPad *src = gst_element_get_static_pad(p.get("mux"), "src");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), 1u);
  GstBuffer *b = p.out()[0];
  EXPECT_EQ(gst_buffer_n_memory(b), 3u);
  EXPECT_EQ(GST_BUFFER_PTS(b), 40u);
  EXPECT_EQ(GST_BUFFER_DURATION(b), 100u) << "metadata of the buffer that set the time";
  EXPECT_EQ(tensor_bytes(b, 2)[0], 9);
  gst_object_unref(src);
}

TEST(TensorMux, NegotiatedCaps) {
  GstHarness *h0 = mux_harness("nosync");
  HarnessPtr hp0(h0);
  GstHarness *h1 = gst_harness_new_with_element(h0->element, "sink_1", nullptr);
  HarnessPtr hp1(h1);
  gst_harness_set_src_caps_str(
      h0,
      "other/tensors,format=static,num_tensors=2,dimensions=3:4.2,types=uint8.int16,"
      "framerate=30/1");
  gst_harness_set_src_caps_str(h1, "other/tensor,dimension=(string)5,type=float32,framerate=15/1");
  ASSERT_EQ(
      gst_harness_push(h0, make_buffer({std::vector<uint8_t>(12), std::vector<uint8_t>(4)}, 0)),
      GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(h1, make_buffer({std::vector<uint8_t>(20)}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h0);
  ASSERT_NE(out, nullptr);
  gst_buffer_unref(out);
  GstCaps *caps = gst_pad_get_current_caps(h0->sinkpad);
  ASSERT_NE(caps, nullptr);
  auto c = nns::gst::config_from_caps(caps);
  EXPECT_EQ(c.info.dims_string(), "3:4,2,5");
  EXPECT_EQ(c.info.types_string(), "uint8,int16,float32");
  EXPECT_EQ(c.rate_n, 15);
  EXPECT_EQ(c.rate_d, 1);
  gst_caps_unref(caps);
}

// Zero-copy: the GstMemory objects that leave the mux are the ones that came in.
TEST(TensorMux, OutputMemoriesAreInputMemories) {
  GstHarness *h0 = gst_harness_new_with_padnames("tensor_mux", "sink_0", "src");
  HarnessPtr hp0(h0);
  GstHarness *h1 = gst_harness_new_with_element(h0->element, "sink_1", nullptr);
  HarnessPtr hp1(h1);
  gst_harness_set_src_caps_str(h0, caps_rate(30).c_str());
  gst_harness_set_src_caps_str(h1, caps_rate(30).c_str());
  GstBuffer *b0 = make_buffer({{1, 2, 3, 4}}, 0);
  GstBuffer *b1 = make_buffer({{5, 6, 7, 8}}, 0);
  GstMemory *m0 = gst_buffer_peek_memory(b0, 0), *m1 = gst_buffer_peek_memory(b1, 0);
  ASSERT_EQ(gst_harness_push(h0, b0), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(h1, b1), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h0);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_peek_memory(out, 0), m0);
  EXPECT_EQ(gst_buffer_peek_memory(out, 1), m1);
  gst_buffer_unref(out);
}

TEST(TensorMux, FlexibleInputMakesFlexibleOutput) {
  GstHarness *h0 = mux_harness("nosync");
  HarnessPtr hp0(h0);
  GstHarness *h1 = gst_harness_new_with_element(h0->element, "sink_1", nullptr);
  HarnessPtr hp1(h1);
  gst_harness_set_src_caps_str(h0, caps_rate(30).c_str());
  gst_harness_set_src_caps_str(h1, "other/tensors,format=flexible,framerate=30/1");
  MetaHeader h;
  h.type = TensorType::kInt8;
  h.dims = make_dims({2});
  h.format = TensorFormat::kFlexible;
  std::vector<uint8_t> flex(kMetaHeaderSize + 2);
  write_meta_header(h, flex.data());
  flex[kMetaHeaderSize] = 42;
  ASSERT_EQ(gst_harness_push(h0, make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(h1, make_buffer({flex}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h0);
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(gst_buffer_n_memory(out), 2u);
  auto t0 = tensor_bytes(out, 0);
  ASSERT_EQ(t0.size(), kMetaHeaderSize + 4);
  auto m = parse_meta_header(t0.data(), t0.size());
  EXPECT_EQ(m.type, TensorType::kUInt8);
  EXPECT_EQ(t0[kMetaHeaderSize + 3], 4);
  EXPECT_EQ(tensor_bytes(out, 1), flex);
  gst_buffer_unref(out);
  GstCaps *caps = gst_pad_get_current_caps(h0->sinkpad);
  EXPECT_EQ(nns::gst::config_from_caps(caps).info.format, TensorFormat::kFlexible);
  gst_caps_unref(caps);
}

// refresh: an output for every arriving buffer once each pad has one; GstHarness pushes are
// synchronous, so the arrival order is exact.
TEST(TensorMux, RefreshOutputsOnEveryArrival) {
  GstHarness *h0 = mux_harness("refresh");
  HarnessPtr hp0(h0);
  GstHarness *h1 = gst_harness_new_with_element(h0->element, "sink_1", nullptr);
  HarnessPtr hp1(h1);
  GstHarness *h2 = gst_harness_new_with_element(h0->element, "sink_2", nullptr);
  HarnessPtr hp2(h2);
  GstHarness *hs[3] = {h0, h1, h2};
  for (auto *h : hs) gst_harness_set_src_caps_str(h, caps_rate(30).c_str());
  // The table of the upstream document: arrival i carries value i.
  struct Arrival {
    int pad;
    GstClockTime pts;
  };
  std::vector<Arrival> arrivals = {{0, 0},  {1, 0},  {2, 0},  {1, 10},
                                   {2, 20}, {2, 30}, {0, 40}, {2, 50}};
  std::vector<std::vector<uint8_t>> want = {{0, 1, 2}, {0, 3, 2}, {0, 3, 4},
                                            {0, 3, 5}, {6, 3, 5}, {6, 3, 7}};
  std::vector<GstClockTime> want_pts = {0, 10, 20, 30, 40, 50};
  std::vector<std::vector<uint8_t>> got;
  std::vector<GstClockTime> got_pts;
  for (std::size_t i = 0; i < arrivals.size(); ++i) {
    auto a = arrivals[i];
    ASSERT_EQ(gst_harness_push(hs[a.pad], make_buffer({{static_cast<uint8_t>(i), 0, 0, 0}}, a.pts)),
              GST_FLOW_OK);
    if (i >= 2) {
      GstBuffer *out = gst_harness_pull(h0);
      ASSERT_NE(out, nullptr);
      std::vector<uint8_t> v;
      for (guint m = 0; m < gst_buffer_n_memory(out); ++m) v.push_back(tensor_bytes(out, m)[0]);
      got.push_back(v);
      got_pts.push_back(GST_BUFFER_PTS(out));
      gst_buffer_unref(out);
    }
  }
  EXPECT_EQ(got, want);
  EXPECT_EQ(got_pts, want_pts);
  EXPECT_EQ(gst_harness_buffers_in_queue(h0), 0u);
  // EOS only after every pad ended.
  for (auto *h : hs) EXPECT_TRUE(gst_harness_push_event(h, gst_event_new_eos()));
  GstEvent *ev;
  bool eos = false;
  while ((ev = gst_harness_pull_event(h0))) {
    eos = eos || GST_EVENT_TYPE(ev) == GST_EVENT_EOS;
    gst_event_unref(ev);
    if (eos) break;
  }
  EXPECT_TRUE(eos);
}

TEST(TensorMux, RefreshWithAppsrc) {
  Pipe p(appsrc("a0", caps_rate(30)) + "! mux.sink_0 " + appsrc("a1", caps_rate(10)) +
         "! mux.sink_1 tensor_mux name=mux sync-mode=refresh ! appsink name=out sync=false");
  p.collect("out");
  feed(p, "a0", 0, k30, 6);
  feed(p, "a1", 1, k10, 2);
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  // 8 arrivals; the first output needs both pads, so 2 to 7 outputs depending on how the two
  // appsrc threads interleave. The last output holds the last frame of each pad.
  ASSERT_GE(p.out().size(), 2u);
  EXPECT_LE(p.out().size(), 7u);
  GstBuffer *last = p.out().back();
  EXPECT_EQ(tensor_bytes(last, 0)[1], 5);
  EXPECT_EQ(tensor_bytes(last, 1)[1], 1);
}

TEST(TensorMux, BadSyncModeIsABusError) {
  auto r = run_pipeline(appsrc("a0", caps_rate(30)) +
                        "! mux.sink_0 tensor_mux name=mux sync-mode=fastest ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("mux: sync-mode='fastest' is not one of nosync, slowest, basepad, "
                              "refresh"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorMux, BadSyncOptionIsABusError) {
  auto r = run_pipeline(appsrc("a0", caps_rate(30)) +
                        "! mux.sink_0 tensor_mux name=mux sync-mode=basepad sync-option=one:5 "
                        "! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("sync-option: sink id 'one' is not a non-negative integer"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorMux, BasepadOutOfRangeIsABusError) {
  Pipe p(appsrc("a0", caps_rate(30)) + "! mux.sink_0 " + appsrc("a1", caps_rate(30)) +
         "! mux.sink_1 tensor_mux name=mux sync-mode=basepad sync-option=5:100 ! fakesink");
  feed(p, "a0", 0, k30, 2);
  feed(p, "a1", 1, k30, 2);
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("sync-option: base pad sink_5 does not exist (the element has 2 "
                              "sink pads)"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorMux, WrongBufferSizeIsABusError) {
  Pipe p(appsrc("a0", caps_rate(30)) + "! mux.sink_0 " + appsrc("a1", caps_rate(30)) +
         "! mux.sink_1 tensor_mux name=mux ! fakesink");
  p.push("a0", make_buffer({{1, 2, 3, 4}}, 0));
  p.push("a1", make_buffer({{1, 2, 3}}, 0));
  p.eos("a0");
  p.eos("a1");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("mux: sink_1: tensor 0 has 3 bytes, expected 4 for uint8 4"),
            std::string::npos)
      << r.error_text;
}

// Caps for `n` uint8 tensors of dimension 1.
std::string n_tensors_caps(int n) {
  std::string dims, types;
  for (int i = 0; i < n; ++i) {
    dims += i ? ",1" : "1";
    types += i ? ",uint8" : "uint8";
  }
  return "other/tensors,format=static,num_tensors=" + std::to_string(n) + ",dimensions=(string)\"" +
         dims + "\",types=(string)\"" + types + "\",framerate=30/1";
}

TEST(TensorMux, MoreThan256TensorsIsABusError) {
  Pipe p(appsrc("a0", n_tensors_caps(200)) + "! mux.sink_0 " + appsrc("a1", n_tensors_caps(57)) +
         "! mux.sink_1 tensor_mux name=mux sync-mode=nosync ! fakesink");
  p.push("a0", make_buffer({std::vector<uint8_t>(200)}, 0));
  p.push("a1", make_buffer({std::vector<uint8_t>(57)}, 0));
  p.eos("a0");
  p.eos("a1");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("mux: the sink pads carry 257 tensors in all (sink_0: 200, sink_1: "
                              "57), more than the limit of 256"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorMux, DataWithoutCapsIsABusError) {
  // appsrc without caps pushes its buffers without a CAPS event.
  Pipe p(appsrc("a0", caps_rate(30)) +
         "! mux.sink_0 appsrc name=a1 format=time ! mux.sink_1 tensor_mux name=mux ! fakesink");
  p.push("a0", make_buffer({{1, 2, 3, 4}}, 0));
  p.push("a1", make_buffer({{5, 6, 7, 8}}, 0));
  p.eos("a0");
  p.eos("a1");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("mux: sink_1 received data without caps"), std::string::npos)
      << r.error_text;
}

TEST(TensorMux, EosOnOnePadEndsTheStream) {
  Pipe p(appsrc("a0", caps_rate(30)) + "! mux.sink_0 " + appsrc("a1", caps_rate(30)) +
         "! mux.sink_1 tensor_mux name=mux sync-mode=nosync ! appsink name=out sync=false");
  p.collect("out");
  feed(p, "a0", 0, k30, 3);
  feed(p, "a1", 1, k30, 50);
  auto r = p.run(10);
  ASSERT_TRUE(r.eos) << (r.timed_out ? "timed out" : r.error_text);
  std::vector<Frame> want = {{0, {0, 0}}, {k30, {1, 1}}, {2 * k30, {2, 2}}};
  EXPECT_EQ(frames_of(p), want);
}

// In every mode: no output can be built and the stream ends (refresh used to spin in its
// policy loop here, holding the element lock, so that even NULL hung).
TEST(TensorMux, EosBeforeAnyDataOnOnePad) {
  for (std::string mode : {"nosync", "slowest", "basepad", "refresh"}) {
    SCOPED_TRACE(mode);
    Pipe p(appsrc("a0", caps_rate(30)) + "! mux.sink_0 " + appsrc("a1", caps_rate(30)) +
           "! mux.sink_1 tensor_mux name=mux sync-mode=" + mode + " ! appsink name=out sync=false");
    p.collect("out");
    p.eos("a0");
    feed(p, "a1", 1, k30, 5);
    auto r = p.run(10);
    ASSERT_TRUE(r.eos) << (r.timed_out ? "timed out" : r.error_text);
    EXPECT_EQ(p.out().size(), 0u);
  }
}

TEST(TensorMux, ReleasePadWhilePlaying) {
  GstHarness *h0 = mux_harness("nosync");
  HarnessPtr hp0(h0);
  GstPad *extra = gst_element_request_pad_simple(h0->element, "sink_%u");
  ASSERT_NE(extra, nullptr);
  gst_harness_set_src_caps_str(h0, caps_rate(30).c_str());
  // sink_1 never gets data; releasing it lets sink_0 alone drive the output.
  gst_element_release_request_pad(h0->element, extra);
  gst_object_unref(extra);
  ASSERT_EQ(gst_harness_push(h0, make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h0);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_n_memory(out), 1u);
  gst_buffer_unref(out);
}

TEST(TensorMux, ReleasePadWithDataWhilePlaying) {
  GstHarness *h0 = mux_harness("nosync");
  HarnessPtr hp0(h0);
  GstHarness *h1 = gst_harness_new_with_element(h0->element, "sink_1", nullptr);
  gst_harness_set_src_caps_str(h0, caps_rate(30).c_str());
  gst_harness_set_src_caps_str(h1, caps_rate(30).c_str());
  ASSERT_EQ(gst_harness_push(h1, make_buffer({{5, 6, 7, 8}}, 0)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(h0, make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h0);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_n_memory(out), 2u);
  gst_buffer_unref(out);
  gst_harness_teardown(h1);  // releases sink_1
  ASSERT_EQ(gst_harness_push(h0, make_buffer({{1, 2, 3, 4}}, k30)), GST_FLOW_OK);
  out = gst_harness_pull(h0);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_n_memory(out), 1u);
  gst_buffer_unref(out);
}

// 100 PLAYING<->NULL cycles per sync mode: a third stop after two outputs, a third while the
// mux waits for sink_1, a third after EOS on sink_1 ended the stream (refresh ends only when
// every pad ended, so sink_0 ends too there). No hang, nothing left alive after any cycle.
TEST(TensorMux, HundredPlayingNullCyclesNoHangNoLeak) {
  for (std::string mode : {"nosync", "slowest", "basepad", "refresh"}) {
    SCOPED_TRACE(mode);
    Pipe q(appsrc("a0", caps_rate(30)) + "! mux.sink_0 " + appsrc("a1", caps_rate(30)) +
           "! mux.sink_1 tensor_mux name=mux sync-mode=" + mode + " ! fakesink name=out");
    state_cycles(q.pipeline(), 100, [&](int i, LiveObjects &live) {
      std::size_t before = live.delivered("out");
      q.push("a0", make_buffer({{0, 0, 0, 0}}, 0));
      q.push("a0", make_buffer({{0, 1, 0, 0}}, k30));
      if (i % 3 == 0) {
        q.push("a1", make_buffer({{1, 0, 0, 0}}, 0));
        q.push("a1", make_buffer({{1, 1, 0, 0}}, k30));
        EXPECT_TRUE(live.wait_delivered("out", before + 2)) << "cycle " << i;
      } else if (i % 3 == 2) {
        q.eos("a1");
        if (mode == "refresh") q.eos("a0");
        std::string err;
        EXPECT_TRUE(wait_eos(q.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
      }
    });
  }
}

}  // namespace
}  // namespace nns::test

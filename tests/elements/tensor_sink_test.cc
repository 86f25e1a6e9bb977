// SPDX-License-Identifier: LGPL-2.1-only
// tensor_sink: signals (new-data with the buffer, stream-start, eos), signal-rate throttling,
// emit-signal=false, property defaults as upstream, and caps rejection on the bus.
#include <gst/app/gstappsrc.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <mutex>
#include <string>
#include <vector>

#include "support/harness.h"

namespace {

using nns::test::run_pipeline;

constexpr const char *kU8Caps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)4:1:1:1,types=(string)uint8,"
    "framerate=(fraction)0/1";

// What the sink's signals delivered, in order.
struct Recorder {
  std::mutex m;
  std::vector<std::vector<std::vector<uint8_t>>> frames;  // frame -> memory -> bytes
  std::vector<GstClockTime> pts;
  std::vector<std::string> events;  // "stream-start", "data", "eos"
  int count(const std::string &ev) {
    std::lock_guard<std::mutex> l(m);
    int n = 0;
    for (auto &e : events) n += (e == ev);
    return n;
  }
};

void on_new_data(GstElement *, GstBuffer *buf, gpointer user) {
  auto *r = static_cast<Recorder *>(user);
  std::vector<std::vector<uint8_t>> mems;
  for (guint i = 0; i < gst_buffer_n_memory(buf); ++i) {
    GstMemory *mem = gst_buffer_peek_memory(buf, i);
    GstMapInfo map;
    ASSERT_TRUE(gst_memory_map(mem, &map, GST_MAP_READ));
    mems.emplace_back(map.data, map.data + map.size);
    gst_memory_unmap(mem, &map);
  }
  std::lock_guard<std::mutex> l(r->m);
  r->frames.push_back(std::move(mems));
  r->pts.push_back(GST_BUFFER_PTS(buf));
  r->events.push_back("data");
}
void on_stream_start(GstElement *, gpointer user) {
  auto *r = static_cast<Recorder *>(user);
  std::lock_guard<std::mutex> l(r->m);
  r->events.push_back("stream-start");
}
void on_eos(GstElement *, gpointer user) {
  auto *r = static_cast<Recorder *>(user);
  std::lock_guard<std::mutex> l(r->m);
  r->events.push_back("eos");
}

// A pipeline "appsrc name=src caps=<caps> ! <middle> tensor_sink name=sink <sink_props>" whose
// appsrc already holds `frames` (each a list of memories) and EOS.
struct SinkPipeline {
  GstElement *pipeline = nullptr;
  GstElement *sink = nullptr;
  Recorder rec;

  SinkPipeline(const std::string &caps, const std::string &sink_props,
               const std::vector<std::vector<std::vector<uint8_t>>> &frames,
               const std::string &middle = "") {
    std::string desc = "appsrc name=src format=time caps=\"" + caps + "\" ! " + middle +
                       "tensor_sink name=sink " + sink_props;
    GError *err = nullptr;
    pipeline = gst_parse_launch(desc.c_str(), &err);
    EXPECT_EQ(err, nullptr) << (err ? err->message : "");
    if (err) g_error_free(err);
    if (!pipeline) return;
    sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
    g_signal_connect(sink, "new-data", G_CALLBACK(on_new_data), &rec);
    g_signal_connect(sink, "stream-start", G_CALLBACK(on_stream_start), &rec);
    g_signal_connect(sink, "eos", G_CALLBACK(on_eos), &rec);
    GstElement *src = gst_bin_get_by_name(GST_BIN(pipeline), "src");
    g_object_set(src, "max-bytes", static_cast<guint64>(0), nullptr);  // queue everything
    GstClockTime t = 0;
    for (const auto &frame : frames) {
      GstBuffer *buf = gst_buffer_new();
      for (const auto &m : frame) {
        gpointer data = g_memdup2(m.data(), m.size());
        gst_buffer_append_memory(buf, gst_memory_new_wrapped(static_cast<GstMemoryFlags>(0), data,
                                                             m.size(), 0, m.size(), data, g_free));
      }
      GST_BUFFER_PTS(buf) = t;
      t += 10 * GST_MSECOND;
      EXPECT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), buf), GST_FLOW_OK);
    }
    gst_app_src_end_of_stream(GST_APP_SRC(src));
    gst_object_unref(src);
  }
  ~SinkPipeline() {
    if (sink) gst_object_unref(sink);
    if (pipeline) gst_object_unref(pipeline);
  }
};

std::vector<std::vector<std::vector<uint8_t>>> u8_frames(int n) {
  std::vector<std::vector<std::vector<uint8_t>>> f;
  for (int i = 0; i < n; ++i) {
    uint8_t b = static_cast<uint8_t>(i * 4);
    f.push_back({{b, static_cast<uint8_t>(b + 1), static_cast<uint8_t>(b + 2),
                  static_cast<uint8_t>(b + 3)}});
  }
  return f;
}

TEST(TensorSink, NewDataDeliversEveryBufferInOrderBetweenStreamStartAndEos) {
  auto frames = u8_frames(5);
  SinkPipeline p(kU8Caps, "", frames);
  ASSERT_NE(p.pipeline, nullptr);
  auto r = run_pipeline(p.pipeline);
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.rec.frames.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    EXPECT_EQ(p.rec.frames[i], frames[i]) << "frame " << i;
    EXPECT_EQ(p.rec.pts[i], static_cast<GstClockTime>(i) * 10 * GST_MSECOND);
  }
  std::vector<std::string> want{"stream-start", "data", "data", "data", "data", "data", "eos"};
  EXPECT_EQ(p.rec.events, want);
}

TEST(TensorSink, MultiTensorFrameKeepsOneMemoryPerTensor) {
  std::vector<uint8_t> a{1, 2}, b(12);
  float fv[3] = {1.5f, -2.0f, 3.25f};
  std::memcpy(b.data(), fv, sizeof fv);
  SinkPipeline p(
      "other/tensors,format=static,num_tensors=2,dimensions=(string)\\\"2:1,3:1\\\","
      "types=(string)\\\"uint8,float32\\\",framerate=(fraction)30/1",
      "", {{a, b}, {a, b}});
  ASSERT_NE(p.pipeline, nullptr);
  auto r = run_pipeline(p.pipeline);
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.rec.frames.size(), 2u);
  ASSERT_EQ(p.rec.frames[0].size(), 2u);
  EXPECT_EQ(p.rec.frames[0][0], a);
  EXPECT_EQ(p.rec.frames[0][1], b);
}

TEST(TensorSink, AcceptsLegacyTensorFlexibleAndSparseCaps) {
  for (const char *caps : {"other/tensor,dimension=(string)4:1:1:1,type=(string)uint8,"
                           "framerate=(fraction)0/1",
                           "other/tensors,format=flexible,framerate=(fraction)0/1",
                           "other/tensors,format=sparse,framerate=(fraction)0/1"}) {
    SinkPipeline p(caps, "", u8_frames(2));
    ASSERT_NE(p.pipeline, nullptr);
    auto r = run_pipeline(p.pipeline);
    EXPECT_TRUE(r.eos) << caps << ": " << r.error_text;
    EXPECT_EQ(p.rec.count("data"), 2) << caps;
  }
}

TEST(TensorSink, EmitSignalFalseEmitsNothing) {
  SinkPipeline p(kU8Caps, "emit-signal=false", u8_frames(4));
  ASSERT_NE(p.pipeline, nullptr);
  auto r = run_pipeline(p.pipeline);
  ASSERT_TRUE(r.eos) << r.error_text;
  EXPECT_TRUE(p.rec.events.empty()) << "got " << p.rec.events.size() << " signals";
}

TEST(TensorSink, SignalRateDropsSignalsThatComeTooSoon) {
  // 40 buffers pushed as fast as possible, at most 1 signal per second: the first buffer is
  // delivered, (almost) everything else falls within the second that follows.
  auto frames = u8_frames(40);
  SinkPipeline p(kU8Caps, "signal-rate=1", frames);
  ASSERT_NE(p.pipeline, nullptr);
  auto t0 = std::chrono::steady_clock::now();
  auto r = run_pipeline(p.pipeline);
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_GE(p.rec.frames.size(), 1u);
  EXPECT_EQ(p.rec.frames[0], frames[0]);  // the first buffer always passes
  EXPECT_LE(p.rec.frames.size(), static_cast<std::size_t>(s) + 1) << "ran " << s << " s";
  // stream-start and eos are not throttled
  EXPECT_EQ(p.rec.count("stream-start"), 1);
  EXPECT_EQ(p.rec.count("eos"), 1);
}

TEST(TensorSink, SignalRateLetsThroughAboutRatePerSecondOnPacedInput) {
  // Buffers arrive every >=20 ms (identity sleeps); signal-rate=10 allows one per 100 ms.
  const int n = 20;
  SinkPipeline p(kU8Caps, "signal-rate=10", u8_frames(n), "identity sleep-time=20000 ! ");
  ASSERT_NE(p.pipeline, nullptr);
  auto t0 = std::chrono::steady_clock::now();
  auto r = run_pipeline(p.pipeline);
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  ASSERT_TRUE(r.eos) << r.error_text;
  std::size_t got = p.rec.frames.size();
  EXPECT_GE(got, 2u) << "ran " << s << " s";
  EXPECT_LE(got, static_cast<std::size_t>(s * 10) + 1) << "ran " << s << " s";
  EXPECT_LT(got, static_cast<std::size_t>(n));

  // Without a rate every paced buffer is delivered.
  SinkPipeline all(kU8Caps, "signal-rate=0", u8_frames(5), "identity sleep-time=20000 ! ");
  ASSERT_TRUE(run_pipeline(all.pipeline).eos);
  EXPECT_EQ(all.rec.frames.size(), 5u);
}

TEST(TensorSink, DefaultsMatchUpstream) {
  GstElement *e = gst_element_factory_make("tensor_sink", nullptr);
  ASSERT_NE(e, nullptr);
  gboolean sync = TRUE, qos = FALSE, emit = FALSE, silent = FALSE;
  guint rate = 99;
  g_object_get(e, "sync", &sync, "qos", &qos, "emit-signal", &emit, "silent", &silent,
               "signal-rate", &rate, nullptr);
  EXPECT_FALSE(sync);
  EXPECT_TRUE(qos);
  EXPECT_TRUE(emit);
  EXPECT_TRUE(silent);
  EXPECT_EQ(rate, 0u);
  GParamSpec *ps = g_object_class_find_property(G_OBJECT_GET_CLASS(e), "signal-rate");
  ASSERT_NE(ps, nullptr);
  ASSERT_EQ(G_PARAM_SPEC_VALUE_TYPE(ps), G_TYPE_UINT);
  EXPECT_EQ(G_PARAM_SPEC_UINT(ps)->minimum, 0u);
  EXPECT_EQ(G_PARAM_SPEC_UINT(ps)->maximum, 500u);
  EXPECT_EQ(G_PARAM_SPEC_UINT(ps)->default_value, 0u);
  ps = g_object_class_find_property(G_OBJECT_GET_CLASS(e), "emit-signal");
  ASSERT_NE(ps, nullptr);
  EXPECT_EQ(G_PARAM_SPEC_VALUE_TYPE(ps), G_TYPE_BOOLEAN);
  EXPECT_TRUE(G_PARAM_SPEC_BOOLEAN(ps)->default_value);
  // Properties round-trip.
  g_object_set(e, "signal-rate", 500u, "emit-signal", FALSE, "silent", FALSE, nullptr);
  g_object_get(e, "signal-rate", &rate, "emit-signal", &emit, "silent", &silent, nullptr);
  EXPECT_EQ(rate, 500u);
  EXPECT_FALSE(emit);
  EXPECT_FALSE(silent);
  // Signals exist with upstream's signatures.
  GSignalQuery q;
  g_signal_query(g_signal_lookup("new-data", G_OBJECT_TYPE(e)), &q);
  ASSERT_NE(q.signal_id, 0u);
  ASSERT_EQ(q.n_params, 1u);
  EXPECT_EQ(q.param_types[0] & ~G_SIGNAL_TYPE_STATIC_SCOPE, GST_TYPE_BUFFER);
  EXPECT_NE(g_signal_lookup("stream-start", G_OBJECT_TYPE(e)), 0u);
  EXPECT_NE(g_signal_lookup("eos", G_OBJECT_TYPE(e)), 0u);
  gst_object_unref(e);
}

TEST(TensorSink, PadTemplateTakesOnlyTensorCaps) {
  GstElementFactory *f = gst_element_factory_find("tensor_sink");
  ASSERT_NE(f, nullptr);
  GstCaps *tmpl = nullptr;
  for (const GList *l = gst_element_factory_get_static_pad_templates(f); l; l = l->next) {
    auto *t = static_cast<GstStaticPadTemplate *>(l->data);
    if (t->direction == GST_PAD_SINK) tmpl = gst_static_pad_template_get_caps(t);
  }
  ASSERT_NE(tmpl, nullptr);
  auto can = [&](const char *s) {
    GstCaps *c = gst_caps_from_string(s);
    bool ok = gst_caps_can_intersect(tmpl, c);
    gst_caps_unref(c);
    return ok;
  };
  EXPECT_TRUE(can(kU8Caps));
  EXPECT_TRUE(can("other/tensor"));
  EXPECT_TRUE(can("other/tensors,format=flexible"));
  EXPECT_TRUE(can("other/tensors,format=sparse"));
  EXPECT_FALSE(can("video/x-raw"));
  EXPECT_FALSE(can("other/tensors,format=bogus"));
  gst_caps_unref(tmpl);
  gst_object_unref(f);
}

TEST(TensorSink, NonTensorCapsFailNegotiationOnTheBus) {
  SinkPipeline p("video/x-raw,format=GRAY8,width=2,height=2,framerate=0/1", "", u8_frames(1));
  ASSERT_NE(p.pipeline, nullptr);
  auto r = run_pipeline(p.pipeline);
  ASSERT_TRUE(r.error) << "expected an error, eos=" << r.eos;
  EXPECT_NE(r.error_text.find("not-negotiated"), std::string::npos) << r.error_text;
  EXPECT_EQ(p.rec.count("data"), 0);
}

TEST(TensorSink, MalformedTensorCapsPostAnErrorNamingTheSink) {
  struct Case {
    const char *caps;
    const char *needle;
  };
  for (const Case &c : {
           Case{"other/tensors,format=static,num_tensors=1,dimensions=(string)4:x,"
                "types=(string)uint8,framerate=(fraction)0/1",
                "4:x"},
           Case{"other/tensors,format=static,num_tensors=1,dimensions=(string)4,"
                "types=(string)uint7,framerate=(fraction)0/1",
                "uint7"},
           Case{"other/tensors,format=static,num_tensors=1,framerate=(fraction)0/1", "dimensions"},
       }) {
    SinkPipeline p(c.caps, "", u8_frames(1));
    ASSERT_NE(p.pipeline, nullptr);
    auto r = run_pipeline(p.pipeline);
    ASSERT_TRUE(r.error) << c.caps;
    EXPECT_NE(r.error_text.find("sink:"), std::string::npos) << r.error_text;
    EXPECT_NE(r.error_text.find(c.needle), std::string::npos) << r.error_text;
    EXPECT_EQ(p.rec.count("data"), 0) << c.caps;
  }
}

// A num_tensors that disagrees with well-formed lists is accepted with a warning, as NNStreamer's
// sink takes it (tests/elements/tensor_sink_upstream_test.cc has its extra-tensors case).
TEST(TensorSink, NumTensorsDisagreeingWithTheListsIsAWarning) {
  SinkPipeline p(
      "other/tensors,format=static,num_tensors=2,dimensions=(string)4,"
      "types=(string)uint8,framerate=(fraction)0/1",
      "", u8_frames(1));
  ASSERT_NE(p.pipeline, nullptr);
  auto r = run_pipeline(p.pipeline);
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_NE(r.warning_text.find("num_tensors=2"), std::string::npos) << r.warning_text;
  EXPECT_EQ(p.rec.count("data"), 1);
}

}  // namespace

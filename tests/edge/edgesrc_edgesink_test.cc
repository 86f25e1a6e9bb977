// SPDX-License-Identifier: LGPL-2.1-only
// edgesink publishing to edgesrc subscribers over TCP on 127.0.0.1; subscribers in a second
// process (this binary re-executed) and in this one.
#include <cstring>

#include "edge_test_util.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

using namespace edge_test;

namespace {
const char *kOctet = "application/octet-stream";

std::vector<uint8_t> payload(int n) {
  std::vector<uint8_t> v(100 + n);
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = static_cast<uint8_t>(n * 13 + i);
  return v;
}
}  // namespace

TEST(EdgeChild, Run) {
  edge_test::run_child();
}

TEST(Edge, SubscriberInAnotherProcessGetsExactBytes) {
  const uint16_t port = free_port();
  TempFile out_file("edgesrc_out.bin");
  const std::string &out = out_file.path;
  AppPipeline pub("edgesink host=127.0.0.1 port=" + std::to_string(port) +
                      " wait-connection=true connection-timeout=10000 sync=false",
                  kOctet, true);
  pub.play();
  ASSERT_TRUE([&] {
    for (int i = 0; i < 200; ++i) {
      if (port_open(port)) return true;
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }());
  Child sub("edgesrc dest-host=127.0.0.1 dest-port=" + std::to_string(port) +
                " num-buffers=10 ! filesink location=" + out,
            "sub");
  std::string want;
  for (int n = 0; n < 10; ++n) {
    const auto p = payload(n);
    want.append(reinterpret_cast<const char *>(p.data()), p.size());
    ASSERT_EQ(pub.push(p, n * GST_MSECOND), GST_FLOW_OK);
    std::this_thread::sleep_for(5ms);
  }
  ASSERT_EQ(sub.wait_exit(), 0) << sub.log();
  EXPECT_EQ(slurp(out), want);
}

TEST(Edge, SubscriberTakesThePublisherCapsAndEndsWithIt) {
  const uint16_t port = free_port();
  AppPipeline pub(
      "edgesink host=127.0.0.1 port=" + std::to_string(port) + " wait-connection=true sync=false",
      "video/x-raw,format=GRAY8,width=4,height=2,framerate=0/1", true);
  pub.play();
  for (int i = 0; i < 200 && !port_open(port); ++i) std::this_thread::sleep_for(10ms);
  std::thread feeder([&] {
    for (int n = 0; n < 3; ++n) pub.push(std::vector<uint8_t>(8, static_cast<uint8_t>(n)), 0);
  });
  // Caps of the first buffer must exist before the subscriber asks: let one frame through.
  std::this_thread::sleep_for(50ms);
  GError *err = nullptr;
  GstElement *sub =
      gst_parse_launch(("edgesrc name=s dest-host=127.0.0.1 dest-port=" + std::to_string(port) +
                        " ! appsink name=k sync=false")
                           .c_str(),
                       &err);
  ASSERT_TRUE(sub);
  gst_element_set_state(sub, GST_STATE_PLAYING);
  GstElement *k = gst_bin_get_by_name(GST_BIN(sub), "k");
  feeder.join();
  pub.push(std::vector<uint8_t>(8, 9), 0);
  GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(k), 5 * GST_SECOND);
  ASSERT_TRUE(s);
  GstCaps *caps = gst_sample_get_caps(s);
  gchar *cs = gst_caps_to_string(caps);
  EXPECT_NE(std::string(cs).find("video/x-raw, format=(string)GRAY8, width=(int)4"),
            std::string::npos)
      << cs;
  g_free(cs);
  gst_sample_unref(s);
  // The publisher stops: a goodbye, so the subscriber ends with EOS, not an error.
  pub.stop();
  // appsink holds EOS until its queue is drained: drain it.
  for (int i = 0; i < 50 && !gst_app_sink_is_eos(GST_APP_SINK(k)); ++i) {
    GstSample *rest = gst_app_sink_try_pull_sample(GST_APP_SINK(k), GST_SECOND / 10);
    if (rest) gst_sample_unref(rest);
  }
  EXPECT_TRUE(gst_app_sink_is_eos(GST_APP_SINK(k)));
  GstBus *bus = gst_element_get_bus(sub);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 2 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  ASSERT_TRUE(m);
  EXPECT_EQ(GST_MESSAGE_TYPE(m), GST_MESSAGE_EOS);
  gst_message_unref(m);
  gst_object_unref(bus);
  gst_element_set_state(sub, GST_STATE_NULL);
  gst_object_unref(k);
  gst_object_unref(sub);
}

TEST(Edge, NoPublisherIsAnErrorNamingIt) {
  const uint16_t port = free_port();
  auto r = nns::test::run_pipeline(
      "edgesrc dest-host=127.0.0.1 dest-port=" + std::to_string(port) + " ! fakesink", 5);
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("cannot subscribe to the edgesink: cannot connect to 127.0.0.1:" +
                              std::to_string(port)),
            std::string::npos)
      << r.error_text;
}

TEST(Edge, WaitConnectionTimesOut) {
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=1 ! edgesink host=127.0.0.1 port=0 wait-connection=true "
      "connection-timeout=200",
      5);
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("no edgesrc connected within connection-timeout=200 ms"),
            std::string::npos)
      << r.error_text;
}

TEST(Edge, OtherConnectTypesSayWhatTheyNeed) {
  // HYBRID works (tests/edge/hybrid_test.cc); without a topic it says what is missing.
  auto h = nns::test::run_pipeline(
      "videotestsrc num-buffers=1 ! edgesink port=0 connect-type=HYBRID", 5);
  EXPECT_TRUE(h.error);
  EXPECT_NE(h.error_text.find("connect-type HYBRID needs the topic property"), std::string::npos)
      << h.error_text;
  // MQTT (edge_mqtt_test.cc) and CUSTOM (edge_custom_test.cc) likewise.
  auto c = nns::test::run_pipeline("videotestsrc num-buffers=1 ! edgesink connect-type=CUSTOM", 5);
  EXPECT_NE(c.error_text.find("connect-type CUSTOM needs the custom-lib property"),
            std::string::npos)
      << c.error_text;
  auto r = nns::test::run_pipeline("edgesrc connect-type=MQTT ! fakesink", 5);
  EXPECT_NE(r.error_text.find("connect-type MQTT needs the topic property"), std::string::npos)
      << r.error_text;
}

TEST(Edge, NoSubscriberDropsWithoutWaiting) {
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=5 ! edgesink host=127.0.0.1 port=0 sync=false", 5);
  EXPECT_TRUE(r.eos) << r.error_text;
}

namespace {
// Two tensors, 3:4:2 uint8 and 5 float32 (44 bytes), as our edgesink announces them.
const char *kTwoTensors =
    "other/tensors,format=static,num_tensors=2,dimensions=(string)\"3:4:2,5\","
    "types=(string)\"uint8,float32\",framerate=(fraction)0/1";

// A subscriber `edgesrc ! <filter> ! appsink` of a publisher of kTwoTensors; returns the
// subscriber's first sample (nullptr if none came) and its bus error text in `error`.
GstSample *subscribe_with_filter(const std::string &filter, std::string *error) {
  const uint16_t port = free_port();
  AppPipeline pub(
      "edgesink host=127.0.0.1 port=" + std::to_string(port) + " wait-connection=true sync=false",
      kTwoTensors, true);
  pub.play();
  for (int i = 0; i < 200 && !port_open(port); ++i) std::this_thread::sleep_for(10ms);
  std::thread feeder([&] {
    for (int n = 0; n < 2; ++n) pub.push(std::vector<uint8_t>(44, static_cast<uint8_t>(n)), 0);
  });
  std::this_thread::sleep_for(50ms);
  GstElement *sub =
      gst_parse_launch(("edgesrc name=s dest-host=127.0.0.1 dest-port=" + std::to_string(port) +
                        " ! " + filter + " ! appsink name=k sync=false")
                           .c_str(),
                       nullptr);
  EXPECT_TRUE(sub);
  if (!sub) {
    feeder.join();
    return nullptr;
  }
  gst_element_set_state(sub, GST_STATE_PLAYING);
  GstElement *k = gst_bin_get_by_name(GST_BIN(sub), "k");
  feeder.join();
  pub.push(std::vector<uint8_t>(44, 7), 0);
  GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(k), 3 * GST_SECOND);
  GstBus *bus = gst_element_get_bus(sub);
  if (GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR)) {
    GError *e = nullptr;
    gchar *dbg = nullptr;
    gst_message_parse_error(m, &e, &dbg);
    *error = std::string(e->message) + " | " + (dbg ? dbg : "");
    g_error_free(e);
    g_free(dbg);
    gst_message_unref(m);
  }
  gst_object_unref(bus);
  pub.stop();
  gst_element_set_state(sub, GST_STATE_NULL);
  gst_object_unref(k);
  gst_object_unref(sub);
  return s;
}
}  // namespace

// A capsfilter written as upstream's tests write several tensors ('.' between them, no quotes)
// negotiates with the publisher's caps: the same config, the filter's spelling downstream.
TEST(Edge, DotSpelledCapsfilterAfterEdgesrc) {
  std::string error;
  GstSample *s = subscribe_with_filter(
      "other/tensors,format=static,num_tensors=2,types=uint8.float32,dimensions=3:4:2:1.5,"
      "framerate=0/1",
      &error);
  ASSERT_TRUE(s) << error;
  GstCaps *caps = gst_sample_get_caps(s);
  nns::gst::CapsPtr want(gst_caps_from_string(kTwoTensors));
  EXPECT_TRUE(nns::gst::config_from_caps(caps).same_as(nns::gst::config_from_caps(want.get())))
      << nns::gst::caps_to_string(caps);
  const GstStructure *st = gst_caps_get_structure(caps, 0);
  EXPECT_STREQ(gst_structure_get_string(st, "types"), "uint8.float32");
  EXPECT_STREQ(gst_structure_get_string(st, "dimensions"), "3:4:2:1.5");
  std::vector<uint8_t> bytes(gst_buffer_get_size(gst_sample_get_buffer(s)));
  gst_buffer_extract(gst_sample_get_buffer(s), 0, bytes.data(), bytes.size());
  EXPECT_EQ(bytes.size(), 44u);
  gst_sample_unref(s);
}

// The same filter with another dimension fails, naming the publisher's caps and the filter's.
TEST(Edge, DotSpelledCapsfilterWithOtherDimensionsFails) {
  std::string error;
  GstSample *s = subscribe_with_filter(
      "other/tensors,format=static,num_tensors=2,types=uint8.float32,dimensions=3:4:2.6", &error);
  EXPECT_FALSE(s);
  if (s) gst_sample_unref(s);
  EXPECT_NE(error.find("3:4:2\\,5"), std::string::npos) << error;
  EXPECT_NE(error.find("3:4:2.6"), std::string::npos) << error;
}

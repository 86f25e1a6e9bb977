// SPDX-License-Identifier: LGPL-2.1-only
// edgesink / edgesrc with connect-type=MQTT through a real mosquitto started by the test:
// publisher and subscriber in separate processes, exact payloads, caps other than tensors,
// nnstreamer-edge's payload layout and topic, a broker restart, and malformed messages on the
// topic (each an error naming the topic and what was wrong).
#include <cstring>
#include <map>
#include <mutex>

#include "../mqtt/mosquitto_broker.h"
#include "edge/edge_data.h"
#include "edge_test_util.h"
#include "mqtt/mqtt_client.h"
#include "support/harness.h"

using namespace edge_test;

namespace {

std::string unique_topic(const char *name) {
  return std::string("mqtt_") + name + "_" + std::to_string(getpid());
}

std::string sub_props(const mqtt_test::Broker &b, const std::string &topic) {
  return "connect-type=MQTT dest-host=127.0.0.1 dest-port=" + b.port_str() + " topic=" + topic;
}

// A file of `n` blocks of `block` bytes, each block distinct.
void write_blocks(const std::string &path, int n, int block, std::string *bytes) {
  bytes->clear();
  for (int i = 0; i < n * block; ++i)
    bytes->push_back(static_cast<char>((i * 7 + i / block) & 0xff));
  std::ofstream(path, std::ios::binary) << *bytes;
}

}  // namespace

TEST(EdgeChild, Run) {
  edge_test::run_child();
}

TEST(EdgeMqtt, PublisherInAnotherProcessExactBytes) {
  mqtt_test::Broker broker;
  MQTT_REQUIRE_BROKER(broker);
  const std::string topic = unique_topic("exact");
  SubPipeline sub(sub_props(broker, topic));
  ASSERT_TRUE(sub.play());  // subscribed before the publisher exists
  std::string want;
  TempFile in_file("edge_mqtt_in.bin");
  const std::string &in = in_file.path;
  write_blocks(in, 12, 100, &want);
  Child pub("filesrc location=" + in + " blocksize=100 ! application/octet-stream ! edgesink " +
                sub_props(broker, topic) + " sync=false",
            "mqtt_pub");
  std::string got, caps;
  for (int i = 0; i < 12; ++i) {
    std::string b;
    ASSERT_TRUE(sub.pull(&b, i == 0 ? &caps : nullptr)) << "buffer " << i << "\n" << pub.log();
    EXPECT_EQ(b.size(), 100u);
    got += b;
  }
  EXPECT_EQ(got, want);
  EXPECT_EQ(caps, "application/octet-stream");
  EXPECT_EQ(pub.wait_exit(), 0) << pub.log();
}

TEST(EdgeMqtt, SubscriberInAnotherProcessTakesVideoCaps) {
  mqtt_test::Broker broker;
  MQTT_REQUIRE_BROKER(broker);
  const std::string topic = unique_topic("video");
  TempFile out_file("edgesrc_out_mqtt.bin");
  const std::string &out = out_file.path;
  // The subscriber process prints the caps it got and stores the frames.
  Child sub("edgesrc " + sub_props(broker, topic) +
                " num-buffers=3 ! video/x-raw,format=GRAY8 ! filesink location=" + out,
            "mqtt_sub");
  AppPipeline pub("edgesink " + sub_props(broker, topic) + " sync=false",
                  "video/x-raw,format=GRAY8,width=4,height=2,framerate=0/1", true);
  pub.play();
  // The subscriber may join late: the retained message gives it the newest frame, so keep
  // publishing (each frame distinct) until it has three.
  std::string want_tail;
  int n = 0;
  for (; n < 400 && !sub.exited(); ++n) {
    ASSERT_EQ(pub.push(std::vector<uint8_t>(8, static_cast<uint8_t>(n)), n * GST_MSECOND),
              GST_FLOW_OK);
    std::this_thread::sleep_for(20ms);
  }
  ASSERT_EQ(sub.wait_exit(), 0) << sub.log();
  const std::string got = slurp(out);
  ASSERT_EQ(got.size(), 24u);
  // Three consecutive frames of the sequence, 8 equal bytes each.
  for (int f = 0; f < 3; ++f) {
    EXPECT_EQ(got.substr(f * 8, 8), std::string(8, got[f * 8])) << f;
    if (f) {
      EXPECT_EQ(static_cast<uint8_t>(got[f * 8]), static_cast<uint8_t>(got[f * 8 - 8] + 1));
    }
  }
}

TEST(EdgeMqtt, PayloadAndTopicAreNnstreamerEdges) {
  mqtt_test::Broker broker;
  MQTT_REQUIRE_BROKER(broker);
  const std::string topic = unique_topic("layout");
  std::mutex m;
  std::vector<std::pair<std::string, std::string>> got;  // topic, payload
  nns::mqtt::Client peek({"127.0.0.1", broker.port(), "edge-mqtt-peek", 60, true},
                         [&](const std::string &t, const uint8_t *d, std::size_t n) {
                           std::lock_guard<std::mutex> l(m);
                           got.emplace_back(t, std::string(reinterpret_cast<const char *>(d), n));
                         });
  peek.subscribe("edge/inference/+/" + topic + "/#", 1);
  peek.start();
  ASSERT_TRUE(peek.wait_connected(std::chrono::seconds(5)));
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=1 pattern=white ! video/x-raw,format=GRAY8,width=2,height=2 ! "
      "edgesink sync=false " +
          sub_props(broker, topic),
      10);
  ASSERT_TRUE(r.eos) << r.error_text;
  for (int i = 0; i < 100; ++i) {
    {
      std::lock_guard<std::mutex> l(m);
      if (got.size() >= 2) break;
    }
    std::this_thread::sleep_for(20ms);
  }
  peek.stop();
  ASSERT_EQ(got.size(), 2u);  // the frame, then the empty message clearing the retained one
  const std::string &t = got[0].first, &p = got[0].second;
  EXPECT_EQ(t.rfind("edge/inference/device-", 0), 0u) << t;
  EXPECT_EQ(t.substr(t.size() - topic.size() - 2), "/" + topic + "/") << t;
  EXPECT_EQ(got[1].first, t);
  EXPECT_TRUE(got[1].second.empty());
  // GRAY8 2x2 rows are 4-byte aligned: 8 bytes, videotestsrc's white is 235 (0xeb).
  const std::string caps =
      "video/x-raw, format=(string)GRAY8, width=(int)2, height=(int)2, "
      "framerate=(fraction)30/1, multiview-mode=(string)mono, pixel-aspect-ratio=(fraction)1/1, "
      "interlace-mode=(string)progressive";
  ASSERT_GE(p.size(), 2080u + 8);
  EXPECT_EQ(p.substr(0, 4), std::string("\xda\xed\xda\xed", 4));
  EXPECT_EQ(p.substr(8, 8), std::string("\x02\x00\x00\x06\x00\x00\xdd\xef", 8));
  EXPECT_EQ(p.substr(16, 4), std::string("\x01\x00\x00\x00", 4));
  EXPECT_EQ(p.substr(24, 8), std::string("\x08\x00\x00\x00\x00\x00\x00\x00", 8));
  EXPECT_EQ(p.substr(2080, 2), "\xeb\xeb");
  nns::edge::Message msg;
  std::string why;
  ASSERT_TRUE(nns::edge::parse_data(reinterpret_cast<const uint8_t *>(p.data()), p.size(), {}, {},
                                    &msg, &why))
      << why;
  auto c = msg.meta.get("caps");
  ASSERT_TRUE(c);
  GstCaps *a = gst_caps_from_string(c->c_str()), *b = gst_caps_from_string(caps.c_str());
  EXPECT_TRUE(gst_caps_is_equal(a, b)) << *c;
  gst_caps_unref(a);
  gst_caps_unref(b);
}

TEST(EdgeMqtt, BrokerRestartReconnectsBothSides) {
  mqtt_test::Broker broker;
  MQTT_REQUIRE_BROKER(broker);
  const std::string topic = unique_topic("restart");
  SubPipeline sub(sub_props(broker, topic));
  ASSERT_TRUE(sub.play());
  Child pub(
      "videotestsrc is-live=true num-buffers=200 ! "
      "video/x-raw,format=GRAY8,width=4,height=2,framerate=20/1 ! edgesink sync=false " +
          sub_props(broker, topic),
      "mqtt_restart");
  std::string b;
  ASSERT_TRUE(sub.pull(&b)) << pub.log();
  broker.stop();
  // Drain what was in flight, then nothing arrives while the broker is away.
  while (sub.pull(&b, nullptr, GST_SECOND / 2)) {
  }
  ASSERT_TRUE(broker.start());
  // Both reconnect (1..4 s back-off) and frames flow again.
  ASSERT_TRUE(sub.pull(&b, nullptr, 15 * GST_SECOND)) << pub.log();
  ASSERT_TRUE(sub.pull(&b, nullptr, 5 * GST_SECOND));
  EXPECT_EQ(b.size(), 8u);
  std::string warnings;
  EXPECT_EQ(sub.error(GST_SECOND / 10, &warnings), "");
  EXPECT_NE(warnings.find("lost the MQTT broker 127.0.0.1:" + broker.port_str()), std::string::npos)
      << warnings;
  pub.kill_now();
}

TEST(EdgeMqtt, MalformedMessagesAreErrorsNamingTheTopic) {
  mqtt_test::Broker broker;
  MQTT_REQUIRE_BROKER(broker);
  static const uint8_t one = 1;
  nns::edge::OutFrame f;
  f.mems = {{&one, 1}};
  const auto good = nns::edge::serialize_data(f);
  auto huge = good;
  huge[24 + 4] = 1;  // memory 0 claims 4 GiB + 1
  auto trunc = good;
  trunc.resize(good.size() - 1);
  const std::vector<std::pair<std::vector<uint8_t>, std::string>> cases = {
      {{'g', 'a', 'r', 'b', 'a', 'g', 'e'}, "7 bytes, shorter than the 2080-byte edge data header"},
      {huge, "memory 0 claims 4294967297 bytes, over the frame limit of 1073741824"},
      {trunc, "memory 0 claims 1 bytes but only 0 are left in the 2080-byte message (truncated)"},
  };
  int i = 0;
  for (const auto &[bytes, want] : cases) {
    const std::string topic = unique_topic("bad") + std::to_string(i++);
    SubPipeline sub(sub_props(broker, topic));
    ASSERT_TRUE(sub.play());
    nns::mqtt::Client c({"127.0.0.1", broker.port(), "edge-mqtt-bad", 60, true});
    c.start();
    ASSERT_TRUE(c.wait_connected(std::chrono::seconds(5)));
    const std::string t = "edge/inference/device-x/" + topic + "/";
    ASSERT_TRUE(c.publish(t, bytes.data(), bytes.size(), 1, false));
    c.flush(std::chrono::seconds(2));
    c.stop();
    const std::string err = sub.error(5 * GST_SECOND);
    EXPECT_NE(
        err.find("message on topic '" + t + "' (MQTT broker 127.0.0.1:" + broker.port_str() + ", " +
                 std::to_string(bytes.size()) + " bytes) is not nnstreamer-edge data: " + want),
        std::string::npos)
        << err;
  }
}

TEST(EdgeMqtt, SettingsErrors) {
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=1 ! edgesink connect-type=MQTT dest-port=1", 5);
  EXPECT_NE(r.error_text.find("connect-type MQTT needs the topic property"), std::string::npos)
      << r.error_text;
  const uint16_t port = free_port();
  r = nns::test::run_pipeline("edgesrc connect-type=MQTT topic=t dest-host=127.0.0.1 dest-port=" +
                                  std::to_string(port) + " ! fakesink",
                              15);
  EXPECT_NE(r.error_text.find("connect-type MQTT: cannot connect to the MQTT broker 127.0.0.1:" +
                              std::to_string(port)),
            std::string::npos)
      << r.error_text;
}

TEST(EdgeMqtt, TensorsKeepOneMemoryEach) {
  mqtt_test::Broker broker;
  MQTT_REQUIRE_BROKER(broker);
  const std::string topic = unique_topic("tensors");
  SubPipeline sub(sub_props(broker, topic));
  ASSERT_TRUE(sub.play());
  const char *caps =
      "other/tensors,format=static,num_tensors=2,dimensions=(string)4:1.2:1,"
      "types=(string)uint8.uint8,framerate=(fraction)0/1";
  AppPipeline pub("edgesink sync=false " + sub_props(broker, topic), caps, true);
  pub.play();
  GstBuffer *b = gst_buffer_new();
  gst_buffer_append_memory(
      b, gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, const_cast<char *>("abcd"), 4, 0, 4,
                                nullptr, nullptr));
  gst_buffer_append_memory(
      b, gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, const_cast<char *>("xy"), 2, 0, 2,
                                nullptr, nullptr));
  ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(pub.src), b), GST_FLOW_OK);
  GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sub.sink), 5 * GST_SECOND);
  ASSERT_TRUE(s);
  GstBuffer *got = gst_sample_get_buffer(s);
  ASSERT_EQ(gst_buffer_n_memory(got), 2u);
  EXPECT_EQ(gst_buffer_peek_memory(got, 0)->size, 4u);
  EXPECT_EQ(gst_buffer_peek_memory(got, 1)->size, 2u);
  char bytes[6];
  gst_buffer_extract(got, 0, bytes, 6);
  EXPECT_EQ(std::string(bytes, 6), "abcdxy");
  GstCaps *want = gst_caps_from_string(caps);
  EXPECT_TRUE(gst_caps_is_equal(gst_sample_get_caps(s), want));
  gst_caps_unref(want);
  gst_sample_unref(s);
}

// SPDX-License-Identifier: LGPL-2.1-only
// connect-type HYBRID with a real mosquitto started by the test: query servers in two other
// processes announce themselves on the broker, the client here discovers them, talks TCP to
// one and fails over to the other when it is killed; the announcement bytes are
// nnstreamer-edge's.
#include <cstring>
#include <mutex>

#include "../mqtt/mosquitto_broker.h"
#include "edge_test_util.h"
#include "mqtt/mqtt_client.h"
#include "support/harness.h"

using namespace edge_test;

namespace {

const char *kCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)64:1,types=(string)uint8,"
    "framerate=(fraction)0/1";

std::string server_desc(uint16_t port, const mqtt_test::Broker &b, const std::string &topic) {
  return "tensor_query_serversrc connect-type=HYBRID host=127.0.0.1 port=" + std::to_string(port) +
         " dest-host=127.0.0.1 dest-port=" + b.port_str() + " topic=" + topic +
         " ! tensor_query_serversink connect-type=HYBRID";
}

// Retained announcements on the broker for `topic`: announcement topic -> payload.
std::map<std::string, std::string> announcements(const mqtt_test::Broker &b,
                                                 const std::string &topic, std::size_t want) {
  std::mutex m;
  std::map<std::string, std::string> got;
  nns::mqtt::Client c({"127.0.0.1", b.port(), "hybrid-test-peek", 60, true},
                      [&](const std::string &t, const uint8_t *d, std::size_t n) {
                        std::lock_guard<std::mutex> l(m);
                        got[t] = std::string(reinterpret_cast<const char *>(d), n);
                      });
  c.subscribe("edge/inference/+/" + topic + "/#", 1);
  c.start();
  c.wait_connected(std::chrono::seconds(5));
  for (int i = 0; i < 100; ++i) {
    {
      std::lock_guard<std::mutex> l(m);
      if (got.size() >= want) break;
    }
    std::this_thread::sleep_for(20ms);
  }
  c.stop();
  return got;
}

}  // namespace

TEST(EdgeChild, Run) {
  edge_test::run_child();
}

TEST(Hybrid, ServerAnnouncesItselfAsNNStreamerEdgeDoes) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "ann" + std::to_string(getpid());
  const uint16_t port = free_port();
  auto server = std::make_unique<Child>(server_desc(port, b, topic), "hyb_ann");
  ASSERT_TRUE(server->wait_port(port)) << server->log();
  auto got = announcements(b, topic, 1);
  ASSERT_EQ(got.size(), 1u) << server->log();
  const std::string want_prefix = "edge/inference/device-";
  EXPECT_EQ(got.begin()->first.rfind(want_prefix, 0), 0u) << got.begin()->first;
  EXPECT_EQ(got.begin()->first.substr(got.begin()->first.size() - topic.size() - 2),
            "/" + topic + "/");
  EXPECT_EQ(got.begin()->second, "127.0.0.1:" + std::to_string(port) + std::string(1, '\0'));
}

TEST(Hybrid, ClientDiscoversAndFailsOverToAnotherServer) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "fo" + std::to_string(getpid());
  const uint16_t pa = free_port();
  auto a = std::make_unique<Child>(server_desc(pa, b, topic), "hyb_a");
  ASSERT_TRUE(a->wait_port(pa)) << a->log();
  ASSERT_EQ(announcements(b, topic, 1).size(), 1u);
  AppPipeline c(
      "tensor_query_client connect-type=HYBRID dest-host=127.0.0.1 dest-port=" + b.port_str() +
          " topic=" + topic + " host=127.0.0.1 port=0 timeout=300 max-request=1",
      kCaps);
  c.play();
  int pushed = 0, received = 0;
  auto step = [&] {
    std::vector<uint8_t> v(64, static_cast<uint8_t>(pushed));
    c.push(v, pushed * GST_MSECOND);
    ++pushed;
    std::vector<uint8_t> got;
    while (c.pull(&got, nullptr, 0)) {
      EXPECT_EQ(got.size(), 64u);
      ++received;
    }
    std::this_thread::sleep_for(5ms);
  };
  // At least 30 steps; more (bounded) while a loaded machine answers late.
  for (int i = 0; i < 30 || (i < 400 && received <= 10); ++i) step();
  EXPECT_GT(received, 10) << joined(c.messages(GST_MESSAGE_ERROR)) << a->log();
  // A second server on the same topic; then the first one dies (its retained announcement stays,
  // as after a crash): the client must move to the second.
  const uint16_t pb = free_port();
  Child bsrv(server_desc(pb, b, topic), "hyb_b");
  ASSERT_TRUE(bsrv.wait_port(pb)) << bsrv.log();
  ASSERT_EQ(announcements(b, topic, 2).size(), 2u);
  a->kill_now();
  const int before = received;
  for (int i = 0; i < 400 && received < before + 10; ++i) step();
  EXPECT_GE(received, before + 10) << joined(c.messages(GST_MESSAGE_ERROR));
  const auto warnings = joined(c.messages(GST_MESSAGE_WARNING));
  EXPECT_NE(warnings.find("lost the connection to the query server (server 127.0.0.1:" +
                          std::to_string(pa)),
            std::string::npos)
      << warnings;
  const auto infos = joined(c.messages(GST_MESSAGE_INFO));
  EXPECT_NE(infos.find("reconnected to the query server 127.0.0.1:" + std::to_string(pb)),
            std::string::npos)
      << infos;
  EXPECT_LT(c.stop().count(), 3000);
}

TEST(Hybrid, NoServerOnTheTopicIsNamed) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  AppPipeline c("tensor_query_client connect-type=HYBRID dest-host=127.0.0.1 dest-port=" +
                    b.port_str() + " topic=nobody host=127.0.0.1 port=0 timeout=300",
                kCaps);
  c.play();
  c.push(std::vector<uint8_t>(64, 1), 0);
  std::string errors;
  for (int i = 0; i < 300 && errors.empty(); ++i) {  // the first connect waits 5 s
    errors = joined(c.messages(GST_MESSAGE_ERROR));
    std::this_thread::sleep_for(50ms);
  }
  EXPECT_NE(
      errors.find("no server announcing topic 'nobody' on the broker 127.0.0.1:" + b.port_str()),
      std::string::npos)
      << errors;
}

// edgesink / edgesrc with HYBRID: the subscriber (another process) finds the publisher through
// the broker and gets its stream byte for byte.
TEST(Hybrid, EdgesrcFindsEdgesinkThroughTheBroker) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "pub" + std::to_string(getpid());
  const uint16_t port = free_port();
  const std::string out =
      std::string(::testing::TempDir()) + "hybrid_edgesrc_" + std::to_string(getpid()) + ".bin";
  AppPipeline pub("edgesink connect-type=HYBRID host=127.0.0.1 port=" + std::to_string(port) +
                      " dest-host=127.0.0.1 dest-port=" + b.port_str() + " topic=" + topic +
                      " wait-connection=true connection-timeout=10000 sync=false",
                  "application/octet-stream", true);
  pub.play();
  ASSERT_EQ(announcements(b, topic, 1).size(), 1u) << joined(pub.messages(GST_MESSAGE_ERROR));
  Child sub("edgesrc connect-type=HYBRID dest-host=127.0.0.1 dest-port=" + b.port_str() +
                " topic=" + topic + " num-buffers=10 ! filesink location=" + out,
            "hyb_sub");
  std::string want;
  for (int n = 0; n < 10; ++n) {
    std::vector<uint8_t> p(50 + n, static_cast<uint8_t>(n * 7));
    want.append(reinterpret_cast<const char *>(p.data()), p.size());
    ASSERT_EQ(pub.push(p, n * GST_MSECOND), GST_FLOW_OK);
    std::this_thread::sleep_for(5ms);
  }
  ASSERT_EQ(sub.wait_exit(), 0) << sub.log();
  EXPECT_EQ(slurp(out), want) << sub.log();
  std::remove(out.c_str());
}

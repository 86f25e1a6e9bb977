// SPDX-License-Identifier: LGPL-2.1-only
// tensor_query_client load-balance (docs/elements/tensor_query_client.md): clients in this
// process spread their requests over query servers in other processes, found through a real
// mosquitto (HYBRID) or a static dest-host list; answers come back once each, in input order,
// equal to what the servers' model computes; a server killed mid-run loses no frame with
// resend-on-failover (and its losses are counted without).
#include <atomic>
#include <map>
#include <mutex>

#include "../mqtt/mosquitto_broker.h"
#include "mqtt/mqtt_client.h"
#include "edge_test_util.h"
#include "support/harness.h"

using namespace edge_test;

namespace {

const char *kCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)64:1,types=(string)uint8,"
    "framerate=(fraction)0/1";

// The servers' "model": a tensor_transform, computed locally by expected().
const char *kModel = "tensor_transform mode=arithmetic option=add:3 ! ";

std::vector<uint8_t> frame(int client, int n) {
  std::vector<uint8_t> v(64);
  for (std::size_t j = 0; j < v.size(); ++j) v[j] = static_cast<uint8_t>(n * 7 + j);
  v[0] = static_cast<uint8_t>(client);
  v[1] = static_cast<uint8_t>(n & 0xff);
  v[2] = static_cast<uint8_t>(n >> 8);
  return v;
}

std::vector<uint8_t> expected(int client, int n) {
  auto v = frame(client, n);
  for (auto &x : v) x = static_cast<uint8_t>(x + 3);
  return v;
}

// Caps of a batch of `n` 64:1 requests.
std::string batch_caps(int n) {
  return "other/tensors,format=static,num_tensors=1,dimensions=(string)64:" + std::to_string(n) +
         ",types=(string)uint8,framerate=(fraction)0/1";
}

// `batch` > 1: a batching server (max-batch, batch-timeout 1 ms); 1: as an upstream server.
std::string hybrid_server(uint16_t port, const mqtt_test::Broker &b, const std::string &topic,
                          int batch = 1) {
  return "tensor_query_serversrc connect-type=HYBRID host=127.0.0.1 port=" + std::to_string(port) +
         " dest-host=127.0.0.1 dest-port=" + b.port_str() + " topic=" + topic +
         (batch > 1 ? " max-batch=" + std::to_string(batch) + " batch-timeout=1000" : "") + " ! " +
         batch_caps(batch) + " ! " + kModel + "tensor_query_serversink connect-type=HYBRID";
}

// A slow server (each request held `sleep_us`) announcing `topic`, as hybrid_server.
std::string slow_hybrid_server(uint16_t port, const mqtt_test::Broker &b, const std::string &topic,
                               int sleep_us) {
  return "tensor_query_serversrc connect-type=HYBRID host=127.0.0.1 port=" + std::to_string(port) +
         " dest-host=127.0.0.1 dest-port=" + b.port_str() + " topic=" + topic + " ! " + kCaps +
         " ! " + kModel + "identity sleep-time=" + std::to_string(sleep_us) +
         " ! tensor_query_serversink connect-type=HYBRID";
}

std::string tcp_server(uint16_t port) {
  return server_pipeline(port, std::string(kCaps) + " ! " + kModel);
}

struct Servers {
  std::vector<uint16_t> ports;
  std::vector<std::unique_ptr<Child>> procs;
  void add(const std::string &desc, uint16_t port, const std::string &tag) {
    ports.push_back(port);
    procs.push_back(std::make_unique<Child>(desc, tag + std::to_string(procs.size())));
  }
  ::testing::AssertionResult wait() {
    for (std::size_t i = 0; i < procs.size(); ++i)
      if (!procs[i]->wait_port(ports[i]))
        return ::testing::AssertionFailure() << "server " << i << ": " << procs[i]->log();
    return ::testing::AssertionSuccess();
  }
  std::string logs() {
    std::string s;
    for (auto &p : procs) s += p->log();
    return s;
  }
};

// Runs `clients` client pipelines pushing `frames` frames each (paced by `gap`), calls
// `mid()` once the clients together received `mid_at` answers, then checks every client got
// its answers in its own order, each equal to the model's. Returns per-client stats.
struct RunResult {
  std::vector<guint64> received, lost, dropped;
  std::vector<std::string> warnings, errors, infos;
  std::vector<std::string> servers;  // stats, serialized (for failure messages)
  // Per client, per server: the "servers" entries of stats.
  std::vector<std::vector<std::map<std::string, guint64>>> per_server;
  guint64 sum(const char *field) const {
    guint64 n = 0;
    for (auto &c : per_server)
      for (auto &sv : c) n += sv.at(field);
    return n;
  }
};

std::vector<std::map<std::string, guint64>> server_rows(GstStructure *st) {
  std::vector<std::map<std::string, guint64>> out;
  const GValue *arr = gst_structure_get_value(st, "servers");
  if (!arr) return out;
  for (guint i = 0; i < gst_value_array_get_size(arr); ++i) {
    const GstStructure *one = gst_value_get_structure(gst_value_array_get_value(arr, i));
    std::map<std::string, guint64> row;
    for (const char *f : {"sent", "received", "lost", "resent", "in-flight"}) {
      guint64 v = 0;
      gst_structure_get_uint64(one, f, &v);
      row[f] = v;
    }
    out.push_back(row);
  }
  return out;
}

RunResult run_clients(int clients, int frames, const std::string &client_desc,
                      std::chrono::microseconds gap, std::function<void()> mid = {},
                      guint64 mid_at = 0) {
  RunResult r;
  std::vector<std::unique_ptr<AppPipeline>> cs;
  for (int c = 0; c < clients; ++c) {
    cs.push_back(std::make_unique<AppPipeline>(client_desc, kCaps));
    cs.back()->play();
  }
  std::vector<std::thread> pushers;
  for (int c = 0; c < clients; ++c)
    pushers.emplace_back([&, c] {
      for (int n = 0; n < frames; ++n) {
        cs[c]->push(frame(c, n), static_cast<GstClockTime>(n) * GST_MSECOND);
        std::this_thread::sleep_for(gap);
      }
      cs[c]->eos();
    });
  if (mid) {
    const auto end = std::chrono::steady_clock::now() + 30s;
    for (;;) {
      guint64 total = 0;
      for (auto &c : cs) {
        GstStructure *st = c->stats();
        total += stat(st, "received");
        gst_structure_free(st);
      }
      if (total >= mid_at || std::chrono::steady_clock::now() > end) break;
      std::this_thread::sleep_for(2ms);
    }
    mid();
  }
  for (auto &t : pushers) t.join();
  for (int c = 0; c < clients; ++c) {
    int next = 0;  // answers must come in input order: frame numbers only go up
    std::vector<uint8_t> got;
    GstClockTime pts = 0;
    guint64 n_got = 0;
    while (cs[c]->pull(&got, &pts, 20 * GST_SECOND)) {
      if (got.size() != 64u) {
        ADD_FAILURE() << "client " << c << ": answer of " << got.size() << " bytes";
        break;
      }
      // Frame number: bytes 1-2 carry it (+3 from the model).
      const int num = static_cast<uint8_t>(got[1] - 3) | (static_cast<uint8_t>(got[2] - 3) << 8);
      EXPECT_GE(num, next) << "client " << c << ": answer for frame " << num << " after frame "
                           << next - 1;
      if (num < frames) {
        EXPECT_EQ(got, expected(c, num)) << "client " << c << " frame " << num;
      }
      EXPECT_EQ(pts, static_cast<GstClockTime>(num) * GST_MSECOND) << "client " << c;
      next = num + 1;
      ++n_got;
      if (static_cast<int>(n_got) == frames) break;
    }
    GstStructure *st = cs[c]->stats();
    EXPECT_EQ(stat(st, "received"), n_got) << "client " << c;
    r.received.push_back(stat(st, "received"));
    r.lost.push_back(stat(st, "lost"));
    r.dropped.push_back(stat(st, "dropped"));
    r.per_server.push_back(server_rows(st));
    gchar *s = gst_structure_to_string(st);
    r.servers.push_back(s);
    g_free(s);
    gst_structure_free(st);
    r.warnings.push_back(joined(cs[c]->messages(GST_MESSAGE_WARNING)));
    r.errors.push_back(joined(cs[c]->messages(GST_MESSAGE_ERROR)));
    r.infos.push_back(joined(cs[c]->messages(GST_MESSAGE_INFO)));
  }
  return r;
}

std::string hybrid_client(const mqtt_test::Broker &b, const std::string &topic,
                          const std::string &extra) {
  return "tensor_query_client connect-type=HYBRID dest-host=127.0.0.1 dest-port=" + b.port_str() +
         " topic=" + topic + " host=127.0.0.1 port=0 timeout=5000 max-request=8 " + extra;
}

// How many servers got requests from one client.
int servers_used(const std::vector<std::map<std::string, guint64>> &rows) {
  int n = 0;
  for (auto &r : rows) n += r.at("sent") > 0 ? 1 : 0;
  return n;
}

}  // namespace

TEST(EdgeChild, Run) {
  edge_test::run_child();
}

// 8 clients x 500 frames over 3 servers found through the broker (two batching, one as an
// upstream server): each frame answered once, in order, equal to the model; every server used.
TEST(QueryBalance, EightClientsThreeServersEveryFrameOnceInOrder) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "lb" + std::to_string(getpid());
  Servers s;
  for (int i = 0; i < 3; ++i) {
    const uint16_t port = free_port();
    s.add(hybrid_server(port, b, topic, i == 2 ? 1 : 4), port, "lb");
  }
  ASSERT_TRUE(s.wait());
  std::this_thread::sleep_for(200ms);  // the three announcements reach the broker
  const auto r = run_clients(8, 500, hybrid_client(b, topic, "load-balance=round-robin"), 200us);
  for (int c = 0; c < 8; ++c) {
    EXPECT_EQ(r.received[c], 500u)
        << "client " << c << " " << r.errors[c] << r.warnings[c] << s.logs();
    EXPECT_EQ(r.lost[c] + r.dropped[c], 0u) << r.servers[c];
    EXPECT_EQ(servers_used(r.per_server[c]), 3) << r.servers[c];
  }
}

// One of three servers killed mid-run: with resend-on-failover its requests in flight go to
// the others, and no frame is lost.
TEST(QueryBalance, KilledServerLosesNothingWithResend) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "lbk" + std::to_string(getpid());
  Servers s;
  for (int i = 0; i < 3; ++i) {
    const uint16_t port = free_port();
    s.add(hybrid_server(port, b, topic, i == 0 ? 1 : 8), port, "lbk");
  }
  ASSERT_TRUE(s.wait());
  std::this_thread::sleep_for(200ms);
  const auto r = run_clients(
      8, 500, hybrid_client(b, topic, "load-balance=least-outstanding"), 1ms,
      [&] { s.procs[1]->kill_now(); }, 1200);
  for (int c = 0; c < 8; ++c) {
    EXPECT_EQ(r.received[c], 500u) << "client " << c << " " << r.errors[c] << r.warnings[c];
    EXPECT_EQ(r.lost[c], 0u) << r.servers[c];
    EXPECT_NE(r.warnings[c].find("lost the connection to the query server 127.0.0.1:" +
                                 std::to_string(s.ports[1])),
              std::string::npos)
        << r.warnings[c];
  }
  EXPECT_GT(r.sum("resent"), 0u)
      << "no request was in flight at the kill: the test did not test it";
}

// Static list, resend off: the killed server's requests in flight are counted as lost, the
// others still come in order; received + lost = frames.
TEST(QueryBalance, KilledServerWithoutResendCountsLost) {
  Servers s;
  std::string list;
  for (int i = 0; i < 3; ++i) {
    const uint16_t port = free_port();
    s.add(tcp_server(port), port, "lbs");
    list += (i ? "," : "") + std::string("127.0.0.1:") + std::to_string(port);
  }
  ASSERT_TRUE(s.wait());
  const auto r = run_clients(
      8, 500,
      "tensor_query_client dest-host=" + list +
          " host=127.0.0.1 port=0 timeout=5000 max-request=8 load-balance=round-robin "
          "resend-on-failover=false",
      1ms, [&] { s.procs[0]->kill_now(); }, 1200);
  guint64 lost = 0;
  for (int c = 0; c < 8; ++c) {
    EXPECT_EQ(r.received[c] + r.lost[c] + r.dropped[c], 500u) << r.servers[c] << r.errors[c];
    EXPECT_EQ(r.dropped[c], 0u) << r.servers[c];
    lost += r.lost[c];
  }
  EXPECT_GT(lost, 0u) << "no request was in flight at the kill: the test did not test it";
}

// A server that appears mid-run gets requests from then on.
TEST(QueryBalance, ServerThatAppearsIsUsed) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "lbn" + std::to_string(getpid());
  Servers s;
  const uint16_t p0 = free_port();
  s.add(hybrid_server(p0, b, topic), p0, "lbn");
  ASSERT_TRUE(s.wait());
  std::this_thread::sleep_for(100ms);
  const uint16_t p1 = free_port();
  const auto r = run_clients(
      1, 400, hybrid_client(b, topic, "load-balance=round-robin"), 2ms,
      [&] {
        s.add(hybrid_server(p1, b, topic), p1, "lbn");
        ASSERT_TRUE(s.wait());
      },
      50);
  EXPECT_EQ(r.received[0], 400u) << r.errors[0];
  EXPECT_EQ(servers_used(r.per_server[0]), 2) << r.servers[0];
  EXPECT_NE(r.infos[0].find("query server 127.0.0.1:" + std::to_string(p1) + " joined"),
            std::string::npos)
      << r.infos[0];
}

TEST(QueryBalance, BadServerListIsNamed) {
  AppPipeline c("tensor_query_client dest-host=127.0.0.1:1,:x port=0 load-balance=round-robin",
                kCaps);
  c.play();
  c.push(std::vector<uint8_t>(64, 1), 0);
  std::string errors;
  for (int i = 0; i < 100 && errors.empty(); ++i) {
    errors = joined(c.messages(GST_MESSAGE_ERROR));
    std::this_thread::sleep_for(20ms);
  }
  EXPECT_NE(errors.find("dest-host '127.0.0.1:1,:x': entry ':x' is not host or host:port"),
            std::string::npos)
      << errors;
}

// A server leaving through the broker only (its retained announcement cleared, as its will or
// its stop does; its TCP session stays up): the clients send it nothing more and re-send its
// requests in flight to the other server; no frame is lost or answered twice.
TEST(QueryBalance, ServerLeavingThroughTheBrokerIsDrainedAndResent) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "lbl" + std::to_string(getpid());
  Servers s;
  for (int i = 0; i < 2; ++i) {
    const uint16_t port = free_port();
    // Server 0 holds each request 20 ms: requests are in flight there when it leaves.
    s.add(i == 0 ? slow_hybrid_server(port, b, topic, 20000) : hybrid_server(port, b, topic), port,
          "lbl");
  }
  ASSERT_TRUE(s.wait());
  std::this_thread::sleep_for(200ms);
  // The announcement topic of server 0 (docs/hybrid.md): device-<pid>_<port>.
  const std::string announced = "edge/inference/device-" + std::to_string(s.procs[0]->pid()) + "_" +
                                std::to_string(s.ports[0]) + "/" + topic + "/";
  nns::mqtt::Client pub({"127.0.0.1", b.port(), "lbl_test_" + std::to_string(getpid()), 60, true});
  pub.start();
  ASSERT_TRUE(pub.wait_connected(5s)) << pub.why();
  const auto r = run_clients(
      4, 300, hybrid_client(b, topic, "load-balance=round-robin"), 1ms,
      [&] {
        ASSERT_TRUE(pub.publish(announced, nullptr, 0, 1, true)) << pub.why();
        pub.flush(2s);
      },
      120);
  for (int c = 0; c < 4; ++c) {
    EXPECT_EQ(r.received[c], 300u) << "client " << c << " " << r.errors[c] << r.warnings[c];
    EXPECT_EQ(r.lost[c] + r.dropped[c], 0u) << r.servers[c];
    EXPECT_NE(r.warnings[c].find("lost the connection to the query server 127.0.0.1:" +
                                 std::to_string(s.ports[0]) +
                                 " (its announcement was cleared on the broker)"),
              std::string::npos)
        << r.warnings[c];
  }
  EXPECT_GT(r.sum("resent"), 0u) << "no request was in flight when the server left";
  EXPECT_FALSE(s.procs[0]->exited()) << "the server process itself must still be up";
}

// A server that dies without stopping (SIGKILL) has its announcement cleared by the broker
// (its MQTT will: an empty retained message), so clients that come later do not try it.
TEST(QueryBalance, KilledServerIsForgottenThroughItsWill) {
  mqtt_test::Broker b;
  MQTT_REQUIRE_BROKER(b);
  const std::string topic = "lbw" + std::to_string(getpid());
  Servers s;
  for (int i = 0; i < 2; ++i) {
    const uint16_t port = free_port();
    s.add(hybrid_server(port, b, topic), port, "lbw");
  }
  ASSERT_TRUE(s.wait());
  // The retained announcements a new subscriber gets: "host:port" per server.
  auto announced = [&] {
    std::mutex m;
    std::set<std::string> got;
    nns::mqtt::Client sub({"127.0.0.1", b.port(), "lbw_sub_" + std::to_string(getpid()), 60, true},
                          [&](const std::string &, const uint8_t *data, std::size_t n) {
                            std::lock_guard<std::mutex> l(m);
                            if (n > 1)
                              got.insert(std::string(reinterpret_cast<const char *>(data), n - 1));
                          });
    sub.subscribe("edge/inference/+/" + topic + "/#", 1);
    sub.start();
    EXPECT_TRUE(sub.wait_connected(5s)) << sub.why();
    std::this_thread::sleep_for(300ms);
    sub.stop();
    std::lock_guard<std::mutex> l(m);
    return got;
  };
  const std::string a = "127.0.0.1:" + std::to_string(s.ports[0]),
                    c = "127.0.0.1:" + std::to_string(s.ports[1]);
  std::set<std::string> before;
  for (int i = 0; i < 20 && before.size() < 2; ++i) before = announced();
  ASSERT_EQ(before, (std::set<std::string>{a, c}));
  s.procs[0]->kill_now();
  std::set<std::string> after = announced();
  for (int i = 0; i < 10 && after.count(a); ++i) after = announced();
  EXPECT_EQ(after, std::set<std::string>{c})
      << "the killed server's announcement stayed: " << b.log();
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_query_client / tensor_query_serversrc / tensor_query_serversink over TCP on
// 127.0.0.1: the server runs in a second process (this binary re-executed), the clients here.
#include <atomic>
#include <cstring>

#include "edge/edge_io.h"
#include "edge_test_util.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

using namespace edge_test;

namespace {

const char *kCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)64:1,types=(string)uint8,"
    "framerate=(fraction)0/1";

std::vector<uint8_t> frame(int client, int n, std::size_t size = 64) {
  std::vector<uint8_t> v(size);
  for (std::size_t i = 0; i < size; ++i) v[i] = static_cast<uint8_t>(client * 31 + n * 7 + i);
  std::memcpy(v.data(), &client, sizeof client);
  std::memcpy(v.data() + 4, &n, sizeof n);
  return v;
}

std::string client_desc(uint16_t port, const std::string &extra = "") {
  return "tensor_query_client dest-host=127.0.0.1 dest-port=" + std::to_string(port) +
         " host=127.0.0.1 port=0 " + extra;
}

}  // namespace

TEST(EdgeChild, Run) {
  edge_test::run_child();
}

TEST(TensorQuery, RoundTripExactBytesAndTimestamps) {
  const uint16_t port = free_port();
  Child server(server_pipeline(port), "rt");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  AppPipeline c(client_desc(port, "timeout=2000"), kCaps);
  c.play();
  for (int n = 0; n < 5; ++n) ASSERT_EQ(c.push(frame(1, n), n * GST_MSECOND), GST_FLOW_OK);
  for (int n = 0; n < 5; ++n) {
    std::vector<uint8_t> got;
    GstClockTime pts = 0;
    ASSERT_TRUE(c.pull(&got, &pts)) << n << "\n" << joined(c.messages(GST_MESSAGE_ERROR));
    EXPECT_EQ(got, frame(1, n));
    EXPECT_EQ(pts, n * GST_MSECOND);
  }
  GstStructure *st = c.stats();
  EXPECT_EQ(stat(st, "sent"), 5u);
  EXPECT_EQ(stat(st, "received"), 5u);
  EXPECT_EQ(stat(st, "dropped"), 0u);
  gst_structure_free(st);
  GstPad *pad = gst_element_get_static_pad(c.sink, "sink");
  GstCaps *caps = gst_pad_get_current_caps(pad);
  gst_object_unref(pad);
  ASSERT_TRUE(caps);
  GstCaps *want = gst_caps_from_string(kCaps);
  EXPECT_TRUE(gst_caps_is_equal(caps, want)) << nns::gst::caps_to_string(caps);
  gst_caps_unref(want);
  gst_caps_unref(caps);
}

TEST(TensorQuery, EightClientsGetTheirOwnAnswersInOrder) {
  const uint16_t port = free_port();
  Child server(server_pipeline(port), "eight");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  constexpr int kClients = 8, kFrames = 1000;
  std::vector<std::unique_ptr<AppPipeline>> cs;
  for (int i = 0; i < kClients; ++i) {
    cs.push_back(std::make_unique<AppPipeline>(client_desc(port, "max-request=0"), kCaps));
    cs.back()->play();
  }
  std::vector<std::thread> pushers, pullers;
  std::vector<int> good(kClients, 0);
  std::vector<std::string> bad(kClients);
  for (int i = 0; i < kClients; ++i) {
    pushers.emplace_back([&, i] {
      for (int n = 0; n < kFrames; ++n) cs[i]->push(frame(i, n), n * GST_MSECOND);
      cs[i]->eos();
    });
    pullers.emplace_back([&, i] {
      for (int n = 0; n < kFrames; ++n) {
        std::vector<uint8_t> got;
        if (!cs[i]->pull(&got, nullptr, 20 * GST_SECOND)) {
          bad[i] = "timed out at frame " + std::to_string(n);
          return;
        }
        if (got != frame(i, n)) {
          int c = -1, k = -1;
          std::memcpy(&c, got.data(), 4);
          std::memcpy(&k, got.data() + 4, 4);
          bad[i] = "frame " + std::to_string(n) + " carries client " + std::to_string(c) +
                   " frame " + std::to_string(k);
          return;
        }
        ++good[i];
      }
    });
  }
  for (auto &t : pushers) t.join();
  for (auto &t : pullers) t.join();
  for (int i = 0; i < kClients; ++i) {
    EXPECT_EQ(good[i], kFrames) << "client " << i << ": " << bad[i] << "\n"
                                << joined(cs[i]->messages(GST_MESSAGE_ERROR));
    GstStructure *st = cs[i]->stats();
    EXPECT_EQ(stat(st, "received"), static_cast<guint64>(kFrames));
    gst_structure_free(st);
  }
}

TEST(TensorQuery, ServerKilledAndRestartedClientReconnects) {
  const uint16_t port = free_port();
  auto server = std::make_unique<Child>(server_pipeline(port), "restart1");
  ASSERT_TRUE(server->wait_port(port)) << server->log();
  AppPipeline c(client_desc(port, "timeout=300 max-request=1"), kCaps);
  c.play();
  int pushed = 0, received = 0;
  auto step = [&] {
    c.push(frame(0, pushed), pushed * GST_MSECOND);
    ++pushed;
    std::vector<uint8_t> got;
    while (c.pull(&got, nullptr, 0)) ++received;
    std::this_thread::sleep_for(5ms);
  };
  // At least 20 steps; more (bounded) while a loaded machine answers late.
  for (int i = 0; i < 20 || (i < 400 && received <= 10); ++i) step();
  EXPECT_GT(received, 10);
  server->kill_now();
  const std::string lost =
      "lost the connection to the query server (server 127.0.0.1:" + std::to_string(port);
  std::string warnings;
  for (int i = 0; i < 10 || (i < 400 && warnings.find(lost) == std::string::npos); ++i) {
    step();
    warnings = joined(c.messages(GST_MESSAGE_WARNING));
  }
  EXPECT_NE(warnings.find(lost), std::string::npos) << warnings;
  server = std::make_unique<Child>(server_pipeline(port), "restart2");
  ASSERT_TRUE(server->wait_port(port)) << server->log();
  const int before = received;
  for (int i = 0; i < 200 && received < before + 10; ++i) step();
  EXPECT_GE(received, before + 10) << joined(c.messages(GST_MESSAGE_ERROR));
  const auto infos = joined(c.messages(GST_MESSAGE_INFO));
  EXPECT_NE(infos.find("reconnected to the query server 127.0.0.1:" + std::to_string(port)),
            std::string::npos)
      << infos;
  c.eos();
  std::vector<uint8_t> got;
  while (c.pull(&got, nullptr, GST_SECOND)) ++received;
  GstStructure *st = c.stats();
  EXPECT_GE(stat(st, "lost"), 1u);
  EXPECT_GE(stat(st, "reconnects"), 1u);
  EXPECT_EQ(stat(st, "received"), static_cast<guint64>(received));
  EXPECT_EQ(stat(st, "received") + stat(st, "lost") + stat(st, "dropped"),
            static_cast<guint64>(pushed))
      << gst_structure_to_string(st);
  gst_structure_free(st);
  EXPECT_LT(c.stop().count(), 3000);
}

TEST(TensorQuery, CapsTheServerCannotTakeNameBoth) {
  const uint16_t port = free_port();
  Child server(server_pipeline(port,
                               "other/tensors,format=static,num_tensors=1,dimensions=4:4:1:1,"
                               "types=float32,framerate=0/1 ! "),
               "caps");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  AppPipeline c(client_desc(port), kCaps);
  c.play();
  c.push(frame(0, 0), 0);
  std::vector<uint8_t> got;
  EXPECT_FALSE(c.pull(&got, nullptr, GST_SECOND));
  const auto errors = joined(c.messages(GST_MESSAGE_ERROR));
  EXPECT_NE(errors.find("the server cannot take the client's caps: client sends "
                        "'other/tensors, format=(string)static, num_tensors=(int)1, "
                        "dimensions=(string)64:1"),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("server (tensor_query_serversrc) takes 'other/tensors, "
                        "format=(string)static, num_tensors=(int)1, dimensions=(string)4:4:1:1"),
            std::string::npos)
      << errors;
  // The server names the client that refused it.
  for (int i = 0; i < 50 && server.log().find("refused") == std::string::npos; ++i)
    std::this_thread::sleep_for(20ms);
  EXPECT_NE(server.log().find("WARNING: tensorqueryserversrc0: client 127.0.0.1:"),
            std::string::npos)
      << server.log();
  EXPECT_NE(server.log().find("refused the server capability"), std::string::npos);
}

TEST(TensorQuery, GarbageTruncatedAndHugeFramesAreNamedAndSurvived) {
  const uint16_t port = free_port();
  Child server(server_pipeline(port), "garbage");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  namespace e = nns::edge;
  auto raw = [&](const std::vector<uint8_t> &bytes) {
    std::string why;
    uint16_t lport = 0;
    e::Fd listener = e::tcp_listen("127.0.0.1", 0, &lport, &why);
    e::Fd fd = e::tcp_connect("127.0.0.1", port, 2000, &why);
    std::atomic<bool> stop{false};
    e::Message cap;
    EXPECT_EQ(e::read_frame(fd.get(), e::Limits{}, e::heap_payload, stop, 2000, &cap, &why),
              e::IoStatus::kOk);
    e::write_string_frame(fd.get(), e::Cmd::kHostInfo, cap.header.client_id,
                          "127.0.0.1:" + std::to_string(lport), &why);
    ::send(fd.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL);
    std::this_thread::sleep_for(100ms);
  };
  raw(std::vector<uint8_t>(4096, 0x5a));
  e::Header h;
  h.cmd = e::Cmd::kTransferData;
  h.mem_sizes = {4294967296ULL};
  auto hb = e::encode_header(h);
  raw(std::vector<uint8_t>(hb.data(), hb.data() + hb.size()));
  h.mem_sizes = {1000};
  hb = e::encode_header(h);
  std::vector<uint8_t> trunc(hb.data(), hb.data() + hb.size());
  trunc.resize(trunc.size() + 10);
  raw(trunc);
  for (int i = 0; i < 100 && server.log().find("truncated") == std::string::npos; ++i)
    std::this_thread::sleep_for(20ms);
  const std::string log = server.log();
  EXPECT_NE(log.find("invalid frame header: bad magic 0x5a5a5a5a"), std::string::npos) << log;
  EXPECT_NE(log.find("memory 0 claims 4294967296 bytes, over the frame limit of 1073741824"),
            std::string::npos)
      << log;
  EXPECT_NE(log.find("truncated frame: memory 0 got 10 of 1000 bytes"), std::string::npos) << log;
  EXPECT_NE(log.find("client 127.0.0.1:"), std::string::npos) << log;
  EXPECT_FALSE(server.exited()) << log;
  // And it still serves.
  AppPipeline c(client_desc(port, "timeout=2000"), kCaps);
  c.play();
  c.push(frame(3, 3), 0);
  std::vector<uint8_t> got;
  ASSERT_TRUE(c.pull(&got));
  EXPECT_EQ(got, frame(3, 3));
}

TEST(TensorQuery, ClientNamesAServerSendingGarbage) {
  // A fake server: valid handshake, then a 4 GiB size field on the answer connection.
  namespace e = nns::edge;
  std::string why;
  uint16_t port = 0;
  e::Fd listener = e::tcp_listen("127.0.0.1", 0, &port, &why);
  std::thread fake([&] {
    std::atomic<bool> stop{false};
    if (e::wait_readable(listener.get(), 5000, stop) != e::IoStatus::kOk) return;
    e::Fd fd(accept(listener.get(), nullptr, nullptr));
    e::write_string_frame(
        fd.get(), e::Cmd::kCapability, 77,
        std::string("@query_server_src_caps@") + kCaps + "@query_server_sink_caps@" + kCaps, &why);
    e::Message hi;
    e::read_frame(fd.get(), e::Limits{}, e::heap_payload, stop, 5000, &hi, &why);
    const std::string hs(reinterpret_cast<char *>(hi.mems[0]->data()));
    e::Fd back = e::tcp_connect("127.0.0.1", std::stoi(hs.substr(hs.rfind(':') + 1)), 2000, &why);
    e::Header h;
    h.cmd = e::Cmd::kTransferData;
    h.mem_sizes = {4294967296ULL};
    const auto hb = e::encode_header(h);
    ::send(back.get(), hb.data(), hb.size(), MSG_NOSIGNAL);
    std::this_thread::sleep_for(1500ms);
  });
  AppPipeline c(client_desc(port, "timeout=500"), kCaps);
  c.play();
  for (int n = 0; n < 4; ++n) {
    c.push(frame(0, n), 0);
    std::this_thread::sleep_for(100ms);
  }
  fake.join();
  const auto errors = joined(c.messages(GST_MESSAGE_ERROR));
  EXPECT_NE(errors.find("the query server sent an invalid frame: server 127.0.0.1:" +
                        std::to_string(port)),
            std::string::npos)
      << errors;
  EXPECT_NE(errors.find("memory 0 claims 4294967296 bytes"), std::string::npos) << errors;
}

TEST(TensorQuery, NoServerIsAnErrorNamingIt) {
  const uint16_t port = free_port();
  AppPipeline c(client_desc(port), kCaps);
  c.play();
  c.push(frame(0, 0), 0);
  std::vector<uint8_t> got;
  EXPECT_FALSE(c.pull(&got, nullptr, GST_SECOND / 2));
  const auto errors = joined(c.messages(GST_MESSAGE_ERROR));
  EXPECT_NE(errors.find("cannot reach the query server: cannot connect to 127.0.0.1:" +
                        std::to_string(port) + ": Connection refused"),
            std::string::npos)
      << errors;
}

TEST(TensorQuery, HybridWithoutBrokerOrTopicIsNamed) {
  const uint16_t nobody = free_port();
  auto r = nns::test::run_pipeline(
      "tensor_query_serversrc connect-type=HYBRID port=0 topic=t dest-host=127.0.0.1 dest-port=" +
          std::to_string(nobody) + " ! tensor_query_serversink",
      10);
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("connect-type HYBRID: cannot connect to the MQTT broker 127.0.0.1:" +
                              std::to_string(nobody)),
            std::string::npos)
      << r.error_text;
  r = nns::test::run_pipeline(
      "tensor_query_serversrc connect-type=HYBRID port=0 ! tensor_query_serversink", 5);
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("connect-type HYBRID needs the topic property"), std::string::npos)
      << r.error_text;
}

TEST(TensorQuery, PortInUseIsNamed) {
  const uint16_t port = free_port();
  Child server(server_pipeline(port), "inuse");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  auto r = nns::test::run_pipeline(server_pipeline(port), 5);
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("cannot listen on 127.0.0.1:" + std::to_string(port) +
                              ": Address already in use"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorQuery, NullWhileWaitingForAnswersDoesNotHang) {
  const uint16_t port = free_port();
  // A server that never answers.
  Child server("tensor_query_serversrc host=127.0.0.1 port=" + std::to_string(port) + " ! fakesink",
               "silent");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  AppPipeline c(client_desc(port, "timeout=60000 max-request=0"), kCaps);
  c.play();
  std::thread pusher([&] {
    for (int n = 0; n < 3; ++n) c.push(frame(0, n), 0);
  });
  std::this_thread::sleep_for(300ms);
  EXPECT_LT(c.stop().count(), 3000);
  pusher.join();
}

TEST(TensorQuery, MetalessBuffersHitTheLimit) {
  const uint16_t port = free_port();
  // tensor_query_serversink alone in a pipeline: buffers never carry a GstMetaQuery.
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=3 ! video/x-raw,width=4,height=4 ! "
      "tensor_query_serversink limit=2",
      5);
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("2 buffer(s) in a row arrived without the GstMetaQuery"),
            std::string::npos)
      << r.error_text;
  (void)port;
}

TEST(TensorQuery, TensorCapsCompareAsTensors) {
  // The server takes dimensions=64:1:1:1, the client sends 64:1: the same tensor (as upstream).
  const uint16_t port = free_port();
  Child server(server_pipeline(port,
                               "other/tensors,format=static,num_tensors=1,dimensions=64:1:1:1,"
                               "types=uint8,framerate=0/1 ! "),
               "dims");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  AppPipeline c(client_desc(port, "timeout=2000"), kCaps);
  c.play();
  c.push(frame(2, 0), 0);
  std::vector<uint8_t> got;
  ASSERT_TRUE(c.pull(&got)) << joined(c.messages(GST_MESSAGE_ERROR));
  EXPECT_EQ(got, frame(2, 0));
}

TEST(TensorQuery, MaxRequestDropsTheNewestAndTimeoutBoundsTheWait) {
  const uint16_t port = free_port();
  // A server that never answers.
  Child server("tensor_query_serversrc host=127.0.0.1 port=" + std::to_string(port) + " ! fakesink",
               "mute");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  AppPipeline c(client_desc(port, "max-request=2 timeout=100"), kCaps);
  c.play();
  const auto t0 = std::chrono::steady_clock::now();
  for (int n = 0; n < 5; ++n) c.push(frame(0, n), n * GST_MSECOND);
  c.eos();
  // Each input waits at most 100 ms, EOS waits 100 ms for what is in flight.
  std::vector<uint8_t> got;
  EXPECT_FALSE(c.pull(&got, nullptr, 5 * GST_SECOND));
  EXPECT_TRUE(gst_app_sink_is_eos(GST_APP_SINK(c.sink)));
  const auto ms =
      std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() - t0)
          .count();
  EXPECT_LT(ms, 2500);
  GstStructure *st = c.stats();
  EXPECT_EQ(stat(st, "sent"), 2u);
  EXPECT_EQ(stat(st, "dropped"), 3u);
  EXPECT_EQ(stat(st, "lost"), 2u);  // the two in flight never answered
  EXPECT_EQ(stat(st, "received"), 0u);
  gst_structure_free(st);
}

TEST(TensorQuery, ClientIdSurvivesAProcessingServer) {
  // tensor_transform makes a new buffer per frame: GstMetaQuery must be carried over to it.
  const uint16_t port = free_port();
  Child server(
      server_pipeline(
          port, std::string(kCaps) + " ! queue ! tensor_transform mode=arithmetic option=add:1 ! "),
      "transform");
  ASSERT_TRUE(server.wait_port(port)) << server.log();
  AppPipeline a(client_desc(port, "timeout=2000"), kCaps),
      b(client_desc(port, "timeout=2000"), kCaps);
  a.play();
  b.play();
  for (int n = 0; n < 20; ++n) {
    a.push(frame(1, n), n * GST_MSECOND);
    b.push(frame(2, n), n * GST_MSECOND);
  }
  for (int n = 0; n < 20; ++n) {
    for (auto *c : {&a, &b}) {
      const int id = c == &a ? 1 : 2;
      std::vector<uint8_t> got;
      ASSERT_TRUE(c->pull(&got)) << id << " " << n << joined(c->messages(GST_MESSAGE_ERROR));
      auto want = frame(id, n);
      for (auto &v : want) v = static_cast<uint8_t>(v + 1);
      ASSERT_EQ(got, want) << "client " << id << " frame " << n;
    }
  }
}

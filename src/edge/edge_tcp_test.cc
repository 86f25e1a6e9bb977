// SPDX-License-Identifier: LGPL-2.1-only
// The TCP transport on 127.0.0.1 with free ports: handshake, round trip, routing by client id,
// caps refusal, and a raw peer sending garbage / truncated frames / a 4 GiB size field.
#include <gtest/gtest.h>
#include <sys/socket.h>

#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "edge/edge_node.h"

using namespace nns::edge;
using namespace std::chrono_literals;

namespace {

template <typename T>
class Queue {
 public:
  void push(T v) {
    std::lock_guard<std::mutex> l(m_);
    q_.push_back(std::move(v));
    cv_.notify_all();
  }
  bool pop(T *out, std::chrono::milliseconds t = 5000ms) {
    std::unique_lock<std::mutex> l(m_);
    if (!cv_.wait_for(l, t, [&] { return !q_.empty(); })) return false;
    *out = std::move(q_.front());
    q_.pop_front();
    return true;
  }

 private:
  std::mutex m_;
  std::condition_variable cv_;
  std::deque<T> q_;
};

struct EchoServer {
  std::unique_ptr<ServerNode> node;
  Queue<std::string> warnings;
  explicit EchoServer(std::string caps = "@query_server_src_caps@ANY@query_server_sink_caps@ANY") {
    NodeOptions o;
    o.role = Role::kQueryServer;
    o.host = "127.0.0.1";
    NodeCallbacks cb;
    cb.caps = [caps] { return caps; };
    cb.on_warning = [this](const std::string &s) { warnings.push(s); };
    cb.on_data = [this](Message &&m) {
      const int64_t id = std::stoll(*m.meta.get("client_id"));
      OutFrame f;
      for (auto &p : m.mems) f.mems.push_back({p->data(), p->size()});
      std::string why;
      node->send_to(id, f, &why);
    };
    node = make_tcp_server(o, cb);
    node->start();
  }
};

std::unique_ptr<ClientNode> make_query_client(uint16_t port, Queue<std::string> *answers,
                                              Queue<std::string> *closed = nullptr) {
  NodeOptions o;
  o.role = Role::kQueryClient;
  o.host = "127.0.0.1";
  o.dest_host = "127.0.0.1";
  o.dest_port = port;
  NodeCallbacks cb;
  cb.on_data = [answers](Message &&m) {
    std::string s;
    for (auto &p : m.mems) s.append(reinterpret_cast<char *>(p->data()), p->size());
    answers->push(s);
  };
  if (closed) cb.on_closed = [closed](const std::string &s, CloseKind) { closed->push(s); };
  return make_tcp_client(o, cb);
}

bool send_str(ClientNode &c, const std::string &s) {
  OutFrame f;
  f.mems.push_back({s.data(), s.size()});
  std::string why;
  return c.send(f, &why);
}

}  // namespace

TEST(EdgeTcp, QueryRoundTripExactBytes) {
  EchoServer srv;
  Queue<std::string> answers;
  auto c = make_query_client(srv.node->port(), &answers);
  c->connect();
  EXPECT_EQ(c->server_caps(), "@query_server_src_caps@ANY@query_server_sink_caps@ANY");
  EXPECT_NE(c->client_id(), 0);
  std::string payload(150528, '\0');
  for (std::size_t i = 0; i < payload.size(); ++i) payload[i] = static_cast<char>(i * 7);
  ASSERT_TRUE(send_str(*c, payload));
  std::string got;
  ASSERT_TRUE(answers.pop(&got));
  EXPECT_EQ(got, payload);
}

TEST(EdgeTcp, AnswersGoToTheirClient) {
  EchoServer srv;
  constexpr int kClients = 4, kFrames = 200;
  std::vector<Queue<std::string>> answers(kClients);
  std::vector<std::unique_ptr<ClientNode>> cs;
  for (int i = 0; i < kClients; ++i) {
    cs.push_back(make_query_client(srv.node->port(), &answers[i]));
    cs.back()->connect();
  }
  std::vector<std::thread> th;
  for (int i = 0; i < kClients; ++i)
    th.emplace_back([&, i] {
      for (int n = 0; n < kFrames; ++n)
        send_str(*cs[i], std::to_string(i) + ":" + std::to_string(n));
    });
  for (auto &t : th) t.join();
  for (int i = 0; i < kClients; ++i)
    for (int n = 0; n < kFrames; ++n) {
      std::string got;
      ASSERT_TRUE(answers[i].pop(&got)) << i << " " << n;
      ASSERT_EQ(got, std::to_string(i) + ":" + std::to_string(n));
    }
}

TEST(EdgeTcp, ClientRefusesCapsAndServerIsTold) {
  EchoServer srv("@query_server_src_caps@video/x-raw@query_server_sink_caps@ANY");
  NodeOptions o;
  o.role = Role::kQueryClient;
  o.host = o.dest_host = "127.0.0.1";
  o.dest_port = srv.node->port();
  NodeCallbacks cb;
  cb.accept_caps = [](const std::string &caps) -> std::optional<std::string> {
    return "cannot take " + *caps_field(caps, "query_server_src_caps");
  };
  auto c = make_tcp_client(o, cb);
  try {
    c->connect();
    FAIL() << "connect should throw";
  } catch (const nns::Error &e) {
    EXPECT_STREQ(e.what(), "cannot take video/x-raw");
    EXPECT_EQ(e.kind(), nns::ErrorKind::kNegotiation);
  }
  std::string w;
  ASSERT_TRUE(srv.warnings.pop(&w));
  EXPECT_NE(w.find("refused the server capability"), std::string::npos) << w;
}

TEST(EdgeTcp, ConnectRefusedNamesTheServer) {
  uint16_t port = 0;
  std::string why;
  { Fd l = tcp_listen("127.0.0.1", 0, &port, &why); }  // a port nobody listens on now
  Queue<std::string> answers;
  auto c = make_query_client(port, &answers);
  try {
    c->connect();
    FAIL();
  } catch (const nns::Error &e) {
    EXPECT_NE(std::string(e.what()).find("cannot connect to 127.0.0.1:" + std::to_string(port)),
              std::string::npos)
        << e.what();
  }
}

namespace {
std::vector<uint8_t> header_bytes(const Header &h, std::size_t keep = kHeaderSize,
                                  std::size_t extra = 0) {
  const auto hb = encode_header(h);
  std::vector<uint8_t> v(keep + extra, 7);
  std::memcpy(v.data(), hb.data(), keep);
  return v;
}
// Connects raw to the server, completes the handshake by hand, then writes `bytes`.
std::string raw_peer_warning(EchoServer &srv, const std::vector<uint8_t> &bytes,
                             bool close_after = true) {
  std::string why;
  uint16_t lport = 0;
  Fd listener = tcp_listen("127.0.0.1", 0, &lport, &why);
  Fd fd = tcp_connect("127.0.0.1", srv.node->port(), 2000, &why);
  std::atomic<bool> stop{false};
  Message cap;
  EXPECT_EQ(read_frame(fd.get(), Limits{}, heap_payload, stop, 2000, &cap, &why), IoStatus::kOk);
  write_string_frame(fd.get(), Cmd::kHostInfo, cap.header.client_id,
                     "127.0.0.1:" + std::to_string(lport), &why);
  ::send(fd.get(), bytes.data(), bytes.size(), MSG_NOSIGNAL);
  if (close_after) fd.reset();
  std::string w;
  srv.warnings.pop(&w);
  return w;
}
}  // namespace

TEST(EdgeTcp, GarbagePeerIsNamedAndDropped) {
  EchoServer srv;
  std::vector<uint8_t> garbage(3000, 0x41);
  const std::string w = raw_peer_warning(srv, garbage);
  EXPECT_NE(w.find("client 127.0.0.1:"), std::string::npos) << w;
  EXPECT_NE(w.find("invalid frame header: bad magic 0x41414141"), std::string::npos) << w;
  EXPECT_EQ(srv.node->client_count(), 0u);
}

TEST(EdgeTcp, TruncatedFrameIsNamed) {
  EchoServer srv;
  Header h;
  h.cmd = Cmd::kTransferData;
  h.mem_sizes = {1000};
  // 10 of the 1000 bytes, then close
  const std::string w = raw_peer_warning(srv, header_bytes(h, kHeaderSize, 10));
  EXPECT_NE(w.find("truncated frame: memory 0 got 10 of 1000 bytes"), std::string::npos) << w;
  const std::string w2 = raw_peer_warning(srv, header_bytes(h, 100));
  EXPECT_NE(w2.find("closed after 100 of 2088 header bytes"), std::string::npos) << w2;
}

TEST(EdgeTcp, FourGiBSizeIsRejectedWithoutAllocating) {
  EchoServer srv;
  Header h;
  h.cmd = Cmd::kTransferData;
  h.mem_sizes = {4294967296ULL};
  const std::string w = raw_peer_warning(srv, header_bytes(h), false);
  EXPECT_NE(w.find("memory 0 claims 4294967296 bytes, over the frame limit"), std::string::npos)
      << w;
}

TEST(EdgeTcp, ServerGoneClosesTheSession) {
  auto srv = std::make_unique<EchoServer>();
  Queue<std::string> answers, closed;
  auto c = make_query_client(srv->node->port(), &answers, &closed);
  c->connect();
  srv.reset();
  std::string why;
  ASSERT_TRUE(closed.pop(&why));
  EXPECT_NE(why.find("server 127.0.0.1:"), std::string::npos) << why;
  EXPECT_FALSE(c->connected());
}

TEST(EdgeTcp, PublisherReachesEverySubscriber) {
  NodeOptions o;
  o.role = Role::kPublisher;
  o.host = "127.0.0.1";
  NodeCallbacks cb;
  cb.caps = [] { return std::string("@edge_sink_caps@text/x-raw,format=utf8"); };
  auto pub = make_tcp_server(o, cb);
  pub->start();
  std::vector<Queue<std::string>> got(3);
  std::vector<std::unique_ptr<ClientNode>> subs;
  for (int i = 0; i < 3; ++i) {
    NodeOptions so;
    so.role = Role::kSubscriber;
    so.dest_host = "127.0.0.1";
    so.dest_port = pub->port();
    NodeCallbacks scb;
    scb.on_data = [&got, i](Message &&m) {
      got[i].push(std::string(reinterpret_cast<char *>(m.mems[0]->data()), m.mems[0]->size()));
    };
    subs.push_back(make_tcp_client(so, scb));
    subs.back()->connect();
    EXPECT_EQ(*caps_field(subs.back()->server_caps(), "edge_sink_caps"), "text/x-raw,format=utf8");
  }
  for (int i = 0; i < 50 && pub->client_count() < 3; ++i) std::this_thread::sleep_for(10ms);
  OutFrame f;
  const std::string msg = "hello";
  f.mems.push_back({msg.data(), msg.size()});
  EXPECT_EQ(pub->broadcast(f), 3u);
  for (auto &q : got) {
    std::string s;
    ASSERT_TRUE(q.pop(&s));
    EXPECT_EQ(s, "hello");
  }
}

TEST(EdgeTcp, CustomNeedsALibrary) {
  auto server = make_server(ConnectType::kCustom, NodeOptions{}, NodeCallbacks{});
  try {
    server->start();
    FAIL();
  } catch (const nns::Error &e) {
    EXPECT_STREQ(e.what(),
                 "connect-type CUSTOM needs the custom-lib property (the connection library)");
  }
  EXPECT_THROW(make_client(ConnectType::kCustom, NodeOptions{}, NodeCallbacks{})->connect(),
               nns::Error);
}

// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer-edge's TCP connect type. Query: the client connects to the server, gets
// CAPABILITY (with its client id), answers HOST_INFO "host:port" of its own listener (or
// ERROR to refuse the caps), and the server connects back to that listener; requests travel
// client->server on the first connection, answers server->client on the second. Pub/sub: the
// subscriber connects, gets CAPABILITY, answers HOST_INFO, and data flows publisher->subscriber
// on that one connection. One thread per connection; all waits poll a stop flag.
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <sys/socket.h>

#include <chrono>
#include <cstring>
#include <list>
#include <map>
#include <mutex>
#include <thread>

#include "core/error.h"
#include "edge/edge_node.h"

namespace nns::edge {

namespace {

std::string frame_string(const Message &m) {
  if (m.mems.empty()) return {};
  const auto *p = reinterpret_cast<const char *>(m.mems[0]->data());
  return std::string(p, strnlen(p, m.mems[0]->size()));
}

// Threads that end by themselves and are joined later.
class ThreadSet {
 public:
  template <typename F>
  void spawn(F &&f) {
    std::lock_guard<std::mutex> l(m_);
    reap_locked();
    auto done = std::make_shared<std::atomic<bool>>(false);
    threads_.push_back({std::thread([fn = std::forward<F>(f), done]() mutable {
                          fn();
                          done->store(true);
                        }),
                        done});
  }
  void join_all() {
    std::list<Item> all;
    {
      std::lock_guard<std::mutex> l(m_);
      all.swap(threads_);
    }
    for (auto &t : all)
      if (t.th.joinable()) t.th.join();
  }

 private:
  struct Item {
    std::thread th;
    std::shared_ptr<std::atomic<bool>> done;
  };
  void reap_locked() {
    for (auto it = threads_.begin(); it != threads_.end();) {
      if (it->done->load()) {
        it->th.join();
        it = threads_.erase(it);
      } else {
        ++it;
      }
    }
  }
  std::mutex m_;
  std::list<Item> threads_;
};

class TcpServer final : public ServerNode {
 public:
  TcpServer(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~TcpServer() override { stop(); }

  void start() override {
    std::string why;
    listener_ = tcp_listen(o_.host, o_.port, &port_, &why);
    if (!listener_.valid()) fail(ErrorKind::kNotFound, why);
    stop_ = false;
    accept_thread_ = std::thread([this] { accept_loop(); });
  }

  uint16_t port() const override { return port_; }

  bool send_to(int64_t id, const OutFrame &frame, std::string *why) override {
    std::shared_ptr<Client> c;
    {
      std::lock_guard<std::mutex> l(lock_);
      auto it = clients_.find(id);
      if (it != clients_.end()) c = it->second;
    }
    if (!c) {
      if (why) *why = "no connected client with id " + std::to_string(id);
      return false;
    }
    return send_client(*c, frame, why);
  }

  std::size_t broadcast(const OutFrame &frame) override {
    std::vector<std::shared_ptr<Client>> all;
    {
      std::lock_guard<std::mutex> l(lock_);
      for (auto &kv : clients_) all.push_back(kv.second);
    }
    std::size_t n = 0;
    for (auto &c : all) {
      std::string why;
      if (send_client(*c, frame, &why)) {
        ++n;
      } else {
        warn("subscriber " + c->peer + " (client id " + std::to_string(c->id) +
             ") dropped: " + why);
        remove(c->id);
      }
    }
    return n;
  }

  std::size_t client_count() const override {
    std::lock_guard<std::mutex> l(lock_);
    return clients_.size();
  }

  void stop() override {
    if (!listener_.valid() && !accept_thread_.joinable()) return;
    stop_ = true;
    if (accept_thread_.joinable()) accept_thread_.join();
    threads_.join_all();
    std::map<int64_t, std::shared_ptr<Client>> all;
    {
      std::lock_guard<std::mutex> l(lock_);
      all.swap(clients_);
    }
    for (auto &kv : all) {  // tell each peer we are going (nnstreamer-edge does the same)
      std::lock_guard<std::mutex> l(kv.second->send_lock);
      write_frame(kv.second->out.get(), Cmd::kError, 0, OutFrame{}, nullptr);
    }
    listener_.reset();
  }

 private:
  struct Client {
    int64_t id = 0;
    std::string peer;
    Fd in;   // query server: requests arrive here (the client's connection)
    Fd out;  // answers / published data go here
    std::mutex send_lock;
  };

  bool send_client(Client &c, const OutFrame &frame, std::string *why) {
    OutFrame f;
    f.mems = frame.mems;
    f.meta = frame.meta;
    if (o_.role == Role::kQueryServer) f.meta.set("client_id", std::to_string(c.id));
    std::lock_guard<std::mutex> l(c.send_lock);
    return write_frame(c.out.get(), Cmd::kTransferData, c.id, f, why);
  }

  void warn(const std::string &s) {
    if (cb_.on_warning) cb_.on_warning(s);
  }

  void remove(int64_t id) {
    std::lock_guard<std::mutex> l(lock_);
    clients_.erase(id);
  }

  void accept_loop() {
    while (!stop_) {
      const IoStatus st = wait_readable(listener_.get(), -1, stop_);
      if (st != IoStatus::kOk) {
        if (st == IoStatus::kError) std::this_thread::sleep_for(std::chrono::milliseconds(20));
        continue;
      }
      Fd fd(accept4(listener_.get(), nullptr, nullptr, SOCK_CLOEXEC));
      if (!fd.valid()) continue;
      int one = 1;
      setsockopt(fd.get(), IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
      auto shared = std::make_shared<Fd>(std::move(fd));
      threads_.spawn([this, shared] { serve(std::move(*shared)); });
    }
  }

  void serve(Fd fd) {
    auto c = std::make_shared<Client>();
    c->peer = peer_name(fd.get());
    c->id = new_client_id();
    const std::string who = "client " + c->peer + " (client id " + std::to_string(c->id) + ")";
    std::string why;
    const std::string caps = cb_.caps ? cb_.caps() : std::string();
    if (!write_string_frame(fd.get(), Cmd::kCapability, c->id, caps, &why)) {
      warn(who + ": cannot send the capability: " + why);
      return;
    }
    int read_fd = fd.get();
    if (o_.role == Role::kQueryServer) {
      Message m;
      const IoStatus st =
          read_frame(fd.get(), o_.limits, heap_payload, stop_, o_.connect_timeout_ms, &m, &why);
      if (st == IoStatus::kStopped) return;
      if (st != IoStatus::kOk) {
        warn(who + ": handshake failed: " +
             (st == IoStatus::kTimeout
                  ? "no HOST_INFO within " + std::to_string(o_.connect_timeout_ms) + " ms"
              : st == IoStatus::kClosed ? std::string("connection closed")
                                        : why));
        return;
      }
      if (m.header.cmd == Cmd::kError) {
        warn(who + " refused the server capability '" + caps + "'");
        return;
      }
      std::string host;
      uint16_t port = 0;
      const std::string hs = frame_string(m);
      if (m.header.cmd != Cmd::kHostInfo || !parse_host_string(hs, &host, &port)) {
        warn(who + ": expected HOST_INFO \"host:port\", got " + cmd_name(m.header.cmd) + " '" + hs +
             "'");
        return;
      }
      Fd back = tcp_connect(host, port, o_.connect_timeout_ms, &why);
      if (!back.valid()) {
        warn(who + ": cannot connect back to its listener " + hs + ": " + why);
        return;
      }
      c->in = std::move(fd);
      c->out = std::move(back);
      read_fd = c->in.get();
    } else {
      c->out = std::move(fd);
      read_fd = c->out.get();
    }
    {
      std::lock_guard<std::mutex> l(lock_);
      clients_[c->id] = c;
    }
    if (cb_.on_connected) cb_.on_connected(c->id, c->peer);
    const Allocator alloc =
        (o_.role == Role::kQueryServer && cb_.alloc) ? cb_.alloc : Allocator(heap_payload);
    for (;;) {
      Message m;
      const IoStatus st = read_frame(read_fd, o_.limits, alloc, stop_, -1, &m, &why);
      if (st == IoStatus::kStopped) return;  // stop() handles the table
      if (st == IoStatus::kClosed) break;
      if (st == IoStatus::kError || st == IoStatus::kProtocol) {
        remove(c->id);
        warn(who + ": " + why + "; connection dropped");
        return;
      }
      if (m.header.cmd == Cmd::kError) break;  // the peer says goodbye
      if (m.header.cmd != Cmd::kTransferData || o_.role != Role::kQueryServer) continue;
      m.meta.set("client_id", std::to_string(c->id));
      if (cb_.on_data) cb_.on_data(std::move(m));
    }
    remove(c->id);
  }

  NodeOptions o_;
  NodeCallbacks cb_;
  Fd listener_;
  uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::thread accept_thread_;
  ThreadSet threads_;
  mutable std::mutex lock_;
  std::map<int64_t, std::shared_ptr<Client>> clients_;
};

class TcpClient final : public ClientNode {
 public:
  TcpClient(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~TcpClient() override { disconnect(); }

  void connect() override {
    disconnect();
    std::string why;
    const std::string server = host_string(o_.dest_host, o_.dest_port);
    if (o_.role == Role::kQueryClient && !listener_.valid()) {
      listener_ = tcp_listen(o_.host, o_.port, &listen_port_, &why);
      if (!listener_.valid()) fail(ErrorKind::kNotFound, "answer listener: " + why);
    }
    Fd fd = tcp_connect(o_.dest_host, o_.dest_port, o_.connect_timeout_ms, &why);
    if (!fd.valid()) fail(ErrorKind::kNotFound, why);
    Message m;
    stop_ = false;
    const IoStatus st =
        read_frame(fd.get(), o_.limits, heap_payload, stop_, o_.connect_timeout_ms, &m, &why);
    if (st != IoStatus::kOk || m.header.cmd != Cmd::kCapability) {
      fail(ErrorKind::kStream,
           "server " + server + ": expected its CAPABILITY, " +
               (st == IoStatus::kOk ? std::string("got ") + cmd_name(m.header.cmd)
                : st == IoStatus::kTimeout
                    ? "got nothing within " + std::to_string(o_.connect_timeout_ms) + " ms"
                : st == IoStatus::kClosed ? std::string("the connection closed")
                                          : why));
    }
    const std::string caps = frame_string(m);
    if (cb_.accept_caps) {
      if (auto refuse = cb_.accept_caps(caps)) {
        write_frame(fd.get(), Cmd::kError, m.header.client_id, OutFrame{}, nullptr);
        fail(ErrorKind::kNegotiation, *refuse);
      }
    }
    const std::string me =
        o_.role == Role::kQueryClient ? host_string(o_.host, listen_port_) : local_name(fd.get());
    if (!write_string_frame(fd.get(), Cmd::kHostInfo, m.header.client_id, me, &why))
      fail(ErrorKind::kStream, "server " + server + ": cannot send HOST_INFO: " + why);
    {
      std::lock_guard<std::mutex> l(send_lock_);
      out_ = std::move(fd);
    }
    id_ = m.header.client_id;
    caps_ = caps;
    connected_ = true;
    const int out_fd = out_.get();
    threads_.spawn([this, out_fd, server] { read_loop(out_fd, "server " + server); });
    if (o_.role == Role::kQueryClient) threads_.spawn([this, server] { accept_loop(server); });
  }

  bool connected() const override { return connected_; }

  bool send(const OutFrame &frame, std::string *why) override {
    std::lock_guard<std::mutex> l(send_lock_);
    if (!connected_ || !out_.valid()) {
      if (why) *why = "not connected";
      return false;
    }
    OutFrame f;
    f.mems = frame.mems;
    f.meta = frame.meta;
    f.meta.set("client_id", std::to_string(id_));
    if (write_frame(out_.get(), Cmd::kTransferData, id_, f, why)) return true;
    closed("server " + server_name() + ": " + (why ? *why : std::string("send failed")));
    return false;
  }

  int64_t client_id() const override { return id_; }
  std::string server_caps() const override { return caps_; }
  std::string server_name() const override { return host_string(o_.dest_host, o_.dest_port); }

  void disconnect() override {
    stop_ = true;
    threads_.join_all();
    std::lock_guard<std::mutex> l(send_lock_);
    if (out_.valid()) {
      write_frame(out_.get(), Cmd::kError, id_, OutFrame{}, nullptr);
      out_.reset();
    }
    connected_ = false;
  }

 private:
  void closed(const std::string &why, CloseKind kind = CloseKind::kBroken) {
    if (connected_.exchange(false) && cb_.on_closed) cb_.on_closed(why, kind);
  }

  void read_loop(int fd, const std::string &who) {
    std::string why;
    const Allocator alloc = cb_.alloc ? cb_.alloc : Allocator(heap_payload);
    for (;;) {
      Message m;
      const IoStatus st = read_frame(fd, o_.limits, alloc, stop_, -1, &m, &why);
      if (st == IoStatus::kStopped) return;
      if (st == IoStatus::kClosed) return closed(who + " closed the connection");
      if (st == IoStatus::kError) return closed(who + ": " + why);
      if (st == IoStatus::kProtocol) return closed(who + ": " + why, CloseKind::kProtocol);
      if (m.header.cmd == Cmd::kError)
        return closed(who + " ended the session", CloseKind::kGoodbye);
      if (m.header.cmd == Cmd::kTransferData && cb_.on_data) cb_.on_data(std::move(m));
    }
  }

  void accept_loop(const std::string &server) {
    while (!stop_) {
      if (wait_readable(listener_.get(), -1, stop_) != IoStatus::kOk) continue;
      Fd fd(accept4(listener_.get(), nullptr, nullptr, SOCK_CLOEXEC));
      if (!fd.valid()) continue;
      read_loop(fd.get(), "server " + server + " (answers from " + peer_name(fd.get()) + ")");
      if (!connected_) return;
    }
  }

  NodeOptions o_;
  NodeCallbacks cb_;
  Fd listener_;
  uint16_t listen_port_ = 0;
  std::mutex send_lock_;
  Fd out_;
  int64_t id_ = 0;
  std::string caps_;
  std::atomic<bool> connected_{false};
  std::atomic<bool> stop_{false};
  ThreadSet threads_;
};

}  // namespace

const char *connect_type_name(ConnectType t) {
  switch (t) {
    case ConnectType::kTcp:
      return "TCP";
    case ConnectType::kMqtt:
      return "MQTT";
    case ConnectType::kHybrid:
      return "HYBRID";
    case ConnectType::kCustom:
      return "CUSTOM";
  }
  return "?";
}

std::unique_ptr<ServerNode> make_tcp_server(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<TcpServer>(opts, std::move(cb));
}

std::unique_ptr<ClientNode> make_tcp_client(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<TcpClient>(opts, std::move(cb));
}

std::unique_ptr<ServerNode> make_server(ConnectType type, const NodeOptions &opts,
                                        NodeCallbacks cb) {
  if (type == ConnectType::kTcp) return make_tcp_server(opts, std::move(cb));
  if (type == ConnectType::kHybrid) return make_hybrid_server(opts, std::move(cb));
  if (type == ConnectType::kMqtt) return make_mqtt_server(opts, std::move(cb));
  return make_custom_server(opts, std::move(cb));
}

std::unique_ptr<ClientNode> make_client(ConnectType type, const NodeOptions &opts,
                                        NodeCallbacks cb) {
  if (type == ConnectType::kTcp) return make_tcp_client(opts, std::move(cb));
  if (type == ConnectType::kHybrid) return make_hybrid_client(opts, std::move(cb));
  if (type == ConnectType::kMqtt) return make_mqtt_client(opts, std::move(cb));
  return make_custom_client(opts, std::move(cb));
}

}  // namespace nns::edge

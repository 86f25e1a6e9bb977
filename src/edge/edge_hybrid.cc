// SPDX-License-Identifier: LGPL-2.1-only
// connect-type HYBRID, as nnstreamer-edge does it: MQTT for discovery, edge TCP for the data.
//
// A server (query server, publisher) starts its TCP server as for TCP, then connects to the
// broker at dest-host:dest-port (client id "nns_edge_<id>_<pid>", MQTT 3.1.1) and publishes
// "<host>:<port>" plus a NUL byte, QoS 1, retained, on "edge/inference/device-<id>/<topic>/".
// When it stops it clears that retained message (an empty retained publish). A client
// subscribes to "edge/inference/+/<topic>/#" (QoS 1), takes the announced servers and connects
// over TCP to the first that answers; when that session ends, the next connect() goes to
// another server announcing the same topic.
#include <unistd.h>

#include <chrono>
#include <condition_variable>
#include <mutex>
#include <vector>

#include "core/error.h"
#include "edge/edge_discovery.h"
#include "edge/edge_node.h"
#include "mqtt/mqtt_client.h"

namespace nns::edge {

namespace {

constexpr int kBrokerWaitMs = 5000;

std::string announce_topic(const std::string &id, const std::string &topic) {
  return "edge/inference/device-" + id + "/" + topic + "/";
}

void require_topic(const NodeOptions &o) {
  if (o.topic.empty())
    fail(ErrorKind::kSettings,
         "connect-type HYBRID needs the topic property (the MQTT topic "
         "servers announce themselves on)");
}

std::string broker_name(const NodeOptions &o) {
  return o.dest_host + ":" + std::to_string(o.dest_port);
}

class HybridServer final : public ServerNode {
 public:
  HybridServer(const NodeOptions &o, NodeCallbacks cb)
      : o_(o), tcp_(make_tcp_server(o, std::move(cb))) {}
  ~HybridServer() override { stop(); }

  void start() override {
    require_topic(o_);
    tcp_->start();
    const std::string id = std::to_string(getpid()) + "_" + std::to_string(tcp_->port());
    topic_ = announce_topic(id, o_.topic);
    announcement_ = o_.host + ":" + std::to_string(tcp_->port());
    announcement_.push_back('\0');  // nnstreamer-edge sends strlen + 1 bytes
    mqtt::ClientOptions mo{o_.dest_host, o_.dest_port,
                           "nns_edge_" + id + "_" + std::to_string(getpid()), 60, true};
    mqtt_ = std::make_unique<mqtt::Client>(mo, nullptr, [this](bool up, const std::string &) {
      if (up) announce();  // again after a broker restart (it may have forgotten it)
    });
    // Ours: a server that dies (no clean stop) has the broker clear its announcement too.
    mqtt_->set_will(topic_, std::string(), true);
    mqtt_->start();
    if (!mqtt_->wait_connected(std::chrono::milliseconds(kBrokerWaitMs))) {
      const std::string why = mqtt_->why();
      mqtt_.reset();
      tcp_->stop();
      fail(ErrorKind::kNotFound, "connect-type HYBRID: cannot connect to the MQTT broker " +
                                     broker_name(o_) + " (dest-host/dest-port)" +
                                     (why.empty() ? "" : ": " + why));
    }
    announce();
  }
  uint16_t port() const override { return tcp_->port(); }
  bool send_to(int64_t id, const OutFrame &f, std::string *why) override {
    return tcp_->send_to(id, f, why);
  }
  std::size_t broadcast(const OutFrame &f) override { return tcp_->broadcast(f); }
  std::size_t client_count() const override { return tcp_->client_count(); }
  void stop() override {
    if (mqtt_) {
      if (mqtt_->connected()) {
        mqtt_->publish(topic_, nullptr, 0, 1, true);  // clear the retained announcement
        mqtt_->flush(std::chrono::milliseconds(1000));
      }
      mqtt_->stop();
      mqtt_.reset();
    }
    tcp_->stop();
  }

 private:
  void announce() {
    if (mqtt_) mqtt_->publish(topic_, announcement_.data(), announcement_.size(), 1, true);
  }

  NodeOptions o_;
  std::unique_ptr<ServerNode> tcp_;
  std::unique_ptr<mqtt::Client> mqtt_;
  std::string topic_, announcement_;
};

class HybridClient final : public ClientNode {
 public:
  HybridClient(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~HybridClient() override { disconnect(); }

  void connect() override {
    require_topic(o_);
    disconnect();
    const auto deadline =
        std::chrono::steady_clock::now() + std::chrono::milliseconds(o_.connect_timeout_ms);
    if (!disc_) {
      auto d = std::make_unique<Discovery>(o_);
      d->start();
      disc_ = std::move(d);
    }
    std::string why;
    for (;;) {
      // Newest announcement first; a server that fails is forgotten until it announces again.
      while (auto s = disc_->take_newest()) {
        std::string host;
        uint16_t port = 0;
        if (!split_host_port(s->address, &host, &port)) {
          why += "; '" + s->address + "' on " + s->topic + " is not host:port";
          continue;
        }
        NodeOptions t = o_;
        t.dest_host = host;
        t.dest_port = port;
        auto c = make_tcp_client(t, cb_);
        try {
          c->connect();
          tcp_ = std::move(c);
          return;
        } catch (const Error &e) {
          why += std::string("; ") + e.what();
        }
      }
      if (disc_->wait_any(deadline)) continue;
      fail(ErrorKind::kNotFound, "connect-type HYBRID: no server announcing topic '" + o_.topic +
                                     "' on the broker " + broker_name(o_) + " answered within " +
                                     std::to_string(o_.connect_timeout_ms) + " ms" + why);
    }
  }
  bool connected() const override { return tcp_ && tcp_->connected(); }
  bool send(const OutFrame &f, std::string *why) override {
    if (!tcp_) {
      if (why) *why = "not connected";
      return false;
    }
    return tcp_->send(f, why);
  }
  int64_t client_id() const override { return tcp_ ? tcp_->client_id() : 0; }
  std::string server_caps() const override { return tcp_ ? tcp_->server_caps() : ""; }
  std::string server_name() const override {
    return tcp_ ? tcp_->server_name() : "topic '" + o_.topic + "' on " + broker_name(o_);
  }
  void disconnect() override {
    if (tcp_) tcp_->disconnect();
    tcp_.reset();
  }

 private:
  NodeOptions o_;
  NodeCallbacks cb_;
  std::unique_ptr<Discovery> disc_;
  std::unique_ptr<ClientNode> tcp_;
};

}  // namespace

bool split_host_port(const std::string &s, std::string *host, uint16_t *port) {
  const std::size_t c = s.rfind(':');
  if (c == std::string::npos || c == 0 || c + 1 >= s.size()) return false;
  char *end = nullptr;
  const unsigned long v = std::strtoul(s.c_str() + c + 1, &end, 10);
  if (*end != '\0' || v == 0 || v > 65535) return false;
  *host = s.substr(0, c);
  *port = static_cast<uint16_t>(v);
  return true;
}

Discovery::Discovery(const NodeOptions &o, std::function<void()> on_change)
    : o_(o), on_change_(std::move(on_change)) {}

Discovery::~Discovery() {
  if (mqtt_) mqtt_->stop();
}

std::string Discovery::broker() const {
  return broker_name(o_);
}

void Discovery::start() {
  require_topic(o_);
  mqtt::ClientOptions mo{o_.dest_host, o_.dest_port,
                         "nns_edge_client_" + std::to_string(getpid()) + "_" +
                             std::to_string(reinterpret_cast<uintptr_t>(this)),
                         60, true};
  mqtt_ = std::make_unique<mqtt::Client>(
      mo, [this](const std::string &topic, const uint8_t *d, std::size_t n) {
        std::string hp(reinterpret_cast<const char *>(d), n);
        if (const auto z = hp.find('\0'); z != std::string::npos) hp.resize(z);
        {
          std::lock_guard<std::mutex> l(m_);
          for (auto it = order_.begin(); it != order_.end(); ++it)
            if (it->topic == topic) {
              order_.erase(it);
              break;
            }
          if (!hp.empty()) order_.push_back({topic, hp, ++gen_});  // empty: that server left
          cv_.notify_all();
        }
        if (on_change_) on_change_();
      });
  mqtt_->subscribe("edge/inference/+/" + o_.topic + "/#", 1);
  mqtt_->start();
  if (!mqtt_->wait_connected(std::chrono::milliseconds(kBrokerWaitMs))) {
    const std::string why = mqtt_->why();
    mqtt_.reset();
    fail(ErrorKind::kNotFound, "connect-type HYBRID: cannot connect to the MQTT broker " +
                                   broker_name(o_) + " (dest-host/dest-port)" +
                                   (why.empty() ? "" : ": " + why));
  }
}

std::vector<Discovery::Server> Discovery::servers() const {
  std::lock_guard<std::mutex> l(m_);
  return order_;
}

std::optional<Discovery::Server> Discovery::take_newest() {
  std::lock_guard<std::mutex> l(m_);
  if (order_.empty()) return std::nullopt;
  Server s = order_.back();
  order_.pop_back();
  return s;
}

bool Discovery::wait_any(std::chrono::steady_clock::time_point deadline) {
  std::unique_lock<std::mutex> l(m_);
  return cv_.wait_until(l, deadline, [&] { return !order_.empty(); });
}

std::unique_ptr<ServerNode> make_hybrid_server(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<HybridServer>(opts, std::move(cb));
}

std::unique_ptr<ClientNode> make_hybrid_client(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<HybridClient>(opts, std::move(cb));
}

}  // namespace nns::edge

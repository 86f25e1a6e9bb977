// SPDX-License-Identifier: LGPL-2.1-only
// connect-type MQTT, as nnstreamer-edge does it (docs/wire-edge-mqtt.md): the publisher
// (edgesink) connects to the broker at dest-host:dest-port (client id "nns_edge_<id>_<pid>",
// MQTT 3.1.1, clean session) and publishes every buffer as one serialized edge data
// (edge_data.h), QoS 1, retained, on "edge/inference/device-<id>/<topic>/". When it stops it
// clears the retained message (an empty retained publish). The subscriber (edgesrc) subscribes
// to "edge/inference/+/<topic>/#" with QoS 1 and parses every non-empty message; an empty one
// (a publisher leaving) is skipped. There is no capability exchange: the caps travel as the
// "caps" metadata of each message (our addition; nnstreamer-edge ignores unknown keys).
//
// Broker restarts: mqtt::Client (libmosquitto) reconnects with a 1..4 s back-off and
// subscribes again; the publisher drops (and counts) what it cannot publish meanwhile.
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <mutex>

#include "core/error.h"
#include "edge/edge_data.h"
#include "edge/edge_node.h"
#include "mqtt/mqtt_client.h"

namespace nns::edge {

namespace {

void require_topic(const NodeOptions &o) {
  if (o.topic.empty())
    fail(ErrorKind::kSettings,
         "connect-type MQTT needs the topic property (the MQTT topic the stream is "
         "published on)");
}

std::string broker_name(const NodeOptions &o) {
  return o.dest_host + ":" + std::to_string(o.dest_port);
}

// The broker connection of both roles: connects (MQTT 3.1.1, clean session), subscribes when
// asked, waits up to connect_timeout_ms, and warns once each time the link drops (libmosquitto
// reconnects by itself).
class BrokerLink {
 public:
  BrokerLink(const NodeOptions &o, const NodeCallbacks &cb) : o_(o), cb_(cb) {}
  void open(const std::string &client_id, const std::string &sub_topic,
            mqtt::Client::OnMessage on_message, const char *meanwhile) {
    mqtt::ClientOptions mo{o_.dest_host, o_.dest_port, client_id, 60, true};
    client_ = std::make_unique<mqtt::Client>(
        mo, std::move(on_message), [this, meanwhile](bool up, const std::string &why) {
          if (up_.exchange(up) && !up && cb_.on_warning)
            cb_.on_warning("connect-type MQTT: lost the MQTT broker " + broker_name(o_) +
                           (why.empty() ? "" : " (" + why + ")") + "; reconnecting" + meanwhile);
        });
    if (!sub_topic.empty()) client_->subscribe(sub_topic, 1);
    client_->start();
    if (!client_->wait_connected(std::chrono::milliseconds(o_.connect_timeout_ms))) {
      const std::string why = client_->why();
      client_.reset();
      fail(ErrorKind::kNotFound, "connect-type MQTT: cannot connect to the MQTT broker " +
                                     broker_name(o_) + " (dest-host/dest-port)" +
                                     (why.empty() ? "" : ": " + why));
    }
    up_ = true;
  }
  mqtt::Client *client() const { return client_.get(); }
  bool connected() const { return client_ && client_->connected(); }
  void close() {
    if (client_) client_->stop();
    client_.reset();
  }

 private:
  const NodeOptions &o_;
  const NodeCallbacks &cb_;
  std::unique_ptr<mqtt::Client> client_;
  std::atomic<bool> up_{false};
};

class MqttPublisher final : public ServerNode {
 public:
  MqttPublisher(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~MqttPublisher() override { stop(); }

  void start() override {
    require_topic(o_);
    const std::string id = std::to_string(new_client_id());
    topic_ = "edge/inference/device-" + id + "/" + o_.topic + "/";
    link_.open("nns_edge_" + id + "_" + std::to_string(getpid()), "", nullptr,
               ", buffers are dropped meanwhile");
  }
  uint16_t port() const override { return 0; }
  bool send_to(int64_t, const OutFrame &f, std::string *why) override {
    if (broadcast(f) > 0) return true;
    if (why) *why = "not published to the MQTT broker " + broker_name(o_);
    return false;
  }
  std::size_t broadcast(const OutFrame &f) override {
    if (!link_.client()) return 0;
    const std::vector<uint8_t> bytes = serialize_data(f);
    return link_.client()->publish(topic_, bytes.data(), bytes.size(), 1, true) ? 1 : 0;
  }
  // The broker is our only peer: "connected" while the broker link is up.
  std::size_t client_count() const override { return link_.connected() ? 1 : 0; }
  void stop() override {
    if (link_.connected()) {
      link_.client()->publish(topic_, nullptr, 0, 1, true);  // clear the retained message
      link_.client()->flush(std::chrono::milliseconds(1000));
    }
    link_.close();
  }

 private:
  NodeOptions o_;
  NodeCallbacks cb_;
  BrokerLink link_{o_, cb_};
  std::string topic_;
};

class MqttSubscriber final : public ClientNode {
 public:
  MqttSubscriber(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~MqttSubscriber() override { disconnect(); }

  void connect() override {
    require_topic(o_);
    disconnect();
    failed_ = false;
    link_.open(
        "nns_edge_sub_" + std::to_string(new_client_id()) + "_" + std::to_string(getpid()),
        "edge/inference/+/" + o_.topic + "/#",
        [this](const std::string &topic, const uint8_t *d, std::size_t n) {
          on_message(topic, d, n);
        },
        "");
  }
  bool connected() const override { return link_.connected(); }
  bool send(const OutFrame &, std::string *why) override {
    if (why) *why = "an MQTT subscriber does not send";
    return false;
  }
  int64_t client_id() const override { return 0; }
  std::string server_caps() const override { return ""; }
  std::string server_name() const override {
    return "topic '" + o_.topic + "' on the MQTT broker " + broker_name(o_);
  }
  void disconnect() override { link_.close(); }

 private:
  void on_message(const std::string &topic, const uint8_t *d, std::size_t n) {
    if (n == 0 || failed_) return;  // a publisher cleared its retained message
    Message m;
    std::string why;
    if (parse_data(d, n, o_.limits, cb_.alloc, &m, &why)) {
      if (cb_.on_data) cb_.on_data(std::move(m));
      return;
    }
    failed_ = true;
    if (cb_.on_closed)
      cb_.on_closed("message on topic '" + topic + "' (MQTT broker " + broker_name(o_) + ", " +
                        std::to_string(n) + " bytes) is not nnstreamer-edge data: " + why,
                    CloseKind::kProtocol);
  }

  NodeOptions o_;
  NodeCallbacks cb_;
  BrokerLink link_{o_, cb_};
  std::atomic<bool> failed_{false};
};

}  // namespace

std::unique_ptr<ServerNode> make_mqtt_server(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<MqttPublisher>(opts, std::move(cb));
}

std::unique_ptr<ClientNode> make_mqtt_client(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<MqttSubscriber>(opts, std::move(cb));
}

}  // namespace nns::edge

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

[[noreturn]] void broker_failed(const NodeOptions &o, const std::string &why) {
  fail(ErrorKind::kNotFound, "connect-type MQTT: cannot connect to the MQTT broker " +
                                 broker_name(o) + " (dest-host/dest-port)" +
                                 (why.empty() ? "" : ": " + why));
}

class MqttPublisher final : public ServerNode {
 public:
  MqttPublisher(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~MqttPublisher() override { stop(); }

  void start() override {
    require_topic(o_);
    const std::string id = std::to_string(new_client_id());
    topic_ = "edge/inference/device-" + id + "/" + o_.topic + "/";
    mqtt::ClientOptions mo{o_.dest_host, o_.dest_port,
                           "nns_edge_" + id + "_" + std::to_string(getpid()), 60, true};
    mqtt_ = std::make_unique<mqtt::Client>(mo, nullptr, [this](bool up, const std::string &why) {
      const bool was = up_.exchange(up);
      if (was && !up && cb_.on_warning)
        cb_.on_warning("connect-type MQTT: lost the MQTT broker " + broker_name(o_) +
                       (why.empty() ? "" : " (" + why + ")") +
                       "; reconnecting, buffers are dropped meanwhile");
    });
    mqtt_->start();
    if (!mqtt_->wait_connected(std::chrono::milliseconds(o_.connect_timeout_ms))) {
      const std::string why = mqtt_->why();
      mqtt_.reset();
      broker_failed(o_, why);
    }
    up_ = true;
  }
  uint16_t port() const override { return 0; }
  bool send_to(int64_t, const OutFrame &f, std::string *why) override {
    if (broadcast(f) > 0) return true;
    if (why) *why = "not published to the MQTT broker " + broker_name(o_);
    return false;
  }
  std::size_t broadcast(const OutFrame &f) override {
    if (!mqtt_) return 0;
    const std::vector<uint8_t> bytes = serialize_data(f);
    return mqtt_->publish(topic_, bytes.data(), bytes.size(), 1, true) ? 1 : 0;
  }
  // The broker is our only peer: "connected" while the broker link is up.
  std::size_t client_count() const override { return mqtt_ && mqtt_->connected() ? 1 : 0; }
  void stop() override {
    if (!mqtt_) return;
    if (mqtt_->connected()) {
      mqtt_->publish(topic_, nullptr, 0, 1, true);  // clear the retained message
      mqtt_->flush(std::chrono::milliseconds(1000));
    }
    mqtt_->stop();
    mqtt_.reset();
  }

 private:
  NodeOptions o_;
  NodeCallbacks cb_;
  std::unique_ptr<mqtt::Client> mqtt_;
  std::string topic_;
  std::atomic<bool> up_{false};
};

class MqttSubscriber final : public ClientNode {
 public:
  MqttSubscriber(const NodeOptions &o, NodeCallbacks cb) : o_(o), cb_(std::move(cb)) {}
  ~MqttSubscriber() override { disconnect(); }

  void connect() override {
    require_topic(o_);
    disconnect();
    failed_ = false;
    const std::string sub = "edge/inference/+/" + o_.topic + "/#";
    mqtt::ClientOptions mo{
        o_.dest_host, o_.dest_port,
        "nns_edge_sub_" + std::to_string(new_client_id()) + "_" + std::to_string(getpid()), 60,
        true};
    mqtt_ = std::make_unique<mqtt::Client>(
        mo,
        [this](const std::string &topic, const uint8_t *d, std::size_t n) {
          on_message(topic, d, n);
        },
        [this](bool up, const std::string &why) {
          const bool was = up_.exchange(up);
          if (was && !up && cb_.on_warning)
            cb_.on_warning("connect-type MQTT: lost the MQTT broker " + broker_name(o_) +
                           (why.empty() ? "" : " (" + why + ")") + "; reconnecting");
        });
    mqtt_->subscribe(sub, 1);
    mqtt_->start();
    if (!mqtt_->wait_connected(std::chrono::milliseconds(o_.connect_timeout_ms))) {
      const std::string why = mqtt_->why();
      mqtt_.reset();
      broker_failed(o_, why);
    }
    up_ = true;
  }
  bool connected() const override { return mqtt_ && mqtt_->connected(); }
  bool send(const OutFrame &, std::string *why) override {
    if (why) *why = "an MQTT subscriber does not send";
    return false;
  }
  int64_t client_id() const override { return 0; }
  std::string server_caps() const override { return ""; }
  std::string server_name() const override {
    return "topic '" + o_.topic + "' on the MQTT broker " + broker_name(o_);
  }
  void disconnect() override {
    if (mqtt_) mqtt_->stop();
    mqtt_.reset();
  }

 private:
  void on_message(const std::string &topic, const uint8_t *d, std::size_t n) {
    if (n == 0 || failed_) return;  // a publisher cleared its retained message
    Message m;
    std::string why;
    Limits limits = o_.limits;
    if (parse_data(d, n, limits, cb_.alloc, &m, &why)) {
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
  std::unique_ptr<mqtt::Client> mqtt_;
  std::atomic<bool> up_{false}, failed_{false};
};

}  // namespace

std::unique_ptr<ServerNode> make_mqtt_server(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<MqttPublisher>(opts, std::move(cb));
}

std::unique_ptr<ClientNode> make_mqtt_client(const NodeOptions &opts, NodeCallbacks cb) {
  return std::make_unique<MqttSubscriber>(opts, std::move(cb));
}

}  // namespace nns::edge

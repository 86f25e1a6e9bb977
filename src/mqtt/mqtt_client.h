// SPDX-License-Identifier: LGPL-2.1-only
// A small MQTT 3.1.1 client over libmosquitto (GStreamer-free) for mqttsink / mqttsrc.
// libmosquitto's own network thread connects, keeps the session alive and reconnects after a
// broker restart (1 s .. 4 s back-off); subscriptions are renewed on every connect.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <mutex>
#include <string>
#include <unordered_set>

struct mosquitto;
struct mosquitto_message;

namespace nns::mqtt {

struct ClientOptions {
  std::string host = "127.0.0.1";
  int port = 1883;
  std::string client_id;
  int keep_alive = 60;  // seconds
  bool clean_session = true;
};

class Client {
 public:
  // Called on libmosquitto's thread for every message of a subscribed topic; the bytes are
  // valid during the call only.
  using OnMessage = std::function<void(const std::string &topic, const uint8_t *data, std::size_t)>;
  // Called on libmosquitto's thread when the connection comes up (true) or goes down (false).
  using OnLink = std::function<void(bool up, const std::string &why)>;

  Client(ClientOptions opts, OnMessage on_message = {}, OnLink on_link = {});
  ~Client();
  Client(const Client &) = delete;
  Client &operator=(const Client &) = delete;

  // Last will, before start(): published by the broker (QoS 1) when the connection ends
  // without a DISCONNECT (the process died, the network broke). An empty payload with `retain`
  // clears a retained message. Throws nns::Error when libmosquitto refuses it.
  void set_will(const std::string &topic, const std::string &payload, bool retain);
  // Starts the network thread and the first connection attempt; returns at once. Throws
  // nns::Error when the host cannot be used at all.
  void start();
  // Waits until connected (and subscribed when subscribe() was called first).
  bool wait_connected(std::chrono::milliseconds t);
  bool connected() const;
  // Subscribed now when connected, and again after every reconnect.
  void subscribe(const std::string &topic, int qos);
  // Queues one message. Returns false (with why()) when not connected or refused.
  bool publish(const std::string &topic, const void *data, std::size_t size, int qos, bool retain);
  // Waits until every message queued with qos > 0 was acknowledged, or `t` passed.
  bool flush(std::chrono::milliseconds t);
  // Disconnects and stops the network thread (also done by the destructor).
  void stop();
  std::string why() const;
  const ClientOptions &options() const { return opts_; }

 private:
  static void on_connect_cb(mosquitto *, void *self, int rc);
  static void on_disconnect_cb(mosquitto *, void *self, int rc);
  static void on_subscribe_cb(mosquitto *, void *self, int mid, int n, const int *granted);
  static void on_message_cb(mosquitto *, void *self, const mosquitto_message *msg);
  static void on_publish_cb(mosquitto *, void *self, int mid);

  ClientOptions opts_;
  OnMessage on_message_;
  OnLink on_link_;
  mosquitto *mosq_ = nullptr;
  bool started_ = false;
  mutable std::mutex lock_;
  std::condition_variable cv_;
  bool connected_ = false;
  bool subscribed_ = false;
  std::string sub_topic_;
  int sub_qos_ = 0;
  // Message ids of QoS > 0 messages not yet acknowledged. publish() learns a message's id only
  // after mosquitto_publish() returned, and the acknowledgement can come first (the network
  // thread runs meanwhile): such ids wait in acked_early_ while publishing_ > 0. A counter
  // incremented after mosquitto_publish() lost that decrement and left flush() waiting its full
  // timeout for the rest of the client's life.
  std::unordered_set<int> in_flight_;
  std::unordered_set<int> acked_early_;
  int publishing_ = 0;  // publish() calls of QoS > 0 between the two locks
  std::string why_;
};

}  // namespace nns::mqtt

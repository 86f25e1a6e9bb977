// SPDX-License-Identifier: LGPL-2.1-only
#include "mqtt/mqtt_client.h"

#include <mosquitto.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace nns::mqtt {

namespace {

std::once_flag g_lib_once;

std::string mosq_text(int rc) {
  if (rc == MOSQ_ERR_ERRNO) return std::string("system error: ") + std::strerror(errno);
  return mosquitto_strerror(rc);
}

}  // namespace

Client::Client(ClientOptions opts, OnMessage on_message, OnLink on_link)
    : opts_(std::move(opts)), on_message_(std::move(on_message)), on_link_(std::move(on_link)) {
  std::call_once(g_lib_once, [] { mosquitto_lib_init(); });
  mosq_ = mosquitto_new(opts_.client_id.empty() ? nullptr : opts_.client_id.c_str(),
                        opts_.clean_session, this);
  if (!mosq_)
    fail(ErrorKind::kLibrary, "cannot create an MQTT client (client id '" + opts_.client_id + "')");
  mosquitto_int_option(mosq_, MOSQ_OPT_PROTOCOL_VERSION, MQTT_PROTOCOL_V311);
  mosquitto_reconnect_delay_set(mosq_, 1, 4, true);
  mosquitto_connect_callback_set(mosq_, &Client::on_connect_cb);
  mosquitto_disconnect_callback_set(mosq_, &Client::on_disconnect_cb);
  mosquitto_subscribe_callback_set(mosq_, &Client::on_subscribe_cb);
  mosquitto_message_callback_set(mosq_, &Client::on_message_cb);
  mosquitto_publish_callback_set(mosq_, &Client::on_publish_cb);
}

Client::~Client() {
  stop();
  if (mosq_) mosquitto_destroy(mosq_);
}

void Client::set_will(const std::string &topic, const std::string &payload, bool retain) {
  const int rc = mosquitto_will_set(mosq_, topic.c_str(), static_cast<int>(payload.size()),
                                    payload.data(), 1, retain);
  if (rc != MOSQ_ERR_SUCCESS)
    fail(ErrorKind::kSettings, "MQTT will on topic '" + topic + "': " + mosq_text(rc));
}

void Client::start() {
  if (started_) return;
  const int rc = mosquitto_connect_async(mosq_, opts_.host.c_str(), opts_.port, opts_.keep_alive);
  // A refused first attempt is retried by the network thread; only a host that cannot be used
  // at all is an error here.
  if (rc != MOSQ_ERR_SUCCESS && rc != MOSQ_ERR_ERRNO)
    fail(ErrorKind::kSettings,
         "MQTT broker " + opts_.host + ":" + std::to_string(opts_.port) + ": " + mosq_text(rc));
  const int lr = mosquitto_loop_start(mosq_);
  if (lr != MOSQ_ERR_SUCCESS)
    fail(ErrorKind::kLibrary, "cannot start the MQTT network thread: " + mosq_text(lr));
  started_ = true;
}

void Client::stop() {
  if (!started_) return;
  mosquitto_disconnect(mosq_);
  mosquitto_loop_stop(mosq_, false);
  started_ = false;
  std::lock_guard<std::mutex> l(lock_);
  connected_ = false;
  subscribed_ = false;
  cv_.notify_all();
}

bool Client::wait_connected(std::chrono::milliseconds t) {
  std::unique_lock<std::mutex> l(lock_);
  return cv_.wait_for(l, t, [&] { return connected_ && (sub_topic_.empty() || subscribed_); });
}

bool Client::connected() const {
  std::lock_guard<std::mutex> l(lock_);
  return connected_;
}

std::string Client::why() const {
  std::lock_guard<std::mutex> l(lock_);
  return why_;
}

void Client::subscribe(const std::string &topic, int qos) {
  bool now = false;
  {
    std::lock_guard<std::mutex> l(lock_);
    sub_topic_ = topic;
    sub_qos_ = qos;
    now = connected_;
  }
  if (now) mosquitto_subscribe(mosq_, nullptr, topic.c_str(), qos);
}

bool Client::publish(const std::string &topic, const void *data, std::size_t size, int qos,
                     bool retain) {
  {
    std::lock_guard<std::mutex> l(lock_);
    if (!connected_) {
      why_ = "not connected to the broker";
      return false;
    }
    if (qos > 0) ++publishing_;
  }
  int mid = 0;
  const int rc =
      mosquitto_publish(mosq_, &mid, topic.c_str(), static_cast<int>(size), data, qos, retain);
  std::lock_guard<std::mutex> l(lock_);
  if (qos > 0) {
    // The network thread may have seen the acknowledgement already (it often has under load:
    // it runs while this thread waits for the lock); then its mid is in acked_early_.
    --publishing_;
    if (rc == MOSQ_ERR_SUCCESS && acked_early_.erase(mid) == 0) in_flight_.insert(mid);
    if (publishing_ == 0) acked_early_.clear();  // only QoS 0 mids can be left there
    cv_.notify_all();
  }
  if (rc != MOSQ_ERR_SUCCESS) {
    why_ = mosq_text(rc);
    return false;
  }
  return true;
}

bool Client::flush(std::chrono::milliseconds t) {
  std::unique_lock<std::mutex> l(lock_);
  return cv_.wait_for(l, t, [&] { return in_flight_.empty() || !connected_; });
}

void Client::on_connect_cb(mosquitto *m, void *p, int rc) {
  auto *self = static_cast<Client *>(p);
  std::string topic;
  int qos = 0;
  {
    std::lock_guard<std::mutex> l(self->lock_);
    if (rc != 0) {
      self->why_ = std::string("broker refused the connection: ") + mosquitto_connack_string(rc);
      return;
    }
    self->connected_ = true;
    self->in_flight_.clear();
    topic = self->sub_topic_;
    qos = self->sub_qos_;
    if (topic.empty()) self->cv_.notify_all();
  }
  if (!topic.empty()) mosquitto_subscribe(m, nullptr, topic.c_str(), qos);
  if (self->on_link_) self->on_link_(true, {});
}

void Client::on_disconnect_cb(mosquitto *, void *p, int rc) {
  auto *self = static_cast<Client *>(p);
  std::string why = rc == 0 ? "disconnected" : "connection lost (" + mosq_text(rc) + ")";
  {
    std::lock_guard<std::mutex> l(self->lock_);
    self->connected_ = false;
    self->subscribed_ = false;
    self->why_ = why;
    self->cv_.notify_all();
  }
  if (rc != 0 && self->on_link_) self->on_link_(false, why);
}

void Client::on_subscribe_cb(mosquitto *, void *p, int, int, const int *) {
  auto *self = static_cast<Client *>(p);
  std::lock_guard<std::mutex> l(self->lock_);
  self->subscribed_ = true;
  self->cv_.notify_all();
}

void Client::on_message_cb(mosquitto *, void *p, const mosquitto_message *msg) {
  auto *self = static_cast<Client *>(p);
  if (!self->on_message_ || !msg) return;
  self->on_message_(msg->topic ? msg->topic : "", static_cast<const uint8_t *>(msg->payload),
                    msg->payloadlen > 0 ? static_cast<std::size_t>(msg->payloadlen) : 0);
}

void Client::on_publish_cb(mosquitto *, void *p, int mid) {
  auto *self = static_cast<Client *>(p);
  std::lock_guard<std::mutex> l(self->lock_);
  // A mid not (yet) in in_flight_: a QoS 0 message, or a QoS > 0 one whose publish() has not
  // recorded it yet; kept for that publish() only while one is under way.
  if (self->in_flight_.erase(mid) == 0 && self->publishing_ > 0) self->acked_early_.insert(mid);
  self->cv_.notify_all();
}

}  // namespace nns::mqtt

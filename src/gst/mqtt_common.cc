// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/mqtt_common.h"

#include <unistd.h>

#include <atomic>
#include <cstdlib>

#include "core/error.h"

namespace nns::gst::mqtt {

void install_common_properties(GObjectClass *klass, const Role &role) {
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      klass, kPropDebug,
      g_param_spec_boolean("debug", "Debug", "Produce extra verbose output for debug purpose",
                           FALSE, rw));
  g_object_class_install_property(
      klass, kPropClientId,
      g_param_spec_string("client-id", "Client ID", role.client_id_blurb, role.default_client_id,
                          rw));
  g_object_class_install_property(
      klass, kPropHost,
      g_param_spec_string("host", "Host", "Host (broker) to connect to", kDefaultHost, rw));
  g_object_class_install_property(
      klass, kPropPort,
      g_param_spec_string("port", "Port", "Network port of host (broker) to connect to",
                          kDefaultPort, rw));
  g_object_class_install_property(
      klass, kPropCleanSession,
      g_param_spec_boolean("cleansession", "Cleansession",
                           "When it is TRUE, the state information is discarded at connect and "
                           "disconnect.",
                           TRUE, rw));
  g_object_class_install_property(
      klass, kPropKeepAlive,
      g_param_spec_int("keep-alive-interval", "Keep Alive Interval",
                       "The maximum time (in seconds) that should pass without communication "
                       "between the client and the server (broker)",
                       1, G_MAXINT32, 60, rw));
  g_object_class_install_property(
      klass, kPropQos,
      g_param_spec_int("mqtt-qos", "mqtt QoS level",
                       "The QoS level of MQTT.\n\t\t\t  0: At most once\n\t\t\t  1: At least "
                       "once\n\t\t\t  2: Exactly once",
                       0, 2, role.default_qos, rw));
}

std::string string_value(const GValue *value) {
  const gchar *v = g_value_get_string(value);
  return v ? v : "";
}

bool set_common_property(CommonSettings &s, guint id, const GValue *value) {
  switch (id) {
    case kPropDebug:
      s.debug = g_value_get_boolean(value);
      return true;
    case kPropClientId:
      s.client_id = string_value(value);
      return true;
    case kPropHost:
      s.host = string_value(value);
      return true;
    case kPropPort:
      s.port = string_value(value);
      return true;
    case kPropCleanSession:
      s.clean_session = g_value_get_boolean(value);
      return true;
    case kPropKeepAlive:
      s.keep_alive = g_value_get_int(value);
      return true;
    case kPropQos:
      s.qos = g_value_get_int(value);
      return true;
    default:
      return false;
  }
}

bool get_common_property(const CommonSettings &s, guint id, GValue *value) {
  switch (id) {
    case kPropDebug:
      g_value_set_boolean(value, s.debug);
      return true;
    case kPropClientId:
      g_value_set_string(value, s.client_id.c_str());
      return true;
    case kPropHost:
      g_value_set_string(value, s.host.c_str());
      return true;
    case kPropPort:
      g_value_set_string(value, s.port.c_str());
      return true;
    case kPropCleanSession:
      g_value_set_boolean(value, s.clean_session);
      return true;
    case kPropKeepAlive:
      g_value_set_int(value, s.keep_alive);
      return true;
    case kPropQos:
      g_value_set_int(value, s.qos);
      return true;
    default:
      return false;
  }
}

std::string generated_client_id(const char *role) {
  static std::atomic<unsigned> counter{0};
  return std::string(g_get_host_name()) + "_" + std::to_string(getpid()) + "_" + role +
         std::to_string(counter++);
}

int parse_port(const std::string &s) {
  char *end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || v < 1 || v > 65535)
    fail(ErrorKind::kSettings, "port '" + s + "' is not a TCP port number (1..65535)");
  return static_cast<int>(v);
}

std::string broker_name(const CommonSettings &s) {
  return s.host + ":" + s.port;
}

nns::mqtt::ClientOptions client_options(CommonSettings &s, const Role &role) {
  const int port = parse_port(s.port);
  if (s.client_id == role.default_client_id) s.client_id = generated_client_id(role.name);
  return nns::mqtt::ClientOptions{s.host, port, s.client_id, s.keep_alive, s.clean_session};
}

void connect_or_fail(std::unique_ptr<nns::mqtt::Client> &client, const CommonSettings &s,
                     const std::string &doing) {
  client->start();
  if (client->wait_connected(std::chrono::seconds(kConnectTimeoutSec))) return;
  const std::string why = client->why();
  client.reset();
  fail(ErrorKind::kSettings, "cannot connect to the MQTT broker " + broker_name(s) + doing +
                                 " within " + std::to_string(kConnectTimeoutSec) +
                                 " s (host/port properties)" + (why.empty() ? "" : ": " + why));
}

}  // namespace nns::gst::mqtt

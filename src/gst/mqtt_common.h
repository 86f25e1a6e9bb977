// SPDX-License-Identifier: LGPL-2.1-only
// What mqttsink and mqttsrc share: NNStreamer's property defaults, the properties both have
// (install, set, get), the generated client id, the broker port check and the first connection.
#pragma once

#include <glib-object.h>

#include <chrono>
#include <memory>
#include <string>

#include "mqtt/mqtt_client.h"

namespace nns::gst::mqtt {

inline constexpr char kDefaultHost[] = "127.0.0.1";
inline constexpr char kDefaultPort[] = "1883";
// Upstream's placeholder values: when a property still holds them, start() generates one.
inline constexpr char kSinkDefaultClientId[] = "$HOST_$PID_^[0-9][0-9]?$|^255$";
inline constexpr char kSrcDefaultClientId[] = "$HOSTNAME_$PID_^[0-9][0-9]?$|^255$";
inline constexpr char kDefaultPubTopic[] = "$client-id/topic";
inline constexpr char kDefaultNtpServers[] = "pool.ntp.org:123";
inline constexpr int kConnectTimeoutSec = 5;  // upstream DEFAULT_MQTT_CONN_TIMEOUT_SEC

// How the two elements' shared properties differ (upstream's defaults and texts).
struct Role {
  const char *name;               // "sink" / "src": the generated client id's suffix
  const char *default_client_id;  // the placeholder above
  const char *client_id_blurb;
  int default_qos;
};
inline constexpr Role kSinkRole{"sink", kSinkDefaultClientId,
                                "The client identifier passed to the server (broker).", 0};
inline constexpr Role kSrcRole{"src", kSrcDefaultClientId,
                               "The client identifier passed to the server (broker)", 2};

// The properties both elements have, with their property ids; an element numbers its own
// properties from kPropFirstOwn.
enum CommonProp : guint {
  kPropDebug = 1,
  kPropClientId,
  kPropHost,
  kPropPort,
  kPropCleanSession,
  kPropKeepAlive,
  kPropQos,
  kPropFirstOwn,
};

struct CommonSettings {
  explicit CommonSettings(const Role &r) : client_id(r.default_client_id), qos(r.default_qos) {}
  bool debug = false;
  std::string client_id;
  std::string host = kDefaultHost;
  std::string port = kDefaultPort;
  bool clean_session = true;
  gint keep_alive = 60;
  gint qos;
};

// Installs debug, client-id, host, port, cleansession, keep-alive-interval and mqtt-qos.
void install_common_properties(GObjectClass *klass, const Role &role);
// Set / get one of them: false when `id` is not a common property.
bool set_common_property(CommonSettings &s, guint id, const GValue *value);
bool get_common_property(const CommonSettings &s, guint id, GValue *value);

// A string property's value; "" for NULL.
std::string string_value(const GValue *value);

// "<host name>_<pid>_sink<n>" / "..._src<n>", as upstream names its clients.
std::string generated_client_id(const char *role);

// The `port` property is a string upstream; it must be a TCP port number.
int parse_port(const std::string &s);

// "host:port" of the broker, for messages.
std::string broker_name(const CommonSettings &s);

// The client options of the settings start() took: checks the port and replaces a placeholder
// client id by a generated one (in `s`, so the element's messages use it).
nns::mqtt::ClientOptions client_options(CommonSettings &s, const Role &role);

// Starts `client` and waits up to kConnectTimeoutSec for the broker; when it does not answer,
// drops the client and throws nns::Error naming the broker (and `doing`, e.g. the subscription).
void connect_or_fail(std::unique_ptr<nns::mqtt::Client> &client, const CommonSettings &s,
                     const std::string &doing);

}  // namespace nns::gst::mqtt

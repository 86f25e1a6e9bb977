// SPDX-License-Identifier: LGPL-2.1-only
// What mqttsink and mqttsrc share: NNStreamer's property defaults, the generated client id
// and the broker port check.
#pragma once

#include <glib.h>
#include <unistd.h>

#include <atomic>
#include <cstdlib>
#include <string>

#include "core/error.h"

namespace nns::gst::mqtt {

inline constexpr char kDefaultHost[] = "127.0.0.1";
inline constexpr char kDefaultPort[] = "1883";
// Upstream's placeholder values: when a property still holds them, start() generates one.
inline constexpr char kSinkDefaultClientId[] = "$HOST_$PID_^[0-9][0-9]?$|^255$";
inline constexpr char kSrcDefaultClientId[] = "$HOSTNAME_$PID_^[0-9][0-9]?$|^255$";
inline constexpr char kDefaultPubTopic[] = "$client-id/topic";
inline constexpr char kDefaultNtpServers[] = "pool.ntp.org:123";
inline constexpr int kConnectTimeoutSec = 5;  // upstream DEFAULT_MQTT_CONN_TIMEOUT_SEC

// "<host name>_<pid>_sink<n>" / "..._src<n>", as upstream names its clients.
inline std::string generated_client_id(const char *role) {
  static std::atomic<unsigned> counter{0};
  return std::string(g_get_host_name()) + "_" + std::to_string(getpid()) + "_" + role +
         std::to_string(counter++);
}

// The `port` property is a string upstream; it must be a TCP port number.
inline int parse_port(const std::string &s) {
  char *end = nullptr;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (s.empty() || *end != '\0' || v < 1 || v > 65535)
    fail(ErrorKind::kSettings, "port '" + s + "' is not a TCP port number (1..65535)");
  return static_cast<int>(v);
}

}  // namespace nns::gst::mqtt

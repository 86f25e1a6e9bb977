// SPDX-License-Identifier: LGPL-2.1-only
// The SNTP query behind mqttsink's ntp-sync / ntp-srvs (GStreamer-free): one 48-byte client
// request (version 3, mode 3) over UDP, the server's transmit timestamp turned into Unix
// epoch microseconds, as NNStreamer's gst/mqtt/ntputil.c. Unlike it, every server gets a
// bounded wait instead of a blocking read, and a failure is an exception, not a negative time.
#pragma once

#include <chrono>
#include <cstdint>
#include <string>
#include <vector>

namespace nns::mqtt {

struct NtpServer {
  std::string host;
  uint16_t port = 123;
};

// "host:port[,host:port...]". Pairs whose port is missing, 0 or above 65535 are skipped, as
// upstream's property setter does.
std::vector<NtpServer> parse_ntp_servers(const std::string &pairs);

// NTP timestamp (seconds since 1900, 32-bit fraction) -> microseconds since 1970. Throws
// nns::Error when the seconds are not after 1970.
int64_t ntp_to_epoch_us(uint32_t sec, uint32_t frac);

// Asks each server in turn and returns the first answer as epoch microseconds. Throws
// nns::Error naming every server and why it failed (unresolved, no answer in `wait`, bad
// reply) when none answers.
int64_t ntp_epoch_us(const std::vector<NtpServer> &servers, std::chrono::milliseconds wait);

}  // namespace nns::mqtt

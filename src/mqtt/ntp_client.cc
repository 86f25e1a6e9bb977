// SPDX-License-Identifier: LGPL-2.1-only
#include "mqtt/ntp_client.h"

#include <netdb.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>

#include "core/error.h"

namespace nns::mqtt {

namespace {

constexpr uint64_t kNtpToUnixSeconds = 2208988800ULL;  // 1900-01-01 .. 1970-01-01
constexpr std::size_t kPacketSize = 48;
constexpr std::size_t kXmitOffset = 40;

uint32_t be32(const uint8_t *p) {
  return static_cast<uint32_t>(p[0]) << 24 | static_cast<uint32_t>(p[1]) << 16 |
         static_cast<uint32_t>(p[2]) << 8 | p[3];
}

// One server: the epoch in microseconds, or throws with the reason.
int64_t ask(const NtpServer &s, std::chrono::milliseconds wait) {
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_DGRAM;
  addrinfo *res = nullptr;
  const std::string port = std::to_string(s.port);
  const int gai = getaddrinfo(s.host.c_str(), port.c_str(), &hints, &res);
  if (gai != 0 || !res) fail(ErrorKind::kLibrary, std::string("unresolved: ") + gai_strerror(gai));
  const int fd = socket(res->ai_family, res->ai_socktype | SOCK_CLOEXEC, res->ai_protocol);
  if (fd < 0) {
    freeaddrinfo(res);
    fail(ErrorKind::kLibrary, std::string("socket: ") + std::strerror(errno));
  }
  struct Closer {
    int fd;
    ~Closer() { close(fd); }
  } closer{fd};
  const int rc = connect(fd, res->ai_addr, res->ai_addrlen);
  freeaddrinfo(res);
  if (rc < 0) fail(ErrorKind::kLibrary, std::string("connect: ") + std::strerror(errno));
  uint8_t pkt[kPacketSize] = {};
  pkt[0] = 0x1B;  // leap indicator 0, version 3, mode 3 (client)
  if (send(fd, pkt, sizeof pkt, 0) != static_cast<ssize_t>(sizeof pkt))
    fail(ErrorKind::kLibrary, std::string("send: ") + std::strerror(errno));
  pollfd p{fd, POLLIN, 0};
  const int pr = poll(&p, 1, static_cast<int>(wait.count()));
  if (pr == 0)
    fail(ErrorKind::kLibrary, "no answer within " + std::to_string(wait.count()) + " ms");
  if (pr < 0) fail(ErrorKind::kLibrary, std::string("poll: ") + std::strerror(errno));
  uint8_t reply[kPacketSize] = {};
  const ssize_t n = recv(fd, reply, sizeof reply, 0);
  if (n < 0) fail(ErrorKind::kLibrary, std::string("recv: ") + std::strerror(errno));
  if (static_cast<std::size_t>(n) < kPacketSize)
    fail(ErrorKind::kLibrary, "reply of " + std::to_string(n) + " bytes (48 expected)");
  const int mode = reply[0] & 0x7;
  if (mode != 4 && mode != 5)
    fail(ErrorKind::kLibrary, "reply mode " + std::to_string(mode) + " is not a server's (4)");
  return ntp_to_epoch_us(be32(reply + kXmitOffset), be32(reply + kXmitOffset + 4));
}

}  // namespace

std::vector<NtpServer> parse_ntp_servers(const std::string &pairs) {
  std::vector<NtpServer> out;
  std::size_t start = 0;
  while (start <= pairs.size()) {
    std::size_t comma = pairs.find(',', start);
    if (comma == std::string::npos) comma = pairs.size();
    const std::string pair = pairs.substr(start, comma - start);
    start = comma + 1;
    const std::size_t colon = pair.find(':');
    if (colon == std::string::npos || colon == 0) continue;
    const std::string port = pair.substr(colon + 1);
    char *end = nullptr;
    const unsigned long v = std::strtoul(port.c_str(), &end, 10);
    if (port.empty() || v == 0 || v > 65535) continue;
    out.push_back({pair.substr(0, colon), static_cast<uint16_t>(v)});
  }
  return out;
}

int64_t ntp_to_epoch_us(uint32_t sec, uint32_t frac) {
  if (sec <= kNtpToUnixSeconds)
    fail(ErrorKind::kLibrary, "NTP time " + std::to_string(sec) + " s is not after 1970");
  const int64_t whole = static_cast<int64_t>(sec - kNtpToUnixSeconds) * 1000000;
  const int64_t part = static_cast<int64_t>((static_cast<uint64_t>(frac) * 1000000) >> 32);
  return whole + part;
}

int64_t ntp_epoch_us(const std::vector<NtpServer> &servers, std::chrono::milliseconds wait) {
  if (servers.empty()) fail(ErrorKind::kSettings, "no NTP server given (ntp-srvs)");
  std::string why;
  for (const auto &s : servers) {
    try {
      return ask(s, wait);
    } catch (const Error &e) {
      why += (why.empty() ? "" : "; ") + s.host + ":" + std::to_string(s.port) + ": " + e.what();
    }
  }
  fail(ErrorKind::kLibrary, "no NTP server answered: " + why);
}

}  // namespace nns::mqtt

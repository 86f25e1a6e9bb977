// SPDX-License-Identifier: LGPL-2.1-only
// The SNTP query against a responder on 127.0.0.1 run by the test (no NTP traffic leaves the
// machine).
#include "mqtt/ntp_client.h"

#include <arpa/inet.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstring>
#include <thread>

#include "core/error.h"

using namespace nns::mqtt;
using namespace std::chrono_literals;

namespace {

// Answers every request with transmit time `sec`.`frac` (NTP era), or stays silent.
class FakeNtp {
 public:
  FakeNtp(uint32_t sec, uint32_t frac, bool answer, uint8_t mode = 4) {
    fd_ = socket(AF_INET, SOCK_DGRAM, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    bind(fd_, reinterpret_cast<sockaddr *>(&a), sizeof a);
    socklen_t len = sizeof a;
    getsockname(fd_, reinterpret_cast<sockaddr *>(&a), &len);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([=, this] {
      while (!stop_) {
        pollfd p{fd_, POLLIN, 0};
        if (poll(&p, 1, 50) <= 0) continue;
        uint8_t req[48];
        sockaddr_in from{};
        socklen_t fl = sizeof from;
        const ssize_t n =
            recvfrom(fd_, req, sizeof req, 0, reinterpret_cast<sockaddr *>(&from), &fl);
        if (n != 48 || req[0] != 0x1B) continue;
        ++requests_;
        if (!answer) continue;
        uint8_t rep[48] = {};
        rep[0] = static_cast<uint8_t>(0x18 | mode);
        const uint32_t s = htonl(sec), f = htonl(frac);
        std::memcpy(rep + 40, &s, 4);
        std::memcpy(rep + 44, &f, 4);
        sendto(fd_, rep, sizeof rep, 0, reinterpret_cast<sockaddr *>(&from), fl);
      }
    });
  }
  ~FakeNtp() {
    stop_ = true;
    thread_.join();
    close(fd_);
  }
  uint16_t port() const { return port_; }
  int requests() const { return requests_; }

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::atomic<int> requests_{0};
  std::thread thread_;
};

}  // namespace

TEST(NtpClient, ParseServers) {
  auto v = parse_ntp_servers("pool.ntp.org:123,bad,:5,host:0,host:70000,127.0.0.1:4123");
  ASSERT_EQ(v.size(), 2u);
  EXPECT_EQ(v[0].host, "pool.ntp.org");
  EXPECT_EQ(v[0].port, 123);
  EXPECT_EQ(v[1].host, "127.0.0.1");
  EXPECT_EQ(v[1].port, 4123);
  EXPECT_TRUE(parse_ntp_servers("").empty());
}

TEST(NtpClient, Conversion) {
  // 2021-01-01T00:00:00Z = 1609459200 s after 1970; half a second in the fraction.
  EXPECT_EQ(ntp_to_epoch_us(1609459200u + 2208988800u, 0x80000000u), 1609459200500000LL);
  EXPECT_THROW(ntp_to_epoch_us(100, 0), nns::Error);
}

TEST(NtpClient, AsksTheFirstServerThatAnswers) {
  FakeNtp silent(0, 0, false);
  FakeNtp good(3900000000u, 0x40000000u, true);
  const int64_t us =
      ntp_epoch_us({{"127.0.0.1", silent.port()}, {"127.0.0.1", good.port()}}, 200ms);
  EXPECT_EQ(us, (3900000000LL - 2208988800LL) * 1000000 + 250000);
  EXPECT_EQ(silent.requests(), 1);
  EXPECT_EQ(good.requests(), 1);
}

TEST(NtpClient, FailsNamingEveryServer) {
  FakeNtp silent(0, 0, false);
  FakeNtp client_mode(3900000000u, 0, true, 3);
  try {
    ntp_epoch_us({{"127.0.0.1", silent.port()}, {"127.0.0.1", client_mode.port()}}, 100ms);
    FAIL() << "no error";
  } catch (const nns::Error &e) {
    const std::string w = e.what();
    EXPECT_NE(w.find("127.0.0.1:" + std::to_string(silent.port()) + ": no answer within 100 ms"),
              std::string::npos)
        << w;
    EXPECT_NE(w.find("reply mode 3"), std::string::npos) << w;
  }
  EXPECT_THROW(ntp_epoch_us({}, 10ms), nns::Error);
}

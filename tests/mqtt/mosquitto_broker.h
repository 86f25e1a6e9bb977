// SPDX-License-Identifier: LGPL-2.1-only
// A real MQTT broker for the tests: Debian's mosquitto on 127.0.0.1 and a free port, from a
// tiny config file; started by the test, waited for until it accepts, stopped by its PID. Its
// config and log live in a /tmp/nns_mosquitto_XXXXXX folder that the destructor removes.
#pragma once

#include <fcntl.h>
#include <signal.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>

#include "../support/net_util.h"  // relative: bench/among_device_bench.cc includes this file too

extern char **environ;

namespace mqtt_test {

using namespace std::chrono_literals;

using nns::test::free_port;
using nns::test::port_open;

inline const char *mosquitto_path() {
  for (const char *p : {"/usr/sbin/mosquitto", "/usr/bin/mosquitto"})
    if (access(p, X_OK) == 0) return p;
  return nullptr;
}

class Broker {
 public:
  explicit Broker(uint16_t port = 0) : port_(port ? port : free_port()) {
    char tmpl[] = "/tmp/nns_mosquitto_XXXXXX";
    own_dir_ = mkdtemp(tmpl) != nullptr;
    dir_ = own_dir_ ? tmpl : "/tmp";
    conf_ = dir_ + "/mosquitto.conf";
    log_ = dir_ + "/mosquitto.log";
    std::ofstream(conf_) << "listener " << port_ << " 127.0.0.1\n"
                         << "allow_anonymous true\npersistence false\n"
                         << "log_dest stderr\nlog_type error\nlog_type warning\n";
  }
  // Stops the broker, then removes its config, log and folder.
  ~Broker() {
    stop();
    if (!own_dir_) return;
    std::remove(conf_.c_str());
    std::remove(log_.c_str());
    rmdir(dir_.c_str());
  }
  Broker(const Broker &) = delete;
  Broker &operator=(const Broker &) = delete;
  uint16_t port() const { return port_; }
  std::string port_str() const { return std::to_string(port_); }

  // Starts mosquitto and waits until it accepts connections.
  bool start() {
    const char *exe = mosquitto_path();
    if (!exe) return false;
    std::string e = exe, c = "-c";
    char *argv[] = {e.data(), c.data(), conf_.data(), nullptr};
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log_.c_str(), O_WRONLY | O_CREAT | O_APPEND, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    const int rc = posix_spawn(&pid_, exe, &fa, nullptr, argv, environ);
    posix_spawn_file_actions_destroy(&fa);
    if (rc != 0) {
      pid_ = -1;
      return false;
    }
    const auto end = std::chrono::steady_clock::now() + 10s;
    while (std::chrono::steady_clock::now() < end) {
      if (port_open(port_)) return true;
      int st = 0;
      if (waitpid(pid_, &st, WNOHANG) == pid_) {
        pid_ = -1;
        return false;
      }
      std::this_thread::sleep_for(10ms);
    }
    return false;
  }

  // What mosquitto wrote (errors and warnings), e.g. why it did not start.
  std::string log() const {
    std::ifstream f(log_);
    std::stringstream ss;
    ss << f.rdbuf();
    return ss.str();
  }

  // SIGTERM, then SIGKILL after 3 s; reaps the process.
  void stop() {
    if (pid_ <= 0) return;
    ::kill(pid_, SIGTERM);
    int st = 0;
    const auto end = std::chrono::steady_clock::now() + 3s;
    while (waitpid(pid_, &st, WNOHANG) != pid_) {
      if (std::chrono::steady_clock::now() > end) {
        ::kill(pid_, SIGKILL);
        waitpid(pid_, &st, 0);
        break;
      }
      std::this_thread::sleep_for(10ms);
    }
    pid_ = -1;
  }

 private:
  uint16_t port_;
  pid_t pid_ = -1;
  bool own_dir_ = false;
  std::string dir_, conf_, log_;
};

}  // namespace mqtt_test

// Skips (or fails under CI=true) when Debian's mosquitto is not installed (tests only: needs
// support/harness.h).
#define MQTT_REQUIRE_BROKER(b)                                                   \
  do {                                                                           \
    if (!::mqtt_test::mosquitto_path())                                          \
      NNS_SKIP_UNLESS_CI("mosquitto is not installed (scripts/deps/mqtt.apt)");  \
    ASSERT_TRUE((b).start()) << "mosquitto did not start on port " << (b).port() \
                             << "; its log: " << (b).log();                      \
  } while (0)

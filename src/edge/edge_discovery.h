// SPDX-License-Identifier: LGPL-2.1-only
// The discovery half of connect-type HYBRID, as nnstreamer-edge does it: subscribes to
// "edge/inference/+/<topic>/#" on the broker at dest-host:dest-port and keeps the servers
// announced there ("<host>:<port>" and a NUL byte per retained message; an empty retained
// message removes one). Used by the HYBRID query client (edge_hybrid.cc) and by the
// load-balancing client pool (edge_pool.cc). GStreamer-free.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "edge/edge_node.h"

namespace nns::mqtt {
class Client;
}

namespace nns::edge {

// "host:port" -> parts; false when malformed.
bool split_host_port(const std::string &s, std::string *host, uint16_t *port);

class Discovery {
 public:
  struct Server {
    std::string topic;    // the announcement topic (one per server)
    std::string address;  // "host:port" as announced
    uint64_t generation;  // bumped by every announcement (a restarted server re-announces)
  };
  // `on_change` (optional) runs on the MQTT thread after every change.
  Discovery(const NodeOptions &o, std::function<void()> on_change = {});
  ~Discovery();
  // Connects to the broker and subscribes; throws nns::Error naming the broker.
  void start();
  // The announced servers, oldest announcement first.
  std::vector<Server> servers() const;
  // Removes and returns the newest announcement (HYBRID client: try newest first).
  std::optional<Server> take_newest();
  // Waits until some server is announced or `deadline`; false on timeout.
  bool wait_any(std::chrono::steady_clock::time_point deadline);
  std::string broker() const;

 private:
  NodeOptions o_;
  std::function<void()> on_change_;
  std::unique_ptr<mqtt::Client> mqtt_;
  mutable std::mutex m_;
  std::condition_variable cv_;
  std::vector<Server> order_;  // oldest first
  uint64_t gen_ = 0;
};

}  // namespace nns::edge

// SPDX-License-Identifier: LGPL-2.1-only
// A query client's connections to several query servers (tensor_query_client with
// load-balance, docs/elements/tensor_query_client.md): one nnstreamer-edge TCP session per
// server, servers taken from a static list or discovered through the MQTT broker (HYBRID).
// Each request goes to one server chosen by the policy; a server answers the requests of one
// session in the order it got them (nnstreamer-edge's query servers, ours and upstream's, do),
// so answers are matched to requests per session without anything added to the wire. When a
// session ends, its requests in flight are re-sent once to another server (or reported lost).
// GStreamer-free; the callbacks run on the sessions' and the pool's threads.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "edge/edge_node.h"

namespace nns::edge {

class Discovery;

enum class Balance { kNone = 0, kRoundRobin = 1, kLeastOutstanding = 2 };

struct Endpoint {
  std::string host;
  uint16_t port = 0;
  std::string name() const { return host + ":" + std::to_string(port); }
};

// "h1,h2:3001, h3" -> endpoints (entries without a port take `default_port`). Throws
// nns::Error (kSettings) naming the bad entry.
std::vector<Endpoint> parse_endpoints(const std::string &list, uint16_t default_port);

struct PoolOptions {
  NodeOptions node;  // host/port: our answer listeners (port: the first session's only)
  ConnectType type = ConnectType::kTcp;  // kTcp: `endpoints`; kHybrid: discovery
  std::vector<Endpoint> endpoints;
  Balance policy = Balance::kRoundRobin;
  bool resend = true;
  int retry_ms = 1000;  // a lost static server is tried again this often
};

struct PoolCallbacks {
  std::function<void(uint64_t seq, Message &&)> on_answer;
  std::function<void(uint64_t seq)> on_lost;  // not answered and not re-sent
  std::function<void(const std::string &)> on_warning, on_info;
  // Checks a server's capability string; an error text refuses that server.
  std::function<std::optional<std::string>(const std::string &)> accept_caps;
  Allocator alloc;
};

struct ServerStats {
  std::string name;
  bool live = false;
  uint64_t sent = 0, received = 0, lost = 0, resent = 0, in_flight = 0;
  double latency_mean_us = 0, latency_max_us = 0;
};

// The client's reorder buffer: requests numbered in input order (contiguous numbers), answers
// and losses that arrive out of order held until every older request is resolved. P is what
// the caller keeps per request (its timestamps).
template <typename P>
class InOrder {
 public:
  void add(uint64_t seq, P p) { waiting_.push_back({seq, std::move(p)}); }
  // In flight and not yet resolved (a late duplicate, after a re-send, is not).
  bool unresolved(uint64_t seq) const {
    return !waiting_.empty() && seq >= waiting_.front().first && seq <= waiting_.back().first &&
           !done_.count(seq) && !lost_.count(seq);
  }
  bool answer(uint64_t seq, Message &&m) {
    if (!unresolved(seq)) return false;
    done_.emplace(seq, std::move(m));
    return true;
  }
  bool lose(uint64_t seq) {
    if (!unresolved(seq)) return false;
    lost_.insert(seq);
    return true;
  }
  // Hands the resolved requests at the front over, oldest first: on_answer(P &, Message &&)
  // or on_lost(P &).
  template <typename A, typename L>
  void pop_ready(A on_answer, L on_lost) {
    while (!waiting_.empty()) {
      auto &[seq, p] = waiting_.front();
      if (auto it = done_.find(seq); it != done_.end()) {
        on_answer(p, std::move(it->second));
        done_.erase(it);
      } else if (lost_.erase(seq)) {
        on_lost(p);
      } else {
        break;
      }
      waiting_.pop_front();
    }
  }
  std::size_t size() const { return waiting_.size(); }
  void clear() {
    waiting_.clear();
    done_.clear();
    lost_.clear();
  }

 private:
  std::deque<std::pair<uint64_t, P>> waiting_;
  std::map<uint64_t, Message> done_;
  std::set<uint64_t> lost_;
};

class ClientPool {
 public:
  ClientPool(PoolOptions o, PoolCallbacks cb);
  ~ClientPool();
  ClientPool(const ClientPool &) = delete;
  ClientPool &operator=(const ClientPool &) = delete;

  // Connects to every known server (waiting up to node.connect_timeout_ms for the first one)
  // and starts the thread that follows servers coming and going. Throws nns::Error naming
  // every server tried and why it failed; a caps refusal is kNegotiation.
  void start();
  // Sends request `seq` to a server; false when no server is connected. `frame` stays alive
  // until answered or lost (re-sending needs it).
  bool submit(uint64_t seq, std::shared_ptr<const OutFrame> frame);
  std::vector<ServerStats> stats() const;
  std::size_t live() const;
  void stop();

 private:
  struct Inflight {
    uint64_t seq;
    std::shared_ptr<const OutFrame> frame;
    std::chrono::steady_clock::time_point sent;
    bool resent;
  };
  struct Link;

  std::shared_ptr<Link> add_link_locked(const Endpoint &e);
  bool open(const std::shared_ptr<Link> &l, int timeout_ms, std::string *why, bool *refused);
  void answered(Link *l, Message &&m);
  std::shared_ptr<Link> pick_locked(const Link *exclude);
  bool send_on(const std::shared_ptr<Link> &l, Inflight f);
  bool route(Inflight f, const Link *exclude);
  void fail_over(const std::shared_ptr<Link> &l);
  void maintain(int timeout_ms, std::string *why, bool *refused, bool announce);
  void loop();

  PoolOptions o_;
  PoolCallbacks cb_;
  std::unique_ptr<Discovery> disc_;
  mutable std::mutex m_;
  std::condition_variable cv_;
  std::vector<std::shared_ptr<Link>> links_;  // every server seen, connected or not
  std::size_t rr_ = 0;
  bool stop_ = false, changed_ = false;
  std::thread thread_;
};

}  // namespace nns::edge

// SPDX-License-Identifier: LGPL-2.1-only
// Load balancing over several query servers; see edge_pool.h.
#include "edge/edge_pool.h"

#include <algorithm>

#include "core/error.h"
#include "edge/edge_discovery.h"

namespace nns::edge {

using Clock = std::chrono::steady_clock;

namespace {
constexpr int kTickMs = 100;            // the pool thread looks at the servers this often
constexpr int kRejoinTimeoutMs = 1000;  // a (re)connect from the pool thread is bounded so
}  // namespace

std::vector<Endpoint> parse_endpoints(const std::string &list, uint16_t default_port) {
  std::vector<Endpoint> out;
  std::size_t pos = 0;
  while (pos <= list.size()) {
    std::size_t comma = list.find(',', pos);
    if (comma == std::string::npos) comma = list.size();
    std::string item = list.substr(pos, comma - pos);
    pos = comma + 1;
    const auto b = item.find_first_not_of(" \t");
    const auto e = item.find_last_not_of(" \t");
    item = b == std::string::npos ? "" : item.substr(b, e - b + 1);
    if (item.empty())
      fail(ErrorKind::kSettings, "dest-host '" + list + "': empty entry in the server list");
    Endpoint ep;
    if (item.find(':') != std::string::npos) {
      if (!split_host_port(item, &ep.host, &ep.port))
        fail(ErrorKind::kSettings, "dest-host '" + list + "': entry '" + item +
                                       "' is not host or host:port (port 1..65535)");
    } else {
      ep.host = item;
      ep.port = default_port;
    }
    out.push_back(ep);
  }
  return out;
}

struct ClientPool::Link {
  Endpoint ep;
  std::string name;
  std::mutex send_m;  // the node, and the order of fifo pushes and sends
  std::unique_ptr<ClientNode> node;
  // Under the pool's m_:
  uint64_t session = 0;     // bumped by every connect attempt
  uint64_t generation = 0;  // HYBRID: the newest announcement of this server
  uint64_t tried_gen = 0;   // HYBRID: the announcement last tried
  bool live = false;
  bool closed = false;   // the session ended; fail_over() not done yet
  bool retired = false;  // no longer announced: no new requests
  std::string why;       // how the session ended
  std::deque<Inflight> fifo;
  Clock::time_point last_try{};
  bool tried = false;
  bool warned = false;  // a failed (re)connect was reported
  uint64_t sent = 0, received = 0, lost = 0, resent = 0;
  double lat_sum = 0, lat_max = 0;
};

ClientPool::ClientPool(PoolOptions o, PoolCallbacks cb) : o_(std::move(o)), cb_(std::move(cb)) {}

ClientPool::~ClientPool() {
  stop();
}

std::shared_ptr<ClientPool::Link> ClientPool::add_link_locked(const Endpoint &e) {
  auto l = std::make_shared<Link>();
  l->ep = e;
  l->name = e.name();
  links_.push_back(l);
  return l;
}

bool ClientPool::open(const std::shared_ptr<Link> &l, int timeout_ms, std::string *why,
                      bool *refused) {
  NodeOptions t = o_.node;
  t.role = Role::kQueryClient;
  t.dest_host = l->ep.host;
  t.dest_port = l->ep.port;
  t.connect_timeout_ms = timeout_ms;
  uint64_t sid;
  {
    std::lock_guard<std::mutex> g(m_);
    if (links_.front() != l) t.port = 0;  // only the first session listens on `port`
    sid = ++l->session;
    l->closed = false;
    l->live = false;
    l->last_try = Clock::now();
    l->tried = true;
    l->tried_gen = l->generation;
  }
  Link *raw = l.get();
  NodeCallbacks cb;
  cb.alloc = cb_.alloc;
  cb.accept_caps = cb_.accept_caps;
  cb.on_data = [this, raw](Message &&m) { answered(raw, std::move(m)); };
  cb.on_closed = [this, raw, sid](const std::string &text, CloseKind) {
    std::lock_guard<std::mutex> g(m_);
    if (raw->session != sid || raw->closed) return;
    raw->closed = true;
    raw->live = false;
    raw->why = text;
    changed_ = true;
    cv_.notify_all();
  };
  auto node = make_tcp_client(t, std::move(cb));
  try {
    node->connect();
  } catch (const Error &e) {
    if (why) *why += "; " + l->name + ": " + e.what();
    if (refused && e.kind() == ErrorKind::kNegotiation) *refused = true;
    return false;
  }
  {
    std::lock_guard<std::mutex> g(l->send_m);
    l->node = std::move(node);
  }
  std::lock_guard<std::mutex> g(m_);
  if (!l->closed) l->live = true;
  return l->live;
}

void ClientPool::answered(Link *l, Message &&m) {
  uint64_t seq;
  {
    std::lock_guard<std::mutex> g(m_);
    if (l->fifo.empty()) return;  // its requests were re-sent (session ending): dropped
    const Inflight &f = l->fifo.front();
    seq = f.seq;
    const double us = std::chrono::duration<double, std::micro>(Clock::now() - f.sent).count();
    l->lat_sum += us;
    l->lat_max = std::max(l->lat_max, us);
    ++l->received;
    l->fifo.pop_front();
  }
  if (cb_.on_answer) cb_.on_answer(seq, std::move(m));
}

std::shared_ptr<ClientPool::Link> ClientPool::pick_locked(const Link *exclude) {
  const std::size_t n = links_.size();
  std::shared_ptr<Link> best;
  for (std::size_t k = 0; k < n; ++k) {
    const std::size_t i = o_.policy == Balance::kNone ? k : (rr_ + k) % n;
    const auto &l = links_[i];
    if (!l->live || l->closed || l->retired || l.get() == exclude) continue;
    if (o_.policy != Balance::kLeastOutstanding) {
      best = l;
      rr_ = i + 1;
      break;
    }
    if (!best || l->fifo.size() < best->fifo.size()) best = l;
  }
  if (best && o_.policy == Balance::kLeastOutstanding) ++rr_;  // ties rotate
  return best;
}

bool ClientPool::send_on(const std::shared_ptr<Link> &l, Inflight f) {
  std::lock_guard<std::mutex> s(l->send_m);
  const uint64_t seq = f.seq;
  std::shared_ptr<const OutFrame> frame = f.frame;
  {
    std::lock_guard<std::mutex> g(m_);
    if (!l->live || l->closed || !l->node) return false;
    f.sent = Clock::now();
    l->fifo.push_back(std::move(f));
    ++l->sent;
  }
  std::string why;
  if (l->node->send(*frame, &why)) return true;
  // The session broke while sending (on_closed ran): take the request back unless the
  // fail-over already has it.
  std::lock_guard<std::mutex> g(m_);
  if (!l->fifo.empty() && l->fifo.back().seq == seq) {
    l->fifo.pop_back();
    --l->sent;
    return false;
  }
  return true;
}

bool ClientPool::route(Inflight f, const Link *exclude) {
  for (;;) {
    std::shared_ptr<Link> l;
    {
      std::lock_guard<std::mutex> g(m_);
      l = pick_locked(exclude);
    }
    if (!l) return false;
    if (send_on(l, f)) return true;
  }
}

bool ClientPool::submit(uint64_t seq, std::shared_ptr<const OutFrame> frame) {
  return route({seq, std::move(frame), Clock::now(), false}, nullptr);
}

void ClientPool::fail_over(const std::shared_ptr<Link> &l) {
  {
    std::lock_guard<std::mutex> s(l->send_m);
    l->node.reset();  // joins its threads: no callback of that session after this
  }
  std::deque<Inflight> fifo;
  std::string why;
  {
    std::lock_guard<std::mutex> g(m_);
    fifo.swap(l->fifo);
    why = l->why;
    l->closed = false;
    l->last_try = Clock::now();
  }
  std::size_t resent = 0, lost = 0;
  for (auto &f : fifo) {
    bool ok = false;
    if (o_.resend && !f.resent) {
      f.resent = true;
      ok = route(f, l.get());
    }
    {
      std::lock_guard<std::mutex> g(m_);
      ++(ok ? l->resent : l->lost);
    }
    ++(ok ? resent : lost);
    if (!ok && cb_.on_lost) cb_.on_lost(f.seq);
  }
  if (cb_.on_warning)
    cb_.on_warning("lost the connection to the query server " + l->name + " (" + why + "); " +
                   std::to_string(fifo.size()) + " request(s) in flight: " +
                   std::to_string(resent) + " re-sent to other servers, " + std::to_string(lost) +
                   " lost; " + std::to_string(live()) + " server(s) left");
}

// Follows the broker's announcements (HYBRID) and (re)connects the servers that are due.
void ClientPool::maintain(int timeout_ms, std::string *why, bool *refused, bool announce) {
  if (disc_) {
    const auto announced = disc_->servers();
    std::lock_guard<std::mutex> g(m_);
    for (auto &l : links_) l->retired = true;
    for (const auto &s : announced) {
      Endpoint e;
      if (!split_host_port(s.address, &e.host, &e.port)) continue;
      std::shared_ptr<Link> l;
      for (auto &x : links_)
        if (x->name == e.name()) l = x;
      if (!l) l = add_link_locked(e);
      l->retired = false;
      l->generation = std::max(l->generation, s.generation);
    }
    // A server whose announcement was cleared (it stopped, or the broker published its will)
    // but whose session is still up: it gets nothing more, and its requests in flight are
    // re-sent now (loop() -> fail_over) rather than waited for. Its session is closed there;
    // a later announcement connects it again.
    for (auto &l : links_)
      if (l->retired && l->live && !l->closed) {
        l->closed = true;
        l->live = false;
        l->why = "its announcement was cleared on the broker";
        changed_ = true;
      }
  }
  std::vector<std::shared_ptr<Link>> due;
  {
    std::lock_guard<std::mutex> g(m_);
    const auto now = Clock::now();
    for (auto &l : links_) {
      if (l->live || l->closed || l->retired) continue;
      const bool is_due =
          disc_ ? l->generation > l->tried_gen || !l->tried
                : !l->tried || now - l->last_try >= std::chrono::milliseconds(o_.retry_ms);
      if (is_due) due.push_back(l);
    }
  }
  for (auto &l : due) {
    std::string failed;
    if (open(l, timeout_ms, why ? why : &failed, refused)) {
      l->warned = false;
      if (announce && cb_.on_info)
        cb_.on_info("query server " + l->name + " joined (" + std::to_string(live()) +
                    " server(s) in use)");
    } else if (!why && !l->warned && cb_.on_warning) {
      l->warned = true;  // once until it works again
      cb_.on_warning("query server " + l->name + " not used" + failed);
    }
  }
}

void ClientPool::start() {
  const auto deadline = Clock::now() + std::chrono::milliseconds(o_.node.connect_timeout_ms);
  if (o_.type == ConnectType::kHybrid) {
    disc_ = std::make_unique<Discovery>(o_.node, [this] {
      std::lock_guard<std::mutex> l(m_);
      changed_ = true;
      cv_.notify_all();
    });
    disc_->start();
  } else {
    std::lock_guard<std::mutex> l(m_);
    for (const auto &e : o_.endpoints) add_link_locked(e);
  }
  std::string why;
  bool refused = false;
  for (;;) {
    maintain(o_.node.connect_timeout_ms, &why, &refused, false);
    if (live() > 0) break;
    if (refused || o_.type != ConnectType::kHybrid || !disc_->wait_any(deadline) ||
        Clock::now() >= deadline) {
      const std::string what = o_.type == ConnectType::kHybrid
                                   ? "connect-type HYBRID: no server announcing topic '" +
                                         o_.node.topic + "' on the broker " + disc_->broker() +
                                         " answered within " +
                                         std::to_string(o_.node.connect_timeout_ms) + " ms"
                                   : "cannot reach any of the query servers";
      fail(refused ? ErrorKind::kNegotiation : ErrorKind::kNotFound, what + why);
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
  thread_ = std::thread([this] { loop(); });
}

void ClientPool::loop() {
  for (;;) {
    {
      std::unique_lock<std::mutex> g(m_);
      cv_.wait_for(g, std::chrono::milliseconds(kTickMs), [&] { return stop_ || changed_; });
      if (stop_) return;
      changed_ = false;
    }
    std::vector<std::shared_ptr<Link>> closed;
    {
      std::lock_guard<std::mutex> g(m_);
      for (auto &l : links_)
        if (l->closed) closed.push_back(l);
    }
    for (auto &l : closed) fail_over(l);
    maintain(std::min(o_.node.connect_timeout_ms, kRejoinTimeoutMs), nullptr, nullptr, true);
  }
}

std::size_t ClientPool::live() const {
  std::lock_guard<std::mutex> g(m_);
  std::size_t n = 0;
  for (auto &l : links_) n += l->live && !l->closed ? 1 : 0;
  return n;
}

std::vector<ServerStats> ClientPool::stats() const {
  std::lock_guard<std::mutex> g(m_);
  std::vector<ServerStats> out;
  for (auto &l : links_) {
    ServerStats s;
    s.name = l->name;
    s.live = l->live && !l->closed;
    s.sent = l->sent;
    s.received = l->received;
    s.lost = l->lost;
    s.resent = l->resent;
    s.in_flight = l->fifo.size();
    s.latency_mean_us = l->received ? l->lat_sum / static_cast<double>(l->received) : 0;
    s.latency_max_us = l->lat_max;
    out.push_back(s);
  }
  return out;
}

void ClientPool::stop() {
  {
    std::lock_guard<std::mutex> g(m_);
    stop_ = true;
    cv_.notify_all();
  }
  if (thread_.joinable()) thread_.join();
  std::vector<std::shared_ptr<Link>> all;
  {
    std::lock_guard<std::mutex> g(m_);
    all = links_;
  }
  for (auto &l : all) {
    std::lock_guard<std::mutex> s(l->send_m);
    l->node.reset();
  }
  disc_.reset();
}

}  // namespace nns::edge

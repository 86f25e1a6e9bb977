// SPDX-License-Identifier: LGPL-2.1-only
#include "edge/edge_io.h"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <chrono>
#include <cstring>
#include <mutex>

namespace nns::edge {

namespace {

constexpr int kPollSliceMs = 50;
constexpr int kStallMs = 10000;  // a started frame must make progress within this time

class HeapPayload : public Payload {
 public:
  explicit HeapPayload(std::size_t n) : buf_(new uint8_t[n ? n : 1]), size_(n) {}
  uint8_t *data() override { return buf_.get(); }
  std::size_t size() const override { return size_; }

 private:
  std::unique_ptr<uint8_t[]> buf_;
  std::size_t size_;
};

std::string errno_text(const char *what) {
  return std::string(what) + ": " + std::strerror(errno);
}

bool resolve(const std::string &host, uint16_t port, sockaddr_in *addr, std::string *why) {
  std::memset(addr, 0, sizeof *addr);
  addr->sin_family = AF_INET;
  addr->sin_port = htons(port);
  if (inet_pton(AF_INET, host.c_str(), &addr->sin_addr) == 1) return true;
  addrinfo hints{};
  hints.ai_family = AF_INET;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo *res = nullptr;
  const int rc = getaddrinfo(host.c_str(), nullptr, &hints, &res);
  if (rc != 0 || !res) {
    if (why) *why = "cannot resolve host '" + host + "': " + gai_strerror(rc);
    return false;
  }
  addr->sin_addr = reinterpret_cast<sockaddr_in *>(res->ai_addr)->sin_addr;
  freeaddrinfo(res);
  return true;
}

std::string addr_name(const sockaddr_in &a) {
  char ip[INET_ADDRSTRLEN] = "?";
  inet_ntop(AF_INET, &a.sin_addr, ip, sizeof ip);
  return std::string(ip) + ":" + std::to_string(ntohs(a.sin_port));
}

void set_nodelay(int fd) {
  int one = 1;
  setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

// Reads exactly n bytes. `first_timeout_ms` applies until the first byte of the frame.
IoStatus read_exact(int fd, uint8_t *p, std::size_t n, const std::atomic<bool> &stop,
                    int first_timeout_ms, bool frame_started, std::size_t *got, std::string *why) {
  std::size_t done = 0;
  auto last = std::chrono::steady_clock::now();
  while (done < n) {
    if (stop.load(std::memory_order_relaxed)) return IoStatus::kStopped;
    pollfd pfd{fd, POLLIN, 0};
    const int rc = poll(&pfd, 1, kPollSliceMs);
    if (rc < 0) {
      if (errno == EINTR) continue;
      if (why) *why = errno_text("poll");
      return IoStatus::kError;
    }
    if (rc == 0) {
      const auto waited = std::chrono::duration_cast<std::chrono::milliseconds>(
                              std::chrono::steady_clock::now() - last)
                              .count();
      if (!frame_started && done == 0) {
        if (first_timeout_ms >= 0 && waited >= first_timeout_ms) return IoStatus::kTimeout;
      } else if (waited >= kStallMs) {
        if (why) *why = "peer stalled for " + std::to_string(kStallMs / 1000) + " s mid-frame";
        return IoStatus::kError;
      }
      continue;
    }
    const ssize_t r = recv(fd, p + done, n - done, 0);
    if (r == 0) {
      if (got) *got += done;
      return (!frame_started && done == 0) ? IoStatus::kClosed : IoStatus::kError;
    }
    if (r < 0) {
      if (errno == EINTR || errno == EAGAIN) continue;
      if (why) *why = errno_text("recv");
      return IoStatus::kError;
    }
    done += static_cast<std::size_t>(r);
    last = std::chrono::steady_clock::now();
  }
  if (got) *got += done;
  return IoStatus::kOk;
}

bool send_iov(int fd, iovec *iov, int cnt, std::string *why) {
  while (cnt > 0) {
    msghdr msg{};
    msg.msg_iov = iov;
    msg.msg_iovlen = static_cast<std::size_t>(cnt);
    const ssize_t r = sendmsg(fd, &msg, MSG_NOSIGNAL);
    if (r < 0) {
      if (errno == EINTR) continue;
      if (errno == EAGAIN) {
        pollfd pfd{fd, POLLOUT, 0};
        poll(&pfd, 1, kPollSliceMs);
        continue;
      }
      if (why) *why = errno_text("send");
      return false;
    }
    std::size_t left = static_cast<std::size_t>(r);
    while (cnt > 0 && left >= iov->iov_len) {
      left -= iov->iov_len;
      ++iov;
      --cnt;
    }
    if (cnt > 0) {
      iov->iov_base = static_cast<uint8_t *>(iov->iov_base) + left;
      iov->iov_len -= left;
    }
  }
  return true;
}

}  // namespace

PayloadPtr heap_payload(std::size_t size) {
  return std::make_unique<HeapPayload>(size);
}

void Fd::reset(int fd) {
  if (fd_ >= 0) ::close(fd_);
  fd_ = fd;
}

Fd tcp_connect(const std::string &host, uint16_t port, int timeout_ms, std::string *why) {
  sockaddr_in addr;
  if (!resolve(host, port, &addr, why)) return Fd();
  Fd fd(socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, IPPROTO_TCP));
  if (!fd.valid()) {
    if (why) *why = errno_text("socket");
    return Fd();
  }
  set_nodelay(fd.get());
  const int flags = fcntl(fd.get(), F_GETFL, 0);
  fcntl(fd.get(), F_SETFL, flags | O_NONBLOCK);
  int rc = ::connect(fd.get(), reinterpret_cast<sockaddr *>(&addr), sizeof addr);
  if (rc < 0 && errno == EINPROGRESS) {
    pollfd pfd{fd.get(), POLLOUT, 0};
    rc = poll(&pfd, 1, timeout_ms < 0 ? -1 : timeout_ms);
    if (rc == 0) {
      if (why) *why = "connecting to " + host + ":" + std::to_string(port) + " timed out";
      return Fd();
    }
    int err = 0;
    socklen_t len = sizeof err;
    getsockopt(fd.get(), SOL_SOCKET, SO_ERROR, &err, &len);
    if (rc < 0 || err != 0) {
      if (why)
        *why = "cannot connect to " + host + ":" + std::to_string(port) + ": " +
               std::strerror(err ? err : errno);
      return Fd();
    }
  } else if (rc < 0) {
    if (why)
      *why = "cannot connect to " + host + ":" + std::to_string(port) + ": " + std::strerror(errno);
    return Fd();
  }
  fcntl(fd.get(), F_SETFL, flags);
  return fd;
}

Fd tcp_listen(const std::string &host, uint16_t port, uint16_t *bound, std::string *why) {
  sockaddr_in addr;
  if (!resolve(host, port, &addr, why)) return Fd();
  Fd fd(socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, IPPROTO_TCP));
  if (!fd.valid()) {
    if (why) *why = errno_text("socket");
    return Fd();
  }
  int one = 1;
  setsockopt(fd.get(), SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
  if (bind(fd.get(), reinterpret_cast<sockaddr *>(&addr), sizeof addr) < 0) {
    if (why)
      *why = "cannot listen on " + host + ":" + std::to_string(port) + ": " + std::strerror(errno);
    return Fd();
  }
  if (listen(fd.get(), 64) < 0) {
    if (why) *why = errno_text("listen");
    return Fd();
  }
  sockaddr_in got{};
  socklen_t len = sizeof got;
  getsockname(fd.get(), reinterpret_cast<sockaddr *>(&got), &len);
  if (bound) *bound = ntohs(got.sin_port);
  return fd;
}

std::string peer_name(int fd) {
  sockaddr_in a{};
  socklen_t len = sizeof a;
  if (getpeername(fd, reinterpret_cast<sockaddr *>(&a), &len) < 0) return "?";
  return addr_name(a);
}

std::string local_name(int fd) {
  sockaddr_in a{};
  socklen_t len = sizeof a;
  if (getsockname(fd, reinterpret_cast<sockaddr *>(&a), &len) < 0) return "?";
  return addr_name(a);
}

void shutdown_fd(int fd) {
  if (fd >= 0) ::shutdown(fd, SHUT_RDWR);
}

IoStatus wait_readable(int fd, int timeout_ms, const std::atomic<bool> &stop) {
  int waited = 0;
  while (!stop.load(std::memory_order_relaxed)) {
    pollfd pfd{fd, POLLIN, 0};
    const int rc = poll(&pfd, 1, kPollSliceMs);
    if (rc < 0 && errno != EINTR) return IoStatus::kError;
    if (rc > 0) return (pfd.revents & POLLIN) ? IoStatus::kOk : IoStatus::kError;
    waited += kPollSliceMs;
    if (timeout_ms >= 0 && waited >= timeout_ms) return IoStatus::kTimeout;
  }
  return IoStatus::kStopped;
}

IoStatus read_frame(int fd, const Limits &limits, const Allocator &alloc,
                    const std::atomic<bool> &stop, int timeout_ms, Message *out, std::string *why) {
  uint8_t hdr[kHeaderSize];
  std::size_t got = 0;
  std::string io_why;
  IoStatus st = read_exact(fd, hdr, kHeaderSize, stop, timeout_ms, false, &got, &io_why);
  if (st == IoStatus::kError) {
    if (why)
      *why = io_why.empty()
                 ? "truncated frame: the connection closed after " + std::to_string(got) + " of " +
                       std::to_string(kHeaderSize) + " header bytes"
                 : io_why;
    return st;
  }
  if (st != IoStatus::kOk) return st;
  std::string bad;
  auto h = decode_header(hdr, limits, &bad);
  if (!h) {
    if (why) *why = "invalid frame header: " + bad;
    return IoStatus::kProtocol;
  }
  out->header = *h;
  out->mems.clear();
  out->meta = Metadata();
  for (std::size_t i = 0; i < h->mem_sizes.size(); ++i) {
    const std::size_t n = static_cast<std::size_t>(h->mem_sizes[i]);
    PayloadPtr p = alloc ? alloc(n) : heap_payload(n);
    if (!p || p->size() != n) {
      if (why)
        *why = "cannot allocate " + std::to_string(n) + " bytes for memory " + std::to_string(i);
      return IoStatus::kError;
    }
    got = 0;
    io_why.clear();
    st = read_exact(fd, p->data(), n, stop, -1, true, &got, &io_why);
    if (st == IoStatus::kStopped) return st;
    if (st != IoStatus::kOk) {
      if (why)
        *why = io_why.empty() ? "truncated frame: memory " + std::to_string(i) + " got " +
                                    std::to_string(got) + " of " + std::to_string(n) + " bytes"
                              : io_why;
      return IoStatus::kError;
    }
    out->mems.push_back(std::move(p));
  }
  if (h->meta_size > 0) {
    std::vector<uint8_t> meta(static_cast<std::size_t>(h->meta_size));
    got = 0;
    io_why.clear();
    st = read_exact(fd, meta.data(), meta.size(), stop, -1, true, &got, &io_why);
    if (st == IoStatus::kStopped) return st;
    if (st != IoStatus::kOk) {
      if (why)
        *why = io_why.empty() ? "truncated frame: metadata got " + std::to_string(got) + " of " +
                                    std::to_string(meta.size()) + " bytes"
                              : io_why;
      return IoStatus::kError;
    }
    auto m = Metadata::parse(meta.data(), meta.size(), &bad);
    if (!m) {
      if (why) *why = bad;
      return IoStatus::kProtocol;
    }
    out->meta = std::move(*m);
  }
  return IoStatus::kOk;
}

bool write_frame(int fd, Cmd cmd, int64_t client_id, const OutFrame &frame, std::string *why) {
  if (frame.mems.size() > kMaxMemories - 1) {
    if (why) *why = std::to_string(frame.mems.size()) + " memories, the protocol allows 255";
    return false;
  }
  Header h;
  h.cmd = cmd;
  h.client_id = client_id;
  h.mem_sizes.reserve(frame.mems.size());
  for (const auto &m : frame.mems) h.mem_sizes.push_back(m.size);
  const std::vector<uint8_t> meta = frame.meta.serialize();
  h.meta_size = meta.size();
  const auto hdr = encode_header(h);
  std::vector<iovec> iov;
  iov.reserve(frame.mems.size() + 2);
  iov.push_back({const_cast<uint8_t *>(hdr.data()), hdr.size()});
  for (const auto &m : frame.mems)
    if (m.size) iov.push_back({const_cast<void *>(m.data), m.size});
  if (!meta.empty()) iov.push_back({const_cast<uint8_t *>(meta.data()), meta.size()});
  return send_iov(fd, iov.data(), static_cast<int>(iov.size()), why);
}

bool write_string_frame(int fd, Cmd cmd, int64_t client_id, const std::string &s,
                        std::string *why) {
  OutFrame f;
  f.mems.push_back({s.c_str(), s.size() + 1});
  return write_frame(fd, cmd, client_id, f, why);
}

int64_t new_client_id() {
  static std::mutex m;
  static int64_t last = 0;
  const int64_t now = std::chrono::duration_cast<std::chrono::microseconds>(
                          std::chrono::steady_clock::now().time_since_epoch())
                          .count();
  std::lock_guard<std::mutex> l(m);
  last = now > last ? now : last + 1;
  return last;
}

}  // namespace nns::edge

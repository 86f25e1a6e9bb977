// SPDX-License-Identifier: LGPL-2.1-only
// Sockets and frame I/O for nnstreamer-edge's TCP protocol (no GStreamer). A frame is read
// header first; sizes are validated (edge_wire.h Limits) before the memories are allocated
// through a caller-supplied allocator, so the element can receive straight into GstMemory.
// Frames are written with one sendmsg() over the caller's memories: no copy in user space.
#pragma once

#include <atomic>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <vector>

#include "edge/edge_wire.h"

namespace nns::edge {

// One memory of a received frame. The allocator decides where the bytes land.
class Payload {
 public:
  virtual ~Payload() = default;
  virtual uint8_t *data() = 0;
  virtual std::size_t size() const = 0;
};
using PayloadPtr = std::unique_ptr<Payload>;
using Allocator = std::function<PayloadPtr(std::size_t)>;
PayloadPtr heap_payload(std::size_t size);  // the default allocator

struct Message {
  Header header;
  std::vector<PayloadPtr> mems;
  Metadata meta;
};

struct OutSpan {
  const void *data;
  std::size_t size;
};
struct OutFrame {
  std::vector<OutSpan> mems;
  Metadata meta;
};

// Owning file descriptor.
class Fd {
 public:
  Fd() = default;
  explicit Fd(int fd) : fd_(fd) {}
  ~Fd() { reset(); }
  Fd(Fd &&o) noexcept : fd_(o.release()) {}
  Fd &operator=(Fd &&o) noexcept {
    if (this != &o) reset(o.release());
    return *this;
  }
  Fd(const Fd &) = delete;
  Fd &operator=(const Fd &) = delete;
  int get() const { return fd_; }
  bool valid() const { return fd_ >= 0; }
  int release() {
    int f = fd_;
    fd_ = -1;
    return f;
  }
  void reset(int fd = -1);

 private:
  int fd_ = -1;
};

// Resolves `host` (IPv4, like nnstreamer-edge) and connects within `timeout_ms`.
Fd tcp_connect(const std::string &host, uint16_t port, int timeout_ms, std::string *why);
// Binds and listens (SO_REUSEADDR); port 0 picks a free port, returned in *bound.
Fd tcp_listen(const std::string &host, uint16_t port, uint16_t *bound, std::string *why);
std::string peer_name(int fd);   // "127.0.0.1:40000"
std::string local_name(int fd);  // same, for our end
void shutdown_fd(int fd);        // wakes threads blocked on it

// kError: the connection broke (including mid-frame); kProtocol: the peer sent bytes that are
// not a valid frame (bad header, sizes over the limits, bad metadata).
enum class IoStatus { kOk, kClosed, kStopped, kTimeout, kError, kProtocol };

// Waits up to `timeout_ms` (-1: until stop) for an incoming connection; polls `stop`.
IoStatus wait_readable(int fd, int timeout_ms, const std::atomic<bool> &stop);

// Reads one frame. kClosed: the peer closed before the first header byte. kError/kProtocol:
// `why` says what was wrong (truncated frame; bad header, size over the limits, bad metadata).
// `timeout_ms` bounds the wait for the first byte (-1: none); later bytes must keep coming.
IoStatus read_frame(int fd, const Limits &limits, const Allocator &alloc,
                    const std::atomic<bool> &stop, int timeout_ms, Message *out, std::string *why);

// Writes header + memories + serialized metadata with sendmsg (MSG_NOSIGNAL).
bool write_frame(int fd, Cmd cmd, int64_t client_id, const OutFrame &frame, std::string *why);
// A frame with one NUL-terminated string memory (CAPABILITY, HOST_INFO).
bool write_string_frame(int fd, Cmd cmd, int64_t client_id, const std::string &s, std::string *why);

// Monotonic-microsecond id as nnstreamer-edge makes them, unique within the process.
int64_t new_client_id();

}  // namespace nns::edge

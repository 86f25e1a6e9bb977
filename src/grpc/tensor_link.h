// SPDX-License-Identifier: LGPL-2.1-only
// One end of NNStreamer's gRPC tensor stream (GStreamer-free): the TensorService of
// tensor_src_grpc / tensor_sink_grpc (idl=protobuf or flatbuf), as server or client, sending or
// receiving. Frames are checked on arrival (types, ranks, data sizes) before they are handed on.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

namespace nns::grpclink {

struct Tensor {
  uint32_t type = 0;           // NNStreamer's tensor type number (0 int32 .. 10 float16)
  std::vector<uint32_t> dims;  // innermost first, as sent (upstream sends 16, unused 0)
  std::string data;
};

struct Frame {
  std::vector<Tensor> tensors;
  int32_t rate_n = 0;
  int32_t rate_d = 1;
  uint32_t format = 0;  // 0 static
};

// Checks a received frame: 1..256 tensors (num_tensor agreeing), known types, at most 16
// dimensions, data of exactly the size the type and dimensions give. Returns "" or the problem.
std::string check_frame(const Frame &f, uint32_t num_tensor_field);

// The message a sender puts on the wire for `f` (for tests: pinned against NNStreamer's bytes).
std::string protobuf_wire_bytes(Frame f);
std::string flatbuf_wire_bytes(Frame f);

enum class Role { kServer, kClient };
enum class Direction { kSend, kReceive };  // what this end does with frames
enum class Idl { kProtobuf, kFlatbuf };    // the `idl` property

struct LinkOptions {
  Role role = Role::kClient;
  Direction direction = Direction::kSend;
  Idl idl = Idl::kProtobuf;
  std::string host = "localhost";
  int port = 55115;              // server: 0 = any free port
  std::size_t queue_limit = 16;  // frames waiting to be sent
};

class Link {
 public:
  using OnFrame = std::function<void(Frame &&)>;
  // The stream ended: ok = the peer finished normally; otherwise why names the peer and the
  // problem (unreachable, gone, a bad message).
  using OnEnd = std::function<void(bool ok, const std::string &why)>;

  Link(LinkOptions o, OnFrame on_frame, OnEnd on_end);
  ~Link();
  Link(const Link &) = delete;
  Link &operator=(const Link &) = delete;

  // Server: listens (throws nns::Error when the address cannot be bound). Client: opens the
  // call on a worker thread.
  void start();
  // Stops the server / cancels the call and joins the threads. Frames still queued are lost.
  void stop();
  // Sending ends: queues a frame; blocks while the queue is full. False after stop() or when
  // interrupted by set_flushing(true).
  bool send(Frame &&f);
  void set_flushing(bool on);
  // Sending client: closes the stream after the queued frames (WritesDone) and waits up to t.
  bool finish(std::chrono::milliseconds t);
  int bound_port() const { return bound_port_; }
  std::string peer() const;

  struct Impl;

 private:
  LinkOptions opts_;
  std::unique_ptr<Impl> impl_;
  int bound_port_ = 0;
};

}  // namespace nns::grpclink

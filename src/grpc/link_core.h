// SPDX-License-Identifier: LGPL-2.1-only
// Internal to src/grpc: what the protobuf and flatbuf implementations of Link share (the send
// queue, stop/flush state, the client worker's end report).
#pragma once

#include <grpcpp/grpcpp.h>

#include <functional>
#include <string>

#include "grpc/tensor_link.h"

namespace nns::grpclink {

struct Link::Impl {
  LinkOptions opts;
  OnFrame on_frame;
  OnEnd on_end;
  std::mutex m;
  std::condition_variable cv;
  std::deque<Frame> queue;
  bool stopping = false;
  bool flushing = false;
  bool writes_done = false;
  bool worker_done = false;
  std::unique_ptr<grpc::Server> server;
  std::shared_ptr<grpc::Channel> channel;
  std::unique_ptr<grpc::ClientContext> ctx;
  std::thread worker;

  virtual ~Impl() = default;
  virtual grpc::Service *service() = 0;
  virtual void make_stub() = 0;
  virtual void client_send() = 0;
  virtual void client_receive() = 0;

  std::string address() const { return opts.host + ":" + std::to_string(opts.port); }
  // Waits for a frame to send; false when stopping, or writes are done (client), or
  // `cancelled` says so (server call).
  bool pop(Frame &f, const std::function<bool()> &cancelled);
  bool is_stopping();
  void set_done();
  void finish_worker(const grpc::Status &s, bool broken);
  // A received frame: checked, then handed on. Returns the problem or "".
  std::string deliver(Frame &&f, uint32_t num_tensor_field);

  // Server side of SendTensors (clients stream frames in): `take(msg)` decodes and delivers each
  // message, returning the problem or "". A bad message ends the call and is reported.
  template <typename Msg, typename Take>
  grpc::Status serve_incoming(grpc::ServerContext *c, grpc::ServerReader<Msg> *reader, Take take) {
    if (opts.direction != Direction::kReceive)
      return {grpc::StatusCode::UNIMPLEMENTED, "this server sends tensors (RecvTensors)"};
    Msg msg;
    while (!is_stopping() && reader->Read(&msg)) {
      const std::string bad = take(msg);
      if (!bad.empty()) {
        on_end(false, "client " + c->peer() + " sent a bad message: " + bad);
        return {grpc::StatusCode::INVALID_ARGUMENT, bad};
      }
    }
    return grpc::Status::OK;
  }

  // Client side of RecvTensors: reads the server's stream to its end through `take` (as above);
  // a bad message cancels the call and ends the link with the problem.
  template <typename Msg, typename Take>
  void receive_all(grpc::ClientReader<Msg> &r, Take take) {
    Msg msg;
    while (r.Read(&msg)) {
      const std::string bad = take(msg);
      if (!bad.empty()) {
        ctx->TryCancel();
        r.Finish();
        on_end(false, "server " + address() + " sent a bad message: " + bad);
        set_done();
        return;
      }
    }
    finish_worker(r.Finish(), false);
  }
};

std::unique_ptr<Link::Impl> make_protobuf_impl();
std::unique_ptr<Link::Impl> make_flatbuf_impl();

}  // namespace nns::grpclink

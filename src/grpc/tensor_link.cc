// SPDX-License-Identifier: LGPL-2.1-only
#include "grpc/tensor_link.h"

#include <grpcpp/grpcpp.h>

#include <atomic>

#include "core/error.h"
#include "grpc/link_core.h"

namespace nns::grpclink {

namespace {

constexpr std::size_t kMaxTensors = 256;
constexpr std::size_t kMaxRank = 16;

std::size_t type_bytes(uint32_t t) {
  static const std::size_t sizes[] = {4, 4, 2, 2, 1, 1, 8, 4, 8, 8, 2};
  return t < sizeof sizes / sizeof sizes[0] ? sizes[t] : 0;
}

}  // namespace

std::string check_frame(const Frame &f, uint32_t num_tensor_field) {
  if (f.tensors.empty() || f.tensors.size() > kMaxTensors)
    return "message holds " + std::to_string(f.tensors.size()) + " tensors (1..256 expected)";
  if (num_tensor_field != f.tensors.size())
    return "num_tensor is " + std::to_string(num_tensor_field) + " but the message holds " +
           std::to_string(f.tensors.size()) + " tensors";
  if (f.format != 0) return "tensor format " + std::to_string(f.format) + " is not static (0)";
  for (std::size_t i = 0; i < f.tensors.size(); ++i) {
    const Tensor &t = f.tensors[i];
    const std::string which = "tensor " + std::to_string(i) + ": ";
    const std::size_t es = type_bytes(t.type);
    if (!es) return which + "unknown type " + std::to_string(t.type) + " (0..10 expected)";
    if (t.dims.size() > kMaxRank)
      return which + std::to_string(t.dims.size()) + " dimensions (at most 16)";
    unsigned __int128 n = 0;
    for (uint32_t d : t.dims) {
      if (d == 0) break;
      n = (n == 0 ? 1 : n) * d;
      if (n > (static_cast<unsigned __int128>(1) << 62)) return which + "dimensions overflow";
    }
    if (n == 0) return which + "no dimensions";
    const unsigned __int128 want = n * es;
    if (want != t.data.size())
      return which + std::to_string(t.data.size()) + " bytes of data but its type and " +
             "dimensions need " + std::to_string(static_cast<uint64_t>(want));
  }
  return "";
}

bool Link::Impl::pop(Frame &f, const std::function<bool()> &cancelled) {
  std::unique_lock<std::mutex> l(m);
  for (;;) {
    if (stopping) return false;
    if (!queue.empty()) {
      f = std::move(queue.front());
      queue.pop_front();
      cv.notify_all();
      return true;
    }
    if (writes_done) return false;
    if (cancelled && cancelled()) return false;
    cv.wait_for(l, std::chrono::milliseconds(100));
  }
}

bool Link::Impl::is_stopping() {
  std::lock_guard<std::mutex> l(m);
  return stopping;
}

void Link::Impl::set_done() {
  std::lock_guard<std::mutex> l(m);
  worker_done = true;
  cv.notify_all();
}

void Link::Impl::finish_worker(const grpc::Status &s, bool broken) {
  if (!is_stopping()) {
    if (s.ok() && !broken)
      on_end(true, "");
    else
      on_end(false, "server " + address() + ": " +
                        (s.ok() ? std::string("the stream broke") : s.error_message()) +
                        " (gRPC status " + std::to_string(static_cast<int>(s.error_code())) + ")");
  }
  set_done();
}

std::string Link::Impl::deliver(Frame &&f, uint32_t num_tensor_field) {
  std::string bad = check_frame(f, num_tensor_field);
  if (bad.empty()) on_frame(std::move(f));
  return bad;
}

Link::Link(LinkOptions o, OnFrame on_frame, OnEnd on_end)
    : opts_(std::move(o)),
      impl_(opts_.idl == Idl::kFlatbuf ? make_flatbuf_impl() : make_protobuf_impl()) {
  impl_->opts = opts_;
  impl_->on_frame = std::move(on_frame);
  impl_->on_end = std::move(on_end);
}

Link::~Link() {
  stop();
}

std::string Link::peer() const {
  return impl_->address();
}

void Link::start() {
  Impl &i = *impl_;
  if (opts_.role == Role::kServer) {
    grpc::ServerBuilder b;
    b.AddListeningPort(i.address(), grpc::InsecureServerCredentials(), &bound_port_);
    b.RegisterService(i.service());
    b.SetMaxReceiveMessageSize(-1);
    i.server = b.BuildAndStart();
    if (!i.server || bound_port_ == 0) {
      i.server.reset();
      fail(ErrorKind::kSettings, "cannot listen for gRPC on " + i.address() +
                                     " (host/port properties; is the port in use?)");
    }
    i.opts.port = bound_port_;
    return;
  }
  grpc::ChannelArguments args;
  args.SetMaxReceiveMessageSize(-1);
  i.channel = grpc::CreateCustomChannel(i.address(), grpc::InsecureChannelCredentials(), args);
  i.make_stub();
  i.ctx = std::make_unique<grpc::ClientContext>();
  if (opts_.direction == Direction::kSend)
    i.worker = std::thread([&i] { i.client_send(); });
  else
    i.worker = std::thread([&i] { i.client_receive(); });
}

void Link::stop() {
  Impl &i = *impl_;
  {
    std::lock_guard<std::mutex> l(i.m);
    i.stopping = true;
    i.cv.notify_all();
  }
  if (i.ctx) i.ctx->TryCancel();
  if (i.worker.joinable()) i.worker.join();
  if (i.server) {
    i.server->Shutdown(std::chrono::system_clock::now() + std::chrono::seconds(1));
    i.server.reset();
  }
  std::lock_guard<std::mutex> l(i.m);
  i.queue.clear();
}

bool Link::send(Frame &&f) {
  Impl &i = *impl_;
  std::unique_lock<std::mutex> l(i.m);
  i.cv.wait(l, [&] {
    return i.stopping || i.flushing || i.worker_done || i.queue.size() < opts_.queue_limit;
  });
  if (i.stopping || i.flushing || i.worker_done) return false;
  i.queue.push_back(std::move(f));
  i.cv.notify_all();
  return true;
}

void Link::set_flushing(bool on) {
  std::lock_guard<std::mutex> l(impl_->m);
  impl_->flushing = on;
  impl_->cv.notify_all();
}

bool Link::finish(std::chrono::milliseconds t) {
  Impl &i = *impl_;
  std::unique_lock<std::mutex> l(i.m);
  if (opts_.role == Role::kClient) {
    i.writes_done = true;
    i.cv.notify_all();
    return i.cv.wait_for(l, t, [&] { return i.worker_done; });
  }
  // Server: wait until connected clients took what is queued.
  return i.cv.wait_for(l, t, [&] { return i.queue.empty(); });
}

}  // namespace nns::grpclink

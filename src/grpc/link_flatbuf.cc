// SPDX-License-Identifier: LGPL-2.1-only
// Link over NNStreamer's TensorService with idl=flatbuf (backends/common/wire/nnstreamer.fbs, flatc
// --grpc). Every received message goes through the flatbuffers verifier before it is read.
#include <cstring>

#include "grpc/link_core.h"
#include "nnstreamer.grpc.fb.h"
#include "nnstreamer_generated.h"

namespace nns::grpclink {

namespace {

namespace fb = ::nnstreamer::flatbuf;
using TensorsMsg = flatbuffers::grpc::Message<fb::Tensors>;
using EmptyMsg = flatbuffers::grpc::Message<fb::Empty>;

TensorsMsg to_fb(Frame &&f) {
  flatbuffers::grpc::MessageBuilder b;
  std::vector<flatbuffers::Offset<fb::Tensor>> ts;
  ts.reserve(f.tensors.size());
  for (const auto &t : f.tensors) {
    // Built in upstream's order (dimensions, name, data) so the bytes are NNStreamer's too.
    auto dims = b.CreateVector(t.dims);
    auto name = b.CreateString("Anonymous");  // upstream's name for every tensor
    auto data = b.CreateVector(reinterpret_cast<const uint8_t *>(t.data.data()), t.data.size());
    ts.push_back(fb::CreateTensor(b, name, static_cast<fb::Tensor_type>(t.type), dims, data));
  }
  const fb::frame_rate fr(f.rate_n, f.rate_d);
  auto vec = b.CreateVector(ts);
  b.Finish(fb::CreateTensors(b, static_cast<int32_t>(f.tensors.size()), &fr, vec,
                             static_cast<fb::Tensor_format>(f.format)));
  return b.ReleaseMessage<fb::Tensors>();
}

EmptyMsg empty() {
  flatbuffers::grpc::MessageBuilder b;
  b.Finish(fb::CreateEmpty(b));
  return b.ReleaseMessage<fb::Empty>();
}

// Verifies and reads one message; "" or the problem. `n` gets num_tensor.
std::string from_fb(TensorsMsg &msg, Frame &f, uint32_t &n) {
  // gRPC hands the bytes over at any address; flatbuffers reads 4- and 8-byte fields in place,
  // so a misaligned message is first copied to an aligned buffer.
  const uint8_t *data = msg.data();
  const std::size_t size = msg.size();
  std::vector<uint64_t> aligned;
  if (reinterpret_cast<uintptr_t>(data) % alignof(uint64_t) != 0) {
    aligned.resize((size + sizeof(uint64_t) - 1) / sizeof(uint64_t));
    std::memcpy(aligned.data(), data, size);
    data = reinterpret_cast<const uint8_t *>(aligned.data());
  }
  flatbuffers::Verifier v(data, size);
  if (!data || !v.VerifyBuffer<fb::Tensors>(nullptr))
    return "the message is not a valid flatbuffers Tensors table";
  const fb::Tensors *m = flatbuffers::GetRoot<fb::Tensors>(data);
  n = m->num_tensor() < 0 ? 0xFFFFFFFFu : static_cast<uint32_t>(m->num_tensor());
  if (m->fr()) {
    f.rate_n = m->fr()->rate_n();
    f.rate_d = m->fr()->rate_d();
  }
  f.format = static_cast<uint32_t>(m->format());
  if (m->tensor()) {
    for (const fb::Tensor *t : *m->tensor()) {
      Tensor o;
      o.type = static_cast<uint32_t>(t->type());
      if (t->dimension()) o.dims.assign(t->dimension()->begin(), t->dimension()->end());
      if (t->data())
        o.data.assign(reinterpret_cast<const char *>(t->data()->data()), t->data()->size());
      f.tensors.push_back(std::move(o));
    }
  }
  return "";
}

struct FbImpl final : public Link::Impl, public fb::TensorService::Service {
  std::unique_ptr<fb::TensorService::Stub> stub;

  grpc::Service *service() override { return this; }
  void make_stub() override { stub = fb::TensorService::NewStub(channel); }

  grpc::Status SendTensors(grpc::ServerContext *c, grpc::ServerReader<TensorsMsg> *reader,
                           EmptyMsg *reply) override {
    *reply = empty();
    return serve_incoming(c, reader, [this](TensorsMsg &msg) { return take(msg); });
  }

  grpc::Status RecvTensors(grpc::ServerContext *c, const EmptyMsg *,
                           grpc::ServerWriter<TensorsMsg> *writer) override {
    if (opts.direction != Direction::kSend)
      return {grpc::StatusCode::UNIMPLEMENTED, "this server receives tensors (SendTensors)"};
    Frame f;
    while (pop(f, [c] { return c->IsCancelled(); })) {
      if (!writer->Write(to_fb(std::move(f))))
        return {grpc::StatusCode::CANCELLED, "client " + c->peer() + " went away"};
    }
    return grpc::Status::OK;
  }

  void client_send() override {
    EmptyMsg reply;
    std::unique_ptr<grpc::ClientWriter<TensorsMsg>> w(stub->SendTensors(ctx.get(), &reply));
    Frame f;
    bool broken = false;
    while (pop(f, nullptr)) {
      if (!w->Write(to_fb(std::move(f)))) {
        broken = true;
        break;
      }
    }
    if (!broken) w->WritesDone();
    finish_worker(w->Finish(), broken);
  }

  void client_receive() override {
    std::unique_ptr<grpc::ClientReader<TensorsMsg>> r(stub->RecvTensors(ctx.get(), empty()));
    receive_all(*r, [this](TensorsMsg &msg) { return take(msg); });
  }

  // A received message decoded and delivered; the problem or "".
  std::string take(TensorsMsg &msg) {
    Frame f;
    uint32_t n = 0;
    std::string bad = from_fb(msg, f, n);
    return bad.empty() ? deliver(std::move(f), n) : bad;
  }
};

}  // namespace

std::string flatbuf_wire_bytes(Frame f) {
  TensorsMsg m = to_fb(std::move(f));
  return std::string(reinterpret_cast<const char *>(m.data()), m.size());
}

std::unique_ptr<Link::Impl> make_flatbuf_impl() {
  return std::make_unique<FbImpl>();
}

}  // namespace nns::grpclink

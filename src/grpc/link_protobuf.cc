// SPDX-License-Identifier: LGPL-2.1-only
// Link over NNStreamer's TensorService with idl=protobuf (backends/common/wire/nnstreamer.proto).
#include "grpc/link_core.h"
#include "nnstreamer.grpc.pb.h"

namespace nns::grpclink {

namespace {

namespace pb = ::nnstreamer::protobuf;

pb::Tensors to_proto(Frame &&f) {
  pb::Tensors m;
  m.set_num_tensor(static_cast<uint32_t>(f.tensors.size()));
  m.mutable_fr()->set_rate_n(f.rate_n);
  m.mutable_fr()->set_rate_d(f.rate_d);
  m.set_format(static_cast<pb::Tensors_Tensor_format>(f.format));
  for (auto &t : f.tensors) {
    pb::Tensor *o = m.add_tensor();
    o->set_name("Anonymous");  // upstream's name for every tensor
    o->set_type(static_cast<pb::Tensor_Tensor_type>(t.type));
    for (uint32_t d : t.dims) o->add_dimension(d);
    o->set_data(std::move(t.data));
  }
  return m;
}

Frame from_proto(pb::Tensors &m) {
  Frame f;
  f.rate_n = m.fr().rate_n();
  f.rate_d = m.fr().rate_d();
  f.format = static_cast<uint32_t>(m.format());
  f.tensors.reserve(static_cast<std::size_t>(m.tensor_size()));
  for (int i = 0; i < m.tensor_size(); ++i) {
    pb::Tensor *t = m.mutable_tensor(i);
    Tensor o;
    o.type = static_cast<uint32_t>(t->type());
    o.dims.assign(t->dimension().begin(), t->dimension().end());
    o.data = std::move(*t->mutable_data());
    f.tensors.push_back(std::move(o));
  }
  return f;
}

struct PbImpl final : public Link::Impl, public pb::TensorService::Service {
  std::unique_ptr<pb::TensorService::Stub> stub;

  grpc::Service *service() override { return this; }
  void make_stub() override { stub = pb::TensorService::NewStub(channel); }

  // Server side of tensor_src_grpc: clients stream frames in.
  grpc::Status SendTensors(grpc::ServerContext *c, grpc::ServerReader<pb::Tensors> *reader,
                           google::protobuf::Empty *) override {
    return serve_incoming(c, reader, [this](pb::Tensors &msg) { return take(msg); });
  }

  // Server side of tensor_sink_grpc: each client gets the frames as they come.
  grpc::Status RecvTensors(grpc::ServerContext *c, const google::protobuf::Empty *,
                           grpc::ServerWriter<pb::Tensors> *writer) override {
    if (opts.direction != Direction::kSend)
      return {grpc::StatusCode::UNIMPLEMENTED, "this server receives tensors (SendTensors)"};
    Frame f;
    while (pop(f, [c] { return c->IsCancelled(); })) {
      if (!writer->Write(to_proto(std::move(f))))
        return {grpc::StatusCode::CANCELLED, "client " + c->peer() + " went away"};
    }
    return grpc::Status::OK;
  }

  void client_send() override {
    google::protobuf::Empty reply;
    std::unique_ptr<grpc::ClientWriter<pb::Tensors>> w(stub->SendTensors(ctx.get(), &reply));
    Frame f;
    bool broken = false;
    while (pop(f, nullptr)) {
      if (!w->Write(to_proto(std::move(f)))) {
        broken = true;
        break;
      }
    }
    if (!broken) w->WritesDone();
    const grpc::Status s = w->Finish();
    finish_worker(s, broken);
  }

  void client_receive() override {
    std::unique_ptr<grpc::ClientReader<pb::Tensors>> r(
        stub->RecvTensors(ctx.get(), google::protobuf::Empty()));
    receive_all(*r, [this](pb::Tensors &msg) { return take(msg); });
  }

  // A received message decoded and delivered; the problem or "".
  std::string take(pb::Tensors &msg) {
    const uint32_t n = msg.num_tensor();  // read before from_proto takes the message apart
    return deliver(from_proto(msg), n);
  }
};

}  // namespace

std::string protobuf_wire_bytes(Frame f) {
  return to_proto(std::move(f)).SerializeAsString();
}

std::unique_ptr<Link::Impl> make_protobuf_impl() {
  return std::make_unique<PbImpl>();
}

}  // namespace nns::grpclink

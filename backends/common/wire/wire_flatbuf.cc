// SPDX-License-Identifier: LGPL-2.1-only
// Frames <-> nnstreamer.fbs tables (nnstreamer.flatbuf.Tensors), verified before access.
#include <cstdint>
#include <string>

#include "nnstreamer_generated.h"
#include "wire.h"

namespace nns::wire {

namespace fb = nnstreamer::flatbuf;

void encode_flatbuf(const Frame &f, std::vector<uint8_t> &out) {
  validate(f);
  std::size_t payload = 0;
  for (const Tensor &t : f.tensors) payload += t.size + 128;
  flatbuffers::FlatBufferBuilder b(payload + 256);
  std::vector<flatbuffers::Offset<fb::Tensor>> ts;
  ts.reserve(f.tensors.size());
  for (const Tensor &t : f.tensors) {
    auto name = b.CreateString(t.name);
    auto dims = b.CreateVector(t.dims.data(), kRankLimit);
    auto data = b.CreateVector(t.data, t.size);
    ts.push_back(fb::CreateTensor(b, name, static_cast<fb::Tensor_type>(t.type), dims, data));
  }
  fb::frame_rate fr(f.rate_n, f.rate_d);
  auto vec = b.CreateVector(ts);
  auto root = fb::CreateTensors(b, static_cast<int32_t>(f.tensors.size()), &fr, vec,
                                static_cast<fb::Tensor_format>(f.format));
  b.Finish(root);
  out.assign(b.GetBufferPointer(), b.GetBufferPointer() + b.GetSize());
}

Frame decode_flatbuf(const uint8_t *data, std::size_t size) {
  // Alignment is verified (relative to `data`, which must itself be 8-byte aligned): without
  // it a crafted offset makes the accessors below read misaligned tables (UB; found by
  // fuzz/wire_flatbuf_fuzz.cc).
  if (reinterpret_cast<std::uintptr_t>(data) % 8)
    throw WireError("flatbuf: input is not 8-byte aligned");
  flatbuffers::Verifier v(data, size, 64, 1000000, true);
  if (!fb::VerifyTensorsBuffer(v)) {
    std::string why = "corrupt or truncated";
    if (size < sizeof(flatbuffers::uoffset_t)) {
      why = "truncated at byte " + std::to_string(size) + " before the root offset";
    } else {
      const auto root = flatbuffers::ReadScalar<flatbuffers::uoffset_t>(data);
      if (root >= size)
        why = "truncated at byte " + std::to_string(size) + ": the root table is at byte " +
              std::to_string(root);
    }
    throw WireError("flatbuf: input (" + std::to_string(size) +
                    " bytes) is not a valid nnstreamer.flatbuf.Tensors buffer: " + why);
  }
  const fb::Tensors *root = fb::GetTensors(data);
  Frame f;
  f.format = static_cast<uint32_t>(root->format());
  if (root->fr()) f.rate_n = root->fr()->rate_n(), f.rate_d = root->fr()->rate_d();
  const auto *tv = root->tensor();
  const std::size_t n = tv ? tv->size() : 0;
  if (root->num_tensor() < 0 || static_cast<std::size_t>(root->num_tensor()) != n)
    throw WireError("flatbuf: num_tensor is " + std::to_string(root->num_tensor()) + " but " +
                    std::to_string(n) + " tensors follow");
  if (n > kTensorLimit) throw WireError("flatbuf: " + std::to_string(n) + " tensors, limit is 256");
  f.tensors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const fb::Tensor *ft = tv->Get(static_cast<flatbuffers::uoffset_t>(i));
    Tensor &t = f.tensors[i];
    if (!ft) throw WireError("flatbuf: tensor " + std::to_string(i) + " missing");
    if (ft->name()) t.name = ft->name()->str();
    t.type = static_cast<uint32_t>(ft->type());
    if (const auto *d = ft->dimension()) {
      if (d->size() > kRankLimit)
        throw WireError("flatbuf: tensor " + std::to_string(i) + " has " +
                        std::to_string(d->size()) + " dimensions, limit is 16");
      for (flatbuffers::uoffset_t k = 0; k < d->size(); ++k) t.dims[k] = d->Get(k);
    }
    if (const auto *d = ft->data()) t.data = d->data(), t.size = d->size();
  }
  validate(f);
  return f;
}

}  // namespace nns::wire

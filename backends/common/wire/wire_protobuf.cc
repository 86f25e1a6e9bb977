// SPDX-License-Identifier: LGPL-2.1-only
// Frames <-> nnstreamer.proto messages (nnstreamer::protobuf::Tensors).
#include <string>

#include "nnstreamer.pb.h"
#include "wire.h"

namespace nns::wire {

void encode_protobuf(const Frame &f, std::vector<uint8_t> &out) {
  validate(f);
  nnstreamer::protobuf::Tensors msg;
  msg.set_num_tensor(static_cast<uint32_t>(f.tensors.size()));
  msg.mutable_fr()->set_rate_n(f.rate_n);
  msg.mutable_fr()->set_rate_d(f.rate_d);
  msg.set_format(static_cast<nnstreamer::protobuf::Tensors_Tensor_format>(f.format));
  for (const Tensor &t : f.tensors) {
    nnstreamer::protobuf::Tensor *pt = msg.add_tensor();
    pt->set_name(t.name);
    pt->set_type(static_cast<nnstreamer::protobuf::Tensor_Tensor_type>(t.type));
    for (uint32_t d : t.dims) pt->add_dimension(d);  // all 16 entries, as upstream writes
    pt->set_data(t.data, t.size);
  }
  out.resize(msg.ByteSizeLong());
  if (!msg.SerializeToArray(out.data(), static_cast<int>(out.size())))
    throw WireError("protobuf: serialisation failed");
}

namespace {

// Where a message that failed to parse goes wrong, when it is a framing problem (truncated
// field, bad wire type) of the top level: "" otherwise. Only used on the error path.
std::string framing_problem(const uint8_t *d, std::size_t n) {
  std::size_t i = 0;
  auto varint = [&](uint64_t &v) {
    v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (i >= n) return false;
      const uint8_t b = d[i++];
      v |= uint64_t(b & 0x7f) << shift;
      if (!(b & 0x80)) return true;
    }
    return false;
  };
  while (i < n) {
    const std::size_t at = i;
    uint64_t key, v;
    if (!varint(key)) return "truncated at byte " + std::to_string(n) + " in a field key";
    const std::string field =
        "field " + std::to_string(key >> 3) + " at byte " + std::to_string(at);
    switch (key & 7) {
      case 0:
        if (!varint(v)) return "truncated at byte " + std::to_string(n) + " (" + field + ")";
        break;
      case 1:
      case 5: {
        const std::size_t w = (key & 7) == 1 ? 8 : 4;
        if (n - i < w) return "truncated at byte " + std::to_string(n) + " (" + field + ")";
        i += w;
        break;
      }
      case 2:
        if (!varint(v)) return "truncated at byte " + std::to_string(n) + " (" + field + ")";
        if (v > n - i)
          return "truncated at byte " + std::to_string(n) + ": " + field + " declares " +
                 std::to_string(v) + " bytes, " + std::to_string(n - i) + " remain";
        i += static_cast<std::size_t>(v);
        break;
      default:
        return "invalid wire type " + std::to_string(key & 7) + " (" + field + ")";
    }
  }
  return "";
}

}  // namespace

Frame decode_protobuf(const uint8_t *data, std::size_t size) {
  if (size > INT32_MAX) throw WireError("protobuf: input larger than 2 GiB");
  auto msg = std::make_shared<nnstreamer::protobuf::Tensors>();
  if (!msg->ParseFromArray(data, static_cast<int>(size))) {
    const std::string why = framing_problem(data, size);
    throw WireError("protobuf: input (" + std::to_string(size) +
                    " bytes) is not a valid NNStreamer.Tensors message" +
                    (why.empty() ? "" : ": " + why));
  }
  Frame f;
  f.format = static_cast<uint32_t>(msg->format());
  f.rate_n = msg->fr().rate_n();
  f.rate_d = msg->fr().rate_d();
  if (msg->num_tensor() != static_cast<uint32_t>(msg->tensor_size()))
    throw WireError("protobuf: num_tensor is " + std::to_string(msg->num_tensor()) + " but " +
                    std::to_string(msg->tensor_size()) + " tensors follow");
  if (static_cast<std::size_t>(msg->tensor_size()) > kTensorLimit)
    throw WireError("protobuf: " + std::to_string(msg->tensor_size()) + " tensors, limit is " +
                    std::to_string(kTensorLimit));
  f.tensors.resize(msg->tensor_size());
  for (int i = 0; i < msg->tensor_size(); ++i) {
    const nnstreamer::protobuf::Tensor &pt = msg->tensor(i);
    Tensor &t = f.tensors[i];
    t.name = pt.name();
    t.type = static_cast<uint32_t>(pt.type());
    if (static_cast<std::size_t>(pt.dimension_size()) > kRankLimit)
      throw WireError("protobuf: tensor " + std::to_string(i) + " has " +
                      std::to_string(pt.dimension_size()) + " dimensions, limit is 16");
    for (int k = 0; k < pt.dimension_size(); ++k) t.dims[k] = pt.dimension(k);
    t.data = reinterpret_cast<const uint8_t *>(pt.data().data());
    t.size = pt.data().size();
  }
  f.owner = msg;
  validate(f);
  return f;
}

}  // namespace nns::wire

// SPDX-License-Identifier: LGPL-2.1-only
// Frames <-> NNStreamer's flexbuffers layout:
//   Map { num_tensors: UInt, rate_n: Int, rate_d: Int, format: Int,
//         tensor_<i>: Vector [ String name, Int type, TypedVector dims(16), Blob data ] }
// The buffer is verified (flexbuffers::VerifyBuffer) and every value's type checked.
#include <flatbuffers/flexbuffers.h>

#include <cstdint>
#include <string>

#include "wire.h"

namespace nns::wire {

void encode_flexbuf(const Frame &f, std::vector<uint8_t> &out) {
  validate(f);
  std::size_t payload = 0;
  for (const Tensor &t : f.tensors) payload += t.size + 128;
  flexbuffers::Builder b(payload + 256);
  b.Map([&]() {
    b.UInt("num_tensors", f.tensors.size());
    b.Int("rate_n", f.rate_n);
    b.Int("rate_d", f.rate_d);
    b.Int("format", f.format);
    for (std::size_t i = 0; i < f.tensors.size(); ++i) {
      const Tensor &t = f.tensors[i];
      const std::string key = "tensor_" + std::to_string(i);
      b.Vector(key.c_str(), [&]() {
        b.String(t.name);
        b.Int(t.type);
        b.Vector(t.dims.data(), kRankLimit);
        b.Blob(t.data, t.size);
      });
    }
  });
  b.Finish();
  out = b.GetBuffer();
}

namespace {
[[noreturn]] void bad(std::size_t i, const std::string &what) {
  throw WireError("flexbuf: tensor_" + std::to_string(i) + ": " + what);
}
bool is_integer(const flexbuffers::Reference &r) {
  return r.IsInt() || r.IsUInt();
}
}  // namespace

Frame decode_flexbuf(const uint8_t *data, std::size_t size) {
  // flexbuffers reads scalars in place: the verifier checks alignment relative to `data`.
  if (reinterpret_cast<std::uintptr_t>(data) % 8)
    throw WireError("flexbuf: input is not 8-byte aligned");
  std::vector<uint8_t> reuse;
  if (!flexbuffers::VerifyBuffer(data, size, &reuse))
    throw WireError("flexbuf: input (" + std::to_string(size) +
                    " bytes) is not a valid flexbuffer (corrupt or truncated)");
  flexbuffers::Reference root = flexbuffers::GetRoot(data, size);
  if (!root.IsMap()) throw WireError("flexbuf: root is not a map");
  flexbuffers::Map m = root.AsMap();
  flexbuffers::Reference num = m["num_tensors"];
  if (!is_integer(num)) throw WireError("flexbuf: 'num_tensors' missing or not an integer");
  const uint64_t n = num.AsUInt64();
  if (n == 0 || n > kTensorLimit)
    throw WireError("flexbuf: num_tensors is " + std::to_string(n) + ", expected 1..256");
  Frame f;
  for (const char *key : {"rate_n", "rate_d", "format"}) {
    flexbuffers::Reference r = m[key];
    if (r.IsNull()) continue;  // optional (upstream writers before 'format' existed)
    if (!is_integer(r)) throw WireError(std::string("flexbuf: '") + key + "' is not an integer");
    const int64_t v = r.AsInt64();
    if (v < INT32_MIN || v > INT32_MAX)
      throw WireError(std::string("flexbuf: '") + key + "' out of range");
    if (key[0] == 'f') {
      if (v < 0) throw WireError("flexbuf: invalid tensor format " + std::to_string(v));
      f.format = static_cast<uint32_t>(v);
    } else if (key[5] == 'n') {
      f.rate_n = static_cast<int32_t>(v);
    } else {
      f.rate_d = static_cast<int32_t>(v);
    }
  }
  f.tensors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    const std::string key = "tensor_" + std::to_string(i);
    flexbuffers::Reference r = m[key.c_str()];
    if (!r.IsVector() || r.IsTypedVector() || r.IsFixedTypedVector())
      bad(i, "missing or not a vector");
    flexbuffers::Vector v = r.AsVector();
    if (v.size() < 4) bad(i, "vector has " + std::to_string(v.size()) + " entries, expected 4");
    Tensor &t = f.tensors[i];
    if (v[0].IsString()) {
      t.name = v[0].AsString().str();
    } else if (!v[0].IsNull()) {
      bad(i, "name is not a string");
    }
    if (!is_integer(v[1])) bad(i, "type is not an integer");
    const int64_t ty = v[1].AsInt64();
    if (ty < 0 || ty >= static_cast<int64_t>(kTypeEnd))
      bad(i, "invalid type " + std::to_string(ty));
    t.type = static_cast<uint32_t>(ty);
    flexbuffers::Reference d = v[2];
    if (!d.IsAnyVector()) bad(i, "dimension is not a vector");
    const std::size_t rank = d.IsTypedVector()        ? d.AsTypedVector().size()
                             : d.IsFixedTypedVector() ? d.AsFixedTypedVector().size()
                                                      : d.AsVector().size();
    if (rank > kRankLimit) bad(i, std::to_string(rank) + " dimensions, limit is 16");
    for (std::size_t k = 0; k < rank; ++k) {
      flexbuffers::Reference e = d.IsTypedVector()        ? d.AsTypedVector()[k]
                                 : d.IsFixedTypedVector() ? d.AsFixedTypedVector()[k]
                                                          : d.AsVector()[k];
      if (!is_integer(e)) bad(i, "dimension " + std::to_string(k) + " is not an integer");
      const int64_t dv = e.AsInt64();
      if (dv < 0 || dv > UINT32_MAX) bad(i, "dimension " + std::to_string(k) + " out of range");
      t.dims[k] = static_cast<uint32_t>(dv);
    }
    if (!v[3].IsBlob()) bad(i, "data is not a blob");
    flexbuffers::Blob blob = v[3].AsBlob();
    t.data = blob.data();
    t.size = blob.size();
  }
  validate(f);
  return f;
}

}  // namespace nns::wire

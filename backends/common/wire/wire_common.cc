// SPDX-License-Identifier: LGPL-2.1-only
#include "wire.h"

namespace nns::wire {

std::size_t type_size(uint32_t type) {
  static constexpr std::size_t kSizes[kTypeEnd] = {4, 4, 2, 2, 1, 1, 8, 4, 8, 8, 2};
  return type < kTypeEnd ? kSizes[type] : 0;
}

const char *format_name(Format f) {
  switch (f) {
    case Format::kProtobuf:
      return "protobuf";
    case Format::kFlatbuf:
      return "flatbuf";
    case Format::kFlexbuf:
      return "flexbuf";
  }
  return "?";
}

const char *media_type(Format f) {
  switch (f) {
    case Format::kProtobuf:
      return "other/protobuf-tensor";
    case Format::kFlatbuf:
      return "other/flatbuf-tensor";
    case Format::kFlexbuf:
      return "other/flexbuf";
  }
  return "?";
}

void validate(const Frame &f) {
  const std::size_t n = f.tensors.size();
  if (n == 0 || n > kTensorLimit)
    throw WireError("frame holds " + std::to_string(n) + " tensors, expected 1.." +
                    std::to_string(kTensorLimit));
  if (f.format >= kFormatEnd) throw WireError("invalid tensor format " + std::to_string(f.format));
  for (std::size_t i = 0; i < n; ++i) {
    const Tensor &t = f.tensors[i];
    const std::string who = "tensor " + std::to_string(i);
    const std::size_t es = type_size(t.type);
    if (!es) throw WireError(who + ": invalid type " + std::to_string(t.type));
    if (f.format != 0) {
      if (t.size < kMetaHeaderSize)
        throw WireError(who + ": " + std::to_string(t.size) +
                        " bytes, shorter than the 128-byte flexible header");
      continue;
    }
    std::size_t rank = 0;
    while (rank < kRankLimit && t.dims[rank]) ++rank;
    if (rank == 0) throw WireError(who + ": no dimension");
    for (std::size_t k = rank; k < kRankLimit; ++k)
      if (t.dims[k]) throw WireError(who + ": dimension " + std::to_string(k) + " after a 0");
    // Element count with overflow check.
    unsigned __int128 bytes = es;
    for (std::size_t k = 0; k < rank; ++k) {
      bytes *= t.dims[k];
      if (bytes > (unsigned __int128)SIZE_MAX)
        throw WireError(who + ": dimensions overflow the address space");
    }
    if ((std::size_t)bytes != t.size)
      throw WireError(who + ": carries " + std::to_string(t.size) + " bytes, expected " +
                      std::to_string((std::size_t)bytes) + " for its type and dimensions");
    if (t.size && !t.data) throw WireError(who + ": no data");
  }
}

void encode(Format fmt, const Frame &f, std::vector<uint8_t> &out) {
  switch (fmt) {
    case Format::kProtobuf:
      return encode_protobuf(f, out);
    case Format::kFlatbuf:
      return encode_flatbuf(f, out);
    case Format::kFlexbuf:
      return encode_flexbuf(f, out);
  }
  throw WireError("unknown wire format");
}

Frame decode(Format fmt, const uint8_t *data, std::size_t size) {
  if (!data || !size) throw WireError(std::string(format_name(fmt)) + ": empty input");
  switch (fmt) {
    case Format::kProtobuf:
      return decode_protobuf(data, size);
    case Format::kFlatbuf:
      return decode_flatbuf(data, size);
    case Format::kFlexbuf:
      return decode_flexbuf(data, size);
  }
  throw WireError("unknown wire format");
}

}  // namespace nns::wire

// SPDX-License-Identifier: LGPL-2.1-only
// GStreamer-free (de)serialisation of tensor frames in NNStreamer's wire formats:
// protobuf (nnstreamer.proto), flatbuffers (nnstreamer.fbs) and flexbuffers (a map with
// num_tensors, rate_n, rate_d, format and tensor_<i> = [name, type, dims, blob]).
// Decoders validate everything (counts, types, ranks, sizes) and throw WireError on bad input.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

namespace nns::wire {

constexpr std::size_t kRankLimit = 16;
constexpr std::size_t kTensorLimit = 256;
constexpr uint32_t kTypeEnd = 11;   // NNS_FLOAT16 + 1
constexpr uint32_t kFormatEnd = 3;  // static, flexible, sparse
constexpr std::size_t kMetaHeaderSize = 128;

enum class Format { kProtobuf, kFlatbuf, kFlexbuf };

struct WireError : std::runtime_error {
  using std::runtime_error::runtime_error;
};

struct Tensor {
  std::string name;
  uint32_t type = 0;
  std::array<uint32_t, kRankLimit> dims{};  // innermost first, 0 ends the rank
  const uint8_t *data = nullptr;            // borrowed (see Frame::owner)
  std::size_t size = 0;
};

struct Frame {
  uint32_t format = 0;
  int32_t rate_n = 0;
  int32_t rate_d = 1;
  std::vector<Tensor> tensors;
  // Keeps decoded data alive when it does not point into the input (protobuf).
  std::shared_ptr<const void> owner;
};

std::size_t type_size(uint32_t type);  // 0 for an invalid type
const char *format_name(Format f);     // "protobuf", "flatbuf", "flexbuf"
const char *media_type(Format f);      // "other/protobuf-tensor", ...

// Checks counts, types, ranks and (static format) data sizes; throws WireError.
void validate(const Frame &f);

// Serialises `f` (validated first); replaces the contents of `out`.
void encode(Format fmt, const Frame &f, std::vector<uint8_t> &out);
// Parses and validates; tensor data points into `data` for flatbuf/flexbuf (zero-copy).
Frame decode(Format fmt, const uint8_t *data, std::size_t size);

// Per-format entry points.
void encode_protobuf(const Frame &f, std::vector<uint8_t> &out);
Frame decode_protobuf(const uint8_t *data, std::size_t size);
void encode_flatbuf(const Frame &f, std::vector<uint8_t> &out);
Frame decode_flatbuf(const uint8_t *data, std::size_t size);
void encode_flexbuf(const Frame &f, std::vector<uint8_t> &out);
Frame decode_flexbuf(const uint8_t *data, std::size_t size);

}  // namespace nns::wire

// SPDX-License-Identifier: LGPL-2.1-only
// Tensor element types, dimensions and tensor-set descriptions (GStreamer-free).
// Dimension strings follow NNStreamer: innermost first ("3:224:224:1"), trailing 1s may be
// omitted and compare equal, several tensors separated by ',' or '.'.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace nns {

constexpr std::size_t kRankLimit = 16;
constexpr std::size_t kTensorLimit = 256;
constexpr std::size_t kMemoryMax = 16;  // GstMemory per GstBuffer; the rest is packed in the last

// Same numbering as NNStreamer's tensor_type (it is part of the flexible header).
enum class TensorType : uint32_t {
  kInt32 = 0,
  kUInt32,
  kInt16,
  kUInt16,
  kInt8,
  kUInt8,
  kFloat64,
  kFloat32,
  kInt64,
  kUInt64,
  kFloat16,
  kEnd,
};
constexpr std::size_t kNumTypes = static_cast<std::size_t>(TensorType::kEnd);

enum class TensorFormat : uint32_t { kStatic = 0, kFlexible, kSparse, kEnd };

// Media type recorded in the flexible header (NNStreamer's media_type).
enum class MediaType : int32_t {
  kInvalid = -1,
  kVideo = 0,
  kAudio = 1,
  kText = 2,
  kOctet = 3,
  kTensor = 4,
  kAny = 0x1000
};

std::size_t type_size(TensorType t);       // 0 for kEnd
std::string_view type_name(TensorType t);  // "float32"; "unknown" for kEnd
std::optional<TensorType> type_from_name(std::string_view s);
TensorType parse_type(std::string_view s);     // throws nns::Error naming the token
std::string_view format_name(TensorFormat f);  // "static" / "flexible" / "sparse"
std::optional<TensorFormat> format_from_name(std::string_view s);

// Dimensions: entries past the rank are 0.
using Dims = std::array<uint32_t, kRankLimit>;

std::size_t rank_of(const Dims &d);             // number of leading non-zero entries
std::size_t element_count(const Dims &d);       // product over the rank; 0 if rank is 0
bool dims_equal(const Dims &a, const Dims &b);  // trailing 1s and 0s are equivalent
Dims parse_dims(std::string_view s);            // "3:224:224:1"; throws on bad input
std::string dims_to_string(const Dims &d, std::size_t min_rank = 0);
Dims make_dims(std::initializer_list<uint32_t> v);

struct TensorInfo {
  std::string name;
  TensorType type = TensorType::kEnd;
  Dims dims{};

  std::size_t rank() const { return rank_of(dims); }
  std::size_t element_count() const { return nns::element_count(dims); }
  std::size_t byte_size() const { return element_count() * type_size(type); }
  bool valid() const { return type != TensorType::kEnd && rank() > 0; }
  // Same type and equivalent dims (names are not compared).
  bool same_as(const TensorInfo &o) const { return type == o.type && dims_equal(dims, o.dims); }
  std::string to_string() const;  // "uint8 3:224:224:1"
};

struct TensorsInfo {
  std::vector<TensorInfo> tensors;
  TensorFormat format = TensorFormat::kStatic;

  std::size_t size() const { return tensors.size(); }
  TensorInfo &operator[](std::size_t i) { return tensors[i]; }
  const TensorInfo &operator[](std::size_t i) const { return tensors[i]; }
  bool valid() const;  // static: every tensor valid; flexible/sparse: always
  bool same_as(const TensorsInfo &o) const;
  std::size_t total_bytes() const;
  std::string dims_string(std::size_t min_rank = 0) const;  // "3:224:224:1,10:1"
  std::string types_string() const;                         // "uint8,float32"
  std::string names_string() const;
  std::string to_string() const;  // human-readable, for errors
};

struct TensorsConfig {
  TensorsInfo info;
  int rate_n = -1;  // -1: not set
  int rate_d = -1;

  bool valid() const { return info.valid() && rate_n >= 0 && rate_d > 0; }
  bool same_as(const TensorsConfig &o) const;
};

// Parsing helpers shared by elements. Each throws nns::Error(kSettings) quoting the bad token;
// `what` names the property ("input-dim") for the message.
std::vector<Dims> parse_dims_list(std::string_view s, std::string_view what = "dimension");
std::vector<TensorType> parse_types_list(std::string_view s, std::string_view what = "type");
std::vector<std::string> parse_names_list(std::string_view s);

// Split on any of `seps`, trimming spaces; empty input gives an empty vector.
std::vector<std::string> split(std::string_view s, std::string_view seps, bool trim = true);
std::string trim(std::string_view s);
// The items with `sep` between them ("a,b" for {"a", "b"} and ",").
std::string join(const std::vector<std::string> &items, std::string_view sep);

}  // namespace nns

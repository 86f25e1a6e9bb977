// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_info.h"

#include <charconv>

#include "core/error.h"

namespace nns {
namespace {

constexpr std::array<std::string_view, kNumTypes> kTypeNames = {
    "int32",   "uint32",  "int16", "uint16", "int8",   "uint8",
    "float64", "float32", "int64", "uint64", "float16"};
constexpr std::array<std::size_t, kNumTypes> kTypeSizes = {4, 4, 2, 2, 1, 1, 8, 4, 8, 8, 2};
constexpr std::array<std::string_view, 3> kFormatNames = {"static", "flexible", "sparse"};

std::string quote(std::string_view s) {
  return "'" + std::string(s) + "'";
}

}  // namespace

std::size_t type_size(TensorType t) {
  auto i = static_cast<std::size_t>(t);
  return i < kNumTypes ? kTypeSizes[i] : 0;
}

std::string_view type_name(TensorType t) {
  auto i = static_cast<std::size_t>(t);
  return i < kNumTypes ? kTypeNames[i] : std::string_view("unknown");
}

std::optional<TensorType> type_from_name(std::string_view s) {
  std::string t = trim(s);
  for (std::size_t i = 0; i < kNumTypes; ++i)
    if (t == kTypeNames[i]) return static_cast<TensorType>(i);
  return std::nullopt;
}

TensorType parse_type(std::string_view s) {
  if (auto t = type_from_name(s)) return *t;
  fail(ErrorKind::kSettings, "unknown tensor type " + quote(trim(s)) +
                                 " (expected one of int8, int16, int32, int64, uint8, uint16, "
                                 "uint32, uint64, float16, float32, float64)");
}

std::string_view format_name(TensorFormat f) {
  auto i = static_cast<std::size_t>(f);
  return i < kFormatNames.size() ? kFormatNames[i] : std::string_view("unknown");
}

std::optional<TensorFormat> format_from_name(std::string_view s) {
  for (std::size_t i = 0; i < kFormatNames.size(); ++i)
    if (s == kFormatNames[i]) return static_cast<TensorFormat>(i);
  return std::nullopt;
}

std::size_t rank_of(const Dims &d) {
  std::size_t r = 0;
  while (r < kRankLimit && d[r] != 0) ++r;
  return r;
}

std::size_t element_count(const Dims &d) {
  std::size_t r = rank_of(d);
  if (r == 0) return 0;
  std::size_t n = 1;
  for (std::size_t i = 0; i < r; ++i) n *= d[i];
  return n;
}

bool dims_equal(const Dims &a, const Dims &b) {
  std::size_t ra = rank_of(a), rb = rank_of(b);
  if (ra == 0 || rb == 0) return ra == rb;
  for (std::size_t i = 0; i < kRankLimit; ++i) {
    uint32_t x = i < ra ? a[i] : 1, y = i < rb ? b[i] : 1;
    if (x != y) return false;
  }
  return true;
}

Dims parse_dims(std::string_view s) {
  Dims d{};
  std::string str = trim(s);
  if (str.empty()) fail(ErrorKind::kSettings, "empty dimension string");
  auto parts = split(str, ":");
  if (parts.size() > kRankLimit)
    fail(ErrorKind::kSettings, "dimension " + quote(str) + " has rank " +
                                   std::to_string(parts.size()) + ", the limit is " +
                                   std::to_string(kRankLimit));
  bool ended = false;  // a 0 ends the rank; only 0s may follow
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const std::string &p = parts[i];
    uint64_t v = 0;
    auto [ptr, ec] = std::from_chars(p.data(), p.data() + p.size(), v);
    if (p.empty() || ec != std::errc() || ptr != p.data() + p.size() || v > UINT32_MAX)
      fail(ErrorKind::kSettings, "bad dimension value " + quote(p) + " in " + quote(str) +
                                     " (expected unsigned integers separated by ':')");
    if (v == 0) {
      if (i == 0) fail(ErrorKind::kSettings, "dimension " + quote(str) + " starts with 0");
      ended = true;
    } else if (ended) {
      fail(ErrorKind::kSettings, "dimension " + quote(str) + " has a non-zero value after 0");
    }
    d[i] = static_cast<uint32_t>(v);
  }
  return d;
}

std::string dims_to_string(const Dims &d, std::size_t min_rank) {
  std::size_t r = std::max(rank_of(d), std::min(min_rank, kRankLimit));
  std::string out;
  for (std::size_t i = 0; i < r; ++i) {
    if (i) out += ':';
    out += std::to_string(d[i] == 0 ? 1 : d[i]);
  }
  return out;
}

Dims make_dims(std::initializer_list<uint32_t> v) {
  Dims d{};
  std::size_t i = 0;
  for (uint32_t x : v) {
    if (i >= kRankLimit) break;
    d[i++] = x;
  }
  return d;
}

std::string TensorInfo::to_string() const {
  std::string s = std::string(type_name(type)) + " " + (rank() ? dims_to_string(dims) : "?");
  if (!name.empty()) s += " '" + name + "'";
  return s;
}

bool TensorsInfo::valid() const {
  if (format != TensorFormat::kStatic) return true;
  if (tensors.empty() || tensors.size() > kTensorLimit) return false;
  for (const auto &t : tensors)
    if (!t.valid()) return false;
  return true;
}

bool TensorsInfo::same_as(const TensorsInfo &o) const {
  if (format != o.format) return false;
  if (format != TensorFormat::kStatic) return true;
  if (tensors.size() != o.tensors.size()) return false;
  for (std::size_t i = 0; i < tensors.size(); ++i)
    if (!tensors[i].same_as(o.tensors[i])) return false;
  return true;
}

std::size_t TensorsInfo::total_bytes() const {
  std::size_t n = 0;
  for (const auto &t : tensors) n += t.byte_size();
  return n;
}

std::string TensorsInfo::dims_string(std::size_t min_rank) const {
  std::string s;
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    if (i) s += ',';
    s += dims_to_string(tensors[i].dims, min_rank);
  }
  return s;
}

std::string TensorsInfo::types_string() const {
  std::string s;
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    if (i) s += ',';
    s += type_name(tensors[i].type);
  }
  return s;
}

std::string TensorsInfo::names_string() const {
  std::string s;
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    if (i) s += ',';
    s += tensors[i].name;
  }
  return s;
}

std::string TensorsInfo::to_string() const {
  if (format != TensorFormat::kStatic) return std::string(format_name(format)) + " tensors";
  std::string s = std::to_string(tensors.size()) + " tensor(s): ";
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    if (i) s += ", ";
    s += "[" + std::to_string(i) + "] " + tensors[i].to_string();
  }
  return s;
}

bool TensorsConfig::same_as(const TensorsConfig &o) const {
  if (!info.same_as(o.info)) return false;
  // 0/1 and unset rates only compare by value when both are set
  if (rate_n >= 0 && o.rate_n >= 0 && rate_d > 0 && o.rate_d > 0)
    return static_cast<int64_t>(rate_n) * o.rate_d == static_cast<int64_t>(o.rate_n) * rate_d;
  return true;
}

namespace {

// One item per tensor, separated with ',' (or '.'), each read by `parse`; messages start with
// `what`.
template <typename Parse>
auto parse_list(std::string_view s, std::string_view what, Parse parse) {
  std::vector<decltype(parse(s))> out;
  auto parts = split(s, ",.");
  if (parts.size() > kTensorLimit)
    fail(ErrorKind::kSettings, std::string(what) + " lists " + std::to_string(parts.size()) +
                                   " tensors, the limit is " + std::to_string(kTensorLimit));
  for (const auto &p : parts) {
    try {
      out.push_back(parse(p));
    } catch (const Error &e) {
      fail(ErrorKind::kSettings, std::string(what) + ": " + e.what());
    }
  }
  return out;
}

}  // namespace

std::vector<Dims> parse_dims_list(std::string_view s, std::string_view what) {
  return parse_list(s, what, [](std::string_view p) { return parse_dims(p); });
}

std::vector<TensorType> parse_types_list(std::string_view s, std::string_view what) {
  return parse_list(s, what, [](std::string_view p) { return parse_type(p); });
}

std::vector<std::string> parse_names_list(std::string_view s) {
  return split(s, ",");
}

std::string trim(std::string_view s) {
  std::size_t b = 0, e = s.size();
  while (b < e && (s[b] == ' ' || s[b] == '\t' || s[b] == '\n' || s[b] == '\r')) ++b;
  while (e > b && (s[e - 1] == ' ' || s[e - 1] == '\t' || s[e - 1] == '\n' || s[e - 1] == '\r'))
    --e;
  return std::string(s.substr(b, e - b));
}

std::string join(const std::vector<std::string> &items, std::string_view sep) {
  std::string out;
  for (std::size_t i = 0; i < items.size(); ++i) {
    if (i) out += sep;
    out += items[i];
  }
  return out;
}

std::vector<std::string> split(std::string_view s, std::string_view seps, bool do_trim) {
  std::vector<std::string> out;
  if (trim(s).empty()) return out;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= s.size(); ++i) {
    if (i == s.size() || seps.find(s[i]) != std::string_view::npos) {
      auto piece = s.substr(start, i - start);
      out.push_back(do_trim ? trim(piece) : std::string(piece));
      start = i + 1;
    }
  }
  return out;
}

}  // namespace nns

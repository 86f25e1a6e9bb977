// SPDX-License-Identifier: LGPL-2.1-only
// Small header-only helpers shared by filter back ends (no GStreamer, no runtime headers):
// custom= option parsing, accelerator= parsing, and readable tensor descriptions for messages.
#pragma once

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <string>
#include <string_view>
#include <system_error>
#include <utility>
#include <vector>

#include "nnstreamer/nns_filter_backend.hh"

namespace nns::backend {

inline std::string_view trim(std::string_view s) {
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.front()))) s.remove_prefix(1);
  while (!s.empty() && std::isspace(static_cast<unsigned char>(s.back()))) s.remove_suffix(1);
  return s;
}

inline bool iequals(std::string_view a, std::string_view b) {
  return a.size() == b.size() && std::equal(a.begin(), a.end(), b.begin(), [](char x, char y) {
           return std::tolower(static_cast<unsigned char>(x)) ==
                  std::tolower(static_cast<unsigned char>(y));
         });
}

inline std::string lower(std::string_view s) {
  std::string r(s);
  for (auto &c : r) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return r;
}

inline std::vector<std::string_view> split(std::string_view s, char sep) {
  std::vector<std::string_view> out;
  std::size_t pos = 0;
  while (true) {
    std::size_t next = s.find(sep, pos);
    out.push_back(
        s.substr(pos, next == std::string_view::npos ? std::string_view::npos : next - pos));
    if (next == std::string_view::npos) break;
    pos = next + 1;
  }
  return out;
}

// custom= "key:value,key:value" (NNStreamer grammar). Empty entries are skipped; an entry
// without ':' or with an empty key is an error. Keys keep their spelling; values are trimmed.
struct CustomOption {
  std::string key;
  std::string value;
};

inline std::vector<CustomOption> parse_custom(const char *custom, std::string_view backend) {
  std::vector<CustomOption> out;
  if (!custom) return out;
  for (std::string_view item : split(custom, ',')) {
    item = trim(item);
    if (item.empty()) continue;
    std::size_t colon = item.find(':');
    if (colon == std::string_view::npos || trim(item.substr(0, colon)).empty())
      throw FilterError(std::string(backend) + ": custom option '" + std::string(item) +
                        "' is not of the form key:value");
    out.push_back(
        {std::string(trim(item.substr(0, colon))), std::string(trim(item.substr(colon + 1)))});
  }
  return out;
}

// "true"/"false" (also 1/0, yes/no, on/off), case-insensitive.
inline bool parse_bool_option(std::string_view backend, const CustomOption &o) {
  std::string v = lower(o.value);
  if (v == "true" || v == "1" || v == "yes" || v == "on") return true;
  if (v == "false" || v == "0" || v == "no" || v == "off") return false;
  throw FilterError(std::string(backend) + ": custom option " + o.key + ":" + o.value +
                    ": expected true or false");
}

inline long parse_int_option(std::string_view backend, const CustomOption &o, long lo, long hi) {
  long v = 0;
  bool ok = !o.value.empty();
  try {
    std::size_t used = 0;
    v = std::stol(o.value, &used);
    ok = ok && used == o.value.size();
  } catch (...) {
    ok = false;
  }
  if (!ok || v < lo || v > hi)
    throw FilterError(std::string(backend) + ": custom option " + o.key + ":" + o.value +
                      ": expected an integer in [" + std::to_string(lo) + ", " +
                      std::to_string(hi) + "]");
  return v;
}

// accelerator= "(true|false):name[,name...]" with '!' negating a name. Returns the wanted
// names in order (lower case, negated ones dropped); empty when accelerators are off or unset.
struct AcceleratorRequest {
  bool enabled = false;
  std::vector<std::string> wanted;
  std::vector<std::string> excluded;
};

inline AcceleratorRequest parse_accelerator(const char *accl) {
  AcceleratorRequest r;
  if (!accl) return r;
  std::string_view s = trim(accl);
  if (s.empty()) return r;
  std::size_t colon = s.find(':');
  std::string_view head = trim(s.substr(0, colon));
  std::string_view list = s;  // a bare list (no "true:" prefix) counts as enabled
  if (iequals(head, "false")) return r;
  if (iequals(head, "true"))
    list = colon == std::string_view::npos ? std::string_view() : s.substr(colon + 1);
  r.enabled = true;
  for (std::string_view n : split(list, ',')) {
    n = trim(n);
    if (n.empty()) continue;
    if (n.front() == '!')
      r.excluded.push_back(lower(trim(n.substr(1))));
    else
      r.wanted.push_back(lower(n));
  }
  return r;
}

// Number of leading non-zero dims.
inline uint32_t desc_rank(const nns_tensor_desc &t) {
  uint32_t r = 0;
  while (r < NNS_TENSOR_RANK_LIMIT && t.dims[r] != 0) ++r;
  return r;
}

// Rank without trailing 1s (at least 1 when the rank is non-zero).
inline uint32_t desc_effective_rank(const nns_tensor_desc &t) {
  uint32_t r = desc_rank(t);
  while (r > 1 && t.dims[r - 1] == 1) --r;
  return r;
}

inline uint64_t desc_elements(const nns_tensor_desc &t) {
  uint32_t r = desc_rank(t);
  if (r == 0) return 0;
  uint64_t n = 1;
  for (uint32_t i = 0; i < r; ++i) n *= t.dims[i];
  return n;
}

inline std::size_t type_size(uint32_t type) {
  switch (type) {
    case _NNS_INT8:
    case _NNS_UINT8:
      return 1;
    case _NNS_INT16:
    case _NNS_UINT16:
    case _NNS_FLOAT16:
      return 2;
    case _NNS_INT32:
    case _NNS_UINT32:
    case _NNS_FLOAT32:
      return 4;
    case _NNS_INT64:
    case _NNS_UINT64:
    case _NNS_FLOAT64:
      return 8;
    default:
      return 0;
  }
}

inline const char *type_name(uint32_t type) {
  static const char *const names[] = {"int32",   "uint32",  "int16", "uint16", "int8",   "uint8",
                                      "float64", "float32", "int64", "uint64", "float16"};
  return type < sizeof(names) / sizeof(names[0]) ? names[type] : "unknown";
}

// "uint8 1:28:28:1"
inline std::string desc_to_string(const nns_tensor_desc &t) {
  std::string s = type_name(t.type);
  s += ' ';
  uint32_t r = desc_rank(t);
  if (r == 0) return s + "(no dims)";
  for (uint32_t i = 0; i < r; ++i) {
    if (i) s += ':';
    s += std::to_string(t.dims[i]);
  }
  return s;
}

// Same type and the same dims once trailing 1s are ignored.
inline bool desc_equal(const nns_tensor_desc &a, const nns_tensor_desc &b) {
  if (a.type != b.type) return false;
  uint32_t ra = desc_effective_rank(a), rb = desc_effective_rank(b);
  if (ra != rb) return false;
  for (uint32_t i = 0; i < ra; ++i)
    if (a.dims[i] != b.dims[i]) return false;
  return true;
}

inline void set_name(nns_tensor_desc &t, std::string_view name) {
  std::size_t n = std::min(name.size(), sizeof(t.name) - 1);
  std::memcpy(t.name, name.data(), n);
  t.name[n] = '\0';
}

// The single model file of props, checked to exist and be a regular file.
inline std::string single_model_path(const nns_filter_props &props, std::string_view backend) {
  if (props.num_models != 1 || !props.model_files || !props.model_files[0])
    throw FilterError(std::string(backend) + ": expects exactly one model file, got " +
                          std::to_string(props.num_models),
                      -EINVAL);
  std::string path = props.model_files[0];
  std::error_code ec;
  auto st = std::filesystem::status(path, ec);
  if (ec || !std::filesystem::exists(st))
    throw FilterError(std::string(backend) + ": model file '" + path + "' does not exist", -ENOENT);
  if (!std::filesystem::is_regular_file(st))
    throw FilterError(std::string(backend) + ": model file '" + path + "' is not a regular file",
                      -EINVAL);
  return path;
}

// Collapses a multi-line runtime message into one line of at most `max` characters.
inline std::string one_line(std::string_view msg, std::size_t max = 600) {
  std::string out;
  bool space = false;
  for (char c : msg) {
    if (c == '\n' || c == '\r' || c == '\t') c = ' ';
    if (c == ' ') {
      if (space || out.empty()) continue;
      space = true;
    } else {
      space = false;
    }
    out += c;
  }
  while (!out.empty() && out.back() == ' ') out.pop_back();
  if (out.size() > max) out = out.substr(0, max - 3) + "...";
  return out;
}

}  // namespace nns::backend

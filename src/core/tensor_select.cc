// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_select.h"

#include <algorithm>
#include <charconv>

#include "core/error.h"

namespace nns {
namespace {

constexpr std::string_view kListSeps = ",.;/";

uint32_t parse_index(const std::string &tok, std::string_view prop, std::string_view whole) {
  uint64_t v = 0;
  auto [p, ec] = std::from_chars(tok.data(), tok.data() + tok.size(), v);
  if (tok.empty() || ec != std::errc() || p != tok.data() + tok.size() || v > UINT32_MAX)
    fail(ErrorKind::kSettings,
         std::string(prop) + "='" + std::string(whole) + "': '" + tok + "' is not a tensor index");
  return static_cast<uint32_t>(v);
}

}  // namespace

PickGroups parse_demux_tensorpick(std::string_view s) {
  PickGroups out;
  if (trim(s).empty()) return out;
  for (const auto &group : split(s, kListSeps)) {
    std::vector<uint32_t> g;
    for (const auto &tok : split(group, ":+")) g.push_back(parse_index(tok, "tensorpick", s));
    if (g.empty())
      fail(ErrorKind::kSettings, "tensorpick='" + std::string(s) + "' has an empty pad group");
    out.push_back(std::move(g));
  }
  return out;
}

std::string demux_tensorpick_to_string(const PickGroups &g) {
  std::string s;
  for (std::size_t i = 0; i < g.size(); ++i) {
    if (i) s += ',';
    for (std::size_t j = 0; j < g[i].size(); ++j) {
      if (j) s += ':';
      s += std::to_string(g[i][j]);
    }
  }
  return s;
}

void check_demux_tensorpick(const PickGroups &g, std::size_t num_tensors) {
  for (std::size_t i = 0; i < g.size(); ++i)
    for (uint32_t idx : g[i])
      if (idx >= num_tensors)
        fail(ErrorKind::kNegotiation,
             "tensorpick='" + demux_tensorpick_to_string(g) + "': pad " + std::to_string(i) +
                 " picks tensor " + std::to_string(idx) + " but the input has only " +
                 std::to_string(num_tensors) + " tensor(s) (valid indices 0.." +
                 std::to_string(num_tensors ? num_tensors - 1 : 0) + ")");
}

PickGroups default_demux_groups(std::size_t num_tensors) {
  PickGroups g(num_tensors);
  for (std::size_t i = 0; i < num_tensors; ++i) g[i] = {static_cast<uint32_t>(i)};
  return g;
}

std::vector<Dims> parse_tensorseg(std::string_view s) {
  std::vector<Dims> out;
  if (trim(s).empty()) return out;
  for (const auto &tok : split(s, kListSeps)) {
    try {
      out.push_back(parse_dims(tok));
    } catch (const Error &e) {
      fail(ErrorKind::kSettings, "tensorseg='" + std::string(s) + "': " + e.what());
    }
  }
  return out;
}

std::string tensorseg_to_string(const std::vector<Dims> &seg) {
  std::string s;
  for (std::size_t i = 0; i < seg.size(); ++i) {
    if (i) s += ',';
    s += dims_to_string(seg[i]);
  }
  return s;
}

std::vector<uint32_t> parse_split_tensorpick(std::string_view s) {
  std::vector<uint32_t> out;
  if (trim(s).empty()) return out;
  for (const auto &tok : split(s, kListSeps)) out.push_back(parse_index(tok, "tensorpick", s));
  return out;
}

std::string split_tensorpick_to_string(const std::vector<uint32_t> &pick) {
  std::string s;
  for (std::size_t i = 0; i < pick.size(); ++i) {
    if (i) s += ',';
    s += std::to_string(pick[i]);
  }
  return s;
}

std::vector<Segment> plan_split(const TensorInfo &in, const std::vector<Dims> &seg,
                                const std::vector<uint32_t> &pick) {
  if (seg.empty()) fail(ErrorKind::kSettings, "tensorseg is not set: nothing to split");
  std::vector<Segment> all(seg.size());
  std::size_t offset = 0;
  const std::size_t esize = type_size(in.type);
  for (std::size_t i = 0; i < seg.size(); ++i) {
    Segment &s = all[i];
    s.index = static_cast<uint32_t>(i);
    s.info.type = in.type;
    s.info.dims = seg[i];
    s.offset = offset;
    s.size = element_count(seg[i]) * esize;
    offset += s.size;
  }
  if (offset > in.byte_size())
    fail(ErrorKind::kNegotiation,
         "tensorseg='" + tensorseg_to_string(seg) + "' needs " + std::to_string(offset) +
             " bytes of " + std::string(type_name(in.type)) + " but the input tensor " +
             in.to_string() + " has " + std::to_string(in.byte_size()) + " bytes");
  if (pick.empty()) return all;
  std::vector<uint32_t> sorted = pick;
  std::sort(sorted.begin(), sorted.end());
  sorted.erase(std::unique(sorted.begin(), sorted.end()), sorted.end());
  std::vector<Segment> out;
  for (uint32_t idx : sorted) {
    if (idx >= seg.size())
      fail(ErrorKind::kNegotiation, "tensorpick='" + split_tensorpick_to_string(pick) +
                                        "' picks segment " + std::to_string(idx) +
                                        " but tensorseg has only " + std::to_string(seg.size()) +
                                        " segment(s)");
    out.push_back(all[idx]);
  }
  return out;
}

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_debug_format.h"

#include <cstdio>

namespace nns::tdbg {

Outputs decode_outputs(uint32_t flags) {
  Outputs o;
  static const Level levels[4] = {Level::kNone, Level::kInfo, Level::kWarn, Level::kError};
  if (flags & 0x10) o.console = levels[flags & 0x3];
  if (flags & 0x20) o.gst = levels[(flags >> 2) & 0x3];
  o.unsupported = (flags & (kCircularBuf | kFileWrite)) != 0;
  return o;
}

std::string format_time(uint64_t ns) {
  if (ns == kNoTime) return "none";
  char buf[48];
  std::snprintf(buf, sizeof buf, "%u:%02u:%02u.%09u", unsigned(ns / 3600000000000ull),
                unsigned(ns / 60000000000ull % 60), unsigned(ns / 1000000000ull % 60),
                unsigned(ns % 1000000000ull));
  return buf;
}

std::string describe_tensors(const TensorsInfo &info) {
  std::string s =
      std::string(format_name(info.format)) + ", " + std::to_string(info.size()) + " tensor(s)";
  for (std::size_t i = 0; i < info.size(); ++i)
    s += (i ? ", [" : ": [") + std::to_string(i) + "] " + info[i].to_string();
  return s;
}

std::string describe_headers(const std::vector<MetaHeader> &headers) {
  // Flexible headers carry format 0 or 1 (see flexible_header()); only sparse differs.
  const bool sparse = !headers.empty() && headers[0].format == TensorFormat::kSparse;
  std::string fmt = sparse ? "sparse" : "flexible";
  std::string s = fmt + ", " + std::to_string(headers.size()) + " tensor(s)";
  for (std::size_t i = 0; i < headers.size(); ++i) {
    s += (i ? ", [" : ": [") + std::to_string(i) + "] " + headers[i].info().to_string();
    if (headers[i].format == TensorFormat::kSparse) s += " nnz=" + std::to_string(headers[i].nnz);
  }
  return s;
}

std::string describe_timestamps(uint64_t pts, uint64_t dts, uint64_t duration, uint64_t offset) {
  std::string s = "pts " + format_time(pts) + ", dts " + format_time(dts) + ", duration " +
                  format_time(duration);
  s += ", offset " + (offset == kNoTime ? std::string("none") : std::to_string(offset));
  return s;
}

bool same_headers(const std::vector<MetaHeader> &a, const std::vector<MetaHeader> &b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i)
    if (a[i].type != b[i].type || !dims_equal(a[i].dims, b[i].dims) ||
        (a[i].format == TensorFormat::kSparse) != (b[i].format == TensorFormat::kSparse))
      return false;
  return true;
}

}  // namespace nns::tdbg

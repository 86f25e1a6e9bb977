// SPDX-License-Identifier: LGPL-2.1-only
// Text that tensor_debug logs (GStreamer-free): tensor descriptions, flexible/sparse header
// summaries and timestamps, plus the decoding of upstream's output-method flag values.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/meta_header.h"
#include "core/tensor_info.h"

namespace nns::tdbg {

// Upstream's flag values (gsttensor_debug.h): bit 0x10 = console, 0x20 = GStreamer debug log;
// the low bits carry the level (console: 1 info, 2 warn, 3 error; gst: 4/8/0xC info/warn/error).
enum : uint32_t {
  kOutputDisabled = 0x00,
  kConsoleInfo = 0x11,
  kConsoleWarn = 0x12,
  kConsoleError = 0x13,
  kGstInfo = 0x24,
  kGstWarn = 0x28,
  kGstError = 0x2C,
  kCircularBuf = 0x100,
  kFileWrite = 0x200,
};
enum class Capability : int { kDisabled = 0, kUpdates = 1, kUpdatesFull = 2, kAlways = 3 };
enum : uint32_t { kMetaDisabled = 0, kMetaTimestamp = 0x1, kMetaQueryServer = 0x2 };

enum class Level { kNone, kInfo, kWarn, kError };
struct Outputs {
  Level console = Level::kNone;
  Level gst = Level::kNone;
  bool unsupported = false;  // circularbuf / filewrite (not implemented upstream either)
};
Outputs decode_outputs(uint32_t flags);

constexpr uint64_t kNoTime = UINT64_MAX;
std::string format_time(uint64_t ns);  // "0:00:01.500000000", "none"

// "static, 2 tensor(s): [0] uint8 3:4:1:1, [1] float32 10"
std::string describe_tensors(const TensorsInfo &info);
// "flexible, 1 tensor(s): [0] float32 4:2" ; sparse adds " nnz=3" per tensor.
std::string describe_headers(const std::vector<MetaHeader> &headers);
// "pts 0:00:00.033333333, dts none, duration 0:00:00.033333333, offset 1"
std::string describe_timestamps(uint64_t pts, uint64_t dts, uint64_t duration, uint64_t offset);

// Whether two header lists describe the same tensors (types, dims, format).
bool same_headers(const std::vector<MetaHeader> &a, const std::vector<MetaHeader> &b);

}  // namespace nns::tdbg

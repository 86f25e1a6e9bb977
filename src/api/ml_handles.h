// SPDX-License-Identifier: LGPL-2.1-only
// Internal structures behind the ML API handles, and error reporting helpers.
#pragma once

#include <cstdint>
#include <cstdlib>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "core/tensor_info.h"
#include "ml-api-common.h"

namespace nns::api {

constexpr uint32_t kInfoMagic = 0x6d6c6931;    // "mli1"
constexpr uint32_t kDataMagic = 0x6d6c6431;    // "mld1"
constexpr uint32_t kOptionMagic = 0x6d6c6f31;  // "mlo1"
constexpr uint32_t kSingleMagic = 0x6d6c7331;  // "mls1"

struct TensorsInfoHandle {
  uint32_t magic = kInfoMagic;
  TensorsInfo info;
  bool extended = false;
};

// Tensor buffers, 64-byte aligned (back ends with SIMD kernels take them as they are).
struct TensorsDataHandle {
  uint32_t magic = kDataMagic;
  TensorsInfo info;
  struct Free {
    void operator()(uint8_t *p) const { std::free(p); }
  };
  std::vector<std::unique_ptr<uint8_t, Free>> buffers;
  std::vector<std::size_t> sizes;
};

struct OptionHandle {
  uint32_t magic = kOptionMagic;
  struct Entry {
    void *value = nullptr;
    ml_data_destroy_cb destroy = nullptr;
  };
  std::map<std::string, Entry> entries;
  ~OptionHandle();
};

// Records `msg` as this thread's last error and returns `code`.
int report(int code, const std::string &msg);
void clear_error();

TensorsInfoHandle *as_info(ml_tensors_info_h h);
TensorsDataHandle *as_data(ml_tensors_data_h h);
OptionHandle *as_option(ml_option_h h);
// New data handle with buffers for `info` (zero-filled). Throws std::bad_alloc.
TensorsDataHandle *new_data(const TensorsInfo &info);

}  // namespace nns::api

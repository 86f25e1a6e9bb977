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

constexpr uint32_t kInfoMagic = 0x6d6c6931;         // "mli1"
constexpr uint32_t kDataMagic = 0x6d6c6431;         // "mld1"
constexpr uint32_t kOptionMagic = 0x6d6c6f31;       // "mlo1"
constexpr uint32_t kSingleMagic = 0x6d6c7331;       // "mls1"
constexpr uint32_t kInformationMagic = 0x6d6c6e31;  // "mln1"
constexpr uint32_t kInfoListMagic = 0x6d6c7431;     // "mlt1"

// The rank limit of a handle made by ml_tensors_info_create (NNStreamer's old limit).
constexpr std::size_t kRankLimitPrev = 4;

struct TensorsInfoHandle {
  uint32_t magic = kInfoMagic;
  TensorsInfo info;
  bool extended = false;  // ml_tensors_info_create_extended: rank limit 16, else 4
};

// True when a tensor of `info` uses a dimension past the old rank limit of 4.
bool needs_extended(const TensorsInfo &info);

// Tensor buffers, 64-byte aligned (back ends with SIMD kernels take them as they are), or
// borrowed from the caller (nns_ml_tensors_data_wrap: not freed with the handle).
struct TensorsDataHandle {
  uint32_t magic = kDataMagic;
  TensorsInfo info;
  bool extended = false;  // the kind of info handle ml_tensors_data_get_info gives
  struct Free {
    bool owned = true;
    void operator()(uint8_t *p) const {
      if (owned) std::free(p);
    }
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

// ml_information_h: the same key-value table as an option, with magic kInformationMagic.
using InformationHandle = OptionHandle;

struct InformationListHandle {
  uint32_t magic = kInfoListMagic;
  std::vector<OptionHandle *> items;  // owned; informations (or options)
  ~InformationListHandle();
};

// Records `msg` as this thread's last error and returns `code`.
int report(int code, const std::string &msg);
void clear_error();

TensorsInfoHandle *as_info(ml_tensors_info_h h);
TensorsDataHandle *as_data(ml_tensors_data_h h);
OptionHandle *as_option(ml_option_h h);
InformationHandle *as_information(ml_information_h h);
// New data handle with buffers for `info` (zero-filled). Throws std::bad_alloc.
TensorsDataHandle *new_data(const TensorsInfo &info);
// New info handle holding `info`, extended when its ranks need it (as NNStreamer's handles
// made from a model's info). Returns ML_ERROR_NONE or ML_ERROR_OUT_OF_MEMORY (reported).
int new_info_handle(const TensorsInfo &info, ml_tensors_info_h *out);

}  // namespace nns::api

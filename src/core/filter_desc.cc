// SPDX-License-Identifier: LGPL-2.1-only
#include "core/filter_desc.h"

#include <cstring>

#include "core/error.h"

namespace nns {

std::unique_ptr<nns_tensors_desc> new_desc() {
  auto d = std::make_unique<nns_tensors_desc>();
  std::memset(d.get(), 0, sizeof(nns_tensors_desc));
  return d;
}

void desc_from_info(const TensorsInfo &info, nns_tensors_desc &out) {
  if (info.size() > NNS_TENSOR_SIZE_LIMIT)
    fail(ErrorKind::kSettings, "too many tensors: " + std::to_string(info.size()) + " (at most " +
                                   std::to_string(NNS_TENSOR_SIZE_LIMIT) + ")");
  out.num_tensors = static_cast<uint32_t>(info.size());
  out.format = static_cast<uint32_t>(info.format);
  for (std::size_t i = 0; i < info.size(); ++i) {
    nns_tensor_desc &t = out.tensors[i];
    const TensorInfo &s = info[i];
    if (s.name.size() >= NNS_TENSOR_NAME_MAX)
      fail(ErrorKind::kSettings, "tensor name '" + s.name + "' is longer than " +
                                     std::to_string(NNS_TENSOR_NAME_MAX - 1) + " characters");
    std::memcpy(t.name, s.name.c_str(), s.name.size() + 1);
    t.type = static_cast<uint32_t>(s.type);
    for (std::size_t r = 0; r < kRankLimit; ++r) t.dims[r] = s.dims[r];
  }
}

std::unique_ptr<nns_tensors_desc> make_desc(const TensorsInfo &info) {
  auto d = new_desc();
  desc_from_info(info, *d);
  return d;
}

TensorsInfo info_from_desc(const nns_tensors_desc &desc) {
  if (desc.num_tensors > NNS_TENSOR_SIZE_LIMIT)
    fail(ErrorKind::kLibrary, "back end reported " + std::to_string(desc.num_tensors) +
                                  " tensors (at most " + std::to_string(NNS_TENSOR_SIZE_LIMIT) +
                                  ")");
  TensorsInfo info;
  info.format = desc.format < static_cast<uint32_t>(TensorFormat::kEnd)
                    ? static_cast<TensorFormat>(desc.format)
                    : TensorFormat::kStatic;
  info.tensors.resize(desc.num_tensors);
  for (uint32_t i = 0; i < desc.num_tensors; ++i) {
    const nns_tensor_desc &t = desc.tensors[i];
    TensorInfo &o = info.tensors[i];
    o.name.assign(t.name, strnlen(t.name, NNS_TENSOR_NAME_MAX));
    if (t.type >= static_cast<uint32_t>(TensorType::kEnd))
      fail(ErrorKind::kLibrary, "back end reported an invalid type (" + std::to_string(t.type) +
                                    ") for tensor " + std::to_string(i));
    o.type = static_cast<TensorType>(t.type);
    for (std::size_t r = 0; r < kRankLimit; ++r) o.dims[r] = t.dims[r];
  }
  return info;
}

}  // namespace nns

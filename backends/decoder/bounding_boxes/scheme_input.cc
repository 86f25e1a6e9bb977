// SPDX-License-Identifier: LGPL-2.1-only
#include "scheme_input.h"

#include <algorithm>
#include <cstring>
#include <exception>
#include <utility>

namespace nns::bbox {
namespace {

bool same_c_info(const GstTensorsInfo &a, const GstTensorsInfo &b) {
  if (a.num_tensors != b.num_tensors) return false;
  const unsigned n = std::min<unsigned>(a.num_tensors, NNS_TENSOR_MEMORY_MAX);
  for (unsigned i = 0; i < n; ++i) {
    if (a.info[i].type != b.info[i].type) return false;
    if (std::memcmp(a.info[i].dimension, b.info[i].dimension, sizeof a.info[i].dimension))
      return false;
  }
  return true;
}

}  // namespace

bool SchemeInput::bind(Scheme &scheme, const Context &ctx, const GstTensorsInfo &c,
                       std::string &why) {
  why.clear();
  if (checked_ && same_c_info(checked_c_, c)) return true;
  const unsigned n = std::min<unsigned>(c.num_tensors, NNS_TENSOR_MEMORY_MAX);
  TensorsInfo info;
  for (unsigned i = 0; i < n; ++i) {
    TensorInfo t;
    const GstTensorInfo &ci = c.info[i];
    if (ci.type >= _NNS_END) return false;
    t.type = static_cast<TensorType>(ci.type);
    for (unsigned k = 0; k < NNS_TENSOR_RANK_LIMIT && k < t.dims.size(); ++k)
      t.dims[k] = ci.dimension[k];
    if (t.rank() == 0) return false;  // not fixed yet
    info.tensors.push_back(t);
  }
  try {
    scheme.check_input(info, ctx);
  } catch (const std::exception &e) {
    why = e.what();
    return false;
  }
  in_info_ = std::move(info);
  views_.assign(in_info_.size(), {});
  for (std::size_t i = 0; i < views_.size(); ++i) views_[i].info = &in_info_[i];
  checked_c_ = c;
  checked_c_.extra = nullptr;
  checked_ = true;
  return true;
}

bool SchemeInput::decode(Scheme &scheme, const Context &ctx, const GstTensorMemory *input,
                         std::vector<Box> &boxes, std::string &why) {
  for (std::size_t i = 0; i < views_.size(); ++i) {
    views_[i].data = input[i].data;
    views_[i].size = input[i].size;
  }
  try {
    scheme.decode(views_, ctx, boxes);
  } catch (const std::exception &e) {
    why = e.what();
    return false;
  }
  return true;
}

}  // namespace nns::bbox

// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/c_tensor_info.h"

#include <cstring>

#include "core/error.h"

namespace nns::gst {
namespace {

static_assert(NNS_TENSOR_RANK_LIMIT == kRankLimit);
static_assert(NNS_TENSOR_SIZE_LIMIT == kTensorLimit);
static_assert(NNS_TENSOR_MEMORY_MAX == kMemoryMax);
static_assert(static_cast<int>(_NNS_END) == static_cast<int>(TensorType::kEnd));

void init_one(GstTensorInfo *t) {
  t->name = nullptr;
  t->type = _NNS_END;
  std::memset(t->dimension, 0, sizeof t->dimension);
}

}  // namespace

void init_c(GstTensorsInfo *info) {
  info->num_tensors = 0;
  for (auto &t : info->info) init_one(&t);
  info->extra = nullptr;
  info->format = _NNS_TENSOR_FORMAT_STATIC;
}

void init_c(GstTensorsConfig *config) {
  init_c(&config->info);
  config->rate_n = -1;
  config->rate_d = -1;
}

void free_c(GstTensorsInfo *info) {
  for (auto &t : info->info) g_free(t.name);
  if (info->extra) {
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_EXTRA_LIMIT; ++i) g_free(info->extra[i].name);
    g_free(info->extra);
  }
  init_c(info);
}

void free_c(GstTensorsConfig *config) {
  free_c(&config->info);
  config->rate_n = -1;
  config->rate_d = -1;
}

GstTensorInfo *c_tensor_at(GstTensorsInfo *info, unsigned i) {
  if (i < NNS_TENSOR_MEMORY_MAX) return &info->info[i];
  if (i >= NNS_TENSOR_SIZE_LIMIT) return nullptr;
  if (!info->extra) {
    info->extra = g_new0(GstTensorInfo, NNS_TENSOR_SIZE_EXTRA_LIMIT);
    for (unsigned k = 0; k < NNS_TENSOR_SIZE_EXTRA_LIMIT; ++k) init_one(&info->extra[k]);
  }
  return &info->extra[i - NNS_TENSOR_MEMORY_MAX];
}

const GstTensorInfo *c_tensor_at(const GstTensorsInfo *info, unsigned i) {
  if (i < NNS_TENSOR_MEMORY_MAX) return &info->info[i];
  if (i >= NNS_TENSOR_SIZE_LIMIT || !info->extra) return nullptr;
  return &info->extra[i - NNS_TENSOR_MEMORY_MAX];
}

void to_c(const TensorsInfo &in, GstTensorsInfo *out) {
  if (in.size() > kTensorLimit)
    fail(ErrorKind::kSettings, std::to_string(in.size()) + " tensors exceed the limit of " +
                                   std::to_string(kTensorLimit));
  free_c(out);
  out->num_tensors = static_cast<unsigned>(in.size());
  out->format = static_cast<tensor_format>(in.format);
  for (unsigned i = 0; i < in.size(); ++i) {
    GstTensorInfo *t = c_tensor_at(out, i);
    t->name = in[i].name.empty() ? nullptr : g_strdup(in[i].name.c_str());
    t->type = static_cast<tensor_type>(in[i].type);
    for (std::size_t d = 0; d < kRankLimit; ++d) t->dimension[d] = in[i].dims[d];
  }
}

void to_c(const TensorsConfig &in, GstTensorsConfig *out) {
  to_c(in.info, &out->info);
  out->rate_n = in.rate_n;
  out->rate_d = in.rate_d;
}

TensorsInfo from_c(const GstTensorsInfo *in) {
  TensorsInfo out;
  if (static_cast<unsigned>(in->format) >= static_cast<unsigned>(_NNS_TENSOR_FORMAT_END))
    fail(ErrorKind::kStream,
         "tensors info format " + std::to_string(static_cast<int>(in->format)) + " is unknown");
  out.format = static_cast<TensorFormat>(in->format);
  if (in->num_tensors > kTensorLimit)
    fail(ErrorKind::kStream, "tensors info num_tensors=" + std::to_string(in->num_tensors) +
                                 " exceeds the limit of " + std::to_string(kTensorLimit));
  for (unsigned i = 0; i < in->num_tensors; ++i) {
    const GstTensorInfo *t = c_tensor_at(in, i);
    if (!t)
      fail(ErrorKind::kStream, "tensors info has num_tensors=" + std::to_string(in->num_tensors) +
                                   " but no 'extra' entries for tensor " + std::to_string(i));
    TensorInfo ti;
    if (t->name) ti.name = t->name;
    if (static_cast<unsigned>(t->type) > static_cast<unsigned>(_NNS_END))
      fail(ErrorKind::kStream, "tensor " + std::to_string(i) + " has unknown type value " +
                                   std::to_string(static_cast<int>(t->type)));
    ti.type = static_cast<TensorType>(t->type);
    for (std::size_t d = 0; d < kRankLimit; ++d) ti.dims[d] = t->dimension[d];
    // Entries after a 0 are not part of the rank.
    for (std::size_t d = rank_of(ti.dims); d < kRankLimit; ++d) ti.dims[d] = 0;
    out.tensors.push_back(std::move(ti));
  }
  return out;
}

TensorsConfig from_c(const GstTensorsConfig *in) {
  TensorsConfig out;
  out.info = from_c(&in->info);
  out.rate_n = in->rate_n;
  out.rate_d = in->rate_d;
  return out;
}

}  // namespace nns::gst

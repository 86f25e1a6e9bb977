// SPDX-License-Identifier: LGPL-2.1-only
#include "core/c_tensor_info.h"

#include <cstdlib>
#include <cstring>
#include <string>

#include "core/error.h"

namespace nns {
namespace {

static_assert(NNS_TENSOR_RANK_LIMIT == kRankLimit);
static_assert(NNS_TENSOR_SIZE_LIMIT == kTensorLimit);
static_assert(NNS_TENSOR_MEMORY_MAX == kMemoryMax);
static_assert(static_cast<int>(_NNS_END) == static_cast<int>(TensorType::kEnd));

// The stored value of an enum field that C code filled: it may be outside the enumerators,
// and loading such a value as the enum type is undefined behaviour in C++.
template <typename E>
int raw_value(const E &field) {
  static_assert(sizeof(E) == sizeof(int));
  int v;
  std::memcpy(&v, &field, sizeof v);
  return v;
}

// Entry `i` < NNS_TENSOR_SIZE_LIMIT, allocating the extra block when `i` needs it.
GstTensorInfo *entry_for_write(GstTensorsInfo *info, unsigned i) {
  if (i >= NNS_TENSOR_MEMORY_MAX && !info->extra) {
    info->extra = static_cast<GstTensorInfo *>(
        std::calloc(NNS_TENSOR_SIZE_EXTRA_LIMIT, sizeof(GstTensorInfo)));
    if (!info->extra) throw std::bad_alloc();
    for (unsigned k = 0; k < NNS_TENSOR_SIZE_EXTRA_LIMIT; ++k) info->extra[k].type = _NNS_END;
  }
  return gst_info_at(info, i);
}

}  // namespace

void gst_info_init(GstTensorsInfo *info) {
  std::memset(info, 0, sizeof(*info));
  for (auto &t : info->info) t.type = _NNS_END;
  info->format = _NNS_TENSOR_FORMAT_STATIC;
}

void gst_config_init(GstTensorsConfig *config) {
  gst_info_init(&config->info);
  config->rate_n = -1;
  config->rate_d = -1;
}

void gst_info_clear(GstTensorsInfo *info) {
  for (auto &t : info->info) std::free(t.name);
  if (info->extra) {
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_EXTRA_LIMIT; ++i) std::free(info->extra[i].name);
    std::free(info->extra);
  }
  gst_info_init(info);
}

void gst_config_clear(GstTensorsConfig *config) {
  gst_info_clear(&config->info);
  config->rate_n = -1;
  config->rate_d = -1;
}

GstTensorInfo *gst_info_at(GstTensorsInfo *info, unsigned i) {
  if (i < NNS_TENSOR_MEMORY_MAX) return &info->info[i];
  if (!info->extra || i >= NNS_TENSOR_SIZE_LIMIT) return nullptr;
  return &info->extra[i - NNS_TENSOR_MEMORY_MAX];
}

const GstTensorInfo *gst_info_at(const GstTensorsInfo *info, unsigned i) {
  return gst_info_at(const_cast<GstTensorsInfo *>(info), i);
}

void gst_info_from_desc(const nns_tensors_desc &desc, GstTensorsInfo *out) {
  gst_info_init(out);
  unsigned n = desc.num_tensors > NNS_TENSOR_SIZE_LIMIT ? NNS_TENSOR_SIZE_LIMIT : desc.num_tensors;
  out->num_tensors = n;
  out->format = static_cast<tensor_format>(desc.format);
  for (unsigned i = 0; i < n; ++i) {
    GstTensorInfo *t = entry_for_write(out, i);
    const nns_tensor_desc &s = desc.tensors[i];
    t->name = s.name[0] ? strndup(s.name, NNS_TENSOR_NAME_MAX) : nullptr;
    t->type = static_cast<tensor_type>(s.type);
    std::memcpy(t->dimension, s.dims, sizeof(t->dimension));
  }
}

void desc_from_gst_info(const GstTensorsInfo *info, nns_tensors_desc &out) {
  unsigned n =
      info->num_tensors > NNS_TENSOR_SIZE_LIMIT ? NNS_TENSOR_SIZE_LIMIT : info->num_tensors;
  out.num_tensors = n;
  out.format = static_cast<uint32_t>(raw_value(info->format));
  for (unsigned i = 0; i < n; ++i) {
    nns_tensor_desc &t = out.tensors[i];
    const GstTensorInfo *s = gst_info_at(info, i);
    if (!s) {
      out.num_tensors = i;
      break;
    }
    t.name[0] = '\0';
    if (s->name) {
      std::strncpy(t.name, s->name, NNS_TENSOR_NAME_MAX - 1);
      t.name[NNS_TENSOR_NAME_MAX - 1] = '\0';
    }
    t.type = static_cast<uint32_t>(raw_value(s->type));
    std::memcpy(t.dims, s->dimension, sizeof(t.dims));
  }
}

void to_c(const TensorsInfo &in, GstTensorsInfo *out) {
  if (in.size() > kTensorLimit)
    fail(ErrorKind::kSettings, std::to_string(in.size()) + " tensors exceed the limit of " +
                                   std::to_string(kTensorLimit));
  gst_info_clear(out);
  out->num_tensors = static_cast<unsigned>(in.size());
  out->format = static_cast<tensor_format>(in.format);
  for (unsigned i = 0; i < in.size(); ++i) {
    GstTensorInfo *t = entry_for_write(out, i);
    t->name = in[i].name.empty() ? nullptr : strdup(in[i].name.c_str());
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
  const int format = raw_value(in->format);
  if (static_cast<unsigned>(format) >= static_cast<unsigned>(_NNS_TENSOR_FORMAT_END))
    fail(ErrorKind::kStream, "tensors info format " + std::to_string(format) + " is unknown");
  out.format = static_cast<TensorFormat>(format);
  if (in->num_tensors > kTensorLimit)
    fail(ErrorKind::kStream, "tensors info num_tensors=" + std::to_string(in->num_tensors) +
                                 " exceeds the limit of " + std::to_string(kTensorLimit));
  for (unsigned i = 0; i < in->num_tensors; ++i) {
    const GstTensorInfo *t = gst_info_at(in, i);
    if (!t)
      fail(ErrorKind::kStream, "tensors info has num_tensors=" + std::to_string(in->num_tensors) +
                                   " but no 'extra' entries for tensor " + std::to_string(i));
    TensorInfo ti;
    if (t->name) ti.name = t->name;
    const int type = raw_value(t->type);
    if (static_cast<unsigned>(type) > static_cast<unsigned>(_NNS_END))
      fail(ErrorKind::kStream,
           "tensor " + std::to_string(i) + " has unknown type value " + std::to_string(type));
    ti.type = static_cast<TensorType>(type);
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

}  // namespace nns

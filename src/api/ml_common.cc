// SPDX-License-Identifier: LGPL-2.1-only
// ml_tensors_info_*, ml_tensors_data_*, ml_option_*, ml_error, ml_api_get_version: the common
// part of the ML API (ml_information_*: ml_information.cc).
#include <cstring>
#include <new>
#include <string>

#include "api/ml_api_internal.h"
#include "api/ml_handles.h"
#include "nnstreamer-tizen-internal.h"

// The nnstreamer/api release whose inference API (functions, codes, semantics) this follows.
#define NNS_ML_API_VERSION_MAJOR 1
#define NNS_ML_API_VERSION_MINOR 8
#define NNS_ML_API_VERSION_MICRO 8

namespace nns::api {
namespace {

thread_local std::string t_last_error;

std::size_t round_up(std::size_t n) {
  return (n + 63) / 64 * 64;
}

}  // namespace

int report(int code, const std::string &msg) {
  t_last_error = msg;
  return code;
}

void clear_error() {
  t_last_error.clear();
}

TensorsInfoHandle *as_info(ml_tensors_info_h h) {
  auto *p = static_cast<TensorsInfoHandle *>(h);
  return p && p->magic == kInfoMagic ? p : nullptr;
}

TensorsDataHandle *as_data(ml_tensors_data_h h) {
  auto *p = static_cast<TensorsDataHandle *>(h);
  return p && p->magic == kDataMagic ? p : nullptr;
}

OptionHandle *as_option(ml_option_h h) {
  auto *p = static_cast<OptionHandle *>(h);
  return p && p->magic == kOptionMagic ? p : nullptr;
}

bool needs_extended(const TensorsInfo &info) {
  for (const auto &t : info.tensors)
    if (t.dims[kRankLimitPrev] > 0) return true;
  return false;
}

int new_info_handle(const TensorsInfo &info, ml_tensors_info_h *out) {
  auto *p = new (std::nothrow) TensorsInfoHandle();
  if (!p) return report(ML_ERROR_OUT_OF_MEMORY, "out of memory");
  p->info = info;
  p->extended = needs_extended(info);
  *out = p;
  return ML_ERROR_NONE;
}

TensorsDataHandle *new_data(const TensorsInfo &info) {
  auto d = std::make_unique<TensorsDataHandle>();
  d->info = info;
  d->extended = needs_extended(info);
  for (const auto &t : info.tensors) {
    std::size_t n = t.byte_size();
    auto *buf = static_cast<uint8_t *>(std::aligned_alloc(64, round_up(n ? n : 1)));
    if (!buf) throw std::bad_alloc();
    std::memset(buf, 0, n);
    d->buffers.emplace_back(buf);
    d->sizes.push_back(n);
  }
  return d.release();
}

OptionHandle::~OptionHandle() {
  for (auto &[k, e] : entries)
    if (e.destroy) e.destroy(e.value);
}

}  // namespace nns::api

using namespace nns;
using namespace nns::api;

#define NNS_API extern "C" __attribute__((visibility("default")))

#define REQUIRE_INFO(var, h)                \
  TensorsInfoHandle *var = as_info(h);      \
  if (!var)                                 \
  return report(ML_ERROR_INVALID_PARAMETER, \
                std::string(__func__) + ": the tensors-info handle is NULL or invalid")

#define REQUIRE_INDEX(var, index)                                                   \
  if ((index) >= var->info.size())                                                  \
  return report(ML_ERROR_INVALID_PARAMETER, std::string(__func__) + ": index " +    \
                                                std::to_string(index) +             \
                                                " is out of range; the info has " + \
                                                std::to_string(var->info.size()) + " tensor(s)")

NNS_API const char *ml_error(void) {
  return t_last_error.empty() ? nullptr : t_last_error.c_str();
}

NNS_API void ml_api_get_version(unsigned int *major, unsigned int *minor, unsigned int *micro) {
  if (major) *major = NNS_ML_API_VERSION_MAJOR;
  if (minor) *minor = NNS_ML_API_VERSION_MINOR;
  if (micro) *micro = NNS_ML_API_VERSION_MICRO;
}

NNS_API char *ml_api_get_version_string(void) {
  std::string v = "Machine Learning API " + std::to_string(NNS_ML_API_VERSION_MAJOR) + "." +
                  std::to_string(NNS_ML_API_VERSION_MINOR) + "." +
                  std::to_string(NNS_ML_API_VERSION_MICRO);
  return strdup(v.c_str());
}

NNS_API const char *ml_strerror(int code) {
  switch (code) {
    case ML_ERROR_NONE:
      return "no error";
    case ML_ERROR_INVALID_PARAMETER:
      return "invalid parameter";
    case ML_ERROR_STREAMS_PIPE:
      return "cannot create or access the pipeline";
    case ML_ERROR_TRY_AGAIN:
      return "not ready yet, try again";
    case ML_ERROR_TIMED_OUT:
      return "timed out";
    case ML_ERROR_NOT_SUPPORTED:
      return "not supported";
    case ML_ERROR_PERMISSION_DENIED:
      return "permission denied";
    case ML_ERROR_OUT_OF_MEMORY:
      return "out of memory";
    case ML_ERROR_IO_ERROR:
      return "input/output error";
    case ML_ERROR_UNKNOWN:
      return "unknown error";
    default:
      return nullptr;
  }
}

NNS_API int ml_tensors_info_create(ml_tensors_info_h *info) {
  if (!info) return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_create: info is NULL");
  *info = new (std::nothrow) TensorsInfoHandle();
  return *info ? ML_ERROR_NONE : report(ML_ERROR_OUT_OF_MEMORY, "ml_tensors_info_create");
}

NNS_API int ml_tensors_info_create_extended(ml_tensors_info_h *info) {
  if (!info)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_create_extended: info is NULL");
  auto *p = new (std::nothrow) TensorsInfoHandle();
  if (!p) return report(ML_ERROR_OUT_OF_MEMORY, "ml_tensors_info_create_extended");
  p->extended = true;
  *info = p;
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_destroy(ml_tensors_info_h info) {
  REQUIRE_INFO(p, info);
  p->magic = 0;
  delete p;
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_validate(const ml_tensors_info_h info, bool *valid) {
  REQUIRE_INFO(p, info);
  if (!valid) return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_validate: valid is NULL");
  *valid = p->info.valid();
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_clone(ml_tensors_info_h dest, const ml_tensors_info_h src) {
  REQUIRE_INFO(d, dest);
  REQUIRE_INFO(s, src);
  if (!s->info.valid())
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_clone: src is not valid (" +
                                                  s->info.to_string() +
                                                  "); every tensor needs a type and a dimension");
  d->info = s->info;
  d->extended = s->extended;
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_set_count(ml_tensors_info_h info, unsigned int count) {
  REQUIRE_INFO(p, info);
  if (count == 0 || count > ML_TENSOR_SIZE_LIMIT)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_set_count: count " +
                                                  std::to_string(count) + " is outside 1.." +
                                                  std::to_string(ML_TENSOR_SIZE_LIMIT));
  p->info.tensors.resize(count);
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_get_count(ml_tensors_info_h info, unsigned int *count) {
  REQUIRE_INFO(p, info);
  if (!count) return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_get_count: count is NULL");
  *count = static_cast<unsigned>(p->info.size());
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_set_tensor_name(ml_tensors_info_h info, unsigned int index,
                                            const char *name) {
  REQUIRE_INFO(p, info);
  REQUIRE_INDEX(p, index);
  p->info[index].name = name ? name : "";
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_get_tensor_name(ml_tensors_info_h info, unsigned int index,
                                            char **name) {
  REQUIRE_INFO(p, info);
  REQUIRE_INDEX(p, index);
  if (!name)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_get_tensor_name: name is NULL");
  *name = p->info[index].name.empty() ? nullptr : strdup(p->info[index].name.c_str());
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_set_tensor_type(ml_tensors_info_h info, unsigned int index,
                                            const ml_tensor_type_e type) {
  REQUIRE_INFO(p, info);
  REQUIRE_INDEX(p, index);
  if (type < 0 || type >= ML_TENSOR_TYPE_UNKNOWN)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_set_tensor_type: type " +
                                                  std::to_string(type) + " is not a tensor type");
  p->info[index].type = static_cast<TensorType>(type);
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_get_tensor_type(ml_tensors_info_h info, unsigned int index,
                                            ml_tensor_type_e *type) {
  REQUIRE_INFO(p, info);
  REQUIRE_INDEX(p, index);
  if (!type)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_get_tensor_type: type is NULL");
  *type = p->info[index].type == TensorType::kEnd
              ? ML_TENSOR_TYPE_UNKNOWN
              : static_cast<ml_tensor_type_e>(p->info[index].type);
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_set_tensor_dimension(ml_tensors_info_h info, unsigned int index,
                                                 const ml_tensor_dimension dimension) {
  REQUIRE_INFO(p, info);
  REQUIRE_INDEX(p, index);
  if (!dimension)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_tensors_info_set_tensor_dimension: dimension is NULL");
  // A handle from ml_tensors_info_create reads 4 entries only: applications written for the
  // old rank limit leave the rest uninitialised.
  const std::size_t limit = p->extended ? kRankLimit : kRankLimitPrev;
  if (dimension[0] == 0)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_tensors_info_set_tensor_dimension: dimension[0] is 0; a tensor has at "
                  "least one dimension");
  Dims d{};
  bool ended = false;
  for (std::size_t i = 0; i < limit; ++i) {
    if (dimension[i] == 0)
      ended = true;
    else if (ended)
      return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_set_tensor_dimension: dimension[" +
                                                    std::to_string(i) + "] is " +
                                                    std::to_string(dimension[i]) + " after a 0");
    d[i] = dimension[i];
  }
  p->info[index].dims = d;
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_get_tensor_dimension(ml_tensors_info_h info, unsigned int index,
                                                 ml_tensor_dimension dimension) {
  REQUIRE_INFO(p, info);
  REQUIRE_INDEX(p, index);
  if (!dimension)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_tensors_info_get_tensor_dimension: dimension is NULL");
  const std::size_t limit = p->extended ? kRankLimit : kRankLimitPrev;
  for (std::size_t i = 0; i < kRankLimit; ++i)
    dimension[i] = i < limit ? p->info[index].dims[i] : 0;
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_info_get_tensor_size(ml_tensors_info_h info, int index, size_t *data_size) {
  REQUIRE_INFO(p, info);
  if (!data_size)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_info_get_tensor_size: data_size is NULL");
  *data_size = 0;
  if (index < 0) {
    *data_size = p->info.total_bytes();
    return ML_ERROR_NONE;
  }
  REQUIRE_INDEX(p, static_cast<unsigned>(index));
  *data_size = p->info[index].byte_size();
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_data_create(const ml_tensors_info_h info, ml_tensors_data_h *data) {
  REQUIRE_INFO(p, info);
  if (!data) return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_create: data is NULL");
  if (!p->info.valid())
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_tensors_data_create: the info is not valid (" + p->info.to_string() + ")");
  try {
    *data = new_data(p->info);
  } catch (const std::bad_alloc &) {
    return report(ML_ERROR_OUT_OF_MEMORY, "ml_tensors_data_create: out of memory");
  }
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_data_destroy(ml_tensors_data_h data) {
  TensorsDataHandle *d = as_data(data);
  if (!d) return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_destroy: invalid handle");
  d->magic = 0;
  delete d;
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_data_get_tensor_data(ml_tensors_data_h data, unsigned int index,
                                            void **raw_data, size_t *data_size) {
  TensorsDataHandle *d = as_data(data);
  if (!d || !raw_data || !data_size)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_get_tensor_data: NULL argument");
  if (index >= d->buffers.size())
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_get_tensor_data: index " +
                                                  std::to_string(index) + " is out of range (" +
                                                  std::to_string(d->buffers.size()) + " tensors)");
  *raw_data = d->buffers[index].get();
  *data_size = d->sizes[index];
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_data_set_tensor_data(ml_tensors_data_h data, unsigned int index,
                                            const void *raw_data, const size_t data_size) {
  TensorsDataHandle *d = as_data(data);
  if (!d || !raw_data)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_set_tensor_data: NULL argument");
  if (index >= d->buffers.size())
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_set_tensor_data: index " +
                                                  std::to_string(index) + " is out of range (" +
                                                  std::to_string(d->buffers.size()) + " tensors)");
  if (data_size == 0 || data_size > d->sizes[index])
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_tensors_data_set_tensor_data: tensor " + std::to_string(index) + " holds " +
                      std::to_string(d->sizes[index]) + " bytes, got " + std::to_string(data_size));
  if (d->buffers[index].get() != raw_data)
    std::memcpy(d->buffers[index].get(), raw_data, data_size);
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_data_get_info(const ml_tensors_data_h data, ml_tensors_info_h *info) {
  TensorsDataHandle *d = as_data(data);
  if (!d || !info)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_get_info: NULL argument");
  auto *h = new (std::nothrow) TensorsInfoHandle();
  if (!h) return report(ML_ERROR_OUT_OF_MEMORY, "ml_tensors_data_get_info");
  h->info = d->info;
  h->extended = d->extended;
  *info = h;
  return ML_ERROR_NONE;
}

NNS_API int ml_tensors_data_clone(const ml_tensors_data_h in, ml_tensors_data_h *out) {
  TensorsDataHandle *d = as_data(in);
  if (!d) return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_clone: in is NULL or invalid");
  if (!out) return report(ML_ERROR_INVALID_PARAMETER, "ml_tensors_data_clone: out is NULL");
  auto c = std::make_unique<TensorsDataHandle>();
  try {
    c->info = d->info;
    c->extended = d->extended;
    for (std::size_t i = 0; i < d->buffers.size(); ++i) {
      std::size_t n = d->sizes[i];
      auto *buf = static_cast<uint8_t *>(std::aligned_alloc(64, round_up(n ? n : 1)));
      if (!buf) throw std::bad_alloc();
      c->buffers.emplace_back(buf);
      std::memcpy(buf, d->buffers[i].get(), n);
      c->sizes.push_back(n);
    }
  } catch (const std::bad_alloc &) {
    return report(ML_ERROR_OUT_OF_MEMORY, "ml_tensors_data_clone: out of memory");
  }
  *out = c.release();
  return ML_ERROR_NONE;
}

NNS_API int nns_ml_tensors_data_wrap(const ml_tensors_info_h info, void *const *ptrs,
                                     unsigned int count, ml_tensors_data_h *data) {
  REQUIRE_INFO(p, info);
  if (!data || !ptrs)
    return report(ML_ERROR_INVALID_PARAMETER, "nns_ml_tensors_data_wrap: NULL argument");
  if (!p->info.valid() || count != p->info.size())
    return report(ML_ERROR_INVALID_PARAMETER, "nns_ml_tensors_data_wrap: " + std::to_string(count) +
                                                  " buffers for the info " + p->info.to_string());
  try {
    auto d = std::make_unique<TensorsDataHandle>();
    d->info = p->info;
    d->extended = p->extended;
    for (unsigned i = 0; i < count; ++i) {
      if (!ptrs[i])
        return report(ML_ERROR_INVALID_PARAMETER,
                      "nns_ml_tensors_data_wrap: buffer " + std::to_string(i) + " is NULL");
      d->buffers.emplace_back(static_cast<uint8_t *>(ptrs[i]), TensorsDataHandle::Free{false});
      d->sizes.push_back(p->info[i].byte_size());
    }
    *data = d.release();
  } catch (const std::bad_alloc &) {
    return report(ML_ERROR_OUT_OF_MEMORY, "nns_ml_tensors_data_wrap: out of memory");
  }
  return ML_ERROR_NONE;
}

NNS_API int _ml_tensors_info_compare(const ml_tensors_info_h info1, const ml_tensors_info_h info2,
                                     bool *equal) {
  REQUIRE_INFO(a, info1);
  REQUIRE_INFO(b, info2);
  if (!equal) return report(ML_ERROR_INVALID_PARAMETER, "_ml_tensors_info_compare: equal is NULL");
  *equal = a->info.size() == b->info.size() && a->info.same_as(b->info);
  return ML_ERROR_NONE;
}

NNS_API int ml_option_create(ml_option_h *option) {
  if (!option) return report(ML_ERROR_INVALID_PARAMETER, "ml_option_create: option is NULL");
  *option = new (std::nothrow) OptionHandle();
  return *option ? ML_ERROR_NONE : report(ML_ERROR_OUT_OF_MEMORY, "ml_option_create");
}

NNS_API int ml_option_destroy(ml_option_h option) {
  OptionHandle *o = as_option(option);
  if (!o) return report(ML_ERROR_INVALID_PARAMETER, "ml_option_destroy: invalid handle");
  o->magic = 0;
  delete o;
  return ML_ERROR_NONE;
}

NNS_API int ml_option_set(ml_option_h option, const char *key, void *value,
                          ml_data_destroy_cb destroy) {
  OptionHandle *o = as_option(option);
  if (!o) return report(ML_ERROR_INVALID_PARAMETER, "ml_option_set: option is NULL or invalid");
  if (!key || !*key)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_option_set: key is NULL or empty");
  if (!value) return report(ML_ERROR_INVALID_PARAMETER, "ml_option_set: value is NULL");
  auto &e = o->entries[key];
  if (e.destroy && e.value != value) e.destroy(e.value);
  e.value = value;
  e.destroy = destroy;
  return ML_ERROR_NONE;
}

NNS_API int ml_option_get(ml_option_h option, const char *key, void **value) {
  OptionHandle *o = as_option(option);
  if (!o || !key || !value)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_option_get: NULL argument");
  auto it = o->entries.find(key);
  if (it == o->entries.end())
    return report(ML_ERROR_INVALID_PARAMETER,
                  std::string("ml_option_get: no value for key '") + key + "'");
  *value = it->second.value;
  return ML_ERROR_NONE;
}

// SPDX-License-Identifier: LGPL-2.1-only
// ml_information_* and ml_information_list_*: read-only key-value tables the library hands to
// applications, and the internal calls (_ml_information_create/_set, _list_create/_add) that
// fill them. An information is an option table with its own magic.
#include <new>
#include <string>

#include "api/ml_api_internal.h"
#include "api/ml_handles.h"

namespace nns::api {

InformationHandle *as_information(ml_information_h h) {
  auto *p = static_cast<InformationHandle *>(h);
  return p && p->magic == kInformationMagic ? p : nullptr;
}

namespace {

InformationListHandle *as_list(ml_information_list_h h) {
  auto *p = static_cast<InformationListHandle *>(h);
  return p && p->magic == kInfoListMagic ? p : nullptr;
}

}  // namespace

InformationListHandle::~InformationListHandle() {
  for (OptionHandle *o : items) {
    o->magic = 0;
    delete o;
  }
}

}  // namespace nns::api

using namespace nns::api;

#define NNS_API extern "C" __attribute__((visibility("default")))

NNS_API int _ml_information_create(ml_information_h *ml_info) {
  if (!ml_info)
    return report(ML_ERROR_INVALID_PARAMETER, "_ml_information_create: ml_info is NULL");
  auto *p = new (std::nothrow) InformationHandle();
  if (!p) return report(ML_ERROR_OUT_OF_MEMORY, "_ml_information_create: out of memory");
  p->magic = kInformationMagic;
  *ml_info = p;
  return ML_ERROR_NONE;
}

NNS_API int _ml_information_set(ml_information_h ml_info, const char *key, void *value,
                                ml_data_destroy_cb destroy) {
  InformationHandle *p = as_information(ml_info);
  if (!p)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "_ml_information_set: ml_info is NULL or not an ml_information_h");
  if (!key || !*key)
    return report(ML_ERROR_INVALID_PARAMETER, "_ml_information_set: key is NULL or empty");
  if (!value) return report(ML_ERROR_INVALID_PARAMETER, "_ml_information_set: value is NULL");
  auto &e = p->entries[key];
  if (e.destroy && e.value != value) e.destroy(e.value);
  e.value = value;
  e.destroy = destroy;
  return ML_ERROR_NONE;
}

NNS_API int ml_information_destroy(ml_information_h ml_info) {
  InformationHandle *p = as_information(ml_info);
  if (!p)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_information_destroy: ml_info is NULL or not an ml_information_h");
  p->magic = 0;
  delete p;
  return ML_ERROR_NONE;
}

NNS_API int ml_information_get(ml_information_h ml_info, const char *key, void **value) {
  InformationHandle *p = as_information(ml_info);
  if (!p)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_information_get: ml_info is NULL or not an ml_information_h");
  if (!key) return report(ML_ERROR_INVALID_PARAMETER, "ml_information_get: key is NULL");
  if (!value) return report(ML_ERROR_INVALID_PARAMETER, "ml_information_get: value is NULL");
  auto it = p->entries.find(key);
  if (it == p->entries.end())
    return report(ML_ERROR_INVALID_PARAMETER,
                  std::string("ml_information_get: no value for key '") + key + "'");
  *value = it->second.value;
  return ML_ERROR_NONE;
}

NNS_API int ml_information_iterate(ml_information_h ml_info, ml_information_iterate_cb cb,
                                   void *user_data) {
  InformationHandle *p = as_information(ml_info);
  if (!p)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_information_iterate: ml_info is NULL or not an ml_information_h");
  if (!cb) return report(ML_ERROR_INVALID_PARAMETER, "ml_information_iterate: cb is NULL");
  for (const auto &[k, e] : p->entries) cb(k.c_str(), e.value, user_data);
  return ML_ERROR_NONE;
}

NNS_API int _ml_information_list_create(ml_information_list_h *list) {
  if (!list) return report(ML_ERROR_INVALID_PARAMETER, "_ml_information_list_create: list is NULL");
  *list = new (std::nothrow) InformationListHandle();
  return *list ? ML_ERROR_NONE
               : report(ML_ERROR_OUT_OF_MEMORY, "_ml_information_list_create: out of memory");
}

NNS_API int _ml_information_list_add(ml_information_list_h list, ml_information_h ml_info) {
  InformationListHandle *l = as_list(list);
  if (!l)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "_ml_information_list_add: list is NULL or not an ml_information_list_h");
  auto *p = static_cast<OptionHandle *>(ml_info);
  if (!as_information(ml_info) && !as_option(ml_info))
    return report(ML_ERROR_INVALID_PARAMETER,
                  "_ml_information_list_add: ml_info is NULL or not an ml_information_h");
  try {
    l->items.push_back(p);
  } catch (const std::bad_alloc &) {
    return report(ML_ERROR_OUT_OF_MEMORY, "_ml_information_list_add: out of memory");
  }
  return ML_ERROR_NONE;
}

NNS_API int ml_information_list_destroy(ml_information_list_h list) {
  InformationListHandle *l = as_list(list);
  if (!l)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_information_list_destroy: list is NULL or not an ml_information_list_h");
  l->magic = 0;
  delete l;
  return ML_ERROR_NONE;
}

NNS_API int ml_information_list_length(ml_information_list_h list, unsigned int *length) {
  InformationListHandle *l = as_list(list);
  if (!l)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_information_list_length: list is NULL or not an ml_information_list_h");
  if (!length)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_information_list_length: length is NULL");
  *length = static_cast<unsigned>(l->items.size());
  return ML_ERROR_NONE;
}

NNS_API int ml_information_list_get(ml_information_list_h list, unsigned int index,
                                    ml_information_h *ml_info) {
  InformationListHandle *l = as_list(list);
  if (!l)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_information_list_get: list is NULL or not an ml_information_list_h");
  if (!ml_info)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_information_list_get: ml_info is NULL");
  if (index >= l->items.size()) {
    *ml_info = nullptr;
    return report(ML_ERROR_INVALID_PARAMETER, "ml_information_list_get: index " +
                                                  std::to_string(index) +
                                                  " is out of range; the list has " +
                                                  std::to_string(l->items.size()) + " item(s)");
  }
  *ml_info = l->items[index];
  return ML_ERROR_NONE;
}

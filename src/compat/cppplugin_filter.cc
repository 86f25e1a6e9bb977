// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer::tensor_filter_subplugin (nnstreamer_cppplugin_api_filter.hh): NNStreamer 2.x's
// base class of C++ filter sub-plugins. Each object carries a version-1 table whose callbacks
// (the static cpp_* functions) find the object again from private_data; the registered
// "representative" object answers getFrameworkInfo before open and makes one object per model
// in open. Nothing thrown by a sub-plugin crosses into the C callers.
#include <errno.h>
#include <glib.h>

#include <cstdint>
#include <cstring>
#include <new>
#include <stdexcept>
#include <system_error>
#include <type_traits>

// The table's version-1 members are named (fwdesc.v1.*) here, so the template below is a
// constant initialiser.
#define NO_ANONYMOUS_NESTED_STRUCT
#include "nnstreamer_plugin_api_filter.h"
#undef NO_ANONYMOUS_NESTED_STRUCT

// The class is part of the 2.x ABI: everything it declares is exported, also from objects built
// with -fvisibility=hidden (the vtable and typeinfo included).
#pragma GCC visibility push(default)
#include "nnstreamer_cppplugin_api_filter.hh"
#pragma GCC visibility pop

namespace nnstreamer {

namespace {

// Marks a live tensor_filter_subplugin (NNStreamer's value, so objects are recognised alike).
constexpr uint64_t kSanity = 0xFACE217714DEADE7ULL;

// The registered representative of the framework the host opens.
tensor_filter_subplugin *representative_of(const GstTensorFilterFramework *tf) {
  if (!tf || !checkGstTensorFilterFrameworkVersion(tf->version, 1)) return nullptr;
  return static_cast<tensor_filter_subplugin *>(tf->v1.subplugin_data);
}

}  // namespace

static_assert(sizeof(void *) != 8 || sizeof(GstTensorFilterFramework) == 128,
              "GstTensorFilterFramework must have NNStreamer's size");

tensor_filter_subplugin *tensor_filter_subplugin::get_tfsp_with_checks(void *ptr) {
  // The sanity word is read as bytes (it follows the vtable pointer) before the pointer is
  // used as an object: a caller may hand anything here.
  uint64_t word = 0;
  if (ptr) std::memcpy(&word, static_cast<const char *>(ptr) + sizeof(void *), sizeof word);
  if (word != kSanity) throw std::invalid_argument("not an opened tensor_filter_subplugin");
  auto *t = static_cast<tensor_filter_subplugin *>(ptr);
  // An opened object: sanity set, and not a representative (whose subplugin_data is itself).
  if (t->sanity != kSanity || t->fwdesc.v1.subplugin_data != nullptr)
    throw std::invalid_argument("not an opened tensor_filter_subplugin");
  return t;
}

int tensor_filter_subplugin::cpp_open(const GstTensorFilterProperties *prop, void **private_data) {
  if (!prop || !private_data) return -EINVAL;
  tensor_filter_subplugin *sp = representative_of(nnstreamer_filter_find(prop->fwname));
  if (!sp || sp->sanity != kSanity) {
    g_critical("C++ filter sub-plugin '%s' is not registered", prop->fwname ? prop->fwname : "");
    return -EINVAL;
  }
  tensor_filter_subplugin *obj = nullptr;
  try {
    obj = &sp->getEmptyInstance();
    obj->configure_instance(prop);
  } catch (const std::invalid_argument &e) {
    g_critical("%s", e.what());
    delete obj;
    return -EINVAL;
  } catch (const std::system_error &e) {
    g_critical("%s", e.what());
    delete obj;
    int code = e.code().value();
    return code > 0 ? -code : (code < 0 ? code : -1);
  } catch (const std::exception &e) {
    g_critical("%s", e.what());
    delete obj;
    return -1;
  } catch (...) {
    delete obj;
    return -1;
  }
  obj->fwdesc.v1.subplugin_data = nullptr;  // an opened object, not a representative
  *private_data = obj;
  return 0;
}

void tensor_filter_subplugin::cpp_close(const GstTensorFilterProperties *, void **private_data) {
  if (!private_data) return;
  try {
    delete get_tfsp_with_checks(*private_data);
  } catch (...) {
    return;  // not ours, or a destructor that threw
  }
  *private_data = nullptr;
}

int tensor_filter_subplugin::cpp_invoke(const GstTensorFilterFramework *,
                                        GstTensorFilterProperties *prop, void *private_data,
                                        const GstTensorMemory *input, GstTensorMemory *output) {
  try {
    tensor_filter_subplugin *obj = get_tfsp_with_checks(private_data);
    if (prop && prop->invoke_dynamic)
      obj->invoke_dynamic(prop, input, output);
    else
      obj->invoke(input, output);
  } catch (const std::system_error &e) {
    g_critical("%s", e.what());
    int code = e.code().value();
    return code > 0 ? -code : (code < 0 ? code : -EINVAL);
  } catch (const std::exception &e) {
    g_critical("%s", e.what());
    return -EINVAL;
  } catch (...) {
    return -EINVAL;
  }
  return 0;
}

int tensor_filter_subplugin::cpp_getFrameworkInfo(const GstTensorFilterFramework *tf,
                                                  const GstTensorFilterProperties *prop,
                                                  void *private_data,
                                                  GstTensorFilterFrameworkInfo *fw_info) {
  if (!fw_info) return -EINVAL;
  try {
    tensor_filter_subplugin *obj;
    if (private_data) {
      obj = get_tfsp_with_checks(private_data);
    } else {  // before open: ask the representative
      if (!tf && prop) tf = nnstreamer_filter_find(prop->fwname);
      obj = representative_of(tf);
      if (!obj || obj->sanity != kSanity) return -EINVAL;
    }
    obj->getFrameworkInfo(*fw_info);
  } catch (...) {
    return -EINVAL;
  }
  return 0;
}

int tensor_filter_subplugin::cpp_getModelInfo(const GstTensorFilterFramework *,
                                              const GstTensorFilterProperties *, void *private_data,
                                              model_info_ops ops, GstTensorsInfo *in_info,
                                              GstTensorsInfo *out_info) {
  if (!in_info || !out_info) return -EINVAL;
  try {
    return get_tfsp_with_checks(private_data)->getModelInfo(ops, *in_info, *out_info);
  } catch (...) {
    return -EINVAL;
  }
}

int tensor_filter_subplugin::cpp_eventHandler(const GstTensorFilterFramework *,
                                              const GstTensorFilterProperties *, void *private_data,
                                              event_ops ops,
                                              GstTensorFilterFrameworkEventData *data) {
  // Events without data (SUSPEND, RESUME) still hand the sub-plugin a valid reference.
  GstTensorFilterFrameworkEventData none;
  std::memset(&none, 0, sizeof none);
  try {
    return get_tfsp_with_checks(private_data)->eventHandler(ops, data ? *data : none);
  } catch (...) {
    return -EINVAL;
  }
}

constinit const GstTensorFilterFramework tensor_filter_subplugin::fwdesc_template = {
    .version = GST_TENSOR_FILTER_FRAMEWORK_V1,
    .open = cpp_open,
    .close = cpp_close,
    .v1 = {.invoke = cpp_invoke,
           .getFrameworkInfo = cpp_getFrameworkInfo,
           .getModelInfo = cpp_getModelInfo,
           .eventHandler = cpp_eventHandler,
           .subplugin_data = nullptr},
};

tensor_filter_subplugin::tensor_filter_subplugin() : sanity(kSanity) {
  std::memcpy(&fwdesc, &fwdesc_template, sizeof fwdesc_template);
}

tensor_filter_subplugin::~tensor_filter_subplugin() = default;

int tensor_filter_subplugin::eventHandler(event_ops, GstTensorFilterFrameworkEventData &) {
  return -ENOENT;
}

}  // namespace nnstreamer

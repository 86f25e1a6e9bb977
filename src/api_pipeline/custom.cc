// SPDX-License-Identifier: LGPL-2.1-only
// ml_pipeline_custom_easy_filter_*, ml_pipeline_tensor_if_custom_* and the availability checks.
//
// custom-easy models and tensor_if conditions live in registries of the nnstreamer plugin
// (NNS_custom_easy_register, nnstreamer_if_custom_register). This library does not contain the
// elements: it looks those two entry points up in the loaded plugin module (or, when the
// plugin was registered statically into the executable, in the process), so the registrations
// reach the tensor_filter and tensor_if instances that pipelines actually use.
#include <dlfcn.h>

#include <map>

#include "api_pipeline/pipeline_internal.h"
#include "core/c_tensor_info.h"
#include "core/filter_registry.h"
#include "tensor_filter_custom_easy.h"
#include "tensor_if.h"

namespace nns::capi {
namespace {

using EasyRegisterFn = int (*)(const char *, NNS_custom_invoke, void *, const GstTensorsInfo *,
                               const GstTensorsInfo *);
using EasyUnregisterFn = int (*)(const char *);
using IfRegisterFn = int (*)(const gchar *, tensor_if_custom, void *);
using IfUnregisterFn = int (*)(const gchar *);

// Symbol `name` of the nnstreamer plugin; nullptr with `why` set when it cannot be found.
void *plugin_symbol(const char *name, std::string *why) {
  static std::once_flag once;
  static void *module = nullptr;
  static std::string module_error;
  std::call_once(once, [] {
    GstPlugin *pl = gst_plugin_load_by_name("nnstreamer");
    if (!pl) {
      module_error = "the GStreamer plugin 'nnstreamer' is not installed or not on GST_PLUGIN_PATH";
      return;
    }
    if (const gchar *file = gst_plugin_get_filename(pl)) {
      module = dlopen(file, RTLD_NOW | RTLD_NOLOAD);
      if (!module) module_error = std::string("cannot reach the plugin module ") + file;
    }
    gst_object_unref(pl);
  });
  void *sym = module ? dlsym(module, name) : dlsym(RTLD_DEFAULT, name);
  if (!sym)
    *why = module_error.empty() ? std::string("the nnstreamer plugin does not export ") + name
                                : module_error;
  return sym;
}

struct EasyEntry {
  std::string name;
  ml_custom_easy_invoke_cb cb = nullptr;
  void *user = nullptr;
  api::TensorsInfoHandle in, out;
  int refs = 0;  // pipelines using it (g_custom_mu)
  std::mutex call_mu;
};

struct IfEntry {
  std::string name;
  ml_pipeline_if_custom_cb cb = nullptr;
  void *user = nullptr;
  int refs = 0;
  std::mutex call_mu;
};

std::mutex g_custom_mu;
std::map<std::string, EasyEntry *> g_easy;
std::map<std::string, IfEntry *> g_if;

// Data handle over memories owned by someone else (released before it is destroyed).
struct Borrowed {
  api::TensorsDataHandle d;
  Borrowed(const TensorsInfo &info, const GstTensorMemory *mem) {
    d.info = info;
    d.buffers.resize(info.size());
    d.sizes.resize(info.size());
    for (std::size_t i = 0; i < info.size(); ++i) {
      d.buffers[i].reset(static_cast<uint8_t *>(mem[i].data));
      d.sizes[i] = mem[i].size;
    }
  }
  ~Borrowed() {
    for (auto &b : d.buffers) (void)b.release();
  }
};

int easy_invoke(void *data, const GstTensorFilterProperties *, const GstTensorMemory *in,
                GstTensorMemory *out) {
  auto *e = static_cast<EasyEntry *>(data);
  Borrowed bi(e->in.info, in);
  Borrowed bo(e->out.info, out);
  std::lock_guard lk(e->call_mu);
  return e->cb(&bi.d, &bo.d, e->user);
}

gboolean if_invoke(const GstTensorsInfo *info, const GstTensorMemory *input, void *data,
                   gboolean *result) {
  auto *e = static_cast<IfEntry *>(data);
  api::TensorsInfoHandle ih;
  try {
    fill_info_handle(ih, from_c(info));
  } catch (const std::exception &ex) {
    GST_CAT_WARNING(capi_debug, "tensor_if custom '%s': %s", e->name.c_str(), ex.what());
    return FALSE;
  }
  Borrowed bi(ih.info, input);
  int r = 0;
  int rc;
  {
    std::lock_guard lk(e->call_mu);
    rc = e->cb(&bi.d, &ih, &r, e->user);
  }
  if (rc != 0) {
    GST_CAT_WARNING(capi_debug, "tensor_if custom '%s' returned %d", e->name.c_str(), rc);
    return FALSE;
  }
  *result = r != 0;
  return TRUE;
}

const char *nnfw_subplugin(ml_nnfw_type_e nnfw) {
  switch (nnfw) {
    case ML_NNFW_TYPE_CUSTOM_FILTER:
      return "custom";
    case ML_NNFW_TYPE_TENSORFLOW_LITE:
      return "tensorflow-lite";
    case ML_NNFW_TYPE_TENSORFLOW:
      return "tensorflow";
    case ML_NNFW_TYPE_NNFW:
      return "nnfw";
    case ML_NNFW_TYPE_MVNC:
      return "movidius-ncsdk2";
    case ML_NNFW_TYPE_OPENVINO:
      return "openvino";
    case ML_NNFW_TYPE_VIVANTE:
      return "vivante";
    case ML_NNFW_TYPE_EDGE_TPU:
      return "edgetpu";
    case ML_NNFW_TYPE_ARMNN:
      return "armnn";
    case ML_NNFW_TYPE_SNPE:
      return "snpe";
    case ML_NNFW_TYPE_PYTORCH:
      return "pytorch";
    case ML_NNFW_TYPE_NNTR_INF:
      return "nntrainer";
    case ML_NNFW_TYPE_VD_AIFW:
      return "vd_aifw";
    case ML_NNFW_TYPE_TRIX_ENGINE:
      return "trix-engine";
    case ML_NNFW_TYPE_MXNET:
      return "mxnet";
    case ML_NNFW_TYPE_TVM:
      return "tvm";
    case ML_NNFW_TYPE_ONNX_RUNTIME:
      return "onnxruntime";
    case ML_NNFW_TYPE_NCNN:
      return "ncnn";
    case ML_NNFW_TYPE_TENSORRT:
      return "tensorrt";
    case ML_NNFW_TYPE_QNN:
      return "qnn";
    case ML_NNFW_TYPE_LLAMACPP:
      return "llamacpp";
    case ML_NNFW_TYPE_TIZEN_HAL:
      return "tizen-hal";
    case ML_NNFW_TYPE_SNAP:
      return "snap";
    case ML_NNFW_TYPE_ANY:
      return "";
  }
  return nullptr;
}

// tensor_filter accelerator= name of `hw` ("" for ANY/AUTO: no hardware check), nullptr when
// `hw` is not an ml_nnfw_hw_e value. 0x1nnn, 0x2nnn, 0x3nnn: a numbered CPU, GPU or NPU.
const char *accelerator_name(ml_nnfw_hw_e hw) {
  switch (hw) {
    case ML_NNFW_HW_ANY:
    case ML_NNFW_HW_AUTO:
      return "";
    case ML_NNFW_HW_CPU:
      return "cpu";
    case ML_NNFW_HW_CPU_SIMD:
      return "cpu.simd";
    case ML_NNFW_HW_GPU:
      return "gpu";
    case ML_NNFW_HW_NPU:
      return "npu";
    case ML_NNFW_HW_NPU_MOVIDIUS:
      return "npu.movidius";
    case ML_NNFW_HW_NPU_EDGE_TPU:
      return "npu.edgetpu";
    case ML_NNFW_HW_NPU_VIVANTE:
      return "npu.vivante";
    case ML_NNFW_HW_NPU_SLSI:
      return "npu.slsi";
    case ML_NNFW_HW_NPU_SR:
      return "npu.sr";
  }
  int h = static_cast<int>(hw);
  if (h > 0x1000 && h < 0x1100) return "cpu";
  if (h > 0x2000 && h < 0x3000) return "gpu";
  if (h > 0x3000 && h < 0x4000) return "npu";
  return nullptr;
}

}  // namespace

void custom_easy_ref(const std::string &name, int delta) {
  std::lock_guard lk(g_custom_mu);
  auto it = g_easy.find(name);
  if (it != g_easy.end()) it->second->refs += delta;
}

bool custom_easy_known(const std::string &name) {
  std::lock_guard lk(g_custom_mu);
  return g_easy.count(name) > 0;
}

void if_custom_ref(const std::string &name, int delta) {
  std::lock_guard lk(g_custom_mu);
  auto it = g_if.find(name);
  if (it != g_if.end()) it->second->refs += delta;
}

bool if_custom_known(const std::string &name) {
  std::lock_guard lk(g_custom_mu);
  return g_if.count(name) > 0;
}

}  // namespace nns::capi

using namespace nns;
using namespace nns::capi;

NNS_CAPI int ml_pipeline_custom_easy_filter_register(const char *name, const ml_tensors_info_h in,
                                                     const ml_tensors_info_h out,
                                                     ml_custom_easy_invoke_cb cb, void *user_data,
                                                     ml_custom_easy_filter_h *custom) {
  constexpr const char *F = "ml_pipeline_custom_easy_filter_register";
  if (!custom) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": custom is NULL");
  *custom = nullptr;
  if (!name || !*name)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": name is NULL or empty");
  if (!cb) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": cb is NULL");
  api::TensorsInfoHandle *ii = api::as_info(in), *oi = api::as_info(out);
  if (!ii || !ii->info.valid() || ii->info.size() == 0)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) +
                    ": in is not a valid tensors-info (every tensor needs a type and dimensions)");
  if (!oi || !oi->info.valid() || oi->info.size() == 0)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) +
                    ": out is not a valid tensors-info (every tensor needs a type and dimensions)");
  if (int rc = ensure_gst(F); rc != ML_ERROR_NONE) return rc;
  std::string why;
  auto reg = reinterpret_cast<EasyRegisterFn>(plugin_symbol("NNS_custom_easy_register", &why));
  if (!reg) return fail(ML_ERROR_NOT_SUPPORTED, std::string(F) + ": " + why);

  auto *e = new EasyEntry();
  e->name = name;
  e->cb = cb;
  e->user = user_data;
  e->in = *ii;
  e->out = *oi;
  CTensorsConfig cin, cout;
  int rc;
  try {
    to_c(ii->info, &cin.get()->info);
    to_c(oi->info, &cout.get()->info);
    std::lock_guard lk(g_custom_mu);
    rc = reg(name, easy_invoke, e, &cin.get()->info, &cout.get()->info);
    if (rc == 0) g_easy[name] = e;
  } catch (const std::exception &ex) {
    delete e;
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": " + ex.what());
  }
  if (rc != 0) {
    delete e;
    if (rc == -EEXIST || rc == -EINVAL)
      return fail(
          ML_ERROR_INVALID_PARAMETER,
          std::string(F) + ": " +
              (rc == -EEXIST
                   ? "a custom-easy filter named '" + std::string(name) + "' is already registered"
                   : "the plugin refused '" + std::string(name) + "' (invalid tensors-info)"));
    if (rc == -ENOMEM) return fail(ML_ERROR_OUT_OF_MEMORY, std::string(F) + ": out of memory");
    return fail(ML_ERROR_UNKNOWN,
                std::string(F) + ": NNS_custom_easy_register returned " + std::to_string(rc));
  }
  *custom = e;
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_custom_easy_filter_unregister(ml_custom_easy_filter_h custom) {
  constexpr const char *F = "ml_pipeline_custom_easy_filter_unregister";
  if (!custom) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": custom is NULL");
  std::lock_guard lk(g_custom_mu);
  EasyEntry *e = nullptr;
  for (auto &[n, x] : g_easy)
    if (x == custom) e = x;
  if (!e)
    return fail(
        ML_ERROR_INVALID_PARAMETER,
        std::string(F) +
            ": custom is not a registered custom-easy filter handle (already unregistered?)");
  if (e->refs > 0)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": custom-easy filter '" + e->name +
                                                "' is used by " + std::to_string(e->refs) +
                                                " pipeline(s); destroy them first");
  std::string why;
  auto unreg =
      reinterpret_cast<EasyUnregisterFn>(plugin_symbol("NNS_custom_easy_unregister", &why));
  int rc = unreg ? unreg(e->name.c_str()) : -EINVAL;
  if (rc == -EBUSY)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": custom-easy filter '" + e->name +
                    "' is open in a tensor_filter; destroy its pipeline first");
  if (rc != 0)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": '" + e->name +
                                                "' is not registered in the plugin" +
                                                (why.empty() ? "" : ": " + why));
  g_easy.erase(e->name);
  delete e;
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_tensor_if_custom_register(const char *name, ml_pipeline_if_custom_cb cb,
                                                   void *user_data, ml_pipeline_if_h *if_custom) {
  constexpr const char *F = "ml_pipeline_tensor_if_custom_register";
  if (!if_custom) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": if_custom is NULL");
  *if_custom = nullptr;
  if (!name || !*name)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": name is NULL or empty");
  if (!cb) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": cb is NULL");
  if (int rc = ensure_gst(F); rc != ML_ERROR_NONE) return rc;
  std::string why;
  auto reg = reinterpret_cast<IfRegisterFn>(plugin_symbol("nnstreamer_if_custom_register", &why));
  if (!reg) return fail(ML_ERROR_NOT_SUPPORTED, std::string(F) + ": " + why);
  auto *e = new IfEntry();
  e->name = name;
  e->cb = cb;
  e->user = user_data;
  std::lock_guard lk(g_custom_mu);
  int rc = reg(name, if_invoke, e);
  if (rc != 0) {
    delete e;
    if (rc == -ENOMEM) return fail(ML_ERROR_OUT_OF_MEMORY, std::string(F) + ": out of memory");
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": a tensor_if condition named '" +
                                                name + "' is already registered");
  }
  g_if[name] = e;
  *if_custom = e;
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_pipeline_tensor_if_custom_unregister(ml_pipeline_if_h if_custom) {
  constexpr const char *F = "ml_pipeline_tensor_if_custom_unregister";
  if (!if_custom) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": if_custom is NULL");
  std::lock_guard lk(g_custom_mu);
  IfEntry *e = nullptr;
  for (auto &[n, x] : g_if)
    if (x == if_custom) e = x;
  if (!e)
    return fail(
        ML_ERROR_INVALID_PARAMETER,
        std::string(F) +
            ": if_custom is not a registered tensor_if condition handle (already unregistered?)");
  if (e->refs > 0)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": tensor_if condition '" + e->name +
                                                "' is used by " + std::to_string(e->refs) +
                                                " pipeline(s); destroy them first");
  std::string why;
  auto unreg =
      reinterpret_cast<IfUnregisterFn>(plugin_symbol("nnstreamer_if_custom_unregister", &why));
  int rc = unreg ? unreg(e->name.c_str()) : -EINVAL;
  if (rc != 0)
    return fail(ML_ERROR_STREAMS_PIPE, std::string(F) + ": the plugin could not remove '" +
                                           e->name + "'" + (why.empty() ? "" : ": " + why));
  g_if.erase(e->name);
  delete e;
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_check_nnfw_availability_full(ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw,
                                             const char *custom_option, bool *available) {
  constexpr const char *F = "ml_check_nnfw_availability_full";
  (void)custom_option;  // no back end here takes a hardware-detection option
  if (!available) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": available is NULL");
  const char *name = nnfw_subplugin(nnfw);
  if (!name)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": nnfw " +
                                                std::to_string(static_cast<int>(nnfw)) +
                                                " is not an ml_nnfw_type_e value");
  if (!*name)
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": ML_NNFW_TYPE_ANY names no framework; ask for one");
  const char *accl = accelerator_name(hw);
  if (!accl) {
    char b[16];
    snprintf(b, sizeof b, "%x", static_cast<unsigned>(hw));
    return fail(ML_ERROR_INVALID_PARAMETER,
                std::string(F) + ": hw 0x" + b + " is not an ml_nnfw_hw_e value");
  }
  *available = false;
  try {
    auto conf = current_filter_conf();
    for (const auto &cand : FilterRegistry::name_candidates(name, *conf)) {
      BackendRef ref = FilterRegistry::get().find(cand, *conf);
      if (!ref) continue;
      // ANY/AUTO: the framework is there. Otherwise the back end decides; one without a
      // check runs on the CPU only.
      if (!*accl)
        *available = true;
      else if (ref.iface->check_accelerator)
        *available = ref.iface->check_accelerator(accl) == 0;
      else
        *available = std::string_view(accl).starts_with("cpu");
      if (*available) break;
    }
  } catch (const std::exception &e) {
    GST_CAT_INFO(capi_debug, "%s: %s", F, e.what());
  }
  return ML_ERROR_NONE;
}

NNS_CAPI int ml_check_nnfw_availability(ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw, bool *available) {
  return ml_check_nnfw_availability_full(nnfw, hw, nullptr, available);
}

NNS_CAPI int ml_check_element_availability(const char *element_name, bool *available) {
  constexpr const char *F = "ml_check_element_availability";
  if (!element_name)
    return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": element_name is NULL");
  if (!available) return fail(ML_ERROR_INVALID_PARAMETER, std::string(F) + ": available is NULL");
  if (int rc = ensure_gst(F); rc != ML_ERROR_NONE) return rc;
  GstElementFactory *f = gst_element_factory_find(element_name);
  *available = f != nullptr;
  if (f) gst_object_unref(f);
  return ML_ERROR_NONE;
}

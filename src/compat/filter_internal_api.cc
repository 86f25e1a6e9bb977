// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_internal.h: framework detection from model files and the accelerator check, as
// NNStreamer 2.x gives them to its native APIs, over our filter registry
// (src/core/filter_registry.h) and accelerator names (src/core/filter_accl.h).
#include <glib.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "compat/compat_export.h"
#include "core/filter_accl.h"
#include "core/filter_registry.h"
#include "nnstreamer_internal.h"

namespace {

// NNStreamer's table: one model file's extension (lower case, with the dot) -> framework.
const char *framework_for_extension(const std::string &ext) {
  static const std::pair<const char *, const char *> kTable[] = {
      {".tflite", "tensorflow-lite"},
      {".pb", "tensorflow"},
      {".pt", "pytorch"},
      {".dlc", "snpe"},
      {".py", "python"},
      {".graph", "movidius-ncsdk2"},
      {".ini", "nntrainer"},
      {".circle", "nnfw"},
      {".so", "custom"},
      {".bin", "openvino"},
      {".xml", "openvino"},
      {".tvn", "trix-engine"},
      {".nb", "vivante"},
      {".gguf", "llamacpp"},
  };
  for (const auto &[e, fw] : kTable)
    if (ext == e) return fw;
  return nullptr;
}

// Whether `name` resolves to a back end (ours or an NNStreamer 2.x sub-plugin), loading it.
bool framework_available(const std::string &name, const nns::FilterConf &conf) {
  try {
    for (const auto &cand : nns::FilterRegistry::name_candidates(name, conf))
      if (nns::FilterRegistry::get().find(cand, conf)) return true;
  } catch (const std::exception &) {
  }
  return false;
}

}  // namespace

NNS_COMPAT_API gchar *gst_tensor_filter_detect_framework(const gchar *const *model_files,
                                                         const guint num_models,
                                                         const gboolean load_conf) {
  if (!model_files || num_models == 0 || !model_files[0]) return nullptr;
  try {
    std::error_code ec;
    if (std::filesystem::is_directory(model_files[0], ec)) return g_strdup("nnfw");
    std::vector<std::string> ext;
    for (guint i = 0; i < num_models; ++i) {
      const char *dot = model_files[i] ? std::strrchr(model_files[i], '.') : nullptr;
      if (!dot) return nullptr;
      gchar *lower = g_ascii_strdown(dot, -1);
      ext.emplace_back(lower);
      g_free(lower);
    }
    if (num_models == 1) {
      if (load_conf) {
        auto conf = nns::current_filter_conf();
        for (const auto &fw : conf->framework_priority(ext[0].substr(1)))
          if (framework_available(fw, *conf)) return g_strdup(fw.c_str());
      }
      const char *fw = framework_for_extension(ext[0]);
      return fw ? g_strdup(fw) : nullptr;
    }
    if (num_models == 2) {
      if (ext[0] == ".pb" && ext[1] == ".pb" && std::strcmp(model_files[0], model_files[1]) != 0)
        return g_strdup("caffe2");
      if ((ext[0] == ".so" && ext[1] == ".nb") || (ext[0] == ".nb" && ext[1] == ".so"))
        return g_strdup("vivante");
    }
  } catch (const std::exception &) {  // nothing may cross into C
  }
  return nullptr;
}

NNS_COMPAT_API gboolean gst_tensor_filter_check_hw_availability(const gchar *name, const accl_hw hw,
                                                                const gchar *custom) {
  (void)custom;
  if (!name) return FALSE;
  try {
    auto conf = nns::current_filter_conf();
    for (const auto &cand : nns::FilterRegistry::name_candidates(name, *conf)) {
      nns::BackendRef ref = nns::FilterRegistry::get().find(cand, *conf);
      if (!ref) continue;
      if (hw == ACCL_AUTO || hw == ACCL_DEFAULT) return TRUE;
      const std::string accl = nns::accl::name_of(hw);
      // A back end without a check runs on the CPU only.
      bool ok = ref.iface->check_accelerator ? ref.iface->check_accelerator(accl.c_str()) == 0
                                             : accl.rfind("cpu", 0) == 0;
      if (ok) return TRUE;
    }
  } catch (const std::exception &) {
  }
  return FALSE;
}

// SPDX-License-Identifier: LGPL-2.1-only
#include "api/ml_model_check.h"

#include <glib.h>

#include <filesystem>
#include <initializer_list>

#include "api/ml_nnfw_names.h"
#include "nnstreamer_internal.h"

namespace nns::ml {
namespace {

// The ml_nnfw_type_e whose framework name is `name` (any case), ANY when none.
ml_nnfw_type_e nnfw_of(const char *name) {
  if (!name) return ML_NNFW_TYPE_ANY;
  for (int i = ML_NNFW_TYPE_CUSTOM_FILTER; i < 64; ++i) {  // the dense part of the enum
    const char *n = nnfw_name(static_cast<ml_nnfw_type_e>(i));
    if (n && *n && g_ascii_strcasecmp(n, name) == 0) return static_cast<ml_nnfw_type_e>(i);
  }
  return g_ascii_strcasecmp(name, "snap") == 0 ? ML_NNFW_TYPE_SNAP : ML_NNFW_TYPE_ANY;
}

bool has_extension(const std::string &file, std::initializer_list<const char *> exts) {
  const auto dot = file.rfind('.');
  if (dot == std::string::npos) return false;
  for (const char *e : exts)
    if (g_ascii_strcasecmp(file.c_str() + dot, e) == 0) return true;
  return false;
}

}  // namespace

int check_models_for_nnfw(ml_nnfw_type_e nnfw, const std::vector<std::string> &models,
                          std::string *why) {
  if (nnfw == ML_NNFW_TYPE_ANY || models.empty()) return ML_ERROR_NONE;
  const char *fw = nnfw_name(nnfw);
  const std::string name = fw ? fw : std::to_string(nnfw);
  std::error_code ec;
  if (std::filesystem::is_directory(models[0], ec)) {
    if (nnfw == ML_NNFW_TYPE_NNFW) return ML_ERROR_NONE;
    *why = "model '" + models[0] + "' is a folder, which only ML_NNFW_TYPE_NNFW opens, not '" +
           name + "'";
    return ML_ERROR_INVALID_PARAMETER;
  }
  std::vector<const char *> paths;
  for (const auto &m : models) paths.push_back(m.c_str());
  gchar *detected_name =
      gst_tensor_filter_detect_framework(paths.data(), static_cast<guint>(paths.size()), TRUE);
  const std::string detected = detected_name ? detected_name : "";
  g_free(detected_name);
  if (nnfw_of(detected.c_str()) == nnfw) return ML_ERROR_NONE;
  const std::string said =
      "model '" + models[0] + "'" + (detected.empty() ? "" : " (a '" + detected + "' model)");
  switch (nnfw) {
    case ML_NNFW_TYPE_NNFW:
    case ML_NNFW_TYPE_TVM:
    case ML_NNFW_TYPE_ONNX_RUNTIME:
    case ML_NNFW_TYPE_NCNN:
    case ML_NNFW_TYPE_TENSORRT:
    case ML_NNFW_TYPE_QNN:
    case ML_NNFW_TYPE_LLAMACPP:
    case ML_NNFW_TYPE_TIZEN_HAL:
      return ML_ERROR_NONE;  // the framework checks its own files
    case ML_NNFW_TYPE_MVNC:
    case ML_NNFW_TYPE_OPENVINO:
    case ML_NNFW_TYPE_EDGE_TPU:
    case ML_NNFW_TYPE_SNAP:
      *why = "framework '" + name + "' is not supported by the single-shot API";
      return ML_ERROR_NOT_SUPPORTED;
    case ML_NNFW_TYPE_VD_AIFW:
      if (has_extension(models[0], {".nb", ".ncp", ".tvn", ".bin"})) return ML_ERROR_NONE;
      break;
    case ML_NNFW_TYPE_ARMNN:
      if (has_extension(models[0], {".caffemodel", ".tflite", ".pb", ".prototxt"}))
        return ML_ERROR_NONE;
      break;
    case ML_NNFW_TYPE_MXNET:
      if (has_extension(models[0], {".params", ".json"})) return ML_ERROR_NONE;
      break;
    default:
      break;
  }
  *why = said + " does not match the framework '" + name +
         "' (as NNStreamer, the file's extension must be one that framework opens)";
  return ML_ERROR_INVALID_PARAMETER;
}

}  // namespace nns::ml

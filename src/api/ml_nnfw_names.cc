// SPDX-License-Identifier: LGPL-2.1-only
#include "api/ml_nnfw_names.h"

namespace nns::ml {

const char *nnfw_name(ml_nnfw_type_e nnfw) {
  switch (nnfw) {
    case ML_NNFW_TYPE_ANY:
      return "";
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
  }
  return nullptr;
}

const char *hw_name(ml_nnfw_hw_e hw, bool numbered) {
  switch (hw) {
    case ML_NNFW_HW_ANY:
      return "";
    case ML_NNFW_HW_AUTO:
      return "auto";
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
  if (!numbered) return nullptr;
  const int h = static_cast<int>(hw);
  if (h > 0x1000 && h < 0x1100) return "cpu";
  if (h > 0x2000 && h < 0x3000) return "gpu";
  if (h > 0x3000 && h < 0x4000) return "npu";
  return nullptr;
}

}  // namespace nns::ml

// SPDX-License-Identifier: LGPL-2.1-only
// ml_single_open's check of a framework named by ml_nnfw_type_e against the model files, as
// NNStreamer's ML API (_ml_validate_model_file) does it before looking for the framework.
#pragma once

#include <string>
#include <vector>

#include "ml-api-common.h"

namespace nns::ml {

// ML_ERROR_NONE when `nnfw` (not ML_NNFW_TYPE_ANY) may open `models` (existing files, or a
// folder first); otherwise ML_ERROR_INVALID_PARAMETER or ML_ERROR_NOT_SUPPORTED with `why` set.
// The framework NNStreamer detects from the files' extensions must be `nnfw`, or `nnfw` must be
// one whose files cannot be told by extension (nnfw, tvm, onnxruntime, ncnn, tensorrt, qnn,
// llamacpp, tizen-hal) or accept the extension (armnn, vd_aifw, mxnet).
int check_models_for_nnfw(ml_nnfw_type_e nnfw, const std::vector<std::string> &models,
                          std::string *why);

}  // namespace nns::ml

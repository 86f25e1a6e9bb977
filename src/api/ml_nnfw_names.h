// SPDX-License-Identifier: LGPL-2.1-only
// ML API enums -> tensor_filter names, shared by the single-shot API (libnnstreamer-single) and
// the Pipeline API (libcapi-nnstreamer, which links it).
#pragma once

#include "ml-api-common.h"

namespace nns::ml {

// tensor_filter framework name of `nnfw` ("" for ML_NNFW_TYPE_ANY), nullptr when `nnfw` is not
// an ml_nnfw_type_e value.
const char *nnfw_name(ml_nnfw_type_e nnfw);

// tensor_filter accelerator name of `hw` without the "true:" prefix: "" for ANY, "auto" for
// AUTO, "cpu", "npu.edgetpu" ...; with `numbered`, 0x1nnn / 0x2nnn / 0x3nnn (a numbered CPU,
// GPU or NPU) also map to "cpu" / "gpu" / "npu". nullptr when `hw` is not a known value.
const char *hw_name(ml_nnfw_hw_e hw, bool numbered = false);

}  // namespace nns::ml

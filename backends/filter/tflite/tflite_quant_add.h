// SPDX-License-Identifier: LGPL-2.1-only
// TensorFlow Lite's integer arithmetic for quantized ADD/SUB on its CPU path (the XNNPACK
// delegate's), used to translate ADD/SUB with a constant single-valued operand into an exact
// lookup table (tflite_quant_add.cc).
#pragma once

#include <algorithm>
#include <cstdint>
#include <optional>

namespace nns::tfl {

struct QuantAddParams {
  int32_t a_mul = 0, b_mul = 0;  // b_mul negated for SUB
  int shift = 0;
};

// The multipliers and shift for input scales a, b and output scale out; nullopt when a ratio
// a/out or b/out lies outside [2^-10, 2^8) (XNNPACK refuses the op; TFLite runs its own kernel).
std::optional<QuantAddParams> xnnpack_add_params(float a_scale, float b_scale, float out_scale,
                                                 bool sub);

// One output value (stored integer), clamped to [lo, hi].
int32_t quant_add(const QuantAddParams &p, int32_t a, int32_t za, int32_t b, int32_t zb, int32_t zo,
                  int32_t lo, int32_t hi);

}  // namespace nns::tfl

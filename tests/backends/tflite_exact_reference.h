// SPDX-License-Identifier: LGPL-2.1-only
// An exact-arithmetic reference for quantized (uint8/int8) TFLite CNNs, for tests: every layer
// accumulates in integers, forms the real value of its output in double precision and quantizes
// it once, rounding half away from zero (as Arm NN's armnn::Quantize), then clamps to the type.
// It is "exact" in the sense that matters for quantized outputs: double precision resolves
// every rounding that float32 arithmetic may get wrong near a half step (the values 1e-6 from a
// tie that make Arm NN CpuRef, which accumulates in float32, and ONNX Runtime's integer kernels,
// which requantize with a float32 multiplier, round differently now and then).
//
// Covers what MobileNet-style networks use: CONV_2D, DEPTHWISE_CONV_2D (SAME/VALID, strides,
// dilations, per-tensor or per-channel weights), ADD, AVERAGE_POOL_2D, RESHAPE and SQUEEZE,
// with fused NONE/RELU/RELU6/RELU_N1_TO_1. Anything else throws std::runtime_error naming the
// operator. Scalar code: MobileNet v2 (300 M multiply-adds) takes a fraction of a second.
#pragma once

#include <cstdint>
#include <vector>

#include "tflite_model.h"

namespace nns::test {

// Runs the model's first subgraph on `input` (the stored bytes of its single quantized input)
// and returns the stored values (uint8 or int8, widened) of its first output.
std::vector<int> exact_quantized_run(const nns::tfl::Model &m, const std::vector<uint8_t> &input);

}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// Highway (runtime-dispatched SIMD) kernel of tensor_transform's hot path: convert to float32
// and apply a chain of add/mul/div in registers, one pass over memory.
#pragma once

#include <cstddef>

#include "core/tensor_info.h"

namespace nns::transform::simd {

// One step x = x (+|*|/) c. `table` (when set) gives c per element of a period, else `value`.
struct Op {
  int kind = 0;  // 0 add, 1 mul, 2 div
  float value = 0.0f;
  const float *table = nullptr;
};

// True when arith_f32 handles input type `t` (uint8, int8, uint16, int16, int32, float32).
bool supports_f32_input(TensorType t);

// out[i] = ops(float(in[i])) for i < n, ops applied in order in float32 (IEEE, no fusion).
// With tables, element i uses table[i % period]; period must be a multiple of 64 (0 = none).
void arith_f32(TensorType in_type, const void *in, float *out, std::size_t n, const Op *ops,
               std::size_t nops, std::size_t period);

// out[i] = cast_value<Out>(in[i]) for float32 input and Out in int8, uint8, int16, uint16,
// int32, uint32 (NNStreamer's C-cast semantics: 32-bit truncation, out of range -> INT32_MIN,
// then the low bits). Returns false for other output types.
bool f32_to_int(const float *in, TensorType out_type, void *out, std::size_t n);

// Splits `n` interleaved groups of `channels` (2, 3 or 4) elements of `esize` bytes (1, 2, 4,
// 8) into `channels` planes of n elements: out[c * n + i] = in[i * channels + c].
// Returns false for unsupported channel counts / sizes.
bool deinterleave(std::size_t esize, std::size_t channels, const void *in, void *out,
                  std::size_t n);

// Name of the SIMD target chosen at run time (e.g. "AVX3", "AVX2").
const char *target_name();

}  // namespace nns::transform::simd

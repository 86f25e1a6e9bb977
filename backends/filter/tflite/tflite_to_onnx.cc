// SPDX-License-Identifier: LGPL-2.1-only
#include "tflite_to_onnx.h"

#include "tflite_translator.h"

namespace nns::tfl {

int onnx_type(int t) {
  switch (t) {
    case kFloat32:
      return onnx::kFloat;
    case kFloat16:
      return onnx::kFloat16;
    case kInt32:
      return onnx::kInt32;
    case kUInt8:
      return onnx::kUInt8;
    case kInt64:
      return onnx::kInt64;
    case kBool:
      return onnx::kBool;
    case kInt16:
      return onnx::kInt16;
    case kInt8:
      return onnx::kInt8;
    case kFloat64:
      return onnx::kDouble;
    case kUInt64:
      return onnx::kUInt64;
    case kUInt32:
      return onnx::kUInt32;
    case kUInt16:
      return onnx::kUInt16;
    default:
      return 0;
  }
}

namespace detail {

float half_to_float(uint16_t h) {
  uint32_t sign = (h & 0x8000u) << 16, exp = (h >> 10) & 0x1f, man = h & 0x3ff, bits;
  if (exp == 0) {
    if (man == 0) {
      bits = sign;
    } else {  // subnormal
      exp = 127 - 15 + 1;
      while (!(man & 0x400)) {
        man <<= 1;
        --exp;
      }
      man &= 0x3ff;
      bits = sign | (exp << 23) | (man << 13);
    }
  } else if (exp == 31) {
    bits = sign | 0x7f800000u | (man << 13);
  } else {
    bits = sign | ((exp + 127 - 15) << 23) | (man << 13);
  }
  float f;
  std::memcpy(&f, &bits, 4);
  return f;
}

}  // namespace detail

Translation translate(const Model &m, const std::vector<std::vector<int64_t>> &input_shapes) {
  return detail::Translator(m, input_shapes).run();
}

}  // namespace nns::tfl

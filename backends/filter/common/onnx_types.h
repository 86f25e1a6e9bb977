// SPDX-License-Identifier: LGPL-2.1-only
// ONNX TensorProto.DataType numbering (a format fact), shared by the back ends that read or write
// ONNX protobuf bytes themselves (opencv's model-info reader, the tflite back end's writer).
#pragma once

#include <cstdint>

namespace nns::onnx {

enum ElemType : int32_t {
  kUndefined = 0,
  kFloat = 1,
  kUInt8 = 2,
  kInt8 = 3,
  kUInt16 = 4,
  kInt16 = 5,
  kInt32 = 6,
  kInt64 = 7,
  kString = 8,
  kBool = 9,
  kFloat16 = 10,
  kDouble = 11,
  kUInt32 = 12,
  kUInt64 = 13,
};

}  // namespace nns::onnx

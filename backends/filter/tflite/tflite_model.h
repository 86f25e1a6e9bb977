// SPDX-License-Identifier: LGPL-2.1-only
// TensorFlow Lite flatbuffer reader: loads a .tflite file, verifies the flatbuffer
// (tflite::VerifyModelBuffer from our tflite_schema.fbs) and every cross reference (buffer and
// tensor indices, constant data size against shape and type, quantization arrays, absurd
// sizes) before anything else reads it. Errors are ModelError naming the file and the field
// ("subgraphs[0].tensors[12].buffer: ..."). GStreamer- and engine-free (the fuzz target links
// it alone).
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>
#include <vector>

namespace tflite {
struct Operator;
}

namespace nns::tfl {

class ModelError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// TFLite TensorType values (a format fact).
enum TensorType : int {
  kFloat32 = 0,
  kFloat16 = 1,
  kInt32 = 2,
  kUInt8 = 3,
  kInt64 = 4,
  kString = 5,
  kBool = 6,
  kInt16 = 7,
  kComplex64 = 8,
  kInt8 = 9,
  kFloat64 = 10,
  kUInt64 = 12,
  kUInt32 = 15,
  kUInt16 = 16,
};

// Bytes of one element, 0 for types without a fixed size (string, resource, int4...).
std::size_t type_size(int type);
const char *type_name(int type);
// Builtin operator name ("CONV_2D"), or "BUILTIN_<n>" for codes we do not name.
std::string op_name(int code);

struct Quant {
  std::vector<float> scale;
  std::vector<int64_t> zero_point;
  int axis = 0;  // quantized_dimension (per-channel when scale.size() > 1)
  bool present() const { return !scale.empty(); }
};

struct Tensor {
  std::string name;
  int type = kFloat32;
  std::vector<int32_t> shape;      // as stored (NHWC for images)
  std::vector<int32_t> signature;  // shape_signature (-1 = free), empty when absent
  const uint8_t *data = nullptr;   // constant data (into Model::bytes), null for activations
  std::size_t bytes = 0;           // size of data
  Quant q;
  bool is_const() const { return data != nullptr; }
  int64_t elements() const;  // product of shape (1 for a scalar)
};

constexpr int kCustom = 32;  // BuiltinOperator CUSTOM

struct Op {
  int code = 0;        // BuiltinOperator
  std::string custom;  // custom_code when code == kCustom
  int version = 1;
  std::vector<int> inputs, outputs;  // tensor indices, -1 = optional input absent
  const ::tflite::Operator *raw = nullptr;
  const uint8_t *custom_options = nullptr;
  std::size_t custom_options_size = 0;
  std::string name() const { return code == kCustom ? custom : op_name(code); }
};

struct Model {
  Model() = default;
  Model(Model &&) = default;  // moving keeps `bytes`' storage, so the pointers stay valid
  Model &operator=(Model &&) = default;
  Model(const Model &) = delete;
  Model &operator=(const Model &) = delete;

  std::string path;            // for messages
  std::vector<uint8_t> bytes;  // the whole file (Tensor::data and Op::raw point into it)
  std::vector<Tensor> tensors;
  std::vector<Op> ops;
  std::vector<int> inputs, outputs;
  std::string description;
};

// Caps on what a model may declare (a corrupt file must not make us allocate gigabytes).
constexpr std::size_t kMaxFileBytes = std::size_t{1} << 31;
constexpr int kMaxRank = 8;
constexpr int64_t kMaxTensorElements = int64_t{1} << 31;

// Reads and checks `path`. Throws ModelError.
Model load_model(const std::string &path);
// Checks `bytes` (the content of `path`, which is only used in messages). Throws ModelError.
Model parse_model(std::vector<uint8_t> bytes, const std::string &path);

}  // namespace nns::tfl

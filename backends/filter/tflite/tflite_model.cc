// SPDX-License-Identifier: LGPL-2.1-only
#include "tflite_model.h"

#include <cstring>
#include <fstream>
#include <limits>

#include "tflite_schema_generated.h"

namespace nns::tfl {
namespace {

[[noreturn]] void fail(const std::string &path, const std::string &field, const std::string &what) {
  throw ModelError(path + ": " + field + ": " + what);
}

std::string shape_str(const std::vector<int32_t> &s) {
  std::string o = "[";
  for (std::size_t i = 0; i < s.size(); ++i) o += (i ? "," : "") + std::to_string(s[i]);
  return o + "]";
}

}  // namespace

std::size_t type_size(int type) {
  switch (type) {
    case kFloat32:
    case kInt32:
    case kUInt32:
      return 4;
    case kFloat16:
    case kInt16:
    case kUInt16:
      return 2;
    case kUInt8:
    case kInt8:
    case kBool:
      return 1;
    case kInt64:
    case kUInt64:
    case kFloat64:
    case kComplex64:
      return 8;
    default:
      return 0;
  }
}

const char *type_name(int type) {
  if (type >= 0 && type <= static_cast<int>(::tflite::TensorType_MAX))
    return ::tflite::EnumNameTensorType(static_cast<::tflite::TensorType>(type));
  return "UNKNOWN";
}

std::string op_name(int code) {
  static const char *const kNames[] = {"ADD",
                                       "AVERAGE_POOL_2D",
                                       "CONCATENATION",
                                       "CONV_2D",
                                       "DEPTHWISE_CONV_2D",
                                       "DEPTH_TO_SPACE",
                                       "DEQUANTIZE",
                                       "EMBEDDING_LOOKUP",
                                       "FLOOR",
                                       "FULLY_CONNECTED",
                                       "HASHTABLE_LOOKUP",
                                       "L2_NORMALIZATION",
                                       "L2_POOL_2D",
                                       "LOCAL_RESPONSE_NORMALIZATION",
                                       "LOGISTIC",
                                       "LSH_PROJECTION",
                                       "LSTM",
                                       "MAX_POOL_2D",
                                       "MUL",
                                       "RELU",
                                       "RELU_N1_TO_1",
                                       "RELU6",
                                       "RESHAPE",
                                       "RESIZE_BILINEAR",
                                       "RNN",
                                       "SOFTMAX",
                                       "SPACE_TO_DEPTH",
                                       "SVDF",
                                       "TANH",
                                       "CONCAT_EMBEDDINGS",
                                       "SKIP_GRAM",
                                       "CALL",
                                       "CUSTOM",
                                       "EMBEDDING_LOOKUP_SPARSE",
                                       "PAD",
                                       "UNIDIRECTIONAL_SEQUENCE_RNN",
                                       "GATHER",
                                       "BATCH_TO_SPACE_ND",
                                       "SPACE_TO_BATCH_ND",
                                       "TRANSPOSE",
                                       "MEAN",
                                       "SUB",
                                       "DIV",
                                       "SQUEEZE",
                                       "UNIDIRECTIONAL_SEQUENCE_LSTM",
                                       "STRIDED_SLICE",
                                       "BIDIRECTIONAL_SEQUENCE_RNN",
                                       "EXP",
                                       "TOPK_V2",
                                       "SPLIT",
                                       "LOG_SOFTMAX",
                                       "DELEGATE",
                                       "BIDIRECTIONAL_SEQUENCE_LSTM",
                                       "CAST",
                                       "PRELU",
                                       "MAXIMUM",
                                       "ARG_MAX",
                                       "MINIMUM",
                                       "LESS",
                                       "NEG",
                                       "PADV2",
                                       "GREATER",
                                       "GREATER_EQUAL",
                                       "LESS_EQUAL",
                                       "SELECT",
                                       "SLICE",
                                       "SIN",
                                       "TRANSPOSE_CONV",
                                       "SPARSE_TO_DENSE",
                                       "TILE",
                                       "EXPAND_DIMS",
                                       "EQUAL",
                                       "NOT_EQUAL",
                                       "LOG",
                                       "SUM",
                                       "SQRT",
                                       "RSQRT",
                                       "SHAPE",
                                       "POW",
                                       "ARG_MIN",
                                       "FAKE_QUANT",
                                       "REDUCE_PROD",
                                       "REDUCE_MAX",
                                       "PACK",
                                       "LOGICAL_OR",
                                       "ONE_HOT",
                                       "LOGICAL_AND",
                                       "LOGICAL_NOT",
                                       "UNPACK",
                                       "REDUCE_MIN",
                                       "FLOOR_DIV",
                                       "REDUCE_ANY",
                                       "SQUARE",
                                       "ZEROS_LIKE",
                                       "FILL",
                                       "FLOOR_MOD",
                                       "RANGE",
                                       "RESIZE_NEAREST_NEIGHBOR",
                                       "LEAKY_RELU",
                                       "SQUARED_DIFFERENCE",
                                       "MIRROR_PAD",
                                       "ABS",
                                       "SPLIT_V",
                                       "UNIQUE",
                                       "CEIL",
                                       "REVERSE_V2",
                                       "ADD_N",
                                       "GATHER_ND",
                                       "COS",
                                       "WHERE",
                                       "RANK",
                                       "ELU",
                                       "REVERSE_SEQUENCE",
                                       "MATRIX_DIAG",
                                       "QUANTIZE",
                                       "MATRIX_SET_DIAG",
                                       "ROUND",
                                       "HARD_SWISH",
                                       "IF",
                                       "WHILE",
                                       "NON_MAX_SUPPRESSION_V4",
                                       "NON_MAX_SUPPRESSION_V5",
                                       "SCATTER_ND",
                                       "SELECT_V2",
                                       "DENSIFY",
                                       "SEGMENT_SUM",
                                       "BATCH_MATMUL"};
  if (code >= 0 && code < static_cast<int>(sizeof kNames / sizeof kNames[0])) return kNames[code];
  static const char *const kMore[] = {"PLACEHOLDER_FOR_GREATER_OP_CODES",
                                      "CUMSUM",
                                      "CALL_ONCE",
                                      "BROADCAST_TO",
                                      "RFFT2D",
                                      "CONV_3D",
                                      "IMAG",
                                      "REAL",
                                      "COMPLEX_ABS",
                                      "HASHTABLE",
                                      "HASHTABLE_FIND",
                                      "HASHTABLE_IMPORT",
                                      "HASHTABLE_SIZE",
                                      "REDUCE_ALL",
                                      "CONV_3D_TRANSPOSE",
                                      "VAR_HANDLE",
                                      "READ_VARIABLE",
                                      "ASSIGN_VARIABLE",
                                      "BROADCAST_ARGS",
                                      "RANDOM_STANDARD_NORMAL",
                                      "BUCKETIZE",
                                      "RANDOM_UNIFORM",
                                      "MULTINOMIAL",
                                      "GELU",
                                      "DYNAMIC_UPDATE_SLICE",
                                      "RELU_0_TO_1"};
  int k = code - 127;
  if (k >= 0 && k < static_cast<int>(sizeof kMore / sizeof kMore[0])) return kMore[k];
  return "BUILTIN_" + std::to_string(code);
}

int64_t Tensor::elements() const {
  int64_t n = 1;
  for (auto d : shape) n *= d;
  return n;
}

Model load_model(const std::string &path) {
  std::ifstream f(path, std::ios::binary | std::ios::ate);
  if (!f) throw ModelError(path + ": cannot open the model file");
  std::streamoff size = f.tellg();
  if (size < 0) throw ModelError(path + ": cannot read the model file");
  if (static_cast<uint64_t>(size) > kMaxFileBytes)
    throw ModelError(path + ": the file is " + std::to_string(size) +
                     " bytes; models over 2 GiB (external buffers) are not supported");
  std::vector<uint8_t> bytes(static_cast<std::size_t>(size));
  f.seekg(0);
  if (size && !f.read(reinterpret_cast<char *>(bytes.data()), size))
    throw ModelError(path + ": cannot read the model file");
  return parse_model(std::move(bytes), path);
}

Model parse_model(std::vector<uint8_t> bytes, const std::string &path) {
  Model m;
  m.path = path;
  m.bytes = std::move(bytes);
  const uint8_t *base = m.bytes.data();
  const std::size_t size = m.bytes.size();
  if (size < 8)
    throw ModelError(path + ": not a TensorFlow Lite model (" + std::to_string(size) +
                     " bytes, too short for a flatbuffer)");
  if (size > kMaxFileBytes) throw ModelError(path + ": model larger than 2 GiB");
  if (std::memcmp(base + 4, "TFL3", 4) != 0)
    throw ModelError(path + ": not a TensorFlow Lite model (file identifier is not 'TFL3')");
  flatbuffers::Verifier v(base, size, 64 /*depth*/, 4000000 /*tables*/);
  if (!::tflite::VerifyModelBuffer(v))
    throw ModelError(path +
                     ": the flatbuffer is corrupt or truncated (verification failed); "
                     "the file is not a valid TensorFlow Lite model");
  const ::tflite::Model *fm = ::tflite::GetModel(base);
  if (fm->version() != 3)
    fail(path, "version", "schema version " + std::to_string(fm->version()) + ", expected 3");
  if (fm->description()) m.description = fm->description()->str();
  const auto *subgraphs = fm->subgraphs();
  if (!subgraphs || subgraphs->size() == 0) fail(path, "subgraphs", "the model has no subgraph");
  const auto *buffers = fm->buffers();
  const uint32_t nbuf = buffers ? buffers->size() : 0;
  const auto *codes = fm->operator_codes();
  const uint32_t ncodes = codes ? codes->size() : 0;
  const ::tflite::SubGraph *sg = subgraphs->Get(0);
  const std::string sgp = "subgraphs[0]";

  // Tensors.
  const auto *tensors = sg->tensors();
  const uint32_t ntensors = tensors ? tensors->size() : 0;
  if (ntensors == 0) fail(path, sgp + ".tensors", "the subgraph has no tensors");
  m.tensors.resize(ntensors);
  for (uint32_t i = 0; i < ntensors; ++i) {
    const ::tflite::Tensor *ft = tensors->Get(i);
    Tensor &t = m.tensors[i];
    std::string fp = sgp + ".tensors[" + std::to_string(i) + "]";
    if (ft->name()) t.name = ft->name()->str();
    if (!t.name.empty()) fp += " ('" + t.name + "')";
    t.type = static_cast<int>(ft->type());
    if (ft->shape()) {
      if (ft->shape()->size() > static_cast<uint32_t>(kMaxRank))
        fail(
            path, fp + ".shape",
            "rank " + std::to_string(ft->shape()->size()) + " exceeds " + std::to_string(kMaxRank));
      int64_t n = 1;
      for (int32_t d : *ft->shape()) {
        if (d < 0) fail(path, fp + ".shape", "negative dimension " + std::to_string(d));
        t.shape.push_back(d);
        n *= d;
        if (n > kMaxTensorElements) fail(path, fp + ".shape", "absurd size (over 2^31 elements)");
      }
    }
    if (ft->shape_signature()) {
      if (ft->shape_signature()->size() != t.shape.size())
        fail(path, fp + ".shape_signature", "rank differs from shape " + shape_str(t.shape));
      for (int32_t d : *ft->shape_signature()) t.signature.push_back(d);
    }
    if (ft->sparsity()) fail(path, fp + ".sparsity", "sparse tensors are not supported");
    if (const auto *q = ft->quantization()) {
      if (q->scale()) t.q.scale.assign(q->scale()->begin(), q->scale()->end());
      if (const auto *zp = q->zero_point()) {
        // 8-byte elements: the verifier only guarantees 4-byte alignment of a vector, so copy.
        t.q.zero_point.resize(zp->size());
        if (zp->size()) std::memcpy(t.q.zero_point.data(), zp->Data(), zp->size() * 8);
      }
      t.q.axis = q->quantized_dimension();
      if (!t.q.scale.empty()) {
        if (t.q.zero_point.empty()) t.q.zero_point.assign(t.q.scale.size(), 0);
        if (t.q.zero_point.size() != t.q.scale.size())
          fail(path, fp + ".quantization.zero_point",
               std::to_string(t.q.zero_point.size()) + " values for " +
                   std::to_string(t.q.scale.size()) + " scales");
        for (float s : t.q.scale)
          if (!(s > 0.f) || s == std::numeric_limits<float>::infinity())
            fail(path, fp + ".quantization.scale",
                 "scale " + std::to_string(s) + " is not a positive finite number");
        if (t.q.scale.size() > 1) {
          // Converters copy the weights' quantized_dimension (3) onto 1-D per-channel biases.
          if (t.shape.size() == 1 && t.q.axis != 0 &&
              static_cast<int64_t>(t.q.scale.size()) == t.shape[0])
            t.q.axis = 0;
          if (t.q.axis < 0 || t.q.axis >= static_cast<int>(t.shape.size()))
            fail(path, fp + ".quantization.quantized_dimension",
                 std::to_string(t.q.axis) + " is outside shape " + shape_str(t.shape));
          if (static_cast<int64_t>(t.q.scale.size()) != t.shape[t.q.axis])
            fail(path, fp + ".quantization.scale",
                 std::to_string(t.q.scale.size()) + " per-channel scales for dimension " +
                     std::to_string(t.q.axis) + " of shape " + shape_str(t.shape));
        }
      }
    }
    uint32_t b = ft->buffer();
    if (b >= nbuf && !(b == 0 && nbuf == 0))
      fail(path, fp + ".buffer",
           std::to_string(b) + " is out of range (the model has " + std::to_string(nbuf) +
               " buffers)");
    if (b == 0 || nbuf == 0) continue;
    const ::tflite::Buffer *fb = buffers->Get(b);
    const uint8_t *data = nullptr;
    std::size_t nbytes = 0;
    if (fb->data() && fb->data()->size()) {
      data = fb->data()->data();
      nbytes = fb->data()->size();
    } else if (fb->offset() > 1) {
      uint64_t off = fb->offset(), len = fb->size();
      if (off > size || len > size - off)
        fail(path, "buffers[" + std::to_string(b) + "].offset",
             "external data [" + std::to_string(off) + ", +" + std::to_string(len) +
                 ") lies outside the " + std::to_string(size) + "-byte file");
      data = base + off;
      nbytes = static_cast<std::size_t>(len);
    }
    if (!data) continue;
    std::size_t es = type_size(t.type);
    if (es == 0)
      fail(path, fp + ".type",
           std::string("constant tensor of type ") + type_name(t.type) + " is not supported");
    uint64_t want = static_cast<uint64_t>(t.elements()) * es;
    if (want != nbytes)
      fail(path, fp + ".buffer",
           "buffer " + std::to_string(b) + " holds " + std::to_string(nbytes) + " bytes but " +
               std::string(type_name(t.type)) + " " + shape_str(t.shape) + " needs " +
               std::to_string(want));
    t.data = data;
    t.bytes = nbytes;
  }

  auto check_index = [&](int idx, const std::string &field, bool optional) {
    if ((optional && idx == -1) || (idx >= 0 && static_cast<uint32_t>(idx) < ntensors)) return;
    fail(path, field,
         "tensor index " + std::to_string(idx) + " is out of range (the subgraph has " +
             std::to_string(ntensors) + " tensors)");
  };
  if (!sg->inputs() || sg->inputs()->size() == 0)
    fail(path, sgp + ".inputs", "the subgraph has no inputs");
  if (!sg->outputs() || sg->outputs()->size() == 0)
    fail(path, sgp + ".outputs", "the subgraph has no outputs");
  for (uint32_t i = 0; i < sg->inputs()->size(); ++i) {
    int idx = sg->inputs()->Get(i);
    check_index(idx, sgp + ".inputs[" + std::to_string(i) + "]", false);
    m.inputs.push_back(idx);
  }
  for (uint32_t i = 0; i < sg->outputs()->size(); ++i) {
    int idx = sg->outputs()->Get(i);
    check_index(idx, sgp + ".outputs[" + std::to_string(i) + "]", false);
    m.outputs.push_back(idx);
  }

  // Operators.
  if (const auto *ops = sg->operators()) {
    for (uint32_t i = 0; i < ops->size(); ++i) {
      const ::tflite::Operator *fo = ops->Get(i);
      std::string fp = sgp + ".operators[" + std::to_string(i) + "]";
      Op op;
      op.raw = fo;
      if (fo->opcode_index() >= ncodes)
        fail(path, fp + ".opcode_index",
             std::to_string(fo->opcode_index()) + " is out of range (the model has " +
                 std::to_string(ncodes) + " operator codes)");
      const ::tflite::OperatorCode *oc = codes->Get(fo->opcode_index());
      op.code = std::max<int>(oc->deprecated_builtin_code(), oc->builtin_code());
      op.version = oc->version();
      if (op.code == kCustom) {
        if (!oc->custom_code())
          fail(path, "operator_codes[" + std::to_string(fo->opcode_index()) + "].custom_code",
               "a CUSTOM operator without a name");
        op.custom = oc->custom_code()->str();
      }
      if (fo->inputs())
        for (uint32_t k = 0; k < fo->inputs()->size(); ++k) {
          int idx = fo->inputs()->Get(k);
          check_index(idx, fp + ".inputs[" + std::to_string(k) + "]", true);
          op.inputs.push_back(idx);
        }
      if (fo->outputs())
        for (uint32_t k = 0; k < fo->outputs()->size(); ++k) {
          int idx = fo->outputs()->Get(k);
          check_index(idx, fp + ".outputs[" + std::to_string(k) + "]", false);
          op.outputs.push_back(idx);
        }
      if (fo->custom_options() && fo->custom_options()->size()) {
        op.custom_options = fo->custom_options()->data();
        op.custom_options_size = fo->custom_options()->size();
      } else if (fo->large_custom_options_offset() > 1) {
        uint64_t off = fo->large_custom_options_offset(), len = fo->large_custom_options_size();
        if (off > size || len > size - off)
          fail(path, fp + ".large_custom_options_offset",
               "custom options lie outside the " + std::to_string(size) + "-byte file");
        op.custom_options = base + off;
        op.custom_options_size = static_cast<std::size_t>(len);
      }
      m.ops.push_back(std::move(op));
    }
  }
  return m;
}

}  // namespace nns::tfl

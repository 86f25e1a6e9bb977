// SPDX-License-Identifier: LGPL-2.1-only
// Private to the tflite back end: the translator's state and helpers (emitting initializers,
// DequantizeLinear/QuantizeLinear around float ops, NHWC<->NCHW transposes), shared by
// tflite_to_onnx.cc (driver), tflite_layers.cc (conv, pooling, resize, slice, detection
// post-process) and tflite_ops.cc (the per-operator switch).
#pragma once

#include <flatbuffers/flexbuffers.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>
#include <string>
#include <vector>

#include "onnx_writer.h"
#include "tflite_schema_generated.h"
#include "tflite_to_onnx.h"

namespace nns::tfl::detail {

using onnx::attr_float;
using onnx::attr_int;
using onnx::attr_ints;
using onnx::attr_str;
using Strs = std::vector<std::string>;

float half_to_float(uint16_t h);

// A constant tensor: from the file, or folded here (DEQUANTIZE of a constant).
struct Const {
  int type = kFloat32;
  const uint8_t *data = nullptr;
  std::size_t bytes = 0;
  std::vector<int32_t> shape;
  const Quant *q = nullptr;
};

class Translator {
 public:
  Translator(const Model &m, const std::vector<std::vector<int64_t>> &in_shapes)
      : m_(m), in_shapes_(in_shapes), emitted_(m.tensors.size(), false) {}

  Translation run() {
    Translation tr;
    if (in_shapes_.size() != m_.inputs.size())
      throw ModelError(m_.path + ": " + std::to_string(in_shapes_.size()) +
                       " input shapes given, the model has " + std::to_string(m_.inputs.size()) +
                       " inputs");
    for (std::size_t i = 0; i < m_.inputs.size(); ++i) {
      int t = m_.inputs[i];
      const Tensor &ts = m_.tensors[t];
      int ot = onnx_type(ts.type);
      if (!ot)
        throw ModelError(m_.path + ": input " + std::to_string(i) + " ('" + ts.name +
                         "') has type " + type_name(ts.type) + ", which is not supported");
      g_.input(name(t), ot, in_shapes_[i]);
      emitted_[t] = true;
      tr.in_names.push_back(name(t));
    }
    for (std::size_t k = 0; k < m_.ops.size(); ++k) {
      op_index_ = static_cast<int>(k);
      const Op &op = m_.ops[k];
      try {
        translate_op(op, tr);
      } catch (const ModelError &) {
        throw;
      } catch (const std::exception &e) {
        fail(op, e.what());
      }
    }
    for (int t : m_.outputs) {
      bool by_post = tr.post && std::count(tr.post->outputs.begin(), tr.post->outputs.end(), t);
      if (by_post) {
        tr.out_names.push_back("");  // filled on the CPU
        continue;
      }
      int ot = onnx_type(m_.tensors[t].type);
      if (!ot)
        throw ModelError(m_.path + ": output '" + m_.tensors[t].name + "' has type " +
                         type_name(m_.tensors[t].type) + ", which is not supported");
      std::string src = raw(t);
      std::string out = "out" + std::to_string(t);
      g_.node("Identity", {src}, {out});
      if (std::find(tr.out_names.begin(), tr.out_names.end(), out) == tr.out_names.end())
        g_.output(out, ot, {}, false);
      tr.out_names.push_back(out);
    }
    if (tr.post) {
      g_.output(tr.post->boxes, onnx::kFloat, {}, false);
      g_.output(tr.post->scores, onnx::kFloat, {}, false);
      tr.out_names.push_back(tr.post->boxes);
      tr.out_names.push_back(tr.post->scores);
    }
    tr.onnx = g_.model(17);
    return tr;
  }

 private:
  [[noreturn]] void fail(const Op &op, const std::string &why) const {
    throw ModelError(m_.path + ": operator " + std::to_string(op_index_) + " (" + op.name() +
                     "): " + why);
  }
  [[noreturn]] void unsupported(const Op &op, const std::string &why = "") const {
    fail(op, "not supported by the tflite back end" + (why.empty() ? "" : " (" + why + ")") +
                 "; framework=armnn may run it");
  }

  static std::string name(int t) { return "t" + std::to_string(t); }
  std::string fresh() { return "v" + std::to_string(tmp_++); }

  // Every tensor access goes through here: optional inputs (-1) used where an op needs them
  // are an error, never an out-of-range read.
  const Tensor &T(int t) const {
    if (t < 0 || static_cast<std::size_t>(t) >= m_.tensors.size())
      throw ModelError(m_.path + ": operator " + std::to_string(op_index_) +
                       ": a required input tensor is missing (index " + std::to_string(t) + ")");
    return m_.tensors[t];
  }
  int rank(int t) const { return static_cast<int>(T(t).shape.size()); }
  bool is_quant(int t) const {
    const Tensor &x = T(t);
    return x.q.present() &&
           (x.type == kUInt8 || x.type == kInt8 || x.type == kInt16 || x.type == kInt32);
  }
  bool is_const(int t) const { return T(t).is_const() || folded_.count(t); }

  Const cst(int t) const {
    Const c;
    if (auto it = folded_.find(t); it != folded_.end()) {
      c.type = kFloat32;
      c.data = reinterpret_cast<const uint8_t *>(it->second.data());
      c.bytes = it->second.size() * 4;
    } else {
      c.type = T(t).type;
      c.data = T(t).data;
      c.bytes = T(t).bytes;
      c.q = T(t).q.present() ? &T(t).q : nullptr;
    }
    c.shape = T(t).shape;
    return c;
  }

  // Integer values of a constant int32/int64 tensor (axes, shapes, paddings...).
  std::vector<int64_t> ints(const Op &op, int t) const {
    if (t < 0 || !T(t).is_const())
      fail(op, "input tensor " + std::to_string(t) + " ('" + (t >= 0 ? T(t).name : "") +
                   "') must be a constant");
    std::vector<int64_t> v;
    const Tensor &x = T(t);
    if (x.type == kInt32) {
      for (std::size_t i = 0; i < x.bytes / 4; ++i) {
        int32_t e;
        std::memcpy(&e, x.data + 4 * i, 4);
        v.push_back(e);
      }
    } else if (x.type == kInt64) {
      for (std::size_t i = 0; i < x.bytes / 8; ++i) {
        int64_t e;
        std::memcpy(&e, x.data + 8 * i, 8);
        v.push_back(e);
      }
    } else {
      fail(op, "constant '" + x.name + "' must be int32 or int64, not " + type_name(x.type));
    }
    return v;
  }

  std::string const_i64(const std::vector<int64_t> &v, bool scalar = false) {
    std::string n = fresh();
    std::vector<int64_t> dims;
    if (!scalar) dims.push_back(static_cast<int64_t>(v.size()));
    g_.initializer(n, onnx::kInt64, dims, v.data(), v.size() * 8);
    return n;
  }
  std::string const_f32(const std::vector<float> &v, bool scalar = false) {
    std::string n = fresh();
    std::vector<int64_t> dims;
    if (!scalar) dims.push_back(static_cast<int64_t>(v.size()));
    g_.initializer(n, onnx::kFloat, dims, v.data(), v.size() * 4);
    return n;
  }

  // Emits constant `t` as an initializer in its stored type (fp16 widened to float).
  void emit_const(int t, const std::string &n, const std::vector<int> &perm = {}) {
    Const c = cst(t);
    std::vector<int64_t> dims(c.shape.begin(), c.shape.end());
    std::vector<uint8_t> data(c.data, c.data + c.bytes);
    int type = c.type;
    if (type == kFloat16) {
      std::vector<uint8_t> f(data.size() * 2);
      for (std::size_t i = 0; i < data.size() / 2; ++i) {
        uint16_t h;
        std::memcpy(&h, &data[2 * i], 2);
        float x = half_to_float(h);
        std::memcpy(&f[4 * i], &x, 4);
      }
      data.swap(f);
      type = kFloat32;
    }
    if (!perm.empty()) {
      std::size_t es = type_size(type);
      std::vector<uint8_t> out(data.size());
      int r = static_cast<int>(dims.size());
      std::vector<int64_t> nd(r), in_stride(r), idx(r, 0);
      for (int i = r - 1, s = 1; i >= 0; --i) {
        in_stride[i] = s;
        s *= static_cast<int>(dims[i]);
      }
      for (int i = 0; i < r; ++i) nd[i] = dims[perm[i]];
      std::size_t n = es ? data.size() / es : 0;
      for (std::size_t o = 0; o < n; ++o) {  // idx: position in the output
        int64_t src = 0;
        for (int i = 0; i < r; ++i) src += idx[i] * in_stride[perm[i]];
        std::memcpy(&out[o * es], &data[src * es], es);
        for (int i = r - 1; i >= 0; --i) {
          if (++idx[i] < nd[i]) break;
          idx[i] = 0;
        }
      }
      data.swap(out);
      dims = nd;
    }
    g_.initializer(n, onnx_type(type), dims, data.data(), data.size());
  }

  // The tensor's value in its stored type (quantized stays quantized).
  std::string raw(int t) {
    (void)T(t);  // range check
    if (!emitted_[t]) {
      if (!is_const(t))
        throw ModelError(m_.path + ": tensor " + std::to_string(t) + " ('" + T(t).name +
                         "') is read before any operator writes it");
      emit_const(t, name(t));
      emitted_[t] = true;
    }
    return name(t);
  }

  std::string qparams_scale(const Quant &q) {
    if (q.scale.size() == 1) return const_f32({q.scale[0]}, true);
    return const_f32(q.scale);
  }
  std::string qparams_zp(const Quant &q, int type) {
    std::string n = fresh();
    std::size_t cnt = q.zero_point.size();
    std::vector<int64_t> dims;
    if (cnt != 1) dims.push_back(static_cast<int64_t>(cnt));
    int ot = onnx_type(type);
    if (type == kUInt8) {
      std::vector<uint8_t> v;
      for (auto z : q.zero_point) v.push_back(static_cast<uint8_t>(z));
      g_.initializer(n, ot, dims, v.data(), v.size());
    } else if (type == kInt8) {
      std::vector<int8_t> v;
      for (auto z : q.zero_point) v.push_back(static_cast<int8_t>(z));
      g_.initializer(n, ot, dims, v.data(), v.size());
    } else if (type == kInt16) {
      std::vector<int16_t> v;
      for (auto z : q.zero_point) v.push_back(static_cast<int16_t>(z));
      g_.initializer(n, ot, dims, v.data(), v.size() * 2);
    } else {
      std::vector<int32_t> v;
      for (auto z : q.zero_point) v.push_back(static_cast<int32_t>(z));
      g_.initializer(n, onnx::kInt32, dims, v.data(), v.size() * 4);
    }
    return n;
  }

  // DequantizeLinear of `src` (stored type `type`, quantization q, per-channel axis `axis`).
  std::string dq(const std::string &src, int type, const Quant &q, int axis) {
    std::string out = fresh();
    std::vector<onnx::Msg> at;
    if (q.scale.size() > 1) at.push_back(attr_int("axis", axis));
    g_.node("DequantizeLinear", {src, qparams_scale(q), qparams_zp(q, type)}, {out}, at);
    return out;
  }

  // The tensor as float. Constant weights may be permuted (`perm`: output dim i is input dim
  // perm[i]) at translate time.
  std::string flt(int t, const std::vector<int> &perm = {}) {
    const Tensor &x = T(t);
    int axis = x.q.axis;
    if (!perm.empty())
      for (std::size_t i = 0; i < perm.size(); ++i)
        if (perm[i] == x.q.axis) axis = static_cast<int>(i);
    std::string src;
    if (!perm.empty() && is_const(t)) {
      src = fresh();
      emit_const(t, src, perm);
    } else {
      src = raw(t);
      if (!perm.empty()) {
        std::string p = fresh();
        g_.node("Transpose", {src}, {p},
                {attr_ints("perm", std::vector<int64_t>(perm.begin(), perm.end()))});
        src = p;
      }
    }
    if (folded_.count(t)) return src;
    if (is_quant(t)) return dq(src, x.type, x.q, axis);
    if (x.type == kFloat32 || (x.type == kFloat16 && is_const(t))) return src;
    std::string c = fresh();
    g_.node("Cast", {src}, {c}, {attr_int("to", onnx::kFloat)});
    return c;
  }

  // Writes float value `v` into tensor t (quantizing when t is quantized).
  void store(int t, const std::string &v) {
    const Tensor &x = T(t);
    if (is_quant(t)) {
      std::vector<onnx::Msg> at;
      if (x.q.scale.size() > 1) at.push_back(attr_int("axis", x.q.axis));
      g_.node("QuantizeLinear", {v, qparams_scale(x.q), qparams_zp(x.q, x.type)}, {name(t)}, at);
    } else if (x.type == kFloat32) {
      g_.node("Identity", {v}, {name(t)});
    } else {
      g_.node("Cast", {v}, {name(t)}, {attr_int("to", onnx_type(x.type))});
    }
    emitted_[t] = true;
  }
  // Writes a value already in t's stored type.
  void store_raw(int t, const std::string &v) {
    g_.node("Identity", {v}, {name(t)});
    emitted_[t] = true;
  }
  bool same_q(int a, int b) const {
    const Tensor &x = T(a), &y = T(b);
    if (x.type != y.type) return false;
    if (x.q.present() != y.q.present()) return false;
    return !x.q.present() || (x.q.scale == y.q.scale && x.q.zero_point == y.q.zero_point);
  }

  std::string act(const std::string &x, int fused, const Op &op) {
    std::string o = fresh();
    switch (fused) {
      case 0:
        return x;
      case 1:
        g_.node("Relu", {x}, {o});
        return o;
      case 2:
        g_.node("Clip", {x, const_f32({-1.f}, true), const_f32({1.f}, true)}, {o});
        return o;
      case 3:
        g_.node("Clip", {x, const_f32({0.f}, true), const_f32({6.f}, true)}, {o});
        return o;
      case 4:
        g_.node("Tanh", {x}, {o});
        return o;
      default:
        unsupported(op, "fused activation " + std::to_string(fused));
    }
  }

  std::string nchw(const std::string &x) {
    std::string o = fresh();
    g_.node("Transpose", {x}, {o}, {attr_ints("perm", {0, 3, 1, 2})});
    return o;
  }
  std::string nhwc(const std::string &x) {
    std::string o = fresh();
    g_.node("Transpose", {x}, {o}, {attr_ints("perm", {0, 2, 3, 1})});
    return o;
  }
  static onnx::Msg pad_attr(int padding) {
    return attr_str("auto_pad", padding == 0 ? "SAME_UPPER" : "VALID");
  }
  int norm_axis(int64_t a, int r) const { return static_cast<int>(a < 0 ? a + r : a); }

  std::string unary(const char *onnx_op, const std::string &x,
                    const std::vector<onnx::Msg> &at = {}) {
    std::string o = fresh();
    g_.node(onnx_op, {x}, {o}, at);
    return o;
  }
  std::string binary(const char *onnx_op, const std::string &a, const std::string &b) {
    std::string o = fresh();
    g_.node(onnx_op, {a, b}, {o});
    return o;
  }

  void need(const Op &op, std::size_t nin, std::size_t nout) const {
    if (op.inputs.size() < nin || op.outputs.size() < nout)
      fail(op, "expects " + std::to_string(nin) + " inputs and " + std::to_string(nout) +
                   " outputs, has " + std::to_string(op.inputs.size()) + " and " +
                   std::to_string(op.outputs.size()));
    for (std::size_t i = 0; i < nin; ++i)
      if (op.inputs[i] < 0) fail(op, "input " + std::to_string(i) + " is missing");
  }
  void need_rank(const Op &op, int t, int r) const {
    if (rank(t) != r)
      fail(op, "tensor '" + T(t).name + "' has rank " + std::to_string(rank(t)) + ", expected " +
                   std::to_string(r));
  }

  void translate_op(const Op &op, Translation &tr);
  void conv(const Op &op, bool depthwise);
  void transpose_conv(const Op &op);
  void pool(const Op &op, const char *onnx_op);
  void fully_connected(const Op &op);
  void resize(const Op &op, bool bilinear);
  void strided_slice(const Op &op);
  void detection_post(const Op &op, Translation &tr);
  // Quantized ADD/SUB with a constant single-valued operand as an exact table of TFLite's
  // integer results (tflite_quant_add.cc); false when the op does not qualify.
  bool quant_add_table(const Op &op, bool sub, int fused);

  const Model &m_;
  const std::vector<std::vector<int64_t>> &in_shapes_;
  std::vector<bool> emitted_;
  std::map<int, std::vector<float>> folded_;
  onnx::Graph g_;
  int tmp_ = 0;
  int op_index_ = -1;
};

}  // namespace nns::tfl::detail

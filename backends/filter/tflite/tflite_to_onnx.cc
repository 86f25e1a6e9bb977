// SPDX-License-Identifier: LGPL-2.1-only
#include "tflite_to_onnx.h"

#include <flatbuffers/flexbuffers.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <functional>
#include <limits>
#include <map>

#include "onnx_writer.h"
#include "tflite_schema_generated.h"

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

namespace {

using onnx::attr_float;
using onnx::attr_int;
using onnx::attr_ints;
using onnx::attr_str;
using Strs = std::vector<std::string>;

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

  const Tensor &T(int t) const { return m_.tensors[t]; }
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

  const Model &m_;
  const std::vector<std::vector<int64_t>> &in_shapes_;
  std::vector<bool> emitted_;
  std::map<int, std::vector<float>> folded_;
  onnx::Graph g_;
  int tmp_ = 0;
  int op_index_ = -1;
};

void Translator::conv(const Op &op, bool depthwise) {
  need(op, 2, 1);
  int x = op.inputs[0], w = op.inputs[1], out = op.outputs[0];
  int b = op.inputs.size() > 2 ? op.inputs[2] : -1;
  need_rank(op, x, 4);
  need_rank(op, w, 4);
  int padding, sw, sh, dw, dh, fused;
  int64_t group = 1;
  if (depthwise) {
    auto *o = op.raw->builtin_options_as_DepthwiseConv2DOptions();
    if (!o) fail(op, "DepthwiseConv2DOptions missing");
    padding = o->padding(), sw = o->stride_w(), sh = o->stride_h();
    dw = o->dilation_w_factor(), dh = o->dilation_h_factor(),
    fused = o->fused_activation_function();
    group = T(x).shape[3];
    if (group <= 0 || T(w).shape[3] % group) fail(op, "weights do not match the input channels");
  } else {
    auto *o = op.raw->builtin_options_as_Conv2DOptions();
    if (!o) fail(op, "Conv2DOptions missing");
    padding = o->padding(), sw = o->stride_w(), sh = o->stride_h();
    dw = o->dilation_w_factor(), dh = o->dilation_h_factor(),
    fused = o->fused_activation_function();
    if (T(w).shape[3] > 0 && T(x).shape[3] % T(w).shape[3] == 0)
      group = T(x).shape[3] / T(w).shape[3];
  }
  if (sw <= 0 || sh <= 0 || dw <= 0 || dh <= 0) fail(op, "strides and dilations must be positive");
  std::string xi = nchw(flt(x));
  // TFLite weights: conv OHWI, depthwise 1HW(C*M); ONNX wants OIHW ((C*M)1HW).
  std::string wi = flt(w, depthwise ? std::vector<int>{3, 0, 1, 2} : std::vector<int>{0, 3, 1, 2});
  Strs in{xi, wi};
  if (b >= 0) in.push_back(flt(b));
  std::string y = fresh();
  std::vector<onnx::Msg> at{attr_ints("strides", {sh, sw}), attr_ints("dilations", {dh, dw}),
                            attr_int("group", group),
                            attr_ints("kernel_shape", {T(w).shape[1], T(w).shape[2]})};
  if (padding == 0 && (dh > 1 || dw > 1)) {
    // ORT has no SAME auto_pad with dilation: explicit pads from the declared input size.
    auto pads = [](int64_t in, int64_t k, int64_t s, int64_t d) {
      int64_t out = (in + s - 1) / s, ke = (k - 1) * d + 1;
      int64_t total = std::max<int64_t>((out - 1) * s + ke - in, 0);
      return std::pair<int64_t, int64_t>{total / 2, total - total / 2};
    };
    auto [t0, t1] = pads(T(x).shape[1], T(w).shape[1], sh, dh);
    auto [l0, l1] = pads(T(x).shape[2], T(w).shape[2], sw, dw);
    at.push_back(attr_ints("pads", {t0, l0, t1, l1}));
  } else {
    at.push_back(pad_attr(padding));
  }
  g_.node("Conv", in, {y}, at);
  store(out, nhwc(act(y, fused, op)));
}

void Translator::transpose_conv(const Op &op) {
  need(op, 3, 1);
  int shape_t = op.inputs[0], w = op.inputs[1], x = op.inputs[2], out = op.outputs[0];
  int b = op.inputs.size() > 3 ? op.inputs[3] : -1;
  need_rank(op, x, 4);
  need_rank(op, w, 4);
  auto *o = op.raw->builtin_options_as_TransposeConvOptions();
  if (!o) fail(op, "TransposeConvOptions missing");
  auto oshape = ints(op, shape_t);
  if (oshape.size() != 4) fail(op, "output_shape must have 4 values");
  std::string xi = nchw(flt(x));
  std::string wi = flt(w, {3, 0, 1, 2});  // OHWI -> IOHW
  Strs in{xi, wi};
  if (b >= 0) in.push_back(flt(b));
  std::string y = fresh();
  std::vector<onnx::Msg> at{attr_ints("strides", {o->stride_h(), o->stride_w()}),
                            attr_ints("kernel_shape", {T(w).shape[1], T(w).shape[2]}),
                            attr_ints("output_shape", {oshape[1], oshape[2]})};
  if (o->padding() == 0) at.push_back(attr_str("auto_pad", "SAME_UPPER"));
  g_.node("ConvTranspose", in, {y}, at);
  store(out, nhwc(act(y, o->fused_activation_function(), op)));
}

void Translator::pool(const Op &op, const char *onnx_op) {
  need(op, 1, 1);
  need_rank(op, op.inputs[0], 4);
  auto *o = op.raw->builtin_options_as_Pool2DOptions();
  if (!o) fail(op, "Pool2DOptions missing");
  if (o->stride_w() <= 0 || o->stride_h() <= 0 || o->filter_width() <= 0 || o->filter_height() <= 0)
    fail(op, "strides and filter sizes must be positive");
  std::string y = fresh();
  g_.node(onnx_op, {nchw(flt(op.inputs[0]))}, {y},
          {pad_attr(o->padding()), attr_ints("strides", {o->stride_h(), o->stride_w()}),
           attr_ints("kernel_shape", {o->filter_height(), o->filter_width()})});
  store(op.outputs[0], nhwc(act(y, o->fused_activation_function(), op)));
}

void Translator::fully_connected(const Op &op) {
  need(op, 2, 1);
  int x = op.inputs[0], w = op.inputs[1], out = op.outputs[0];
  int b = op.inputs.size() > 2 ? op.inputs[2] : -1;
  need_rank(op, w, 2);
  auto *o = op.raw->builtin_options_as_FullyConnectedOptions();
  int fused = o ? o->fused_activation_function() : 0;
  if (o && o->weights_format() != 0) unsupported(op, "shuffled weights");
  int64_t k = T(w).shape[1];
  std::string x2 = fresh();
  g_.node("Reshape", {flt(x), const_i64({-1, k})}, {x2});
  Strs in{x2, flt(w)};
  if (b >= 0) in.push_back(flt(b));
  std::string y = fresh();
  g_.node("Gemm", in, {y}, {attr_int("transB", 1)});
  y = act(y, fused, op);
  if (o && o->keep_num_dims()) {
    std::vector<int64_t> s(T(out).shape.begin(), T(out).shape.end());
    for (std::size_t i = 0; i + 1 < s.size(); ++i) s[i] = i == 0 ? -1 : s[i];
    std::string r = fresh();
    g_.node("Reshape", {y, const_i64(s)}, {r});
    y = r;
  }
  store(out, y);
}

void Translator::resize(const Op &op, bool bilinear) {
  need(op, 2, 1);
  need_rank(op, op.inputs[0], 4);
  auto size = ints(op, op.inputs[1]);
  if (size.size() != 2) fail(op, "size must have 2 values");
  bool align = false, half = false;
  if (bilinear) {
    if (auto *o = op.raw->builtin_options_as_ResizeBilinearOptions())
      align = o->align_corners(), half = o->half_pixel_centers();
  } else if (auto *o = op.raw->builtin_options_as_ResizeNearestNeighborOptions()) {
    align = o->align_corners(), half = o->half_pixel_centers();
  }
  int x = op.inputs[0], out = op.outputs[0];
  bool direct = !bilinear && same_q(x, out);
  std::string xi = nchw(direct ? raw(x) : flt(x));
  std::string shp = unary("Shape", xi);
  std::string nc = fresh();
  g_.node("Slice", {shp, const_i64({0}), const_i64({2})}, {nc});
  std::string sizes = fresh();
  g_.node("Concat", {nc, const_i64(size)}, {sizes}, {attr_int("axis", 0)});
  std::string mode = align  ? "align_corners"
                     : half ? (bilinear ? "half_pixel" : "tf_half_pixel_for_nn")
                            : "asymmetric";
  std::vector<onnx::Msg> at{attr_str("mode", bilinear ? "linear" : "nearest"),
                            attr_str("coordinate_transformation_mode", mode)};
  if (!bilinear) at.push_back(attr_str("nearest_mode", align ? "round_prefer_ceil" : "floor"));
  std::string y = fresh();
  g_.node("Resize", {xi, "", "", sizes}, {y}, at);
  if (direct)
    store_raw(out, nhwc(y));
  else
    store(out, nhwc(y));
}

void Translator::strided_slice(const Op &op) {
  need(op, 4, 1);
  auto *o = op.raw->builtin_options_as_StridedSliceOptions();
  int bm = o ? o->begin_mask() : 0, em = o ? o->end_mask() : 0;
  int sm = o ? o->shrink_axis_mask() : 0;
  if (o && (o->ellipsis_mask() || o->new_axis_mask() || o->offset()))
    unsupported(op, "ellipsis/new_axis masks or offset");
  auto begin = ints(op, op.inputs[1]), end = ints(op, op.inputs[2]),
       stride = ints(op, op.inputs[3]);
  if (begin.size() != end.size() || begin.size() != stride.size())
    fail(op, "begin, end and strides differ in length");
  const int64_t kMax = std::numeric_limits<int64_t>::max(),
                kMin = std::numeric_limits<int64_t>::min();
  std::vector<int64_t> axes, squeeze;
  for (std::size_t i = 0; i < begin.size(); ++i) {
    if (stride[i] == 0) fail(op, "stride 0");
    axes.push_back(static_cast<int64_t>(i));
    if (bm & (1 << i)) begin[i] = stride[i] > 0 ? 0 : kMax;
    if (sm & (1 << i)) {
      end[i] = begin[i] == -1 ? kMax : begin[i] + 1;
      stride[i] = 1;
      squeeze.push_back(static_cast<int64_t>(i));
    } else if (em & (1 << i)) {
      end[i] = stride[i] > 0 ? kMax : kMin;
    }
  }
  int x = op.inputs[0], out = op.outputs[0];
  bool direct = same_q(x, out);
  std::string y = fresh();
  g_.node("Slice",
          {direct ? raw(x) : flt(x), const_i64(begin), const_i64(end), const_i64(axes),
           const_i64(stride)},
          {y});
  if (!squeeze.empty()) y = binary("Squeeze", y, const_i64(squeeze));
  if (direct)
    store_raw(out, y);
  else
    store(out, y);
}

void Translator::detection_post(const Op &op, Translation &tr) {
  need(op, 3, 4);
  for (int o : op.outputs)
    for (const Op &other : m_.ops)
      if (std::count(other.inputs.begin(), other.inputs.end(), o))
        unsupported(op, "its outputs feed other operators");
  DetectionPost p;
  if (op.custom_options && op.custom_options_size) {
    std::vector<uint8_t> buf(op.custom_options, op.custom_options + op.custom_options_size);
    if (!flexbuffers::VerifyBuffer(buf.data(), buf.size()))
      fail(op, "custom_options is not a valid flexbuffer");
    auto map = flexbuffers::GetRoot(buf).AsMap();
    auto geti = [&](const char *k, int &v) {
      auto e = map[k];
      if (!e.IsNull()) v = static_cast<int>(e.AsInt64());
    };
    auto getf = [&](const char *k, float &v) {
      auto e = map[k];
      if (!e.IsNull()) v = e.AsFloat();
    };
    geti("max_detections", p.max_detections);
    geti("max_classes_per_detection", p.max_classes_per_detection);
    geti("detections_per_class", p.detections_per_class);
    getf("nms_score_threshold", p.nms_score_threshold);
    getf("nms_iou_threshold", p.nms_iou_threshold);
    geti("num_classes", p.num_classes);
    getf("y_scale", p.y_scale);
    getf("x_scale", p.x_scale);
    getf("h_scale", p.h_scale);
    getf("w_scale", p.w_scale);
    auto r = map["use_regular_nms"];
    if (!r.IsNull()) p.use_regular_nms = r.AsBool();
  }
  if (p.max_detections <= 0 || p.max_detections > 10000 || p.num_classes <= 0 ||
      p.num_classes > 100000 || p.max_classes_per_detection <= 0 ||
      p.max_classes_per_detection > p.num_classes || p.slots() > 100000)
    fail(op, "implausible options (max_detections " + std::to_string(p.max_detections) +
                 ", num_classes " + std::to_string(p.num_classes) + ")");
  int anchors = op.inputs[2];
  if (!is_const(anchors)) unsupported(op, "anchors must be a constant");
  const Tensor &a = T(anchors);
  if (a.shape.size() != 2 || a.shape[1] != 4) fail(op, "anchors must be [num_anchors, 4]");
  p.num_anchors = a.shape[0];
  Const c = cst(anchors);
  std::size_t n = static_cast<std::size_t>(p.num_anchors) * 4;
  p.anchors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (c.type == kFloat32) {
      std::memcpy(&p.anchors[i], c.data + 4 * i, 4);
    } else if (c.type == kUInt8 && c.q) {
      p.anchors[i] = c.q->scale[0] * (static_cast<float>(c.data[i]) - c.q->zero_point[0]);
    } else {
      unsupported(op, std::string("anchors of type ") + type_name(c.type));
    }
  }
  int boxes = op.inputs[0], scores = op.inputs[1];
  int64_t nb = T(boxes).elements(), ns = T(scores).elements();
  if (nb != int64_t{p.num_anchors} * 4 || ns % p.num_anchors ||
      ns / p.num_anchors != p.num_classes + 1)
    fail(op, "box encodings/scores do not match " + std::to_string(p.num_anchors) +
                 " anchors and " + std::to_string(p.num_classes) + " classes (+1 background)");
  p.boxes = "post_boxes";
  p.scores = "post_scores";
  g_.node("Identity", {flt(boxes)}, {p.boxes});
  g_.node("Identity", {flt(scores)}, {p.scores});
  p.outputs = op.outputs;
  p.op_index = op_index_;
  for (int o : op.outputs) emitted_[o] = true;
  tr.post = std::move(p);
}

void Translator::translate_op(const Op &op, Translation &tr) {
  using B = ::tflite::BuiltinOperator;
  const auto code = static_cast<B>(op.code);
  if (op.code == kCustom) {
    if (op.custom == "TFLite_Detection_PostProcess") return detection_post(op, tr);
    unsupported(op, "custom operator");
  }
  auto in0 = [&] { return op.inputs.at(0); };
  auto out0 = [&] { return op.outputs.at(0); };
  // Elementwise float op on dequantized inputs, result quantized as the output declares.
  auto elementwise = [&](const char *onnx_op, int nin, int fused) {
    need(op, static_cast<std::size_t>(nin), 1);
    Strs in;
    for (int i = 0; i < nin; ++i) in.push_back(flt(op.inputs[i]));
    std::string y = fresh();
    g_.node(onnx_op, in, {y});
    store(out0(), act(y, fused, op));
  };
  auto fused_of = [&]() -> int {
    switch (code) {
      case B::BuiltinOperator_ADD:
        return op.raw->builtin_options_as_AddOptions()
                   ? op.raw->builtin_options_as_AddOptions()->fused_activation_function()
                   : 0;
      case B::BuiltinOperator_SUB:
        return op.raw->builtin_options_as_SubOptions()
                   ? op.raw->builtin_options_as_SubOptions()->fused_activation_function()
                   : 0;
      case B::BuiltinOperator_MUL:
        return op.raw->builtin_options_as_MulOptions()
                   ? op.raw->builtin_options_as_MulOptions()->fused_activation_function()
                   : 0;
      case B::BuiltinOperator_DIV:
        return op.raw->builtin_options_as_DivOptions()
                   ? op.raw->builtin_options_as_DivOptions()->fused_activation_function()
                   : 0;
      default:
        return 0;
    }
  };
  // Data movement on the stored values when input and output share type and quantization.
  auto movement = [&](const std::function<std::string(const std::string &)> &f) {
    int x = in0(), out = out0();
    if (same_q(x, out))
      store_raw(out, f(raw(x)));
    else
      store(out, f(flt(x)));
  };
  switch (code) {
    case B::BuiltinOperator_CONV_2D:
      return conv(op, false);
    case B::BuiltinOperator_DEPTHWISE_CONV_2D:
      return conv(op, true);
    case B::BuiltinOperator_TRANSPOSE_CONV:
      return transpose_conv(op);
    case B::BuiltinOperator_AVERAGE_POOL_2D:
      return pool(op, "AveragePool");
    case B::BuiltinOperator_MAX_POOL_2D:
      return pool(op, "MaxPool");
    case B::BuiltinOperator_FULLY_CONNECTED:
      return fully_connected(op);
    case B::BuiltinOperator_ADD:
      return elementwise("Add", 2, fused_of());
    case B::BuiltinOperator_SUB:
      return elementwise("Sub", 2, fused_of());
    case B::BuiltinOperator_MUL:
      return elementwise("Mul", 2, fused_of());
    case B::BuiltinOperator_DIV:
      return elementwise("Div", 2, fused_of());
    case B::BuiltinOperator_MAXIMUM:
      return elementwise("Max", 2, 0);
    case B::BuiltinOperator_MINIMUM:
      return elementwise("Min", 2, 0);
    case B::BuiltinOperator_POW:
      return elementwise("Pow", 2, 0);
    case B::BuiltinOperator_PRELU:
      return elementwise("PRelu", 2, 0);
    case B::BuiltinOperator_LOGISTIC:
      return elementwise("Sigmoid", 1, 0);
    case B::BuiltinOperator_TANH:
      return elementwise("Tanh", 1, 0);
    case B::BuiltinOperator_RELU:
      return elementwise("Relu", 1, 0);
    case B::BuiltinOperator_HARD_SWISH:
      return elementwise("HardSwish", 1, 0);
    case B::BuiltinOperator_EXP:
      return elementwise("Exp", 1, 0);
    case B::BuiltinOperator_LOG:
      return elementwise("Log", 1, 0);
    case B::BuiltinOperator_SQRT:
      return elementwise("Sqrt", 1, 0);
    case B::BuiltinOperator_ABS:
      return elementwise("Abs", 1, 0);
    case B::BuiltinOperator_NEG:
      return elementwise("Neg", 1, 0);
    case B::BuiltinOperator_FLOOR:
      return elementwise("Floor", 1, 0);
    case B::BuiltinOperator_CEIL:
      return elementwise("Ceil", 1, 0);
    case B::BuiltinOperator_ELU:
      return elementwise("Elu", 1, 0);
    case B::BuiltinOperator_SIN:
      return elementwise("Sin", 1, 0);
    case B::BuiltinOperator_COS:
      return elementwise("Cos", 1, 0);
    case B::BuiltinOperator_RSQRT: {
      need(op, 1, 1);
      return store(out0(), unary("Reciprocal", unary("Sqrt", flt(in0()))));
    }
    case B::BuiltinOperator_SQUARE: {
      need(op, 1, 1);
      std::string x = flt(in0());
      return store(out0(), binary("Mul", x, x));
    }
    case B::BuiltinOperator_SQUARED_DIFFERENCE: {
      need(op, 2, 1);
      std::string d = binary("Sub", flt(op.inputs[0]), flt(op.inputs[1]));
      return store(out0(), binary("Mul", d, d));
    }
    case B::BuiltinOperator_FLOOR_DIV: {
      need(op, 2, 1);
      std::string d = unary("Floor", binary("Div", flt(op.inputs[0]), flt(op.inputs[1])));
      return store(out0(), d);
    }
    case B::BuiltinOperator_RELU6:
      need(op, 1, 1);
      return store(out0(), act(flt(in0()), 3, op));
    case B::BuiltinOperator_RELU_N1_TO_1:
      need(op, 1, 1);
      return store(out0(), act(flt(in0()), 2, op));
    case B::BuiltinOperator_LEAKY_RELU: {
      need(op, 1, 1);
      auto *o = op.raw->builtin_options_as_LeakyReluOptions();
      return store(out0(),
                   unary("LeakyRelu", flt(in0()), {attr_float("alpha", o ? o->alpha() : 0.2f)}));
    }
    case B::BuiltinOperator_SOFTMAX:
    case B::BuiltinOperator_LOG_SOFTMAX: {
      need(op, 1, 1);
      std::string x = flt(in0());
      if (code == B::BuiltinOperator_SOFTMAX) {
        auto *o = op.raw->builtin_options_as_SoftmaxOptions();
        float beta = o ? o->beta() : 1.f;
        if (beta != 1.f) x = binary("Mul", x, const_f32({beta}, true));
      }
      return store(out0(), unary(code == B::BuiltinOperator_SOFTMAX ? "Softmax" : "LogSoftmax", x,
                                 {attr_int("axis", -1)}));
    }
    case B::BuiltinOperator_CONCATENATION: {
      need(op, 1, 1);
      auto *o = op.raw->builtin_options_as_ConcatenationOptions();
      int axis = norm_axis(o ? o->axis() : 0, rank(out0()));
      Strs in;
      for (int t : op.inputs) in.push_back(flt(t));
      std::string y = fresh();
      g_.node("Concat", in, {y}, {attr_int("axis", axis)});
      return store(out0(), act(y, o ? o->fused_activation_function() : 0, op));
    }
    case B::BuiltinOperator_PACK: {
      need(op, 1, 1);
      auto *o = op.raw->builtin_options_as_PackOptions();
      int axis = norm_axis(o ? o->axis() : 0, rank(out0()));
      Strs in;
      for (int t : op.inputs) in.push_back(binary("Unsqueeze", flt(t), const_i64({axis})));
      std::string y = fresh();
      g_.node("Concat", in, {y}, {attr_int("axis", axis)});
      return store(out0(), y);
    }
    case B::BuiltinOperator_UNPACK: {
      need(op, 1, 1);
      auto *o = op.raw->builtin_options_as_UnpackOptions();
      int axis = norm_axis(o ? o->axis() : 0, rank(in0()));
      Strs parts;
      for (std::size_t i = 0; i < op.outputs.size(); ++i) parts.push_back(fresh());
      g_.node("Split", {flt(in0())}, parts, {attr_int("axis", axis)});
      for (std::size_t i = 0; i < op.outputs.size(); ++i)
        store(op.outputs[i], binary("Squeeze", parts[i], const_i64({axis})));
      return;
    }
    case B::BuiltinOperator_SPLIT:
    case B::BuiltinOperator_SPLIT_V: {
      bool v = code == B::BuiltinOperator_SPLIT_V;
      need(op, v ? 3 : 2, 1);
      int data = v ? op.inputs[0] : op.inputs[1];
      auto ax = ints(op, v ? op.inputs[2] : op.inputs[0]);
      if (ax.size() != 1) fail(op, "axis must be one value");
      Strs in{flt(data)}, parts;
      if (v) in.push_back(const_i64(ints(op, op.inputs[1])));
      for (std::size_t i = 0; i < op.outputs.size(); ++i) parts.push_back(fresh());
      g_.node("Split", in, parts, {attr_int("axis", norm_axis(ax[0], rank(data)))});
      for (std::size_t i = 0; i < op.outputs.size(); ++i) store(op.outputs[i], parts[i]);
      return;
    }
    case B::BuiltinOperator_MEAN:
    case B::BuiltinOperator_SUM:
    case B::BuiltinOperator_REDUCE_MAX:
    case B::BuiltinOperator_REDUCE_MIN:
    case B::BuiltinOperator_REDUCE_PROD: {
      need(op, 2, 1);
      auto *o = op.raw->builtin_options_as_ReducerOptions();
      auto axes = ints(op, op.inputs[1]);
      for (auto &a : axes) a = norm_axis(a, rank(in0()));
      bool keep = o && o->keep_dims();
      std::string y = fresh();
      if (code == B::BuiltinOperator_SUM) {
        g_.node("ReduceSum", {flt(in0()), const_i64(axes)}, {y}, {attr_int("keepdims", keep)});
      } else {
        const char *n = code == B::BuiltinOperator_MEAN         ? "ReduceMean"
                        : code == B::BuiltinOperator_REDUCE_MAX ? "ReduceMax"
                        : code == B::BuiltinOperator_REDUCE_MIN ? "ReduceMin"
                                                                : "ReduceProd";
        g_.node(n, {flt(in0())}, {y}, {attr_ints("axes", axes), attr_int("keepdims", keep)});
      }
      return store(out0(), y);
    }
    case B::BuiltinOperator_RESHAPE: {
      need(op, 1, 1);
      std::vector<int64_t> s;
      if (op.inputs.size() > 1 && op.inputs[1] >= 0 && T(op.inputs[1]).is_const()) {
        s = ints(op, op.inputs[1]);
      } else if (auto *o = op.raw->builtin_options_as_ReshapeOptions(); o && o->new_shape()) {
        s.assign(o->new_shape()->begin(), o->new_shape()->end());
      } else if (op.inputs.size() > 1 && op.inputs[1] >= 0) {
        std::string sh = unary("Cast", raw(op.inputs[1]), {attr_int("to", onnx::kInt64)});
        return movement([&](const std::string &x) { return binary("Reshape", x, sh); });
      } else {
        s.assign(T(out0()).shape.begin(), T(out0()).shape.end());
      }
      std::string sh = const_i64(s);
      return movement([&](const std::string &x) { return binary("Reshape", x, sh); });
    }
    case B::BuiltinOperator_SQUEEZE: {
      need(op, 1, 1);
      std::vector<int64_t> axes;
      if (auto *o = op.raw->builtin_options_as_SqueezeOptions(); o && o->squeeze_dims())
        for (int a : *o->squeeze_dims()) axes.push_back(norm_axis(a, rank(in0())));
      if (axes.empty())
        for (int i = 0; i < rank(in0()); ++i)
          if (T(in0()).shape[i] == 1) axes.push_back(i);
      std::string ax = const_i64(axes);
      return movement([&](const std::string &x) { return binary("Squeeze", x, ax); });
    }
    case B::BuiltinOperator_EXPAND_DIMS: {
      need(op, 2, 1);
      auto a = ints(op, op.inputs[1]);
      if (a.size() != 1) fail(op, "axis must be one value");
      std::string ax = const_i64({a[0] < 0 ? a[0] + rank(in0()) + 1 : a[0]});
      return movement([&](const std::string &x) { return binary("Unsqueeze", x, ax); });
    }
    case B::BuiltinOperator_TRANSPOSE: {
      need(op, 2, 1);
      auto perm = ints(op, op.inputs[1]);
      return movement(
          [&](const std::string &x) { return unary("Transpose", x, {attr_ints("perm", perm)}); });
    }
    case B::BuiltinOperator_PAD:
    case B::BuiltinOperator_PADV2:
    case B::BuiltinOperator_MIRROR_PAD: {
      need(op, 2, 1);
      auto p = ints(op, op.inputs[1]);
      int r = rank(in0());
      if (static_cast<int>(p.size()) != 2 * r) fail(op, "paddings must be [rank, 2]");
      std::vector<int64_t> pads(2 * r);
      for (int i = 0; i < r; ++i) pads[i] = p[2 * i], pads[r + i] = p[2 * i + 1];
      std::string pn = const_i64(pads);
      if (code == B::BuiltinOperator_MIRROR_PAD) {
        auto *o = op.raw->builtin_options_as_MirrorPadOptions();
        if (o && o->mode() != 0) unsupported(op, "SYMMETRIC mode");
        std::string y = fresh();
        g_.node("Pad", {flt(in0()), pn}, {y}, {attr_str("mode", "reflect")});
        return store(out0(), y);
      }
      int x = in0(), out = out0();
      if (same_q(x, out)) {
        Strs in{raw(x), pn};
        if (code == B::BuiltinOperator_PADV2 && op.inputs.size() > 2 && op.inputs[2] >= 0)
          in.push_back(raw(op.inputs[2]));
        else if (is_quant(x))
          in.push_back(qparams_zp(Quant{{1.f}, {T(x).q.zero_point[0]}, 0}, T(x).type));
        std::string y = fresh();
        g_.node("Pad", in, {y});
        return store_raw(out, y);
      }
      Strs in{flt(x), pn};
      if (code == B::BuiltinOperator_PADV2 && op.inputs.size() > 2 && op.inputs[2] >= 0)
        in.push_back(binary("Reshape", flt(op.inputs[2]), const_i64({})));
      std::string y = fresh();
      g_.node("Pad", in, {y});
      return store(out, y);
    }
    case B::BuiltinOperator_RESIZE_BILINEAR:
      return resize(op, true);
    case B::BuiltinOperator_RESIZE_NEAREST_NEIGHBOR:
      return resize(op, false);
    case B::BuiltinOperator_STRIDED_SLICE:
      return strided_slice(op);
    case B::BuiltinOperator_SLICE: {
      need(op, 3, 1);
      auto begin = ints(op, op.inputs[1]), size = ints(op, op.inputs[2]);
      if (begin.size() != size.size()) fail(op, "begin and size differ in length");
      std::vector<int64_t> end(begin.size()), axes(begin.size());
      for (std::size_t i = 0; i < begin.size(); ++i) {
        end[i] = size[i] < 0 ? std::numeric_limits<int64_t>::max() : begin[i] + size[i];
        axes[i] = static_cast<int64_t>(i);
      }
      std::string b = const_i64(begin), e = const_i64(end), a = const_i64(axes);
      return movement([&](const std::string &x) {
        std::string y = fresh();
        g_.node("Slice", {x, b, e, a}, {y});
        return y;
      });
    }
    case B::BuiltinOperator_GATHER: {
      need(op, 2, 1);
      auto *o = op.raw->builtin_options_as_GatherOptions();
      if (o && o->batch_dims() != 0) unsupported(op, "batch_dims");
      int axis = norm_axis(o ? o->axis() : 0, rank(in0()));
      std::string idx = raw(op.inputs[1]);
      return movement([&](const std::string &x) {
        std::string y = fresh();
        g_.node("Gather", {x, idx}, {y}, {attr_int("axis", axis)});
        return y;
      });
    }
    case B::BuiltinOperator_GATHER_ND: {
      need(op, 2, 1);
      std::string idx = unary("Cast", raw(op.inputs[1]), {attr_int("to", onnx::kInt64)});
      return movement([&](const std::string &x) { return binary("GatherND", x, idx); });
    }
    case B::BuiltinOperator_TILE: {
      need(op, 2, 1);
      std::string rep = unary("Cast", raw(op.inputs[1]), {attr_int("to", onnx::kInt64)});
      return movement([&](const std::string &x) { return binary("Tile", x, rep); });
    }
    case B::BuiltinOperator_DEPTH_TO_SPACE:
    case B::BuiltinOperator_SPACE_TO_DEPTH: {
      need(op, 1, 1);
      need_rank(op, in0(), 4);
      int bs = code == B::BuiltinOperator_DEPTH_TO_SPACE
                   ? (op.raw->builtin_options_as_DepthToSpaceOptions()
                          ? op.raw->builtin_options_as_DepthToSpaceOptions()->block_size()
                          : 0)
                   : (op.raw->builtin_options_as_SpaceToDepthOptions()
                          ? op.raw->builtin_options_as_SpaceToDepthOptions()->block_size()
                          : 0);
      if (bs <= 0) fail(op, "block_size must be positive");
      const char *n = code == B::BuiltinOperator_DEPTH_TO_SPACE ? "DepthToSpace" : "SpaceToDepth";
      std::vector<onnx::Msg> at{attr_int("blocksize", bs)};
      if (code == B::BuiltinOperator_DEPTH_TO_SPACE) at.push_back(attr_str("mode", "DCR"));
      return movement([&](const std::string &x) { return nhwc(unary(n, nchw(x), at)); });
    }
    case B::BuiltinOperator_CAST: {
      need(op, 1, 1);
      int ot = onnx_type(T(out0()).type);
      if (!ot) unsupported(op, std::string("cast to ") + type_name(T(out0()).type));
      return store_raw(out0(), unary("Cast", raw(in0()), {attr_int("to", ot)}));
    }
    case B::BuiltinOperator_BROADCAST_ARGS: {  // broadcast shape of two shape vectors
      need(op, 2, 1);
      auto zeros = [&](int t) {
        return unary("ConstantOfShape", unary("Cast", raw(t), {attr_int("to", onnx::kInt64)}));
      };
      std::string y = unary("Shape", binary("Add", zeros(op.inputs[0]), zeros(op.inputs[1])));
      return store_raw(out0(), unary("Cast", y, {attr_int("to", onnx_type(T(out0()).type))}));
    }
    case B::BuiltinOperator_BROADCAST_TO: {
      need(op, 2, 1);
      std::string shape = unary("Cast", raw(op.inputs[1]), {attr_int("to", onnx::kInt64)});
      return movement([&](const std::string &x) { return binary("Expand", x, shape); });
    }
    case B::BuiltinOperator_SHAPE: {
      need(op, 1, 1);
      std::string y = unary("Shape", raw(in0()));
      if (T(out0()).type == kInt64) return store_raw(out0(), y);
      return store_raw(out0(), unary("Cast", y, {attr_int("to", onnx_type(T(out0()).type))}));
    }
    case B::BuiltinOperator_QUANTIZE:
      need(op, 1, 1);
      return store(out0(), flt(in0()));
    case B::BuiltinOperator_DEQUANTIZE: {
      need(op, 1, 1);
      int x = in0(), out = out0();
      if (is_const(x) && !folded_.count(x)) {  // constant weights: fold once here
        Const c = cst(x);
        std::vector<float> f(static_cast<std::size_t>(T(x).elements()));
        const Quant *q = c.q;
        int64_t inner = 1, ch = 1;
        if (q && q->scale.size() > 1) {
          for (std::size_t i = q->axis + 1; i < c.shape.size(); ++i) inner *= c.shape[i];
          ch = c.shape[q->axis];
        }
        for (std::size_t i = 0; i < f.size(); ++i) {
          std::size_t qi = q && q->scale.size() > 1 ? (i / inner) % ch : 0;
          switch (c.type) {
            case kFloat16: {
              uint16_t h;
              std::memcpy(&h, c.data + 2 * i, 2);
              f[i] = half_to_float(h);
              break;
            }
            case kUInt8:
              f[i] = q ? q->scale[qi] * (static_cast<float>(c.data[i]) - q->zero_point[qi])
                       : c.data[i];
              break;
            case kInt8:
              f[i] = q ? q->scale[qi] * (static_cast<float>(static_cast<int8_t>(c.data[i])) -
                                         q->zero_point[qi])
                       : static_cast<int8_t>(c.data[i]);
              break;
            default:
              unsupported(op, std::string("constant of type ") + type_name(c.type));
          }
        }
        folded_[out] = std::move(f);
        return;
      }
      return store(out, flt(x));
    }
    case B::BuiltinOperator_ARG_MAX:
    case B::BuiltinOperator_ARG_MIN: {
      need(op, 2, 1);
      auto ax = ints(op, op.inputs[1]);
      if (ax.size() != 1) fail(op, "axis must be one value");
      std::string y =
          unary(code == B::BuiltinOperator_ARG_MAX ? "ArgMax" : "ArgMin", flt(in0()),
                {attr_int("axis", norm_axis(ax[0], rank(in0()))), attr_int("keepdims", 0)});
      if (T(out0()).type == kInt64) return store_raw(out0(), y);
      return store_raw(out0(), unary("Cast", y, {attr_int("to", onnx_type(T(out0()).type))}));
    }
    default:
      unsupported(op);
  }
}

}  // namespace

Translation translate(const Model &m, const std::vector<std::vector<int64_t>> &input_shapes) {
  return Translator(m, input_shapes).run();
}

}  // namespace nns::tfl

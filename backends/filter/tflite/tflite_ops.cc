// SPDX-License-Identifier: LGPL-2.1-only
// The per-operator switch of the TFLite -> ONNX translation.
#include "tflite_translator.h"

namespace nns::tfl::detail {

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
      if (quant_add_table(op, false, fused_of())) return;
      return elementwise("Add", 2, fused_of());
    case B::BuiltinOperator_SUB:
      if (quant_add_table(op, true, fused_of())) return;
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
        if (!o || o->mode() == 0) {  // REFLECT: the edge is not repeated
          std::string y = fresh();
          g_.node("Pad", {flt(in0()), pn}, {y}, {attr_str("mode", "reflect")});
          return store(out0(), y);
        }
        // SYMMETRIC (edge repeated) has no ONNX Pad mode: one Gather per padded axis, indices
        // from the input's shape (a model input's as given to this translation; an inner
        // tensor's as the model declares it).
        std::vector<int64_t> dims(T(in0()).shape.begin(), T(in0()).shape.end());
        for (std::size_t k = 0; k < m_.inputs.size(); ++k)
          if (m_.inputs[k] == in0() && in_shapes_[k].size() == dims.size()) dims = in_shapes_[k];
        return movement([&](const std::string &x) {
          std::string y = x;
          for (int i = 0; i < r; ++i) {
            const int64_t n = dims[i], before = p[2 * i], after = p[2 * i + 1];
            if (before == 0 && after == 0) continue;
            if (before < 0 || after < 0 || before > n || after > n)
              fail(op, "SYMMETRIC paddings must be 0.." + std::to_string(n) + " on axis " +
                           std::to_string(i));
            std::vector<int64_t> idx;
            for (int64_t j = -before; j < n + after; ++j)
              idx.push_back(j < 0 ? -j - 1 : j >= n ? 2 * n - 1 - j : j);
            std::string z = fresh();
            g_.node("Gather", {y, const_i64(idx)}, {z}, {attr_int("axis", i)});
            y = z;
          }
          return y;
        });
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

}  // namespace nns::tfl::detail

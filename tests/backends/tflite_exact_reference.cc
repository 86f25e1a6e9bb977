// SPDX-License-Identifier: LGPL-2.1-only
// See tflite_exact_reference.h.
#include "tflite_exact_reference.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <map>
#include <stdexcept>
#include <string>

#include "tflite_schema_generated.h"

namespace nns::test {
namespace {

using nns::tfl::Model;
using nns::tfl::Op;
using nns::tfl::Tensor;

struct Range {
  int lo, hi;
};

Range type_range(const Tensor &t) {
  if (t.type == nns::tfl::kUInt8) return {0, 255};
  if (t.type == nns::tfl::kInt8) return {-128, 127};
  throw std::runtime_error("tensor '" + t.name + "' is " + nns::tfl::type_name(t.type) +
                           ", the exact reference handles uint8/int8 only");
}

// Quantization parameter c of t (per-tensor when it has one).
float scale_of(const Tensor &t, std::size_t c = 0) {
  if (!t.q.present()) throw std::runtime_error("tensor '" + t.name + "' is not quantized");
  return t.q.scale[t.q.scale.size() == 1 ? 0 : c];
}
int zp_of(const Tensor &t, std::size_t c = 0) {
  if (t.q.zero_point.empty()) return 0;
  return static_cast<int>(t.q.zero_point[t.q.zero_point.size() == 1 ? 0 : c]);
}

// Stored values of a constant or computed tensor, widened to int.
std::vector<int> const_values(const Tensor &t) {
  if (!t.is_const()) throw std::runtime_error("tensor '" + t.name + "' must be a constant");
  std::vector<int> v(static_cast<std::size_t>(t.elements()));
  for (std::size_t i = 0; i < v.size(); ++i) {
    if (t.type == nns::tfl::kUInt8) {
      v[i] = t.data[i];
    } else if (t.type == nns::tfl::kInt8) {
      v[i] = static_cast<int8_t>(t.data[i]);
    } else if (t.type == nns::tfl::kInt32) {
      int32_t e;
      std::memcpy(&e, t.data + 4 * i, 4);
      v[i] = e;
    } else {
      throw std::runtime_error("constant '" + t.name + "' has type " + nns::tfl::type_name(t.type));
    }
  }
  return v;
}

// The real value `r` after fused activation `act`, quantized as t declares.
int quantize(double r, int act, const Tensor &t) {
  switch (act) {
    case 0:
      break;
    case 1:
      r = std::max(r, 0.0);
      break;
    case 2:
      r = std::clamp(r, -1.0, 1.0);
      break;
    case 3:
      r = std::clamp(r, 0.0, 6.0);
      break;
    default:
      throw std::runtime_error("fused activation " + std::to_string(act));
  }
  Range rg = type_range(t);
  double q = std::round(r / static_cast<double>(scale_of(t))) + zp_of(t);  // half away from 0
  return static_cast<int>(std::clamp(q, double(rg.lo), double(rg.hi)));
}

int same_pad(int in, int out, int k, int s, int d) {
  int total = std::max((out - 1) * s + (k - 1) * d + 1 - in, 0);
  return total / 2;
}

class Runner {
 public:
  explicit Runner(const Model &m) : m_(m) {}

  std::vector<int> run(const std::vector<uint8_t> &input) {
    if (m_.inputs.size() != 1 || m_.outputs.empty())
      throw std::runtime_error("the exact reference needs one input");
    const Tensor &in = m_.tensors.at(m_.inputs[0]);
    Range rg = type_range(in);
    if (input.size() != static_cast<std::size_t>(in.elements()))
      throw std::runtime_error("input size " + std::to_string(input.size()) + ", expected " +
                               std::to_string(in.elements()));
    std::vector<int> &x = vals_[m_.inputs[0]];
    for (uint8_t b : input) x.push_back(rg.lo < 0 ? static_cast<int8_t>(b) : b);
    for (const Op &op : m_.ops) step(op);
    return vals_.at(m_.outputs[0]);
  }

 private:
  const Tensor &T(int t) const { return m_.tensors.at(t); }
  const std::vector<int> &V(int t) {
    auto it = vals_.find(t);
    if (it == vals_.end()) throw std::runtime_error("tensor '" + T(t).name + "' is not computed");
    return it->second;
  }

  void step(const Op &op) {
    using B = tflite::BuiltinOperator;
    switch (static_cast<B>(op.code)) {
      case B::BuiltinOperator_CONV_2D:
        return conv(op, false);
      case B::BuiltinOperator_DEPTHWISE_CONV_2D:
        return conv(op, true);
      case B::BuiltinOperator_ADD:
        return add(op);
      case B::BuiltinOperator_AVERAGE_POOL_2D:
        return avg_pool(op);
      case B::BuiltinOperator_RESHAPE:
      case B::BuiltinOperator_SQUEEZE: {
        int x = op.inputs.at(0), y = op.outputs.at(0);
        const Tensor &a = T(x), &b = T(y);
        if (a.type != b.type || a.q.scale != b.q.scale || a.q.zero_point != b.q.zero_point)
          throw std::runtime_error(op.name() + " with requantization");
        vals_[y] = V(x);
        return;
      }
      default:
        throw std::runtime_error("operator " + op.name() + " is not in the exact reference");
    }
  }

  void conv(const Op &op, bool depthwise) {
    int xi = op.inputs.at(0), wi = op.inputs.at(1), yi = op.outputs.at(0);
    int bi = op.inputs.size() > 2 ? op.inputs[2] : -1;
    const Tensor &xt = T(xi), &wt = T(wi), &yt = T(yi);
    int padding, sw, sh, dw, dh, act;
    if (depthwise) {
      auto *o = op.raw->builtin_options_as_DepthwiseConv2DOptions();
      if (!o) throw std::runtime_error("DepthwiseConv2DOptions missing");
      padding = o->padding(), sw = o->stride_w(), sh = o->stride_h();
      dw = o->dilation_w_factor(), dh = o->dilation_h_factor(),
      act = o->fused_activation_function();
    } else {
      auto *o = op.raw->builtin_options_as_Conv2DOptions();
      if (!o) throw std::runtime_error("Conv2DOptions missing");
      padding = o->padding(), sw = o->stride_w(), sh = o->stride_h();
      dw = o->dilation_w_factor(), dh = o->dilation_h_factor(),
      act = o->fused_activation_function();
    }
    const int H = xt.shape[1], W = xt.shape[2], C = xt.shape[3];
    const int OH = yt.shape[1], OW = yt.shape[2], OC = yt.shape[3];
    const int KH = wt.shape[1], KW = wt.shape[2], WC = wt.shape[3];
    if (!depthwise && WC != C) throw std::runtime_error("grouped CONV_2D");
    if (WC > 16384) throw std::runtime_error("more than 16384 input channels");
    if (depthwise && (C <= 0 || OC % C)) throw std::runtime_error("depth multiplier");
    const int mult = depthwise ? OC / C : 1, group_in = depthwise ? 1 : WC;
    const int pt = padding == 0 ? same_pad(H, OH, KH, sh, dh) : 0;
    const int pl = padding == 0 ? same_pad(W, OW, KW, sw, dw) : 0;
    // Centred values: the padding contributes zero, as the input's zero point.
    std::vector<int> x = V(xi), w = const_values(wt), b;
    for (int &v : x) v -= zp_of(xt);
    const std::size_t wcount = w.size();
    for (std::size_t i = 0; i < wcount; ++i) {
      std::size_t oc = depthwise ? i % static_cast<std::size_t>(OC) : i / (wcount / OC);
      w[i] -= zp_of(wt, oc);
    }
    if (bi >= 0) b = const_values(T(bi));
    std::vector<int> &y = vals_[yi];
    y.assign(static_cast<std::size_t>(OH) * OW * OC, 0);
    for (int oy = 0; oy < OH; ++oy)
      for (int ox = 0; ox < OW; ++ox)
        for (int oc = 0; oc < OC; ++oc) {
          int64_t acc = 0;
          for (int ky = 0; ky < KH; ++ky) {
            int iy = oy * sh - pt + ky * dh;
            if (iy < 0 || iy >= H) continue;
            for (int kx = 0; kx < KW; ++kx) {
              int ix = ox * sw - pl + kx * dw;
              if (ix < 0 || ix >= W) continue;
              const int *xp = &x[(static_cast<std::size_t>(iy) * W + ix) * C];
              if (depthwise) {
                acc +=
                    int64_t{xp[oc / mult]} * w[(static_cast<std::size_t>(ky) * KW + kx) * OC + oc];
              } else {
                const int *wp = &w[((static_cast<std::size_t>(oc) * KH + ky) * KW + kx) * WC];
                int32_t s = 0;  // |x|,|w| <= 255: a row of WC <= 16384 products fits
                for (int ic = 0; ic < group_in; ++ic) s += xp[ic] * wp[ic];
                acc += s;
              }
            }
          }
          double real = static_cast<double>(scale_of(xt)) * scale_of(wt, oc) * acc;
          if (!b.empty()) real += static_cast<double>(scale_of(T(bi), oc)) * b.at(oc);
          y[(static_cast<std::size_t>(oy) * OW + ox) * OC + oc] = quantize(real, act, yt);
        }
  }

  void add(const Op &op) {
    int ai = op.inputs.at(0), bi = op.inputs.at(1), yi = op.outputs.at(0);
    const std::vector<int> &a = V(ai), &b = V(bi);
    if (a.size() != b.size()) throw std::runtime_error("ADD with broadcasting");
    auto *o = op.raw->builtin_options_as_AddOptions();
    int act = o ? o->fused_activation_function() : 0;
    double sa = scale_of(T(ai)), sb = scale_of(T(bi));
    int za = zp_of(T(ai)), zb = zp_of(T(bi));
    std::vector<int> &y = vals_[yi];
    y.resize(a.size());
    for (std::size_t i = 0; i < a.size(); ++i)
      y[i] = quantize(sa * (a[i] - za) + sb * (b[i] - zb), act, T(yi));
  }

  void avg_pool(const Op &op) {
    int xi = op.inputs.at(0), yi = op.outputs.at(0);
    const Tensor &xt = T(xi), &yt = T(yi);
    auto *o = op.raw->builtin_options_as_Pool2DOptions();
    if (!o) throw std::runtime_error("Pool2DOptions missing");
    const int H = xt.shape[1], W = xt.shape[2], C = xt.shape[3];
    const int OH = yt.shape[1], OW = yt.shape[2];
    const int KH = o->filter_height(), KW = o->filter_width();
    const int sh = o->stride_h(), sw = o->stride_w();
    const int pt = o->padding() == 0 ? same_pad(H, OH, KH, sh, 1) : 0;
    const int pl = o->padding() == 0 ? same_pad(W, OW, KW, sw, 1) : 0;
    const std::vector<int> &x = V(xi);
    std::vector<int> &y = vals_[yi];
    y.assign(static_cast<std::size_t>(OH) * OW * C, 0);
    for (int oy = 0; oy < OH; ++oy)
      for (int ox = 0; ox < OW; ++ox)
        for (int c = 0; c < C; ++c) {
          int64_t sum = 0, n = 0;  // padding is not counted, as TFLite
          for (int iy = std::max(oy * sh - pt, 0); iy < std::min(oy * sh - pt + KH, H); ++iy)
            for (int ix = std::max(ox * sw - pl, 0); ix < std::min(ox * sw - pl + KW, W); ++ix) {
              sum += x[(static_cast<std::size_t>(iy) * W + ix) * C + c] - zp_of(xt);
              ++n;
            }
          double real = n ? static_cast<double>(scale_of(xt)) * static_cast<double>(sum) / n : 0;
          y[(static_cast<std::size_t>(oy) * OW + ox) * C + c] =
              quantize(real, o->fused_activation_function(), yt);
        }
  }

  const Model &m_;
  std::map<int, std::vector<int>> vals_;
};

}  // namespace

std::vector<int> exact_quantized_run(const nns::tfl::Model &m, const std::vector<uint8_t> &input) {
  return Runner(m).run(input);
}

}  // namespace nns::test

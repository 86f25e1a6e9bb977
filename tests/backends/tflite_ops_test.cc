// SPDX-License-Identifier: LGPL-2.1-only
// The tflite back end (libnnstreamer_filter_tensorflow2-lite.so) on generated one-op models
// (tflite_builder.h), each against a scalar reference written here: float within 1e-5
// relative, quantized within one quantization step.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <functional>
#include <numeric>

#include <flatbuffers/flexbuffers.h>

#include "backends/tflite_op_util.h"

namespace nns::test {
namespace {

using namespace tflite_ops;

// NHWC conv reference (TFLite padding semantics), weights OHWI (depthwise: 1HW(C*M)).
std::vector<float> conv_ref(const std::vector<float> &x, int H, int W, int C,
                            const std::vector<float> &w, int O, int KH, int KW,
                            const std::vector<float> &b, int sh, int sw, bool same, bool dw,
                            int *OH, int *OW) {
  int oh = same ? (H + sh - 1) / sh : (H - KH) / sh + 1;
  int ow = same ? (W + sw - 1) / sw : (W - KW) / sw + 1;
  int pt = same ? std::max((oh - 1) * sh + KH - H, 0) / 2 : 0;
  int pl = same ? std::max((ow - 1) * sw + KW - W, 0) / 2 : 0;
  std::vector<float> y(static_cast<std::size_t>(oh * ow * O));
  for (int oy = 0; oy < oh; ++oy)
    for (int ox = 0; ox < ow; ++ox)
      for (int o = 0; o < O; ++o) {
        float s = b.empty() ? 0.f : b[o];
        for (int ky = 0; ky < KH; ++ky)
          for (int kx = 0; kx < KW; ++kx) {
            int iy = oy * sh + ky - pt, ix = ox * sw + kx - pl;
            if (iy < 0 || ix < 0 || iy >= H || ix >= W) continue;
            if (dw) {
              int c = o / (O / C);
              s += x[(iy * W + ix) * C + c] * w[(ky * KW + kx) * O + o];
            } else {
              for (int c = 0; c < C; ++c)
                s += x[(iy * W + ix) * C + c] * w[((o * KH + ky) * KW + kx) * C + c];
            }
          }
        y[(oy * ow + ox) * O + o] = s;
      }
  *OH = oh;
  *OW = ow;
  return y;
}

TEST(TfliteOps, Conv2DSameStride2BiasRelu6) {
  REQUIRE_TFLITE();
  const int H = 7, W = 6, C = 3, O = 4, K = 3;
  auto x = ramp(H * W * C), w = ramp(O * K * K * C, 0.05f, -0.5f), b = ramp(O, 0.3f, -0.2f);
  int oh, ow;
  auto want = conv_ref(x, H, W, C, w, O, K, K, b, 2, 2, true, false, &oh, &ow);
  for (auto &v : want) v = std::min(6.f, std::max(0.f, v));
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, H, W, C});
  int wi = t.constant("w", TT::TensorType_FLOAT32, {O, K, K, C}, w);
  int bi = t.constant("b", TT::TensorType_FLOAT32, {O}, b);
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, oh, ow, O});
  auto opt = tflite::CreateConv2DOptions(t.fb(), tflite::Padding_SAME, 2, 2,
                                         tflite::ActivationFunctionType_RELU6);
  t.op(tflite::BuiltinOperator_CONV_2D, {xi, wi, bi}, {yi}, tflite::BuiltinOptions_Conv2DOptions,
       opt.Union());
  auto out = run(t.finish({xi}, {yi}), {bytes_of(x)});
  ASSERT_EQ(out.size(), 1u);
  expect_near(values_of<float>(out[0]), want);
}

TEST(TfliteOps, DepthwiseConvValidMultiplier2) {
  REQUIRE_TFLITE();
  const int H = 5, W = 5, C = 2, M = 2, K = 3;
  auto x = ramp(H * W * C), w = ramp(K * K * C * M, 0.07f, -0.4f), b = ramp(C * M);
  int oh, ow;
  auto want = conv_ref(x, H, W, C, w, C * M, K, K, b, 1, 1, false, true, &oh, &ow);
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, H, W, C});
  int wi = t.constant("w", TT::TensorType_FLOAT32, {1, K, K, C * M}, w);
  int bi = t.constant("b", TT::TensorType_FLOAT32, {C * M}, b);
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, oh, ow, C * M});
  auto opt = tflite::CreateDepthwiseConv2DOptions(t.fb(), tflite::Padding_VALID, 1, 1, M);
  t.op(tflite::BuiltinOperator_DEPTHWISE_CONV_2D, {xi, wi, bi}, {yi},
       tflite::BuiltinOptions_DepthwiseConv2DOptions, opt.Union());
  auto out = run(t.finish({xi}, {yi}), {bytes_of(x)});
  ASSERT_EQ(out.size(), 1u);
  expect_near(values_of<float>(out[0]), want);
}

// uint8 conv, per-tensor quantization: within one output step of the float reference.
TEST(TfliteOps, QuantizedConvUint8) {
  REQUIRE_TFLITE();
  const int H = 6, W = 6, C = 3, O = 5, K = 3;
  const float sx = 0.02f, sw = 0.01f, sy = 0.05f;
  const int zx = 128, zw = 120, zy = 10;
  std::vector<uint8_t> xq(H * W * C), wq(O * K * K * C);
  for (std::size_t i = 0; i < xq.size(); ++i) xq[i] = static_cast<uint8_t>((i * 37) % 256);
  for (std::size_t i = 0; i < wq.size(); ++i) wq[i] = static_cast<uint8_t>((i * 53 + 7) % 256);
  std::vector<int32_t> bq(O);
  for (int o = 0; o < O; ++o) bq[o] = (o - 2) * 300;
  std::vector<float> x(xq.size()), w(wq.size()), b(O);
  for (std::size_t i = 0; i < xq.size(); ++i) x[i] = sx * (xq[i] - zx);
  for (std::size_t i = 0; i < wq.size(); ++i) w[i] = sw * (wq[i] - zw);
  for (int o = 0; o < O; ++o) b[o] = sx * sw * bq[o];
  int oh, ow;
  auto ref = conv_ref(x, H, W, C, w, O, K, K, b, 1, 1, true, false, &oh, &ow);
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_UINT8, {1, H, W, C}, nullptr, 0, {sx}, {zx});
  int wi = t.constant("w", TT::TensorType_UINT8, {O, K, K, C}, wq, {sw}, {zw});
  int bi = t.constant("b", TT::TensorType_INT32, {O}, bq, {sx * sw}, {0});
  int yi = t.tensor("y", TT::TensorType_UINT8, {1, oh, ow, O}, nullptr, 0, {sy}, {zy});
  auto opt = tflite::CreateConv2DOptions(t.fb(), tflite::Padding_SAME, 1, 1);
  t.op(tflite::BuiltinOperator_CONV_2D, {xi, wi, bi}, {yi}, tflite::BuiltinOptions_Conv2DOptions,
       opt.Union());
  auto out = run(t.finish({xi}, {yi}), {xq});
  ASSERT_EQ(out.size(), 1u);
  ASSERT_EQ(out[0].size(), ref.size());
  for (std::size_t i = 0; i < ref.size(); ++i) {
    float q = std::clamp(std::round(ref[i] / sy) + zy, 0.f, 255.f);
    EXPECT_LE(std::fabs(out[0][i] - q), 1.f) << "at " << i;
  }
}

TEST(TfliteOps, FullyConnected) {
  REQUIRE_TFLITE();
  const int B = 2, K = 6, N = 3;
  auto x = ramp(B * K), w = ramp(N * K, 0.03f), b = ramp(N, 1.f);
  std::vector<float> want(B * N);
  for (int i = 0; i < B; ++i)
    for (int n = 0; n < N; ++n) {
      float s = b[n];
      for (int k = 0; k < K; ++k) s += x[i * K + k] * w[n * K + k];
      want[i * N + n] = std::max(0.f, s);
    }
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {B, K});
  int wi = t.constant("w", TT::TensorType_FLOAT32, {N, K}, w);
  int bi = t.constant("b", TT::TensorType_FLOAT32, {N}, b);
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {B, N});
  auto opt = tflite::CreateFullyConnectedOptions(t.fb(), tflite::ActivationFunctionType_RELU);
  t.op(tflite::BuiltinOperator_FULLY_CONNECTED, {xi, wi, bi}, {yi},
       tflite::BuiltinOptions_FullyConnectedOptions, opt.Union());
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}

void pool_test(bool avg) {
  const int H = 5, W = 4, C = 2;
  auto x = ramp(H * W * C);
  // 2x2 stride 2 SAME: 3x2 outputs; padded cells do not count (TFLite semantics).
  int oh = 3, ow = 2;
  std::vector<float> want(oh * ow * C);
  for (int oy = 0; oy < oh; ++oy)
    for (int ox = 0; ox < ow; ++ox)
      for (int c = 0; c < C; ++c) {
        float s = avg ? 0.f : -1e9f;
        int n = 0;
        for (int ky = 0; ky < 2; ++ky)
          for (int kx = 0; kx < 2; ++kx) {
            int iy = oy * 2 + ky, ix = ox * 2 + kx;
            if (iy >= H || ix >= W) continue;
            float v = x[(iy * W + ix) * C + c];
            s = avg ? s + v : std::max(s, v);
            ++n;
          }
        want[(oy * ow + ox) * C + c] = avg ? s / n : s;
      }
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, H, W, C});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, oh, ow, C});
  auto opt = tflite::CreatePool2DOptions(t.fb(), tflite::Padding_SAME, 2, 2, 2, 2);
  t.op(avg ? tflite::BuiltinOperator_AVERAGE_POOL_2D : tflite::BuiltinOperator_MAX_POOL_2D, {xi},
       {yi}, tflite::BuiltinOptions_Pool2DOptions, opt.Union());
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}
TEST(TfliteOps, AveragePoolSame) {
  REQUIRE_TFLITE();
  pool_test(true);
}
TEST(TfliteOps, MaxPoolSame) {
  REQUIRE_TFLITE();
  pool_test(false);
}

// Binary elementwise ops with broadcasting of a [C] constant over [1,2,2,C].
TEST(TfliteOps, BinaryBroadcast) {
  REQUIRE_TFLITE();
  struct Case {
    tflite::BuiltinOperator code;
    std::function<float(float, float)> f;
  };
  const Case cases[] = {
      {tflite::BuiltinOperator_ADD, [](float a, float b) { return a + b; }},
      {tflite::BuiltinOperator_SUB, [](float a, float b) { return a - b; }},
      {tflite::BuiltinOperator_MUL, [](float a, float b) { return a * b; }},
      {tflite::BuiltinOperator_DIV, [](float a, float b) { return a / b; }},
      {tflite::BuiltinOperator_MAXIMUM, [](float a, float b) { return std::max(a, b); }},
      {tflite::BuiltinOperator_MINIMUM, [](float a, float b) { return std::min(a, b); }},
      {tflite::BuiltinOperator_SQUARED_DIFFERENCE,
       [](float a, float b) { return (a - b) * (a - b); }},
      {tflite::BuiltinOperator_PRELU, [](float a, float b) { return a >= 0 ? a : a * b; }},
  };
  auto x = ramp(12);
  std::vector<float> c{0.5f, -2.f, 3.f};
  for (const auto &k : cases) {
    SCOPED_TRACE(tflite::EnumNameBuiltinOperator(k.code));
    TfliteBuilder t;
    int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, 2, 2, 3});
    int ci = t.constant("c", TT::TensorType_FLOAT32, {3}, c);
    int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, 2, 2, 3});
    t.op(k.code, {xi, ci}, {yi});
    std::vector<float> want(12);
    for (int i = 0; i < 12; ++i) want[i] = k.f(x[i], c[i % 3]);
    expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
  }
}

TEST(TfliteOps, Unary) {
  REQUIRE_TFLITE();
  struct Case {
    tflite::BuiltinOperator code;
    std::function<float(float)> f;
  };
  const Case cases[] = {
      {tflite::BuiltinOperator_LOGISTIC, [](float a) { return 1.f / (1.f + std::exp(-a)); }},
      {tflite::BuiltinOperator_TANH, [](float a) { return std::tanh(a); }},
      {tflite::BuiltinOperator_RELU, [](float a) { return std::max(0.f, a); }},
      {tflite::BuiltinOperator_RELU6, [](float a) { return std::clamp(a, 0.f, 6.f); }},
      {tflite::BuiltinOperator_RELU_N1_TO_1, [](float a) { return std::clamp(a, -1.f, 1.f); }},
      {tflite::BuiltinOperator_HARD_SWISH,
       [](float a) { return a * std::clamp(a + 3.f, 0.f, 6.f) / 6.f; }},
      {tflite::BuiltinOperator_EXP, [](float a) { return std::exp(a); }},
      {tflite::BuiltinOperator_ABS, [](float a) { return std::fabs(a); }},
      {tflite::BuiltinOperator_NEG, [](float a) { return -a; }},
      {tflite::BuiltinOperator_FLOOR, [](float a) { return std::floor(a); }},
      {tflite::BuiltinOperator_SQUARE, [](float a) { return a * a; }},
  };
  auto x = ramp(24, 0.4f, -4.f);
  for (const auto &k : cases) {
    SCOPED_TRACE(tflite::EnumNameBuiltinOperator(k.code));
    TfliteBuilder t;
    int xi = t.tensor("x", TT::TensorType_FLOAT32, {2, 12});
    int yi = t.tensor("y", TT::TensorType_FLOAT32, {2, 12});
    t.op(k.code, {xi}, {yi});
    std::vector<float> want(24);
    for (int i = 0; i < 24; ++i) want[i] = k.f(x[i]);
    expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
  }
  TfliteBuilder t;  // LEAKY_RELU with its alpha
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {24});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {24});
  t.op(tflite::BuiltinOperator_LEAKY_RELU, {xi}, {yi}, tflite::BuiltinOptions_LeakyReluOptions,
       tflite::CreateLeakyReluOptions(t.fb(), 0.3f).Union());
  std::vector<float> want(24);
  for (int i = 0; i < 24; ++i) want[i] = x[i] >= 0 ? x[i] : 0.3f * x[i];
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}

TEST(TfliteOps, SoftmaxBeta) {
  REQUIRE_TFLITE();
  auto x = ramp(10, 0.5f);
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {2, 5});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {2, 5});
  t.op(tflite::BuiltinOperator_SOFTMAX, {xi}, {yi}, tflite::BuiltinOptions_SoftmaxOptions,
       tflite::CreateSoftmaxOptions(t.fb(), 2.f).Union());
  std::vector<float> want(10);
  for (int r = 0; r < 2; ++r) {
    float s = 0;
    for (int i = 0; i < 5; ++i) s += std::exp(2.f * x[r * 5 + i]);
    for (int i = 0; i < 5; ++i) want[r * 5 + i] = std::exp(2.f * x[r * 5 + i]) / s;
  }
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}

TEST(TfliteOps, ConcatenationLastAxis) {
  REQUIRE_TFLITE();
  auto a = ramp(8), b = ramp(4, 1.f);
  TfliteBuilder t;
  int ai = t.tensor("a", TT::TensorType_FLOAT32, {1, 2, 2, 2});
  int bi = t.tensor("b", TT::TensorType_FLOAT32, {1, 2, 2, 1});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, 2, 2, 3});
  t.op(tflite::BuiltinOperator_CONCATENATION, {ai, bi}, {yi},
       tflite::BuiltinOptions_ConcatenationOptions,
       tflite::CreateConcatenationOptions(t.fb(), -1).Union());
  std::vector<float> want;
  for (int p = 0; p < 4; ++p) want.insert(want.end(), {a[2 * p], a[2 * p + 1], b[p]});
  expect_near(values_of<float>(run(t.finish({ai, bi}, {yi}), {bytes_of(a), bytes_of(b)}).at(0)),
              want);
}

TEST(TfliteOps, ReshapeTransposeSqueeze) {
  REQUIRE_TFLITE();
  auto x = ramp(6);
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, 6});
  int si = t.constant("s", TT::TensorType_INT32, {3}, std::vector<int32_t>{1, 2, 3});
  int r = t.tensor("r", TT::TensorType_FLOAT32, {1, 2, 3});
  int pi = t.constant("p", TT::TensorType_INT32, {3}, std::vector<int32_t>{0, 2, 1});
  int tr = t.tensor("t", TT::TensorType_FLOAT32, {1, 3, 2});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {3, 2});
  t.op(tflite::BuiltinOperator_RESHAPE, {xi, si}, {r});
  t.op(tflite::BuiltinOperator_TRANSPOSE, {r, pi}, {tr});
  t.op(tflite::BuiltinOperator_SQUEEZE, {tr}, {yi});
  std::vector<float> want{x[0], x[3], x[1], x[4], x[2], x[5]};
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}

TEST(TfliteOps, PadAndMean) {
  REQUIRE_TFLITE();
  auto x = ramp(4, 1.f, 1.f);  // [1,2,2,1]
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, 2, 2, 1});
  int pi =
      t.constant("p", TT::TensorType_INT32, {4, 2}, std::vector<int32_t>{0, 0, 1, 0, 0, 1, 0, 0});
  int pd = t.tensor("pd", TT::TensorType_FLOAT32, {1, 3, 3, 1});
  int ai = t.constant("a", TT::TensorType_INT32, {2}, std::vector<int32_t>{1, 2});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, 1, 1, 1});
  t.op(tflite::BuiltinOperator_PAD, {xi, pi}, {pd});
  t.op(tflite::BuiltinOperator_MEAN, {pd, ai}, {yi}, tflite::BuiltinOptions_ReducerOptions,
       tflite::CreateReducerOptions(t.fb(), true).Union());
  float s = x[0] + x[1] + x[2] + x[3];
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), {s / 9.f});
}

void resize_test(bool bilinear, bool align, bool half) {
  const int H = 3, W = 2, OH = 5, OW = 4;
  auto x = ramp(H * W, 0.7f);
  std::vector<float> want(OH * OW);
  auto src = [&](int o, int in, int out) -> float {
    float scale = align && out > 1 ? float(in - 1) / (out - 1) : float(in) / out;
    return half ? (o + 0.5f) * scale - (bilinear ? 0.5f : 0.f) : o * scale;
  };
  for (int oy = 0; oy < OH; ++oy)
    for (int ox = 0; ox < OW; ++ox) {
      float fy = src(oy, H, OH), fx = src(ox, W, OW);
      if (bilinear) {
        fy = std::max(0.f, fy), fx = std::max(0.f, fx);
        int y0 = std::min(int(fy), H - 1), x0 = std::min(int(fx), W - 1);
        int y1 = std::min(y0 + 1, H - 1), x1 = std::min(x0 + 1, W - 1);
        float dy = fy - y0, dx = fx - x0;
        want[oy * OW + ox] = x[y0 * W + x0] * (1 - dy) * (1 - dx) + x[y0 * W + x1] * (1 - dy) * dx +
                             x[y1 * W + x0] * dy * (1 - dx) + x[y1 * W + x1] * dy * dx;
      } else {
        int y = std::min(int(align ? std::round(fy) : std::floor(fy)), H - 1);
        int xx = std::min(int(align ? std::round(fx) : std::floor(fx)), W - 1);
        want[oy * OW + ox] = x[y * W + xx];
      }
    }
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, H, W, 1});
  int si = t.constant("s", TT::TensorType_INT32, {2}, std::vector<int32_t>{OH, OW});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, OH, OW, 1});
  if (bilinear)
    t.op(tflite::BuiltinOperator_RESIZE_BILINEAR, {xi, si}, {yi},
         tflite::BuiltinOptions_ResizeBilinearOptions,
         tflite::CreateResizeBilinearOptions(t.fb(), align, half).Union());
  else
    t.op(tflite::BuiltinOperator_RESIZE_NEAREST_NEIGHBOR, {xi, si}, {yi},
         tflite::BuiltinOptions_ResizeNearestNeighborOptions,
         tflite::CreateResizeNearestNeighborOptions(t.fb(), align, half).Union());
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}
TEST(TfliteOps, ResizeBilinear) {
  REQUIRE_TFLITE();
  resize_test(true, false, false);
  resize_test(true, true, false);
  resize_test(true, false, true);
}
TEST(TfliteOps, ResizeNearest) {
  REQUIRE_TFLITE();
  resize_test(false, false, false);
  resize_test(false, true, false);
  resize_test(false, false, true);
}

TEST(TfliteOps, StridedSliceAndGather) {
  REQUIRE_TFLITE();
  auto x = ramp(24);  // [2,3,4]
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {2, 3, 4});
  int b = t.constant("b", TT::TensorType_INT32, {3}, std::vector<int32_t>{1, 0, 1});
  int e = t.constant("e", TT::TensorType_INT32, {3}, std::vector<int32_t>{2, 3, 4});
  int s = t.constant("s", TT::TensorType_INT32, {3}, std::vector<int32_t>{1, 2, 2});
  int sl = t.tensor("sl", TT::TensorType_FLOAT32, {2, 2});  // shrink axis 0, rows 0,2, cols 1,3
  int gi = t.constant("g", TT::TensorType_INT32, {3}, std::vector<int32_t>{1, 0, 1});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {3, 2});
  t.op(tflite::BuiltinOperator_STRIDED_SLICE, {xi, b, e, s}, {sl},
       tflite::BuiltinOptions_StridedSliceOptions,
       tflite::CreateStridedSliceOptions(t.fb(), 0, 0, 0, 0, 1).Union());
  t.op(tflite::BuiltinOperator_GATHER, {sl, gi}, {yi}, tflite::BuiltinOptions_GatherOptions,
       tflite::CreateGatherOptions(t.fb(), 0).Union());
  float r0[2] = {x[12 + 1], x[12 + 3]}, r1[2] = {x[12 + 8 + 1], x[12 + 8 + 3]};
  std::vector<float> want{r1[0], r1[1], r0[0], r0[1], r1[0], r1[1]};
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}

TEST(TfliteOps, ArgMaxAndCast) {
  REQUIRE_TFLITE();
  std::vector<float> x{1, 5, 2, 9, 0, 3};
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {2, 3});
  int ai = t.constant("a", TT::TensorType_INT32, {1}, std::vector<int32_t>{1});
  int am = t.tensor("am", TT::TensorType_INT32, {2});
  int ci = t.tensor("c", TT::TensorType_INT32, {2, 3});
  t.op(tflite::BuiltinOperator_ARG_MAX, {xi, ai}, {am}, tflite::BuiltinOptions_ArgMaxOptions,
       tflite::CreateArgMaxOptions(t.fb(), TT::TensorType_INT32).Union());
  t.op(tflite::BuiltinOperator_CAST, {xi}, {ci});
  auto out = run(t.finish({xi}, {am, ci}), {bytes_of(x)});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(values_of<int32_t>(out[0]), (std::vector<int32_t>{1, 0}));
  EXPECT_EQ(values_of<int32_t>(out[1]), (std::vector<int32_t>{1, 5, 2, 9, 0, 3}));
}

// fp16 constant weights through DEQUANTIZE (MediaPipe style), then QUANTIZE / DEQUANTIZE.
TEST(TfliteOps, Float16WeightsAndQuantizeRoundTrip) {
  REQUIRE_TFLITE();
  // 0.5, -1.5, 2.0, 0.25 as IEEE half.
  std::vector<uint16_t> h{0x3800, 0xBE00, 0x4000, 0x3400};
  std::vector<float> hv{0.5f, -1.5f, 2.f, 0.25f};
  auto x = ramp(4);
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {4});
  int wh = t.constant("wh", TT::TensorType_FLOAT16, {4}, h);
  int wf = t.tensor("wf", TT::TensorType_FLOAT32, {4});
  int s = t.tensor("s", TT::TensorType_FLOAT32, {4});
  int q = t.tensor("q", TT::TensorType_UINT8, {4}, nullptr, 0, {0.05f}, {100});
  int y = t.tensor("y", TT::TensorType_FLOAT32, {4});
  t.op(tflite::BuiltinOperator_DEQUANTIZE, {wh}, {wf});
  t.op(tflite::BuiltinOperator_ADD, {xi, wf}, {s});
  t.op(tflite::BuiltinOperator_QUANTIZE, {s}, {q});
  t.op(tflite::BuiltinOperator_DEQUANTIZE, {q}, {y});
  auto out = run(t.finish({xi}, {q, y}), {bytes_of(x)});
  ASSERT_EQ(out.size(), 2u);
  auto yf = values_of<float>(out[1]);
  for (int i = 0; i < 4; ++i) {
    float sum = x[i] + hv[i];
    float qv = std::clamp(std::round(sum / 0.05f) + 100, 0.f, 255.f);
    EXPECT_LE(std::fabs(out[0][i] - qv), 1.f) << i;
    EXPECT_NEAR(yf[i], 0.05f * (out[0][i] - 100), 1e-6f) << i;
  }
}

TEST(TfliteOps, TransposeConvSame) {
  REQUIRE_TFLITE();
  const int H = 2, W = 3, C = 2, O = 2, K = 3, S = 2, OH = 4, OW = 6;
  auto x = ramp(H * W * C), w = ramp(O * K * K * C, 0.05f, -0.3f);
  // Reference: scatter each input through the kernel, then crop SAME padding.
  int pt = std::max((H - 1) * S + K - OH, 0) / 2, pl = std::max((W - 1) * S + K - OW, 0) / 2;
  std::vector<float> want(OH * OW * O, 0.f);
  for (int iy = 0; iy < H; ++iy)
    for (int ix = 0; ix < W; ++ix)
      for (int ky = 0; ky < K; ++ky)
        for (int kx = 0; kx < K; ++kx) {
          int oy = iy * S + ky - pt, ox = ix * S + kx - pl;
          if (oy < 0 || ox < 0 || oy >= OH || ox >= OW) continue;
          for (int o = 0; o < O; ++o)
            for (int c = 0; c < C; ++c)
              want[(oy * OW + ox) * O + o] +=
                  x[(iy * W + ix) * C + c] * w[((o * K + ky) * K + kx) * C + c];
        }
  TfliteBuilder t;
  int si = t.constant("os", TT::TensorType_INT32, {4}, std::vector<int32_t>{1, OH, OW, O});
  int wi = t.constant("w", TT::TensorType_FLOAT32, {O, K, K, C}, w);
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, H, W, C});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, OH, OW, O});
  t.op(tflite::BuiltinOperator_TRANSPOSE_CONV, {si, wi, xi}, {yi},
       tflite::BuiltinOptions_TransposeConvOptions,
       tflite::CreateTransposeConvOptions(t.fb(), tflite::Padding_SAME, S, S).Union());
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}

TEST(TfliteOps, MissingOptionalInputIsAnError) {
  REQUIRE_TFLITE();
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {1, 2});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {1, 4});
  t.op(tflite::BuiltinOperator_CONCATENATION, {xi, -1}, {yi},
       tflite::BuiltinOptions_ConcatenationOptions,
       tflite::CreateConcatenationOptions(t.fb(), 1).Union());
  std::string err;
  EXPECT_TRUE(run(t.finish({xi}, {yi}), {bytes_of(ramp(2))}, &err).empty());
  EXPECT_NE(err.find("operator 0"), std::string::npos) << err;
  EXPECT_NE(err.find("missing"), std::string::npos) << err;
}

TEST(TfliteOps, UnsupportedOpNamesOpIndexModelAndArmnn) {
  REQUIRE_TFLITE();
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_FLOAT32, {4});
  int yi = t.tensor("y", TT::TensorType_FLOAT32, {4});
  int zi = t.tensor("z", TT::TensorType_FLOAT32, {4});
  t.op(tflite::BuiltinOperator_RELU, {xi}, {yi});
  t.op(tflite::BuiltinOperator_LSH_PROJECTION, {yi}, {zi});
  std::string err;
  auto out = run(t.finish({xi}, {zi}), {bytes_of(ramp(4))}, &err);
  EXPECT_TRUE(out.empty());
  EXPECT_NE(err.find("operator 1 (LSH_PROJECTION)"), std::string::npos) << err;
  EXPECT_NE(err.find(".tflite"), std::string::npos) << err;
  EXPECT_NE(err.find("framework=armnn"), std::string::npos) << err;
}

// TFLite_Detection_PostProcess alone: one anchor, one class. The box encoding 0 decodes to the
// anchor. Options the kernel cannot run (y_scale 0) are refused when the model is loaded.
std::vector<uint8_t> detection_model(float y_scale) {
  flexbuffers::Builder opts;
  opts.Map([&] {
    opts.Int("max_detections", 1);
    opts.Int("max_classes_per_detection", 1);
    opts.Int("num_classes", 1);
    opts.Float("nms_score_threshold", 0.f);
    opts.Float("nms_iou_threshold", 0.5f);
    opts.Float("y_scale", y_scale);
    opts.Float("x_scale", 10.f);
    opts.Float("h_scale", 5.f);
    opts.Float("w_scale", 5.f);
  });
  opts.Finish();
  TfliteBuilder t;
  int boxes = t.tensor("boxes", TT::TensorType_FLOAT32, {1, 1, 4});
  int scores = t.tensor("scores", TT::TensorType_FLOAT32, {1, 1, 2});
  int anchors = t.constant("anchors", TT::TensorType_FLOAT32, {1, 4},
                           std::vector<float>{0.5f, 0.4f, 0.2f, 0.6f});
  int ob = t.tensor("det_boxes", TT::TensorType_FLOAT32, {1, 1, 4});
  int oc = t.tensor("det_classes", TT::TensorType_FLOAT32, {1, 1});
  int os = t.tensor("det_scores", TT::TensorType_FLOAT32, {1, 1});
  int on = t.tensor("num_detections", TT::TensorType_FLOAT32, {1});
  t.op(tflite::BuiltinOperator_CUSTOM, {boxes, scores, anchors}, {ob, oc, os, on},
       tflite::BuiltinOptions_NONE, 0, "TFLite_Detection_PostProcess", opts.GetBuffer());
  return t.finish({boxes, scores}, {ob, oc, os, on});
}

TEST(TfliteOps, DetectionPostProcessRefusesOptionsTheKernelCannotRun) {
  REQUIRE_TFLITE();
  auto out = run(detection_model(10.f),
                 {bytes_of(std::vector<float>(4, 0.f)), bytes_of(std::vector<float>{0.f, 0.9f})});
  ASSERT_EQ(out.size(), 4u);
  expect_near(values_of<float>(out[0]), {0.4f, 0.1f, 0.6f, 0.7f});  // ymin xmin ymax xmax
  expect_near(values_of<float>(out[2]), {0.9f});
  expect_near(values_of<float>(out[3]), {1.f});
  std::string err;
  EXPECT_TRUE(run(detection_model(0.f), {}, &err).empty());
  EXPECT_NE(err.find("implausible options"), std::string::npos) << err;
}

}  // namespace
}  // namespace nns::test

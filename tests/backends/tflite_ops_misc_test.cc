// SPDX-License-Identifier: LGPL-2.1-only
// One-op models for the tflite back end's remaining operators of the op table (LOG, SQRT,
// RSQRT, CEIL, SIN, COS, ELU, POW, FLOOR_DIV, EXPAND_DIMS, PADV2, DEPTH_TO_SPACE,
// SPACE_TO_DEPTH, ARG_MIN, SHAPE, BROADCAST_ARGS, BROADCAST_TO), each against a scalar reference
// written here: float within 1e-5 relative, integer and data-movement results exact.
#include <functional>

#include "backends/tflite_op_util.h"

namespace nns::test {
namespace {

using namespace tflite_ops;
using B = tflite::BuiltinOperator;

int f32(TfliteBuilder &t, const std::string &name, const std::vector<int32_t> &shape) {
  return t.tensor(name, TT::TensorType_FLOAT32, shape);
}

TEST(TfliteOpsMisc, Unary) {
  REQUIRE_TFLITE();
  struct Case {
    B code;
    std::function<float(float)> f;
    bool positive;  // domain x > 0
  };
  const Case cases[] = {
      {B::BuiltinOperator_LOG, [](float a) { return std::log(a); }, true},
      {B::BuiltinOperator_SQRT, [](float a) { return std::sqrt(a); }, true},
      {B::BuiltinOperator_RSQRT, [](float a) { return 1.f / std::sqrt(a); }, true},
      {B::BuiltinOperator_CEIL, [](float a) { return std::ceil(a); }, false},
      {B::BuiltinOperator_SIN, [](float a) { return std::sin(a); }, false},
      {B::BuiltinOperator_COS, [](float a) { return std::cos(a); }, false},
      {B::BuiltinOperator_ELU, [](float a) { return a >= 0 ? a : std::expm1(a); }, false},
  };
  for (const auto &k : cases) {
    SCOPED_TRACE(tflite::EnumNameBuiltinOperator(k.code));
    auto x = k.positive ? ramp(24, 0.37f, 0.05f) : ramp(24, 0.4f, -4.3f);
    TfliteBuilder t;
    int xi = f32(t, "x", {2, 12}), yi = f32(t, "y", {2, 12});
    t.op(k.code, {xi}, {yi});
    std::vector<float> want(24);
    for (int i = 0; i < 24; ++i) want[i] = k.f(x[i]);
    expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
  }
}

TEST(TfliteOpsMisc, PowWithConstantExponent) {
  REQUIRE_TFLITE();
  auto x = ramp(6, 0.3f, 0.2f);
  std::vector<float> e{2.f, 0.5f, 3.f};
  TfliteBuilder t;
  int xi = f32(t, "x", {2, 3}), yi = f32(t, "y", {2, 3});
  int ei = t.constant("e", TT::TensorType_FLOAT32, {3}, e);
  t.op(B::BuiltinOperator_POW, {xi, ei}, {yi});
  std::vector<float> want(6);
  for (int i = 0; i < 6; ++i) want[i] = std::pow(x[i], e[i % 3]);
  expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)), want);
}

// FLOOR_DIV rounds towards minus infinity, in float and in int32 (MoveNet divides ARG_MAX
// indices by the heatmap width).
TEST(TfliteOpsMisc, FloorDivFloatAndInt32) {
  REQUIRE_TFLITE();
  {
    std::vector<float> x{7.f, -7.f, 7.5f, -0.5f, 0.f, 9.f};
    TfliteBuilder t;
    int xi = f32(t, "x", {6}), yi = f32(t, "y", {6});
    int di = t.constant("d", TT::TensorType_FLOAT32, {1}, std::vector<float>{2.f});
    t.op(B::BuiltinOperator_FLOOR_DIV, {xi, di}, {yi});
    expect_near(values_of<float>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)),
                {3.f, -4.f, 3.f, -1.f, 0.f, 4.f});
  }
  std::vector<int32_t> x{2303, 0, 47, 48, 95, -1};
  TfliteBuilder t;
  int xi = t.tensor("x", TT::TensorType_INT32, {6}), yi = t.tensor("y", TT::TensorType_INT32, {6});
  int di = t.constant("d", TT::TensorType_INT32, {}, std::vector<int32_t>{48});
  t.op(B::BuiltinOperator_FLOOR_DIV, {xi, di}, {yi});
  EXPECT_EQ(values_of<int32_t>(run(t.finish({xi}, {yi}), {bytes_of(x)}).at(0)),
            (std::vector<int32_t>{47, 0, 0, 1, 1, -1}));
}

// EXPAND_DIMS then PADV2 with an explicit pad value, on uint8 (stored values, exact) and float.
TEST(TfliteOpsMisc, ExpandDimsAndPadV2) {
  REQUIRE_TFLITE();
  for (bool quant : {false, true}) {
    SCOPED_TRACE(quant ? "uint8" : "float32");
    TfliteBuilder t;
    TT type = quant ? TT::TensorType_UINT8 : TT::TensorType_FLOAT32;
    auto q = [&](const std::string &n, std::vector<int32_t> shape) {
      return quant ? t.tensor(n, type, shape, nullptr, 0, {0.5f}, {10}) : t.tensor(n, type, shape);
    };
    int xi = q("x", {2, 3}), ei = q("e", {2, 1, 3}), yi = q("y", {2, 2, 4});
    int ai = t.constant("a", TT::TensorType_INT32, {}, std::vector<int32_t>{-2});
    int pi = t.constant("p", TT::TensorType_INT32, {3, 2}, std::vector<int32_t>{0, 0, 1, 0, 0, 1});
    int vi = quant ? t.constant("v", type, {}, std::vector<uint8_t>{30}, {0.5f}, {10})
                   : t.constant("v", type, {}, std::vector<float>{10.f});
    t.op(B::BuiltinOperator_EXPAND_DIMS, {xi, ai}, {ei});
    t.op(B::BuiltinOperator_PADV2, {ei, pi, vi}, {yi});
    auto model = t.finish({xi}, {yi});
    // y[b][0][:] = pad, y[b][1][0..2] = x[b][:], y[b][1][3] = pad
    if (quant) {
      std::vector<uint8_t> x{11, 12, 13, 14, 15, 16};
      auto y = run(model, {x}).at(0);
      EXPECT_EQ(y, (std::vector<uint8_t>{30, 30, 30, 30, 11, 12, 13, 30, 30, 30, 30, 30, 14, 15, 16,
                                         30}));
    } else {
      std::vector<float> x{1, 2, 3, 4, 5, 6};
      expect_near(values_of<float>(run(model, {bytes_of(x)}).at(0)),
                  {10, 10, 10, 10, 1, 2, 3, 10, 10, 10, 10, 10, 4, 5, 6, 10});
    }
  }
}

// DEPTH_TO_SPACE and back with SPACE_TO_DEPTH (block 2, TFLite's NHWC order:
// out[h*2+i][w*2+j][c] = in[h][w][(i*2+j)*C+c]).
TEST(TfliteOpsMisc, DepthToSpaceAndBack) {
  REQUIRE_TFLITE();
  const int H = 2, W = 3, C = 2, bs = 2;
  auto x = ramp(H * W * C * bs * bs);
  std::vector<float> want(x.size());
  for (int h = 0; h < H; ++h)
    for (int w = 0; w < W; ++w)
      for (int i = 0; i < bs; ++i)
        for (int j = 0; j < bs; ++j)
          for (int c = 0; c < C; ++c)
            want[((h * bs + i) * W * bs + (w * bs + j)) * C + c] =
                x[((h * W + w) * bs * bs + (i * bs + j)) * C + c];
  TfliteBuilder t;
  int xi = f32(t, "x", {1, H, W, C * bs * bs}), di = f32(t, "d", {1, H * bs, W * bs, C});
  int si = f32(t, "s", {1, H, W, C * bs * bs});
  t.op(B::BuiltinOperator_DEPTH_TO_SPACE, {xi}, {di}, tflite::BuiltinOptions_DepthToSpaceOptions,
       tflite::CreateDepthToSpaceOptions(t.fb(), bs).Union());
  t.op(B::BuiltinOperator_SPACE_TO_DEPTH, {di}, {si}, tflite::BuiltinOptions_SpaceToDepthOptions,
       tflite::CreateSpaceToDepthOptions(t.fb(), bs).Union());
  auto out = run(t.finish({xi}, {di, si}), {bytes_of(x)});
  ASSERT_EQ(out.size(), 2u);
  expect_near(values_of<float>(out[0]), want);
  expect_near(values_of<float>(out[1]), x);
}

TEST(TfliteOpsMisc, ArgMinInt32AndArgMaxInt64) {
  REQUIRE_TFLITE();
  std::vector<float> x{4, 1, 2, -3, 5, 0, 7, 7, 1};  // [3,3]; ties take the first index
  TfliteBuilder t;
  int xi = f32(t, "x", {3, 3});
  int a0 = t.constant("a0", TT::TensorType_INT32, {1}, std::vector<int32_t>{0});
  int a1 = t.constant("a1", TT::TensorType_INT32, {1}, std::vector<int32_t>{1});
  int mn = t.tensor("mn", TT::TensorType_INT32, {3}),
      mx = t.tensor("mx", TT::TensorType_INT64, {3});
  t.op(B::BuiltinOperator_ARG_MIN, {xi, a1}, {mn}, tflite::BuiltinOptions_ArgMinOptions,
       tflite::CreateArgMinOptions(t.fb(), TT::TensorType_INT32).Union());
  t.op(B::BuiltinOperator_ARG_MAX, {xi, a0}, {mx}, tflite::BuiltinOptions_ArgMaxOptions,
       tflite::CreateArgMaxOptions(t.fb(), TT::TensorType_INT64).Union());
  auto out = run(t.finish({xi}, {mn, mx}), {bytes_of(x)});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(values_of<int32_t>(out[0]), (std::vector<int32_t>{1, 0, 2}));
  EXPECT_EQ(values_of<int64_t>(out[1]), (std::vector<int64_t>{2, 2, 0}));
}

// SHAPE of the input, and BROADCAST_TO a constant [3] row to that shape.
TEST(TfliteOpsMisc, ShapeAndBroadcastTo) {
  REQUIRE_TFLITE();
  auto x = ramp(6);
  std::vector<float> row{1.5f, -2.f, 4.f};
  TfliteBuilder t;
  int xi = f32(t, "x", {2, 3});
  int si = t.tensor("s", TT::TensorType_INT32, {2});
  int ri = t.constant("r", TT::TensorType_FLOAT32, {3}, row);
  int yi = f32(t, "y", {2, 3});
  t.op(B::BuiltinOperator_SHAPE, {xi}, {si});  // int32 as the output tensor says
  t.op(B::BuiltinOperator_BROADCAST_TO, {ri, si}, {yi});
  auto out = run(t.finish({xi}, {si, yi}), {bytes_of(x)});
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(values_of<int32_t>(out[0]), (std::vector<int32_t>{2, 3}));
  expect_near(values_of<float>(out[1]), {1.5f, -2.f, 4.f, 1.5f, -2.f, 4.f});
}

// BROADCAST_ARGS of two shape vectors given as inputs: [4,1,3] and [2,1] -> [4,2,3].
TEST(TfliteOpsMisc, BroadcastArgs) {
  REQUIRE_TFLITE();
  std::vector<int32_t> a{4, 1, 3}, b{2, 1};
  TfliteBuilder t;
  int ai = t.tensor("a", TT::TensorType_INT32, {3}), bi = t.tensor("b", TT::TensorType_INT32, {2});
  int yi = t.tensor("y", TT::TensorType_INT32, {3});
  t.op(B::BuiltinOperator_BROADCAST_ARGS, {ai, bi}, {yi});
  EXPECT_EQ(values_of<int32_t>(run(t.finish({ai, bi}, {yi}), {bytes_of(a), bytes_of(b)}).at(0)),
            (std::vector<int32_t>{4, 2, 3}));
}

}  // namespace
}  // namespace nns::test

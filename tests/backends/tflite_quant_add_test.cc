// SPDX-License-Identifier: LGPL-2.1-only
// Quantized ADD/SUB against TensorFlow Lite's integer arithmetic on its CPU path (the XNNPACK
// delegate's, which the TFLite goldens of tests/data/tflite were made with): with a constant
// single-valued operand the back end uses an exact table (tflite_quant_add.cc), checked here
// on every (input, constant) byte pair for several scale sets; two variable operands stay on
// ONNX Runtime's float requantization, checked within one step on all 256x256 pairs.
#include <gtest/gtest.h>

#include <cmath>

#include "backends/tflite_op_util.h"

namespace nns::test {
namespace {

using namespace tflite_ops;

struct Q {
  float scale;
  int zp;
};
struct ScaleSet {
  const char *what;
  TT type;
  bool sub, const_first;
  Q x, c, out;
};

// The reference, from the definition: ratios r = scale / out_scale in float; the multipliers
// are the ratios in fixed point with 20 fractional bits below the larger ratio's leading bit,
// rounded to nearest even; the sum of the multiplied offsets plus half is shifted right
// (floor, so ties go up), then clamped. nullopt-like -1000 when a ratio is outside [2^-10, 2^8).
int reference(Q qa, int a, Q qb, int b, Q qo, bool sub, bool s8) {
  float ra = qa.scale / qo.scale, rb = qb.scale / qo.scale;
  for (float r : {ra, rb})
    if (r < 1.f / 1024.f || r >= 256.f) return -1000;
  int e = 0;
  std::frexp(std::max(ra, rb), &e);  // max = m * 2^e, m in [0.5, 1)
  int shift = 20 - (e - 1);
  auto fixed = [&](float r) { return static_cast<int64_t>(std::nearbyint(std::ldexp(r, shift))); };
  int64_t ma = fixed(ra), mb = sub ? -fixed(rb) : fixed(rb);
  int64_t acc = ma * (a - qa.zp) + mb * (b - qb.zp) + (int64_t{1} << (shift - 1));
  int64_t q = static_cast<int64_t>(std::floor(static_cast<double>(acc) / std::ldexp(1.0, shift)));
  q += qo.zp;
  return static_cast<int>(std::clamp<int64_t>(q, s8 ? -128 : 0, s8 ? 127 : 255));
}

int value(uint8_t byte, bool s8) {
  return s8 ? static_cast<int8_t>(byte) : byte;
}

// One model per scale set: 256 ADD/SUB ops, one per constant byte value, all on the same
// input holding every byte value, concatenated into one [256, 256] output (row = constant).
std::vector<uint8_t> constant_operand_model(const ScaleSet &s) {
  TfliteBuilder t;
  int x = t.tensor("x", s.type, {1, 256}, nullptr, 0, {s.x.scale}, {s.x.zp});
  std::vector<int> rows;
  for (int k = 0; k < 256; ++k) {
    std::vector<uint8_t> cv{static_cast<uint8_t>(k)};
    // A [1, 1] constant broadcast over [1, 256].
    int c = t.constant("c" + std::to_string(k), s.type, {1, 1}, cv, {s.c.scale}, {s.c.zp});
    int y =
        t.tensor("y" + std::to_string(k), s.type, {1, 256}, nullptr, 0, {s.out.scale}, {s.out.zp});
    std::vector<int> in = s.const_first ? std::vector<int>{c, x} : std::vector<int>{x, c};
    t.op(s.sub ? tflite::BuiltinOperator_SUB : tflite::BuiltinOperator_ADD, in, {y});
    rows.push_back(y);
  }
  int all = t.tensor("all", s.type, {256, 256}, nullptr, 0, {s.out.scale}, {s.out.zp});
  t.op(tflite::BuiltinOperator_CONCATENATION, rows, {all},
       tflite::BuiltinOptions_ConcatenationOptions,
       tflite::CreateConcatenationOptions(t.fb(), 0).Union());
  return t.finish({x}, {all});
}

const ScaleSet kSets[] = {
    // MoveNet's `sub_1` (x / 127.5 - 1): every exact result is a .5 tie.
    {"MoveNet sub_1",
     TT::TensorType_INT8,
     true,
     false,
     {0.007843137718737125f, -128},
     {0.003921568859368563f, -128},
     {0.007843137718737125f, -1}},
    {"int8 add",
     TT::TensorType_INT8,
     false,
     false,
     {0.0235294122f, -128},
     {0.0374003499f, -5},
     {0.0410074405f, 7}},
    {"uint8 add, constant first",
     TT::TensorType_UINT8,
     false,
     true,
     {0.02f, 128},
     {0.05f, 3},
     {0.06f, 100}},
    {"uint8 constant minus input",
     TT::TensorType_UINT8,
     true,
     true,
     {0.05f, 200},
     {0.1f, 10},
     {0.08f, 128}},
    {"int8 sub, ratio 1/2 (ties)",
     TT::TensorType_INT8,
     true,
     false,
     {0.5f, 3},
     {0.25f, -7},
     {1.0f, 0}},
};

TEST(TfliteQuantAdd, ConstantOperandEqualsTfliteArithmetic) {
  REQUIRE_TFLITE();
  for (const auto &s : kSets) {
    SCOPED_TRACE(s.what);
    const bool s8 = s.type == TT::TensorType_INT8;
    std::vector<uint8_t> x(256);
    for (int i = 0; i < 256; ++i) x[i] = static_cast<uint8_t>(i);
    auto out = run(constant_operand_model(s), {x});
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0].size(), 65536u);
    int differ = 0;
    for (int k = 0; k < 256; ++k)
      for (int i = 0; i < 256; ++i) {
        int xv = value(x[i], s8), cv = value(static_cast<uint8_t>(k), s8);
        int want = s.const_first ? reference(s.c, cv, s.x, xv, s.out, s.sub, s8)
                                 : reference(s.x, xv, s.c, cv, s.out, s.sub, s8);
        ASSERT_NE(want, -1000);
        int got = value(out[0][k * 256 + i], s8);
        if (got != want && ++differ <= 5)
          ADD_FAILURE() << "input " << xv << ", constant " << cv << ": " << got << ", want "
                        << want;
      }
    EXPECT_EQ(differ, 0) << "of 65536 (input, constant) pairs";
  }
}

// Outside the table's conditions (a ratio below 2^-10, where TFLite's XNNPACK path refuses
// the op; a fused RELU) the float path stays: within one step of the same arithmetic.
TEST(TfliteQuantAdd, OtherCasesWithinOneStep) {
  REQUIRE_TFLITE();
  // Two variable operands on every byte pair: a [65536] tensor per operand.
  for (const auto &s : kSets) {
    SCOPED_TRACE(s.what);
    const bool s8 = s.type == TT::TensorType_INT8;
    TfliteBuilder t;
    int a = t.tensor("a", s.type, {65536}, nullptr, 0, {s.x.scale}, {s.x.zp});
    int b = t.tensor("b", s.type, {65536}, nullptr, 0, {s.c.scale}, {s.c.zp});
    int y = t.tensor("y", s.type, {65536}, nullptr, 0, {s.out.scale}, {s.out.zp});
    t.op(s.sub ? tflite::BuiltinOperator_SUB : tflite::BuiltinOperator_ADD, {a, b}, {y});
    std::vector<uint8_t> av(65536), bv(65536);
    for (int i = 0; i < 65536; ++i) {
      av[i] = static_cast<uint8_t>(i % 256);
      bv[i] = static_cast<uint8_t>(i / 256);
    }
    auto out = run(t.finish({a, b}, {y}), {av, bv});
    ASSERT_EQ(out.size(), 1u);
    ASSERT_EQ(out[0].size(), 65536u);
    int differ = 0, worst = 0;
    for (int i = 0; i < 65536; ++i) {
      int want = reference(s.x, value(av[i], s8), s.c, value(bv[i], s8), s.out, s.sub, s8);
      int d = std::abs(value(out[0][i], s8) - want);
      differ += d != 0;
      worst = std::max(worst, d);
    }
    std::printf("%s, two variable operands: %d of 65536 pairs one step from TFLite's arithmetic\n",
                s.what, differ);
    EXPECT_LE(worst, 1);
  }
  // A ratio of 1e-6 (MoveNet's first SUB, `x - 0` with a constant at scale 1e-6).
  TfliteBuilder t;
  int x = t.tensor("x", TT::TensorType_INT8, {1, 256}, nullptr, 0, {1.f}, {-128});
  int c = t.constant("c", TT::TensorType_INT8, {1, 1}, std::vector<int8_t>{5}, {1e-6f}, {0});
  int y = t.tensor("y", TT::TensorType_INT8, {1, 256}, nullptr, 0, {1.f}, {-128});
  t.op(tflite::BuiltinOperator_SUB, {x, c}, {y});
  std::vector<uint8_t> in(256);
  for (int i = 0; i < 256; ++i) in[i] = static_cast<uint8_t>(i);
  auto out = run(t.finish({x}, {y}), {in});
  ASSERT_EQ(out.size(), 1u);
  for (int i = 0; i < 256; ++i) EXPECT_EQ(out[0][i], in[i]) << "x - 5e-6 at " << i;
}

}  // namespace
}  // namespace nns::test

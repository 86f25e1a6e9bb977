// SPDX-License-Identifier: LGPL-2.1-only
// Quantized ADD/SUB with a constant single-valued operand (input scaling such as MoveNet's
// `x / 127.5 - 1`): TensorFlow Lite's result is reproduced exactly by a 256-entry table,
// Gather(table, Cast(x, int32)). ORT's QDQ path requantizes in float and breaks exact .5 ties
// its own way; TFLite's CPU path (the XNNPACK delegate, which takes quantized ADD/SUB whose
// input-to-output scale ratios lie in [2^-10, 2^8)) computes in integers:
//   shift = 20 - floor(log2(max |ratio|)),  m_a = rint(ratio_a * 2^shift), m_b likewise
//   (ratio_b negated for SUB),  out = (2^(shift-1) + m_a*(a - z_a) + m_b*(b - z_b)) >> shift
// (arithmetic shift: ties round up), clamped, plus the output zero point.
// docs/backends/tflite.md, "Quantized ADD/SUB".
#include "tflite_quant_add.h"

#include <cmath>

#include "tflite_translator.h"

namespace nns::tfl {

std::optional<QuantAddParams> xnnpack_add_params(float a_scale, float b_scale, float out_scale,
                                                 bool sub) {
  const float ra = a_scale / out_scale, rb = b_scale / out_scale;
  auto in_range = [](float r) { return r >= 0x1.0p-10f && r < 0x1.0p+8f; };
  if (!in_range(ra) || !in_range(rb)) return std::nullopt;
  QuantAddParams p;
  p.shift = 20 - std::ilogb(std::max(ra, rb));
  p.a_mul = static_cast<int32_t>(std::nearbyint(std::ldexp(ra, p.shift)));
  p.b_mul = static_cast<int32_t>(std::nearbyint(std::ldexp(rb, p.shift)));
  if (sub) p.b_mul = -p.b_mul;
  return p;
}

int32_t quant_add(const QuantAddParams &p, int32_t a, int32_t za, int32_t b, int32_t zb, int32_t zo,
                  int32_t lo, int32_t hi) {
  int64_t acc =
      (int64_t{1} << (p.shift - 1)) + int64_t{p.a_mul} * (a - za) + int64_t{p.b_mul} * (b - zb);
  int64_t q = (acc >> p.shift) + zo;  // >> of a negative int64 is arithmetic (C++20)
  return static_cast<int32_t>(std::clamp<int64_t>(q, lo, hi));
}

namespace detail {

bool Translator::quant_add_table(const Op &op, bool sub, int fused) {
  if (fused != 0 || op.inputs.size() != 2 || op.outputs.size() != 1) return false;
  const int a = op.inputs[0], b = op.inputs[1], out = op.outputs[0];
  if (a < 0 || b < 0 || is_const(a) == is_const(b)) return false;
  const int x = is_const(a) ? b : a, c = is_const(a) ? a : b;
  const Tensor &tx = T(x), &tc = T(c), &to = T(out);
  if (tx.type != to.type || tc.type != to.type || (to.type != kInt8 && to.type != kUInt8))
    return false;
  for (const Tensor *t : {&tx, &tc, &to})
    if (t->q.scale.size() != 1 || t->q.zero_point.size() != 1) return false;
  if (tx.shape != to.shape || folded_.count(c) || !tc.data || tc.bytes == 0) return false;
  for (std::size_t i = 1; i < tc.bytes; ++i)
    if (tc.data[i] != tc.data[0]) return false;  // one value, however broadcast
  const Tensor &ta = T(a), &tb = T(b);
  auto p = xnnpack_add_params(ta.q.scale[0], tb.q.scale[0], to.q.scale[0], sub);
  if (!p) return false;  // TFLite's own kernel runs it: ORT's float path stays
  const bool s8 = to.type == kInt8;
  const int32_t lo = s8 ? -128 : 0, hi = s8 ? 127 : 255;
  auto value = [&](uint8_t byte) {
    return s8 ? int32_t{static_cast<int8_t>(byte)} : int32_t{byte};
  };
  const int32_t cv = value(tc.data[0]);
  // Entry k is the result for the stored byte k: int8 -1 (byte 255) is index -1, which Gather
  // reads from the end, so Cast(x, int32) indexes the table directly for both types.
  std::vector<uint8_t> table(256);
  for (int k = 0; k < 256; ++k) {
    int32_t xv = value(static_cast<uint8_t>(k));
    int32_t av = x == a ? xv : cv, bv = x == a ? cv : xv;
    table[k] = static_cast<uint8_t>(quant_add(*p, av, static_cast<int32_t>(ta.q.zero_point[0]), bv,
                                              static_cast<int32_t>(tb.q.zero_point[0]),
                                              static_cast<int32_t>(to.q.zero_point[0]), lo, hi));
  }
  std::string tab = fresh();
  g_.initializer(tab, onnx_type(to.type), {256}, table.data(), table.size());
  std::string idx = unary("Cast", raw(x), {attr_int("to", onnx::kInt32)});
  g_.node("Gather", {tab, idx}, {name(out)}, {attr_int("axis", 0)});
  emitted_[out] = true;
  return true;
}

}  // namespace detail
}  // namespace nns::tfl

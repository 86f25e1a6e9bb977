// SPDX-License-Identifier: LGPL-2.1-only
// Every mode x every input type: the accelerated plan (Highway / vectorised loops) against the
// scalar reference, plus hand-computed goldens and NNStreamer's cast semantics.
#include "core/transform_kernels.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <random>

#include "core/error.h"

namespace nns::transform {
namespace {

TensorInfo info(TensorType t, std::initializer_list<uint32_t> d) {
  return TensorInfo{"", t, make_dims(d)};
}

template <typename T>
std::vector<uint8_t> bytes_of(const std::vector<T> &v) {
  std::vector<uint8_t> b(v.size() * sizeof(T));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

template <typename T>
std::vector<T> values_of(const std::vector<uint8_t> &b) {
  std::vector<T> v(b.size() / sizeof(T));
  std::memcpy(v.data(), b.data(), b.size());
  return v;
}

std::vector<uint8_t> run_plan(const Options &o, const TensorInfo &in,
                              const std::vector<uint8_t> &src, bool accelerate) {
  Plan p = make_plan(o, in, accelerate);
  std::vector<uint8_t> dst(p.out.byte_size(), 0xAB);
  p.run(src.data(), dst.data());
  return dst;
}

std::vector<uint8_t> run_ref(const Options &o, const TensorInfo &in,
                             const std::vector<uint8_t> &src) {
  std::vector<uint8_t> dst(output_info(o, in).byte_size(), 0xCD);
  reference_transform(o, in, src.data(), dst.data());
  return dst;
}

// Random tensor data: integers cover their whole range (wrapping is exercised), floats are in
// [-300, 300] with a few exact integers and halves.
std::vector<uint8_t> random_data(TensorType t, std::size_t n, uint32_t seed) {
  std::mt19937 rng(seed);
  std::vector<uint8_t> b(n * type_size(t));
  dispatch_type(t, [&](auto tag) {
    using T = typename decltype(tag)::type;
    std::uniform_real_distribution<double> real(-300.0, 300.0);
    for (std::size_t i = 0; i < n; ++i) {
      T v;
      if constexpr (is_floating_v<T>) {
        double x = real(rng);
        if (i % 7 == 0) x = std::round(x);
        if (i % 11 == 0) x = std::round(x) + 0.5;
        v = cast_value<T>(x);
      } else {
        uint64_t r = (static_cast<uint64_t>(rng()) << 32) | rng();
        std::memcpy(&v, &r, sizeof v);
      }
      std::memcpy(b.data() + i * sizeof(T), &v, sizeof(T));
    }
  });
  return b;
}

// ---- NNStreamer's value semantics -------------------------------------------------------

TEST(TransformCast, CCastSemanticsOnX86) {
  EXPECT_EQ(cast_value<uint8_t>(300.0f), 44);  // low byte of the int32 truncation
  EXPECT_EQ(cast_value<uint8_t>(-1.0f), 255);
  EXPECT_EQ(cast_value<uint8_t>(255.9f), 255);
  EXPECT_EQ(cast_value<int8_t>(-129.7), 127);
  EXPECT_EQ(cast_value<uint8_t>(NAN), 0);
  EXPECT_EQ(cast_value<int32_t>(3e9f), INT32_MIN);
  EXPECT_EQ(cast_value<uint32_t>(3e9f), 2147483648u);  // through int32, as upstream
  EXPECT_EQ(cast_value<uint16_t>(70000.5), 4464);
  EXPECT_EQ(cast_value<int64_t>(1e20), INT64_MIN);
  EXPECT_EQ(cast_value<uint64_t>(-1.0), UINT64_MAX);
  EXPECT_EQ(cast_value<uint8_t>(int64_t{-127}), 129);
  EXPECT_EQ(cast_value<int16_t>(uint32_t{70000}), 4464);
  EXPECT_EQ(cast_value<float>(uint8_t{200}), 200.0f);
  // Same as a C cast wherever the C cast is defined.
  for (float f : {-128.0f, -1.5f, 0.0f, 0.99f, 127.9f})
    EXPECT_EQ(cast_value<int8_t>(f), static_cast<int8_t>(f));
  for (double d : {-2147483648.0, -1.5, 2147483647.0})
    EXPECT_EQ(cast_value<int32_t>(d), static_cast<int32_t>(d));
}

TEST(TransformCast, Float16) {
  EXPECT_EQ(float_to_half(1.0f), 0x3C00);
  EXPECT_EQ(float_to_half(-2.0f), 0xC000);
  EXPECT_EQ(float_to_half(65504.0f), 0x7BFF);
  EXPECT_EQ(float_to_half(65520.0f), 0x7C00);  // rounds to infinity
  EXPECT_EQ(float_to_half(0.1f), 0x2E66);
  EXPECT_EQ(float_to_half(5.9604645e-08f), 0x0001);  // smallest subnormal
  EXPECT_EQ(float_to_half(2.9e-08f), 0x0000);
  EXPECT_EQ(float_to_half(1.0f + 1.0f / 2048), 0x3C00);  // tie to even
  EXPECT_EQ(half_to_float(0x3555), 0.333251953125f);
  EXPECT_TRUE(std::isnan(half_to_float(float_to_half(NAN))));
  for (uint32_t h = 0; h < 0x10000; ++h) {
    if ((h & 0x7C00) == 0x7C00 && (h & 0x3FF)) continue;  // NaN payloads
    ASSERT_EQ(float_to_half(half_to_float(static_cast<uint16_t>(h))), h) << h;
  }
}

// ---- every mode x every input type: accelerated == reference -----------------------------

struct Case {
  Mode mode;
  const char *option;
  bool exact = true;  // stand's statistics are summed differently: toleranced
};

const Case kCases[] = {
    {Mode::kDimchg, "0:2"},
    {Mode::kDimchg, "2:0"},
    {Mode::kDimchg, "1:3"},
    {Mode::kDimchg, "0:5"},
    {Mode::kTypecast, "int8"},
    {Mode::kTypecast, "uint8"},
    {Mode::kTypecast, "int16"},
    {Mode::kTypecast, "uint16"},
    {Mode::kTypecast, "int32"},
    {Mode::kTypecast, "uint32"},
    {Mode::kTypecast, "int64"},
    {Mode::kTypecast, "uint64"},
    {Mode::kTypecast, "float16"},
    {Mode::kTypecast, "float32"},
    {Mode::kTypecast, "float64"},
    {Mode::kArithmetic, "add:3"},
    {Mode::kArithmetic, "mul:-2,add:7"},
    {Mode::kArithmetic, "div:3"},
    {Mode::kArithmetic, "div:-1"},
    {Mode::kArithmetic, "add:-127.5,mul:0.5"},
    {Mode::kArithmetic, "typecast:float32,add:-127.5,div:127.5"},
    {Mode::kArithmetic, "typecast:float32,mul:0.25,add:1,div:3,mul:2"},
    {Mode::kArithmetic, "typecast:float64,add:-1.5e1,div:7"},
    {Mode::kArithmetic, "typecast:int32,mul:3,add:-7,div:2"},
    {Mode::kArithmetic, "typecast:uint8,add:200"},
    {Mode::kArithmetic, "typecast:float16,add:0.1,mul:3"},
    {Mode::kArithmetic, "per-channel:true@0,add:1@1,mul:2"},
    {Mode::kArithmetic,
     "typecast:float32,per-channel:true@0,add:-123.68:-116.78:-103.94,div:58.4@0"},
    {Mode::kArithmetic, "typecast:float32,per-channel:true@2,add:1:2:3:4,mul:3@1"},
    {Mode::kArithmetic, "typecast:int16,per-channel:true@1,mul:5@4,add:1"},
    {Mode::kArithmetic, "per-channel:false,add:2"},
    {Mode::kTranspose, "1:2:0:3"},
    {Mode::kTranspose, "2:0:1:3"},
    {Mode::kTranspose, "0:2:1:3"},
    {Mode::kTranspose, "0:1:2:3"},
    {Mode::kStand, "default", false},
    {Mode::kStand, "dc-average", false},
    {Mode::kStand, "default:float32", false},
    {Mode::kStand, "dc-average:float64,per-channel:true", false},
    {Mode::kStand, "default:float32,per-channel:true", false},
    {Mode::kClamp, "-10:10"},
    {Mode::kClamp, "0.5:100.25"},
    {Mode::kPadding, "left:1,right:2"},
    {Mode::kPadding, "top:1,bottom:1,front:1"},
    {Mode::kPadding, "left:1,top:2,back:1,layout:NHWC"},
    {Mode::kPadding, "left:0"},
};

const TensorType kAllTypes[] = {TensorType::kInt8,    TensorType::kUInt8,  TensorType::kInt16,
                                TensorType::kUInt16,  TensorType::kInt32,  TensorType::kUInt32,
                                TensorType::kInt64,   TensorType::kUInt64, TensorType::kFloat16,
                                TensorType::kFloat32, TensorType::kFloat64};

class AllModesAllTypes : public ::testing::TestWithParam<std::tuple<TensorType, std::size_t>> {};

void expect_close(const TensorInfo &out, const std::vector<uint8_t> &got,
                  const std::vector<uint8_t> &want, const std::string &what) {
  ASSERT_EQ(got.size(), want.size()) << what;
  dispatch_type(out.type, [&](auto tag) {
    using T = typename decltype(tag)::type;
    auto g = values_of<T>(got), w = values_of<T>(want);
    std::size_t bad = 0;
    for (std::size_t i = 0; i < g.size() && bad < 5; ++i) {
      double a = cast_value<double>(g[i]), b = cast_value<double>(w[i]);
      // Integers: the truncation may flip by one; 64-bit values lose bits in the double
      // statistics either way.
      double tol = is_floating_v<T> ? 1e-5 * std::max(1.0, std::fabs(b))
                   : sizeof(T) == 8 ? 16777216.0  // |x| up to 2^63: double keeps 53 bits
                                    : 1.0;
      if (!(std::fabs(a - b) <= tol)) {
        ++bad;
        ADD_FAILURE() << what << " element " << i << ": got " << a << ", want " << b;
      }
    }
  });
}

TEST_P(AllModesAllTypes, AcceleratedMatchesReference) {
  auto [type, ci] = GetParam();
  const Case &c = kCases[ci];
  Options o = parse_options(c.mode, c.option);
  // A small odd shape (tails everywhere) and one large enough for the blocked per-channel
  // layout (channel block >= 64 elements) and several SIMD chunks.
  for (auto in : {info(type, {3, 5, 4, 2}), info(type, {3, 37, 5, 1}), info(type, {5, 40, 4})}) {
    std::string what = std::string(type_name(type)) + " " + in.to_string() + " " + o.describe();
    std::vector<uint8_t> src = random_data(type, in.element_count(), 1234 + ci);
    std::vector<uint8_t> want, fast, slow;
    try {
      want = run_ref(o, in, src);
    } catch (const Error &e) {
      // Only per-channel options that do not fit the shape may be refused.
      EXPECT_EQ(e.kind(), ErrorKind::kNegotiation) << what << ": " << e.what();
      continue;
    }
    try {
      fast = run_plan(o, in, src, true);
      slow = run_plan(o, in, src, false);
    } catch (const Error &e) {
      // Division by a constant that is 0 in the compute type is refused at plan time.
      EXPECT_EQ(e.kind(), ErrorKind::kSettings) << what << ": " << e.what();
      EXPECT_NE(std::string(e.what()).find("divides by zero"), std::string::npos) << e.what();
      continue;
    }
    EXPECT_EQ(slow, want) << what << " (acceleration=false must be the reference)";
    if (c.exact)
      EXPECT_EQ(fast, want) << what;
    else
      expect_close(output_info(o, in), fast, want, what);
  }
}

INSTANTIATE_TEST_SUITE_P(Transform, AllModesAllTypes,
                         ::testing::Combine(::testing::ValuesIn(kAllTypes),
                                            ::testing::Range<std::size_t>(0, std::size(kCases))),
                         [](const auto &info) {
                           std::string name =
                               std::string(type_name(std::get<0>(info.param))) + "_" +
                               std::string(mode_name(kCases[std::get<1>(info.param)].mode)) + "_" +
                               std::to_string(std::get<1>(info.param));
                           return name;
                         });

// ---- hand-computed goldens --------------------------------------------------------------

TEST(TransformGolden, Dimchg) {
  // C:W:H = 2:3:1 -> W:H:C = 3:1:2; out[w][c] = in[c][w] (innermost first)
  auto o = parse_options(Mode::kDimchg, "0:2");
  std::vector<uint8_t> in = {1, 2, 3, 4, 5, 6};  // (c,w): (0,0)=1 (1,0)=2 (0,1)=3 ...
  for (bool acc : {true, false})
    EXPECT_EQ(run_plan(o, info(TensorType::kUInt8, {2, 3, 1}), in, acc),
              (std::vector<uint8_t>{1, 3, 5, 2, 4, 6}));
}

TEST(TransformGolden, Transpose) {
  // 2:3:1:1 with 1:0:2:3 swaps the two inner dimensions.
  auto o = parse_options(Mode::kTranspose, "1:0:2:3");
  std::vector<int16_t> in = {1, 2, 3, 4, 5, 6};
  auto got =
      values_of<int16_t>(run_plan(o, info(TensorType::kInt16, {2, 3, 1, 1}), bytes_of(in), true));
  EXPECT_EQ(got, (std::vector<int16_t>{1, 3, 5, 2, 4, 6}));
}

TEST(TransformGolden, ArithmeticNormalise) {
  auto o = parse_options(Mode::kArithmetic, "typecast:float32,add:-127.5,div:127.5");
  std::vector<uint8_t> in = {0, 127, 128, 255, 64, 191, 1, 254, 10, 20, 30, 40, 50, 60, 70, 80, 90};
  auto got = values_of<float>(run_plan(o, info(TensorType::kUInt8, {17}), in, true));
  ASSERT_EQ(got.size(), in.size());
  for (std::size_t i = 0; i < in.size(); ++i)
    EXPECT_EQ(got[i], (static_cast<float>(in[i]) + -127.5f) / 127.5f) << i;
  EXPECT_EQ(got[0], -1.0f);
  EXPECT_EQ(got[3], 1.0f);
}

TEST(TransformGolden, ArithmeticIntegerWraps) {
  // uint8 without typecast: add:-127.5 becomes (uint8)(int8)-127 = 129, so 200 + 129 wraps to 73.
  auto o = parse_options(Mode::kArithmetic, "add:-127.5");
  EXPECT_EQ(run_plan(o, info(TensorType::kUInt8, {3}), {200, 0, 127}, true),
            (std::vector<uint8_t>{73, 129, 0}));
  auto m = parse_options(Mode::kArithmetic, "mul:3,div:2");
  EXPECT_EQ(values_of<int8_t>(run_plan(m, info(TensorType::kInt8, {3}),
                                       bytes_of(std::vector<int8_t>{100, -3, 7}), true)),
            (std::vector<int8_t>{(int8_t)(44 / 2), -4, 10}));  // 300 wraps to 44; -9/2 = -4
}

TEST(TransformGolden, ArithmeticPerChannel) {
  // RGB 3:2:1:1, add 255 to G only (upstream's example), then per-channel values.
  auto o = parse_options(Mode::kArithmetic, "typecast:int16,per-channel:true@0,add:255@1");
  std::vector<uint8_t> in = {1, 2, 3, 4, 5, 6};
  EXPECT_EQ(values_of<int16_t>(run_plan(o, info(TensorType::kUInt8, {3, 2, 1, 1}), in, true)),
            (std::vector<int16_t>{1, 257, 3, 4, 260, 6}));
  auto v = parse_options(Mode::kArithmetic, "typecast:float32,per-channel:true@0,add:10:20:30");
  EXPECT_EQ(values_of<float>(run_plan(v, info(TensorType::kUInt8, {3, 2}), in, true)),
            (std::vector<float>{11, 22, 33, 14, 25, 36}));
  // Channel dimension 1 (planes of 2 elements).
  auto d1 = parse_options(Mode::kArithmetic, "per-channel:true@1,mul:2@0,add:1@2");
  EXPECT_EQ(run_plan(d1, info(TensorType::kUInt8, {2, 3}), in, true),
            (std::vector<uint8_t>{2, 4, 3, 4, 6, 7}));
}

TEST(TransformGolden, Typecast) {
  auto o = parse_options(Mode::kTypecast, "uint8");
  std::vector<float> in = {300.0f, -1.0f, 1.9f, 255.0f};
  EXPECT_EQ(run_plan(o, info(TensorType::kFloat32, {4}), bytes_of(in), true),
            (std::vector<uint8_t>{44, 255, 1, 255}));
  auto h = parse_options(Mode::kTypecast, "float16");
  EXPECT_EQ(values_of<uint16_t>(run_plan(h, info(TensorType::kFloat32, {4}), bytes_of(in), true)),
            (std::vector<uint16_t>{0x5CB0, 0xBC00, 0x3F9A, 0x5BF8}));
  auto back = parse_options(Mode::kTypecast, "float32");
  std::vector<uint16_t> halves = {0x3C00, 0xC500, 0x7C00};
  EXPECT_EQ(
      values_of<float>(run_plan(back, info(TensorType::kFloat16, {3}), bytes_of(halves), true)),
      (std::vector<float>{1.0f, -5.0f, INFINITY}));
}

TEST(TransformGolden, Stand) {
  // mean 2.5, population std sqrt(1.25); default is |x - mean| / std (upstream takes fabs).
  std::vector<float> in = {1, 2, 3, 4};
  auto d = parse_options(Mode::kStand, "default");
  auto got = values_of<float>(run_plan(d, info(TensorType::kFloat32, {4}), bytes_of(in), true));
  const float s = static_cast<float>(std::sqrt(1.25));
  std::vector<float> want = {1.5f / s, 0.5f / s, 0.5f / s, 1.5f / s};
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(got[i], want[i], 1e-6);
  auto dc = parse_options(Mode::kStand, "dc-average:int8");
  EXPECT_EQ(values_of<int8_t>(run_plan(dc, info(TensorType::kFloat32, {4}), bytes_of(in), true)),
            (std::vector<int8_t>{-1, 0, 0, 1}));  // -1.5, -0.5, 0.5, 1.5 truncated
  auto pc = parse_options(Mode::kStand, "dc-average:float32,per-channel:true");
  std::vector<uint8_t> rgb = {10, 20, 30, 30, 40, 50};  // channel means 20, 30, 40
  EXPECT_EQ(values_of<float>(run_plan(pc, info(TensorType::kUInt8, {3, 2}), rgb, true)),
            (std::vector<float>{-10, -10, -10, 10, 10, 10}));
  // A constant tensor has std 0: upstream divides by 1e-10 instead.
  std::vector<float> flat = {5, 5};
  EXPECT_EQ(values_of<float>(run_plan(d, info(TensorType::kFloat32, {2}), bytes_of(flat), true)),
            (std::vector<float>{0, 0}));
}

TEST(TransformGolden, Clamp) {
  auto o = parse_options(Mode::kClamp, "-1.5:2");
  std::vector<float> in = {-3, -1, 0.5f, 2.5f, NAN};
  auto got = values_of<float>(run_plan(o, info(TensorType::kFloat32, {5}), bytes_of(in), true));
  EXPECT_EQ(got[0], -1.5f);
  EXPECT_EQ(got[1], -1.0f);
  EXPECT_EQ(got[2], 0.5f);
  EXPECT_EQ(got[3], 2.0f);
  EXPECT_TRUE(std::isnan(got[4]));
  auto u = parse_options(Mode::kClamp, "10:20");
  EXPECT_EQ(run_plan(u, info(TensorType::kUInt8, {3}), {5, 15, 250}, true),
            (std::vector<uint8_t>{10, 15, 20}));
}

TEST(TransformGolden, Padding) {
  // 2:2 padded left:1,bottom:1 -> 3:3
  auto o = parse_options(Mode::kPadding, "left:1,bottom:1");
  std::vector<uint8_t> in = {1, 2, 3, 4};
  EXPECT_EQ(run_plan(o, info(TensorType::kUInt8, {2, 2}), in, true),
            (std::vector<uint8_t>{0, 1, 2, 0, 3, 4, 0, 0, 0}));
  // NHWC: front/back pad the channels (dimension 0).
  auto c = parse_options(Mode::kPadding, "front:1,layout:NHWC");
  EXPECT_EQ(run_plan(c, info(TensorType::kUInt8, {1, 2, 2}), in, true),
            (std::vector<uint8_t>{0, 1, 0, 2, 0, 3, 0, 4}));
}

TEST(TransformGolden, TypecastSpecialFloatsMatchReference) {
  // NaN, infinities and values beyond int32 through the SIMD float32 -> int path.
  std::vector<float> in;
  for (int i = 0; i < 5; ++i)
    for (float v : {NAN, INFINITY, -INFINITY, 3e9f, -3e9f, 1e20f, -2147483648.0f, 2147483520.0f,
                    -0.7f, 255.5f, 65535.9f, -32769.2f})
      in.push_back(v);
  auto src = bytes_of(in);
  TensorInfo t = info(TensorType::kFloat32, {static_cast<uint32_t>(in.size())});
  for (const char *to :
       {"int8", "uint8", "int16", "uint16", "int32", "uint32", "int64", "uint64"}) {
    auto o = parse_options(Mode::kTypecast, to);
    EXPECT_EQ(run_plan(o, t, src, true), run_ref(o, t, src)) << to;
  }
  auto u8 = values_of<uint8_t>(run_plan(parse_options(Mode::kTypecast, "uint8"), t, src, true));
  EXPECT_EQ(u8[0], 0);    // NaN -> INT32_MIN -> low byte 0
  EXPECT_EQ(u8[9], 255);  // 255.5 truncates to 255
  auto u32 = values_of<uint32_t>(run_plan(parse_options(Mode::kTypecast, "uint32"), t, src, true));
  EXPECT_EQ(u32[3], 2147483648u);  // 3e9 goes through int32 as upstream does
}

TEST(TransformPlan, IdentityAndErrors) {
  EXPECT_TRUE(
      make_plan(parse_options(Mode::kTypecast, "uint8"), info(TensorType::kUInt8, {3}), true)
          .identity);
  // Moving a dimension of size 1 does not move bytes.
  EXPECT_TRUE(
      make_plan(parse_options(Mode::kDimchg, "0:3"), info(TensorType::kUInt8, {1, 4, 4, 1}), true)
          .identity);
  EXPECT_FALSE(
      make_plan(parse_options(Mode::kDimchg, "0:2"), info(TensorType::kUInt8, {3, 4, 4, 1}), true)
          .identity);
  try {
    make_plan(parse_options(Mode::kArithmetic, "typecast:int32,div:0.5"),
              info(TensorType::kUInt8, {3}), true);
    ADD_FAILURE() << "no error";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("'div:0.5' divides by zero (the value is 0 in int32)"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(
      make_plan(parse_options(Mode::kArithmetic, "div:0"), info(TensorType::kFloat32, {3}), true),
      Error);
  // Per-channel division by 0 only on a channel the op does not apply to is fine.
  EXPECT_NO_THROW(make_plan(parse_options(Mode::kArithmetic, "per-channel:true@0,div:2@1"),
                            info(TensorType::kUInt8, {3}), true));
  std::printf("SIMD target: %s\n", simd::target_name());
}

}  // namespace
}  // namespace nns::transform

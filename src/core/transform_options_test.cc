// SPDX-License-Identifier: LGPL-2.1-only
#include "core/transform_options.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace nns::transform {
namespace {

TensorInfo info(TensorType t, std::initializer_list<uint32_t> d) {
  return TensorInfo{"", t, make_dims(d)};
}

// Expects parse_options to throw a kSettings error whose text contains every fragment.
void expect_bad(Mode mode, const char *option, std::initializer_list<const char *> fragments) {
  try {
    parse_options(mode, option);
    ADD_FAILURE() << "no error for mode=" << mode_name(mode)
                  << " option=" << (option ? option : "(null)");
  } catch (const Error &e) {
    EXPECT_EQ(e.kind(), ErrorKind::kSettings);
    for (const char *f : fragments)
      EXPECT_NE(std::string(e.what()).find(f), std::string::npos)
          << "'" << f << "' not in: " << e.what();
  }
}

TEST(TransformOptions, ModeNames) {
  EXPECT_EQ(mode_name(Mode::kDimchg), "dimchg");
  EXPECT_EQ(mode_name(Mode::kPadding), "padding");
  EXPECT_EQ(mode_name(Mode::kUnknown), "unknown");
  expect_bad(Mode::kUnknown, "0:1", {"property 'mode'", "not set", "dimchg"});
  expect_bad(Mode::kTypecast, nullptr, {"property 'option'", "not set", "typecast"});
  expect_bad(Mode::kTypecast, "", {"property 'option'", "not set"});
}

TEST(TransformOptions, Dimchg) {
  auto o = parse_options(Mode::kDimchg, "0:2");
  EXPECT_EQ(o.get<DimchgOptions>().from, 0u);
  EXPECT_EQ(o.get<DimchgOptions>().to, 2u);
  EXPECT_EQ(parse_options(Mode::kDimchg, "15:10").get<DimchgOptions>().from, 15u);
  expect_bad(Mode::kDimchg, "0:16", {"'16'", "0..15", "mode=dimchg"});
  expect_bad(Mode::kDimchg, "0", {"FROM:TO"});
  expect_bad(Mode::kDimchg, "0:1:2", {"FROM:TO"});
  expect_bad(Mode::kDimchg, "a:1", {"'a'"});
  expect_bad(Mode::kDimchg, "01:1", {"'01'"});
  // [a][H][W][C] -> [a][C][H][W]: C:W:H:N becomes W:H:C:N.
  EXPECT_TRUE(dims_equal(output_info(o, info(TensorType::kUInt8, {3, 640, 480, 1})).dims,
                         make_dims({640, 480, 3, 1})));
  // The other direction (upstream refuses to transform it; we move the dimension back).
  auto back = parse_options(Mode::kDimchg, "2:0");
  EXPECT_TRUE(dims_equal(output_info(back, info(TensorType::kUInt8, {640, 480, 3, 1})).dims,
                         make_dims({3, 640, 480, 1})));
  // Missing dimensions count as 1.
  EXPECT_TRUE(dims_equal(
      output_info(parse_options(Mode::kDimchg, "0:3"), info(TensorType::kUInt8, {3, 4})).dims,
      make_dims({4, 1, 1, 3})));
  EXPECT_TRUE(dims_equal(input_info(o, info(TensorType::kUInt8, {640, 480, 3, 1})).dims,
                         make_dims({3, 640, 480, 1})));
}

TEST(TransformOptions, Typecast) {
  EXPECT_EQ(parse_options(Mode::kTypecast, "float32").get<TypecastOptions>().to,
            TensorType::kFloat32);
  EXPECT_EQ(parse_options(Mode::kTypecast, "UINT8").get<TypecastOptions>().to, TensorType::kUInt8);
  EXPECT_EQ(parse_options(Mode::kTypecast, "float16").get<TypecastOptions>().to,
            TensorType::kFloat16);
  expect_bad(Mode::kTypecast, "flot32", {"unknown type 'flot32'", "float32", "mode=typecast"});
  auto o = parse_options(Mode::kTypecast, "int16");
  auto out = output_info(o, info(TensorType::kUInt8, {3, 4}));
  EXPECT_EQ(out.type, TensorType::kInt16);
  EXPECT_EQ(input_info(o, out).type, TensorType::kEnd);
}

TEST(TransformOptions, Arithmetic) {
  auto o = parse_options(Mode::kArithmetic, "typecast:float32,add:-127.5,div:127.5");
  const auto &a = o.get<ArithOptions>();
  ASSERT_TRUE(a.out_type);
  EXPECT_EQ(*a.out_type, TensorType::kFloat32);
  ASSERT_EQ(a.ops.size(), 2u);
  EXPECT_EQ(a.ops[0].kind, OpKind::kAdd);
  EXPECT_TRUE(a.ops[0].values[0].is_float);
  EXPECT_DOUBLE_EQ(a.ops[0].values[0].f, -127.5);
  EXPECT_EQ(a.ops[1].kind, OpKind::kDiv);
  EXPECT_FALSE(a.per_channel);

  auto ints = parse_options(Mode::kArithmetic, "add:25,mul:4,").get<ArithOptions>();
  ASSERT_EQ(ints.ops.size(), 2u);
  EXPECT_FALSE(ints.ops[0].values[0].is_float);
  EXPECT_EQ(ints.ops[0].values[0].i, 25);
  EXPECT_TRUE(
      parse_options(Mode::kArithmetic, "mul:1e2").get<ArithOptions>().ops[0].values[0].is_float);
  EXPECT_TRUE(
      parse_options(Mode::kArithmetic, "mul:.5").get<ArithOptions>().ops[0].values[0].is_float);

  auto pc =
      parse_options(Mode::kArithmetic, "per-channel:true@0,add:255@1,mul:2").get<ArithOptions>();
  EXPECT_TRUE(pc.per_channel);
  EXPECT_EQ(pc.ch_dim, 0u);
  EXPECT_EQ(pc.ops[0].channel, 1);
  EXPECT_EQ(pc.ops[1].channel, -1);
  // Without per-channel, several values: upstream's reading, the first one, with a warning.
  auto first = parse_options(Mode::kArithmetic, "add:5:2,mul:3").get<ArithOptions>();
  ASSERT_EQ(first.ops.size(), 2u);
  ASSERT_EQ(first.ops[0].values.size(), 1u);
  EXPECT_EQ(first.ops[0].values[0].i, 5);
  ASSERT_EQ(first.warnings.size(), 1u);
  EXPECT_NE(first.warnings[0].find("'add:5:2' has 2 values"), std::string::npos)
      << first.warnings[0];
  EXPECT_NE(first.warnings[0].find("only the first (5) is used"), std::string::npos);
  auto multi = parse_options(Mode::kArithmetic, "per-channel:true@2,add:1:2:3").get<ArithOptions>();
  EXPECT_EQ(multi.ch_dim, 2u);
  EXPECT_EQ(multi.ops[0].values.size(), 3u);
  EXPECT_EQ(
      parse_options(Mode::kArithmetic, "per-channel:true@015,add:1").get<ArithOptions>().ch_dim,
      15u);
  EXPECT_FALSE(
      parse_options(Mode::kArithmetic, "per-channel:false,add:1").get<ArithOptions>().per_channel);

  expect_bad(Mode::kArithmetic, "sub:1", {"unknown operation 'sub'", "add, mul or div"});
  expect_bad(Mode::kArithmetic, "add:x", {"bad number 'x'", "'add:x'"});
  expect_bad(Mode::kArithmetic, "add:1.", {"bad number '1.'"});
  expect_bad(Mode::kArithmetic, "add", {"'add' has no value"});
  expect_bad(Mode::kArithmetic, "add:1,typecast:float32,mul:2",
             {"'typecast:float32' must be the first"});
  // A typecast last is ignored as upstream does (its test arithmetic4), with a warning.
  auto late = parse_options(Mode::kArithmetic, "typecast:float64,add:0.2,add:0.1,typecast:uint16")
                  .get<ArithOptions>();
  EXPECT_EQ(late.out_type, TensorType::kFloat64);
  EXPECT_EQ(late.ops.size(), 2u);
  ASSERT_EQ(late.warnings.size(), 1u);
  EXPECT_NE(late.warnings[0].find("'typecast:uint16' is ignored"), std::string::npos);
  expect_bad(Mode::kArithmetic, "add:1,typecast:float99", {"unknown type 'float99'"});
  expect_bad(Mode::kArithmetic, "typecast:float33,add:1", {"unknown type 'float33'"});
  expect_bad(Mode::kArithmetic, "typecast:float32", {"no add/mul/div"});
  expect_bad(Mode::kArithmetic, "add:1,,mul:2", {"empty item"});
  expect_bad(Mode::kArithmetic, "add:1@0", {"'add:1@0' names channel 0", "per-channel:true@DIM"});
  expect_bad(Mode::kArithmetic, "per-channel:true@16,add:1", {"'16'", "0..15"});
  expect_bad(Mode::kArithmetic, "per-channel:maybe,add:1", {"'per-channel:maybe'"});
  expect_bad(Mode::kArithmetic, "add:1,per-channel:true@0", {"must come before"});
  expect_bad(Mode::kArithmetic, "per-channel:true@0,add:1:2@1", {"both one value per channel"});
  expect_bad(Mode::kArithmetic, "add:99999999999999999999", {"int64 range"});
  expect_bad(Mode::kArithmetic, "per-channel:true@0,add:1@x", {"bad channel index 'x'"});

  // Output type and per-channel checks against a tensor.
  auto out = output_info(o, info(TensorType::kUInt8, {3, 4, 4, 1}));
  EXPECT_EQ(out.type, TensorType::kFloat32);
  auto bad_ch = parse_options(Mode::kArithmetic, "per-channel:true@0,add:1@3");
  try {
    output_info(bad_ch, info(TensorType::kUInt8, {3, 4}));
    ADD_FAILURE() << "no error";
  } catch (const Error &e) {
    EXPECT_EQ(e.kind(), ErrorKind::kNegotiation);
    EXPECT_NE(std::string(e.what()).find("'add:1@3' names channel 3 but dimension 0 has 3"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(output_info(parse_options(Mode::kArithmetic, "per-channel:true@0,add:1:2"),
                           info(TensorType::kUInt8, {3, 4})),
               Error);
}

TEST(TransformOptions, Transpose) {
  auto o = parse_options(Mode::kTranspose, "1:2:0:3");
  EXPECT_EQ(o.get<TransposeOptions>().order, (std::array<uint32_t, 4>{1, 2, 0, 3}));
  // 3:640:480:1 (NHWC) -> 640:480:3:1 (NCHW)
  auto out = output_info(o, info(TensorType::kFloat32, {3, 640, 480, 1}));
  EXPECT_TRUE(dims_equal(out.dims, make_dims({640, 480, 3, 1})));
  EXPECT_TRUE(dims_equal(input_info(o, out).dims, make_dims({3, 640, 480, 1})));
  expect_bad(Mode::kTranspose, "1:1:0:3", {"'1' is repeated"});
  expect_bad(Mode::kTranspose, "1:2:0", {"expected 4 indices"});
  expect_bad(Mode::kTranspose, "1:2:0:2", {"last index must be 3", "'2'"});
  expect_bad(Mode::kTranspose, "3:2:0:1", {"bad index '3'"});
}

TEST(TransformOptions, Stand) {
  auto s = parse_options(Mode::kStand, "dc-average:float32,per-channel:true").get<StandOptions>();
  EXPECT_EQ(s.mode, StandMode::kDcAverage);
  EXPECT_EQ(*s.out_type, TensorType::kFloat32);
  EXPECT_TRUE(s.per_channel);
  auto d = parse_options(Mode::kStand, "default").get<StandOptions>();
  EXPECT_EQ(d.mode, StandMode::kDefault);
  EXPECT_FALSE(d.out_type);
  expect_bad(Mode::kStand, "median", {"unknown stand mode 'median'"});
  expect_bad(Mode::kStand, "default:float", {"unknown type 'float'"});
  expect_bad(Mode::kStand, "default,per-channel:yes", {"'per-channel:yes'"});
  expect_bad(Mode::kStand, "default,per-channel:true,x", {"one or two items"});
}

TEST(TransformOptions, Clamp) {
  auto c = parse_options(Mode::kClamp, "-1.5:2e2").get<ClampOptions>();
  EXPECT_DOUBLE_EQ(c.min, -1.5);
  EXPECT_DOUBLE_EQ(c.max, 200.0);
  expect_bad(Mode::kClamp, "10:1", {"MIN '10' is larger than MAX '1'"});
  expect_bad(Mode::kClamp, "0", {"MIN:MAX"});
  expect_bad(Mode::kClamp, "0:abc", {"bad number 'abc'"});
  expect_bad(Mode::kClamp, "0:1e999", {"out of range"});
}

TEST(TransformOptions, Padding) {
  auto p = parse_options(Mode::kPadding, "left:1,right:2,top:3,bottom:4,front:5,back:6")
               .get<PaddingOptions>();
  EXPECT_EQ(p.pad, (std::array<uint32_t, 6>{1, 2, 3, 4, 5, 6}));
  auto nhwc =
      parse_options(Mode::kPadding, "left:1,right:2,front:5,layout:NHWC").get<PaddingOptions>();
  EXPECT_EQ(nhwc.pad, (std::array<uint32_t, 6>{5, 0, 0, 0, 1, 2}));
  auto o = parse_options(Mode::kPadding, "left:1,right:1,top:2");
  EXPECT_TRUE(dims_equal(output_info(o, info(TensorType::kUInt8, {4, 4, 3, 1})).dims,
                         make_dims({6, 6, 3, 1})));
  // A rank-1 tensor padded on dimension 2 grows the missing dimensions as 1s.
  EXPECT_TRUE(dims_equal(
      output_info(parse_options(Mode::kPadding, "front:1"), info(TensorType::kUInt8, {5})).dims,
      make_dims({5, 1, 2})));
  EXPECT_TRUE(dims_equal(input_info(o, info(TensorType::kUInt8, {6, 6, 3, 1})).dims,
                         make_dims({4, 4, 3, 1})));
  expect_bad(Mode::kPadding, "middle:1", {"unknown padding side 'middle'"});
  expect_bad(Mode::kPadding, "left:x", {"bad padding size 'x'"});
  expect_bad(Mode::kPadding, "left:-1", {"bad padding size '-1'"});
  expect_bad(Mode::kPadding, "layout:NHWC,left:1", {"must be the last item"});
  expect_bad(Mode::kPadding, "layout:NCHW", {"no padding side"});
  expect_bad(Mode::kPadding, "left:1,layout:CHW", {"bad layout 'CHW'"});
  expect_bad(Mode::kPadding, "left:4294967295,right:1", {"add up to more than"});
}

TEST(TransformOptions, Apply) {
  EXPECT_TRUE(parse_apply("").empty());
  EXPECT_EQ(parse_apply("0,2"), (std::vector<uint32_t>{0, 2}));
  EXPECT_EQ(parse_apply(" 1 "), (std::vector<uint32_t>{1}));
  try {
    parse_apply("0,x");
    ADD_FAILURE() << "no error";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("property 'apply' '0,x': 'x' is not a tensor index"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(parse_apply("-1"), Error);
  EXPECT_THROW(parse_apply("256"), Error);
}

}  // namespace
}  // namespace nns::transform

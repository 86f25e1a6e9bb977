// SPDX-License-Identifier: LGPL-2.1-only
// tensor_if condition logic: option grammars, every operator on every type, A_VALUE element
// addressing, TENSOR_AVERAGE_VALUE casting, TENSORPICK outputs and error texts.
#include "core/tensor_if_cond.h"

#include <gtest/gtest.h>

#include <cstring>
#include <functional>

#include "core/error.h"

namespace nns::tif {
namespace {

std::string error_of(const std::function<void()> &f) {
  try {
    f();
  } catch (const Error &e) {
    return e.what();
  }
  return "";
}

TEST(TensorIfOptions, SuppliedValue) {
  auto a = parse_supplied_value("10");
  EXPECT_FALSE(a.is_float);
  ASSERT_EQ(a.i.size(), 1u);
  EXPECT_EQ(a.i[0], 10);
  auto b = parse_supplied_value("-1,2.5");
  EXPECT_TRUE(b.is_float);
  EXPECT_EQ(b.f[0], -1.0);
  EXPECT_EQ(b.f[1], 2.5);
  EXPECT_TRUE(parse_supplied_value("1e2").is_float);
  EXPECT_NE(error_of([] { parse_supplied_value("1,2,3"); }).find("has 3 values"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_supplied_value("abc"); }).find("supplied-value: 'abc'"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_supplied_value(""); }).find("is not set"), std::string::npos);
}

TEST(TensorIfOptions, AValueAndPick) {
  auto r = parse_a_value_option("1:2:0:0,3");
  EXPECT_EQ(r.tensor, 3u);
  EXPECT_EQ(r.index, (std::vector<uint32_t>{1, 2, 0, 0}));
  EXPECT_NE(error_of([] { parse_a_value_option("0:0:0:0"); }).find("compared-value-option"),
            std::string::npos);
  EXPECT_NE(error_of([] { parse_a_value_option("0:-1,0"); }).find("negative"), std::string::npos);
  EXPECT_EQ(parse_pick("0, 2", "then-option"), (std::vector<uint32_t>{0, 2}));
  EXPECT_NE(error_of([] { parse_pick("0,x", "else-option"); }).find("else-option: 'x'"),
            std::string::npos);
  EXPECT_EQ(parse_tensor_index("1", "compared-value-option"), 1u);
  EXPECT_NE(
      error_of([] { parse_tensor_index("0,1", "compared-value-option"); }).find("one tensor index"),
      std::string::npos);
}

// One element tensor of `type` holding `v` (as the type), compared with supplied "a[,b]".
template <typename T>
bool eval1(TensorType type, T v, Op op, const std::string &sv) {
  TensorsInfo in;
  in.tensors.push_back(TensorInfo{"", type, make_dims({1})});
  Condition c(Compared::kAValue, "0,0", op, parse_supplied_value(sv), in);
  uint8_t buf[8] = {};
  std::memcpy(buf, &v, sizeof v);
  const uint8_t *ptrs[1] = {buf};
  return c.evaluate(ptrs);
}

template <typename T>
void check_all_ops(TensorType type) {
  SCOPED_TRACE(std::string(type_name(type)));
  // value 5 against 5, 4, 6 and the ranges [5,7], (5,7), [1,4], (1,5)
  EXPECT_TRUE(eval1<T>(type, 5, Op::kEq, "5"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kEq, "4"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kNe, "4"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kNe, "5"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kGt, "4"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kGt, "5"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kGe, "5"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kGe, "6"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kLt, "6"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kLt, "5"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kLe, "5"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kLe, "4"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kRangeInclusive, "5,7"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kRangeInclusive, "6,7"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kRangeExclusive, "5,7"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kRangeExclusive, "4,7"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kNotInRangeInclusive, "1,4"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kNotInRangeInclusive, "1,5"));
  EXPECT_TRUE(eval1<T>(type, 5, Op::kNotInRangeExclusive, "1,5"));
  EXPECT_FALSE(eval1<T>(type, 5, Op::kNotInRangeExclusive, "1,6"));
  // supplied floats are cast to the element type (2.9 -> 2 for integers)
  if (std::is_integral_v<T>) {
    EXPECT_TRUE(eval1<T>(type, 2, Op::kEq, "2.9"));
  }
}

TEST(TensorIfCondition, AllOperatorsAllTypes) {
  check_all_ops<int32_t>(TensorType::kInt32);
  check_all_ops<uint32_t>(TensorType::kUInt32);
  check_all_ops<int16_t>(TensorType::kInt16);
  check_all_ops<uint16_t>(TensorType::kUInt16);
  check_all_ops<int8_t>(TensorType::kInt8);
  check_all_ops<uint8_t>(TensorType::kUInt8);
  check_all_ops<double>(TensorType::kFloat64);
  check_all_ops<float>(TensorType::kFloat32);
  check_all_ops<int64_t>(TensorType::kInt64);
  check_all_ops<uint64_t>(TensorType::kUInt64);
  // float16 5.0 = 0x4500
  EXPECT_TRUE(eval1<uint16_t>(TensorType::kFloat16, 0x4500, Op::kEq, "5"));
  EXPECT_TRUE(eval1<uint16_t>(TensorType::kFloat16, 0x4500, Op::kGt, "4.5"));
  EXPECT_FALSE(eval1<uint16_t>(TensorType::kFloat16, 0x4500, Op::kLt, "4.5"));
  // signed comparisons stay signed: -1 < 0 for int8
  EXPECT_TRUE(eval1<int8_t>(TensorType::kInt8, -1, Op::kLt, "0"));
  EXPECT_TRUE(eval1<float>(TensorType::kFloat32, 0.25f, Op::kRangeExclusive, "0.2,0.3"));
}

TEST(TensorIfCondition, AValueAddressesInnermostFirst) {
  TensorsInfo in;
  in.tensors.push_back(TensorInfo{"", TensorType::kUInt8, make_dims({2})});
  in.tensors.push_back(TensorInfo{"", TensorType::kUInt16, make_dims({3, 2, 2})});
  uint8_t t0[2] = {0, 0};
  uint16_t t1[12];
  for (int i = 0; i < 12; ++i) t1[i] = static_cast<uint16_t>(100 + i);
  const uint8_t *ptrs[2] = {t0, reinterpret_cast<uint8_t *>(t1)};
  // element [c=2][w=1][h=1] -> flat 2 + 1*3 + 1*6 = 11
  Condition c(Compared::kAValue, "2:1:1:0,1", Op::kEq, parse_supplied_value("111"), in);
  EXPECT_TRUE(c.evaluate(ptrs));
  Condition c2(Compared::kAValue, "1,1", Op::kEq, parse_supplied_value("101"), in);
  EXPECT_TRUE(c2.evaluate(ptrs));
}

TEST(TensorIfCondition, AverageIsCastToElementType) {
  TensorsInfo in;
  in.tensors.push_back(TensorInfo{"", TensorType::kUInt8, make_dims({4})});
  uint8_t t0[4] = {1, 2, 2, 2};  // 1.75 -> 1 in uint8
  const uint8_t *ptrs[1] = {t0};
  EXPECT_TRUE(Condition(Compared::kTensorAverage, "0", Op::kEq, parse_supplied_value("1"), in)
                  .evaluate(ptrs));
  in.tensors[0].type = TensorType::kFloat32;
  float f[4] = {1, 2, 2, 2};
  ptrs[0] = reinterpret_cast<uint8_t *>(f);
  EXPECT_TRUE(Condition(Compared::kTensorAverage, "0", Op::kEq, parse_supplied_value("1.75"), in)
                  .evaluate(ptrs));
}

TEST(TensorIfCondition, ErrorsNameOptionAndBothValues) {
  TensorsInfo in;
  in.tensors.push_back(TensorInfo{"", TensorType::kUInt8, make_dims({3, 4})});
  auto sv = parse_supplied_value("1");
  EXPECT_NE(error_of([&] { Condition(Compared::kAValue, "0:0,2", Op::kEq, sv, in); })
                .find("compared-value-option='0:0,2' names tensor 2 but the input has 1 "
                      "tensor(s)"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              Condition(Compared::kAValue, "0:4,0", Op::kEq, sv, in);
            }).find("index 4 of dimension 1 is outside tensor 0 (uint8 3:4)"),
            std::string::npos)
      << error_of([&] { Condition(Compared::kAValue, "0:4,0", Op::kEq, sv, in); });
  EXPECT_NE(error_of([&] {
              Condition(Compared::kTensorAverage, "1", Op::kEq, sv, in);
            }).find("names tensor 1 but the input has 1"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              Condition(Compared::kAValue, "0,0", Op::kRangeInclusive, sv, in);
            }).find("operator RANGE_INCLUSIVE needs two supplied values"),
            std::string::npos);
  EXPECT_NE(error_of([&] {
              action_output(Action::kTensorPick, {0, 3}, in, "then-option");
            }).find("then-option picks tensor 3 but the input has 1 tensor(s)"),
            std::string::npos);
}

TEST(TensorIfCondition, ActionOutputs) {
  TensorsInfo in;
  in.tensors.push_back(TensorInfo{"", TensorType::kUInt8, make_dims({3})});
  in.tensors.push_back(TensorInfo{"", TensorType::kFloat32, make_dims({2})});
  EXPECT_TRUE(action_output(Action::kPassthrough, {}, in, "then-option").same_as(in));
  auto o = action_output(Action::kTensorPick, {1, 0, 1}, in, "else-option");
  ASSERT_EQ(o.size(), 3u);
  EXPECT_EQ(o[0].type, TensorType::kFloat32);
  EXPECT_EQ(o[1].type, TensorType::kUInt8);
}

}  // namespace
}  // namespace nns::tif

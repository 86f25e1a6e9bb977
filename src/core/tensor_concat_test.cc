// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_concat.h"

#include <gtest/gtest.h>

#include <numeric>

#include "core/error.h"

namespace nns {
namespace {

TensorInfo u16(std::initializer_list<uint32_t> d) {
  return TensorInfo{"", TensorType::kUInt16, make_dims(d)};
}

// Element (c, x, y) of a 3-D tensor stored innermost first.
std::vector<uint16_t> fill(uint16_t base, uint32_t c, uint32_t w, uint32_t h) {
  std::vector<uint16_t> v;
  for (uint32_t y = 0; y < h; ++y)
    for (uint32_t x = 0; x < w; ++x)
      for (uint32_t k = 0; k < c; ++k) v.push_back(base + y * 100 + x * 10 + k);
  return v;
}

std::vector<uint16_t> concat(const std::vector<TensorInfo> &in,
                             const std::vector<std::vector<uint16_t>> &data, std::size_t dim) {
  auto plan = plan_concat(in, dim);
  std::vector<uint16_t> out(plan.total / 2);
  std::vector<const uint8_t *> src;
  for (auto &d : data) src.push_back(reinterpret_cast<const uint8_t *>(d.data()));
  run_concat(plan, src.data(), reinterpret_cast<uint8_t *>(out.data()));
  return out;
}

TEST(TensorConcat, InfoAlongEachDim) {
  std::vector<std::string> names{"sink_0", "sink_1"};
  EXPECT_EQ(concat_info({u16({3, 640, 480}), u16({3, 640, 480})}, 1, names).to_string(),
            "uint16 3:1280:480");
  EXPECT_EQ(concat_info({u16({1, 4, 4}), u16({2, 4, 4})}, 0, names).to_string(), "uint16 3:4:4");
  EXPECT_EQ(concat_info({u16({3, 4}), u16({3, 4})}, 3, names).to_string(), "uint16 3:4:1:2");
}

TEST(TensorConcat, InfoErrorsNameBothValues) {
  std::vector<std::string> names{"sink_0", "sink_1"};
  try {
    concat_info({u16({3, 4}), TensorInfo{"", TensorType::kFloat32, make_dims({3, 4})}}, 0, names);
    FAIL();
  } catch (const Error &e) {
    std::string m = e.what();
    EXPECT_NE(m.find("sink_1 has type float32 but sink_0 has uint16"), std::string::npos) << m;
  }
  try {
    concat_info({u16({3, 4, 4}), u16({3, 5, 4})}, 0, names);
    FAIL();
  } catch (const Error &e) {
    std::string m = e.what();
    EXPECT_NE(m.find("sink_1 has dimensions 3:5:4 but sink_0 has 3:4:4"), std::string::npos) << m;
    EXPECT_NE(m.find("(5 vs 4)"), std::string::npos) << m;
  }
}

TEST(TensorConcat, DataAlongEachDim) {
  auto a = fill(1000, 2, 2, 2), b = fill(2000, 2, 2, 2);
  std::vector<TensorInfo> in{u16({2, 2, 2}), u16({2, 2, 2})};
  // dim 0: channels interleave per pixel.
  auto o = concat(in, {a, b}, 0);
  std::vector<uint16_t> want0;
  for (uint32_t y = 0; y < 2; ++y)
    for (uint32_t x = 0; x < 2; ++x) {
      for (uint32_t k = 0; k < 2; ++k) want0.push_back(1000 + y * 100 + x * 10 + k);
      for (uint32_t k = 0; k < 2; ++k) want0.push_back(2000 + y * 100 + x * 10 + k);
    }
  EXPECT_EQ(o, want0);
  // dim 1: rows of a then rows of b.
  o = concat(in, {a, b}, 1);
  std::vector<uint16_t> want1;
  for (uint32_t y = 0; y < 2; ++y) {
    for (uint32_t i = 0; i < 4; ++i) want1.push_back(a[y * 4 + i]);
    for (uint32_t i = 0; i < 4; ++i) want1.push_back(b[y * 4 + i]);
  }
  EXPECT_EQ(o, want1);
  // dim 2 and 3: plain append.
  std::vector<uint16_t> ab = a;
  ab.insert(ab.end(), b.begin(), b.end());
  EXPECT_EQ(concat(in, {a, b}, 2), ab);
  EXPECT_EQ(concat(in, {a, b}, 3), ab);
  // Different sizes along the concatenated dim.
  auto c = fill(3000, 1, 2, 2);
  o = concat({u16({2, 2, 2}), u16({1, 2, 2})}, {a, c}, 0);
  EXPECT_EQ(o.size(), 12u);
  EXPECT_EQ(o[2], 3000);
  EXPECT_EQ(o[3], 1010);
}

TEST(TensorConcat, AggregatorPlan) {
  AggregatorConfig cfg;
  cfg.frames_out = 10;
  cfg.frames_flush = 5;
  cfg.frames_dim = 3;
  auto p = plan_aggregator(TensorInfo{"", TensorType::kUInt8, make_dims({3, 640, 480, 1})}, cfg);
  EXPECT_EQ(p.out.to_string(), "uint8 3:640:480:10");
  EXPECT_EQ(p.frame_size, 3u * 640 * 480);
  EXPECT_EQ(p.flush_size, 5u * 3 * 640 * 480);
  EXPECT_FALSE(p.reorder);
  cfg.frames_dim = 2;
  p = plan_aggregator(TensorInfo{"", TensorType::kUInt8, make_dims({3, 640, 480, 1})}, cfg);
  EXPECT_EQ(p.out.to_string(), "uint8 3:640:4800:1");
  EXPECT_FALSE(p.reorder);
  // Default frames-dim 15 extends the rank.
  AggregatorConfig d;
  d.frames_out = 2;
  p = plan_aggregator(TensorInfo{"", TensorType::kUInt8, make_dims({3, 4})}, d);
  EXPECT_EQ(p.out.to_string(), "uint8 3:4:1:1:1:1:1:1:1:1:1:1:1:1:1:2");
  // frames-in splits the input.
  AggregatorConfig s;
  s.frames_in = 4;
  s.frames_dim = 1;
  p = plan_aggregator(TensorInfo{"", TensorType::kFloat32, make_dims({2, 8})}, s);
  EXPECT_EQ(p.out.to_string(), "float32 2:2");
  EXPECT_EQ(p.frame_size, 16u);
}

TEST(TensorConcat, AggregatorPlanErrors) {
  AggregatorConfig cfg;
  cfg.frames_in = 3;
  cfg.frames_dim = 1;
  try {
    plan_aggregator(TensorInfo{"", TensorType::kUInt8, make_dims({3, 4})}, cfg);
    FAIL();
  } catch (const Error &e) {
    std::string m = e.what();
    EXPECT_NE(m.find("frames-dim=1"), std::string::npos) << m;
    EXPECT_NE(m.find("is 4, not a multiple of frames-in=3"), std::string::npos) << m;
  }
  AggregatorConfig f;
  f.frames_in = 5;
  f.frames_out = 10;
  f.frames_flush = 20;
  f.frames_dim = 0;
  try {
    plan_aggregator(TensorInfo{"", TensorType::kUInt8, make_dims({5})}, f);
    FAIL();
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("frames-flush=20"), std::string::npos) << e.what();
  }
}

// Upstream's worked example: two frames of 3:4:2:1, concatenated along frames-dim.
TEST(TensorConcat, AggregatorReorderMatchesUpstreamExample) {
  std::vector<uint16_t> two;
  for (uint16_t f = 1; f <= 2; ++f)
    for (uint16_t i = 1; i <= 24; ++i) two.push_back(f * 1000 + 100 + i);
  auto run = [&](uint32_t fd) {
    AggregatorConfig c;
    c.frames_out = 2;
    c.frames_dim = fd;
    // Input is one frame per buffer, 3:4:2:1 (the frames-dim entry becomes per-frame dim).
    auto p = plan_aggregator(u16({3, 4, 2, 1}), c);
    std::vector<uint16_t> out(two.size());
    if (!p.reorder) return std::make_pair(p, two);
    const uint8_t *src[2] = {reinterpret_cast<const uint8_t *>(two.data()),
                             reinterpret_cast<const uint8_t *>(two.data() + 24)};
    run_concat(p.concat, src, reinterpret_cast<uint8_t *>(out.data()));
    return std::make_pair(p, out);
  };
  auto [p3, o3] = run(3);
  EXPECT_EQ(p3.out.to_string(), "uint16 3:4:2:2");
  EXPECT_FALSE(p3.reorder);
  auto [p2, o2] = run(2);
  EXPECT_EQ(p2.out.to_string(), "uint16 3:4:4:1");
  EXPECT_FALSE(p2.reorder);  // nothing above dim 2 is > 1: the frames are already in place
  auto [p1, o1] = run(1);
  EXPECT_EQ(p1.out.to_string(), "uint16 3:8:2:1");
  ASSERT_TRUE(p1.reorder);
  std::vector<uint16_t> want1 = {1101, 1102, 1103, 1104, 1105, 1106, 1107, 1108, 1109, 1110,
                                 1111, 1112, 2101, 2102, 2103, 2104, 2105, 2106, 2107, 2108,
                                 2109, 2110, 2111, 2112, 1113, 1114, 1115, 1116, 1117, 1118,
                                 1119, 1120, 1121, 1122, 1123, 1124, 2113, 2114, 2115, 2116,
                                 2117, 2118, 2119, 2120, 2121, 2122, 2123, 2124};
  EXPECT_EQ(o1, want1);
  auto [p0, o0] = run(0);
  EXPECT_EQ(p0.out.to_string(), "uint16 6:4:2:1");
  std::vector<uint16_t> head = {1101, 1102, 1103, 2101, 2102, 2103, 1104, 1105, 1106, 2104};
  EXPECT_EQ(std::vector<uint16_t>(o0.begin(), o0.begin() + 10), head);
}

}  // namespace
}  // namespace nns

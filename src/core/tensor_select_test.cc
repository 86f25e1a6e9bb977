// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_select.h"

#include <gtest/gtest.h>

#include "core/error.h"

namespace nns {
namespace {

std::string error_of(auto &&f) {
  try {
    f();
  } catch (const Error &e) {
    return e.what();
  }
  return "";
}

TEST(TensorSelect, DemuxTensorpickGrammar) {
  auto g = parse_demux_tensorpick("0,1:2:3:4");
  ASSERT_EQ(g.size(), 2u);
  EXPECT_EQ(g[0], (std::vector<uint32_t>{0}));
  EXPECT_EQ(g[1], (std::vector<uint32_t>{1, 2, 3, 4}));
  g = parse_demux_tensorpick("2+0;1/3.4");
  ASSERT_EQ(g.size(), 4u);
  EXPECT_EQ(g[0], (std::vector<uint32_t>{2, 0}));
  EXPECT_EQ(demux_tensorpick_to_string(g), "2:0,1,3,4");
  EXPECT_TRUE(parse_demux_tensorpick("").empty());
  EXPECT_TRUE(parse_demux_tensorpick("  ").empty());
  auto e = error_of([] { parse_demux_tensorpick("0,a"); });
  EXPECT_NE(e.find("tensorpick"), std::string::npos);
  EXPECT_NE(e.find("'a'"), std::string::npos);
  EXPECT_FALSE(error_of([] { parse_demux_tensorpick("0,,1"); }).empty());
  EXPECT_FALSE(error_of([] { parse_demux_tensorpick("-1"); }).empty());
}

TEST(TensorSelect, DemuxTensorpickRange) {
  EXPECT_NO_THROW(check_demux_tensorpick(parse_demux_tensorpick("0,1:2"), 3));
  auto e = error_of([] { check_demux_tensorpick(parse_demux_tensorpick("0,1:3"), 3); });
  EXPECT_NE(e.find("tensorpick='0,1:3'"), std::string::npos) << e;
  EXPECT_NE(e.find("tensor 3"), std::string::npos) << e;
  EXPECT_NE(e.find("only 3 tensor"), std::string::npos) << e;
  auto d = default_demux_groups(3);
  EXPECT_EQ(demux_tensorpick_to_string(d), "0,1,2");
}

TEST(TensorSelect, Tensorseg) {
  auto s = parse_tensorseg("2:100:100,1:100:100");
  ASSERT_EQ(s.size(), 2u);
  EXPECT_EQ(s[0], make_dims({2, 100, 100}));
  EXPECT_EQ(tensorseg_to_string(s), "2:100:100,1:100:100");
  auto e = error_of([] { parse_tensorseg("2:100,x:1"); });
  EXPECT_NE(e.find("tensorseg='2:100,x:1'"), std::string::npos) << e;
  EXPECT_EQ(parse_split_tensorpick("2,0"), (std::vector<uint32_t>{2, 0}));
  EXPECT_FALSE(error_of([] { parse_split_tensorpick("1:2"); }).empty());
}

TEST(TensorSelect, PlanSplitByteRanges) {
  TensorInfo in{"", TensorType::kUInt8, make_dims({3, 4, 4})};
  auto seg = parse_tensorseg("1:4:4,2:4:4");
  auto p = plan_split(in, seg, {});
  ASSERT_EQ(p.size(), 2u);
  EXPECT_EQ(p[0].offset, 0u);
  EXPECT_EQ(p[0].size, 16u);
  EXPECT_EQ(p[1].offset, 16u);
  EXPECT_EQ(p[1].size, 32u);
  EXPECT_EQ(p[1].info.to_string(), "uint8 2:4:4");
  // Picks go out in ascending index order, each with its own dims.
  auto seg3 = parse_tensorseg("1:4:4,1:4:4,1:4:4");
  auto q = plan_split(in, seg3, {2, 0});
  ASSERT_EQ(q.size(), 2u);
  EXPECT_EQ(q[0].index, 0u);
  EXPECT_EQ(q[1].index, 2u);
  EXPECT_EQ(q[1].offset, 32u);
  TensorInfo f{"", TensorType::kFloat32, make_dims({4, 2})};
  auto r = plan_split(f, parse_tensorseg("4,4"), {});
  EXPECT_EQ(r[1].offset, 16u);
}

TEST(TensorSelect, PlanSplitErrors) {
  TensorInfo in{"", TensorType::kUInt8, make_dims({3, 4, 4})};
  auto e = error_of([&] { plan_split(in, parse_tensorseg("2:4:4,2:4:4"), {}); });
  EXPECT_NE(e.find("needs 64 bytes"), std::string::npos) << e;
  EXPECT_NE(e.find("has 48 bytes"), std::string::npos) << e;
  e = error_of([&] { plan_split(in, parse_tensorseg("1:4:4,2:4:4"), {0, 2}); });
  EXPECT_NE(e.find("picks segment 2"), std::string::npos) << e;
  EXPECT_NE(e.find("only 2 segment"), std::string::npos) << e;
  EXPECT_FALSE(error_of([&] { plan_split(in, {}, {}); }).empty());
}

}  // namespace
}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
#include "core/c_tensor_info.h"

#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>

#include "core/error.h"

namespace nns {
namespace {

TensorsConfig twenty_tensors() {
  TensorsConfig cfg;
  for (uint32_t i = 0; i < 20; ++i)
    cfg.info.tensors.push_back(
        TensorInfo{i == 17 ? "t17" : "", TensorType::kUInt16, make_dims({i + 1, 3})});
  cfg.rate_n = 30;
  cfg.rate_d = 1;
  return cfg;
}

TEST(CTensorInfo, InitIsEmpty) {
  GstTensorsConfig c;
  std::memset(&c, 0x5a, sizeof c);
  gst_config_init(&c);
  EXPECT_EQ(c.info.num_tensors, 0u);
  EXPECT_EQ(c.info.extra, nullptr);
  EXPECT_EQ(c.info.info[15].type, _NNS_END);
  EXPECT_EQ(c.info.info[0].name, nullptr);
  EXPECT_EQ(c.rate_n, -1);
  EXPECT_EQ(gst_info_at(&c.info, 16), nullptr);
  EXPECT_EQ(gst_info_at(&c.info, 3), &c.info.info[3]);
}

TEST(CTensorInfo, ConfigRoundTripUsesExtraBeyondSixteen) {
  TensorsConfig cfg = twenty_tensors();
  CTensorsConfig c(cfg);
  ASSERT_NE(c.get()->info.extra, nullptr);
  EXPECT_EQ(c.get()->info.num_tensors, 20u);
  EXPECT_STREQ(c.get()->info.extra[1].name, "t17");
  EXPECT_EQ(c.get()->info.extra[3].dimension[0], 20u);
  TensorsConfig back = from_c(c.get());
  EXPECT_TRUE(back.info.same_as(cfg.info));
  EXPECT_EQ(back.info[17].name, "t17");
  EXPECT_EQ(back.rate_n, 30);
  // Refilling clears the previous names and extra block.
  to_c(TensorsConfig{}, c.get());
  EXPECT_EQ(c.get()->info.extra, nullptr);
  EXPECT_EQ(c.get()->info.num_tensors, 0u);
}

TEST(CTensorInfo, ClearFreesNamesBeyondNumTensors) {
  GstTensorsInfo g;
  gst_info_init(&g);
  g.num_tensors = 1;
  g.info[5].name = strdup("stale");  // a callback may leave names past num_tensors
  gst_info_clear(&g);                // leak checkers (ASan/valgrind) catch a miss
  EXPECT_EQ(g.info[5].name, nullptr);
}

TEST(CTensorInfo, ToCRejectsTooManyTensors) {
  TensorsInfo info;
  info.tensors.resize(257, TensorInfo{"", TensorType::kUInt8, make_dims({1})});
  GstTensorsInfo g;
  gst_info_init(&g);
  try {
    to_c(info, &g);
    FAIL() << "no exception";
  } catch (const Error &e) {
    EXPECT_EQ(e.kind(), ErrorKind::kSettings);
    EXPECT_STREQ(e.what(), "257 tensors exceed the limit of 256");
  }
  gst_info_clear(&g);
}

TEST(CTensorInfo, FromCNamesTheBadField) {
  CTensorsConfig c(twenty_tensors());
  c.get()->info.info[2].type = static_cast<tensor_type>(99);
  try {
    from_c(c.get());
    FAIL() << "no exception";
  } catch (const Error &e) {
    EXPECT_EQ(e.kind(), ErrorKind::kStream);
    EXPECT_STREQ(e.what(), "tensor 2 has unknown type value 99");
  }
  GstTensorsInfo g;
  gst_info_init(&g);
  g.num_tensors = 17;  // no extra block
  try {
    from_c(&g);
    FAIL() << "no exception";
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("no 'extra' entries for tensor 16"), std::string::npos);
  }
  auto d = std::make_unique<nns_tensors_desc>();
  std::memset(d.get(), 0, sizeof *d);
  desc_from_gst_info(&g, *d);  // stops at the missing block
  EXPECT_EQ(d->num_tensors, 16u);
}

}  // namespace
}  // namespace nns

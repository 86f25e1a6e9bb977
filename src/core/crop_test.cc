// SPDX-License-Identifier: LGPL-2.1-only
// tensor_crop core: region parsing from every info type, clipping rules, NHWC copy.
#include "core/crop.h"

#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"

namespace nns {
namespace {

TEST(Crop, ParsesRegionsOfAnyType) {
  uint32_t u[8] = {1, 2, 3, 4, 5, 6, 7, 8};
  auto r = parse_crop_regions(TensorType::kUInt32, reinterpret_cast<uint8_t *>(u), sizeof u);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_EQ(r[1].x, 5u);
  EXPECT_EQ(r[1].h, 8u);
  float f[4] = {1.9f, 2.0f, 10.5f, -3.0f};
  r = parse_crop_regions(TensorType::kFloat32, reinterpret_cast<uint8_t *>(f), sizeof f);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_EQ(r[0].x, 1u);
  EXPECT_EQ(r[0].w, 10u);
  EXPECT_EQ(r[0].h, 0u);
  uint8_t b[4] = {0, 1, 2, 3};
  r = parse_crop_regions(TensorType::kUInt8, b, 4);
  EXPECT_EQ(r[0].h, 3u);
  try {
    parse_crop_regions(TensorType::kUInt32, reinterpret_cast<uint8_t *>(u), 20);
    FAIL();
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("20 bytes of uint32, not a whole number"),
              std::string::npos);
  }
  std::vector<uint16_t> many(4 * 300, 1);
  EXPECT_EQ(parse_crop_regions(TensorType::kUInt16, reinterpret_cast<uint8_t *>(many.data()),
                               many.size() * 2)
                .size(),
            256u);
}

TEST(Crop, FitClipsAndRejectsOutside) {
  bool clipped = false;
  auto f = fit_crop_region({2, 1, 3, 2}, 10, 8, 0, &clipped);
  EXPECT_FALSE(clipped);
  EXPECT_EQ(f.w, 3u);
  f = fit_crop_region({8, 6, 5, 5}, 10, 8, 0, &clipped);
  EXPECT_TRUE(clipped);
  EXPECT_EQ(f.w, 2u);
  EXPECT_EQ(f.h, 2u);
  f = fit_crop_region({4, 4, 0, 0}, 10, 8, 0, &clipped);
  EXPECT_FALSE(clipped);
  EXPECT_EQ(f.w, 6u);
  EXPECT_EQ(f.h, 4u);
  try {
    fit_crop_region({10, 0, 1, 1}, 10, 8, 3, &clipped);
    FAIL();
  } catch (const Error &e) {
    EXPECT_STREQ(e.what(), "crop region 3 (x=10, y=0, w=1, h=1) starts outside the 10x8 frame");
  }
}

TEST(Crop, CopiesNHWC) {
  // 2 channels, 4x3 frame, uint16: value = (y*4 + x)*2 + c
  uint16_t src[3][4][2];
  for (int y = 0; y < 3; ++y)
    for (int x = 0; x < 4; ++x)
      for (int c = 0; c < 2; ++c) src[y][x][c] = static_cast<uint16_t>((y * 4 + x) * 2 + c);
  CropRegion r{1, 1, 2, 2};
  uint16_t dst[2][2][2];
  crop_nhwc(reinterpret_cast<uint8_t *>(src), 2, 4, 2, r, reinterpret_cast<uint8_t *>(dst));
  for (int y = 0; y < 2; ++y)
    for (int x = 0; x < 2; ++x)
      for (int c = 0; c < 2; ++c) EXPECT_EQ(dst[y][x][c], src[y + 1][x + 1][c]);
}

}  // namespace
}  // namespace nns

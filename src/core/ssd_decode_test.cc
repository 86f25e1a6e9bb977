// SPDX-License-Identifier: LGPL-2.1-only
#include "core/ssd_decode.h"

#include <gtest/gtest.h>

namespace nns::ssd {
namespace {

TEST(SsdAnchors, BlazeFaceFrontHas896Anchors) {
  auto a = generate_anchors(blazeface_front_options());
  ASSERT_EQ(a.size(), 896u);
  // Stride 8: 16x16 cells, 2 anchors each; first cell centre (0.5/16, 0.5/16).
  EXPECT_FLOAT_EQ(a[0].cx, 0.5f / 16);
  EXPECT_FLOAT_EQ(a[0].cy, 0.5f / 16);
  EXPECT_FLOAT_EQ(a[1].cx, a[0].cx);  // second anchor of the same cell
  EXPECT_FLOAT_EQ(a[2].cx, 1.5f / 16);
  EXPECT_FLOAT_EQ(a[511].cx, 15.5f / 16);
  EXPECT_FLOAT_EQ(a[511].cy, 15.5f / 16);
  // Stride 16 (three layers merged): 8x8 cells, 6 anchors each.
  EXPECT_FLOAT_EQ(a[512].cx, 0.5f / 8);
  EXPECT_FLOAT_EQ(a[517].cx, 0.5f / 8);
  EXPECT_FLOAT_EQ(a[518].cx, 1.5f / 8);
  EXPECT_FLOAT_EQ(a[895].cy, 7.5f / 8);
  for (const auto &x : a) {
    EXPECT_FLOAT_EQ(x.w, 1.f);
    EXPECT_FLOAT_EQ(x.h, 1.f);
  }
}

TEST(SsdAnchors, VariableSizeAnchors) {
  AnchorOptions o;
  o.input_width = o.input_height = 32;
  o.strides = {16};
  o.aspect_ratios = {1.0f, 4.0f};
  o.interpolated_scale_aspect_ratio = 0;
  o.fixed_anchor_size = false;
  o.min_scale = o.max_scale = 0.5f;
  auto a = generate_anchors(o);
  ASSERT_EQ(a.size(), 2u * 2u * 2u);
  EXPECT_FLOAT_EQ(a[0].w, 0.5f);
  EXPECT_FLOAT_EQ(a[1].w, 1.0f);   // 0.5 * sqrt(4)
  EXPECT_FLOAT_EQ(a[1].h, 0.25f);  // 0.5 / sqrt(4)
}

TEST(SsdDecode, DecodesBoxAndKeypointsAgainstAnchor) {
  std::vector<Anchor> anchors = {{0.25f, 0.5f, 1, 1}, {0.75f, 0.5f, 1, 1}};
  DecodeOptions o;
  o.num_keypoints = 1;
  o.num_coords = 6;
  std::vector<float> boxes = {12.8f, -6.4f, 32, 64, 0, 12.8f,  // anchor 0
                              0,     0,     10, 10, 0, 0};
  std::vector<float> scores = {3.f, -3.f};  // sigmoid 0.95, 0.047
  auto d = decode(boxes.data(), scores.data(), anchors, o);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NEAR(d[0].score, sigmoid(3.f), 1e-6);
  EXPECT_NEAR(d[0].xmin, 0.35f - 0.125f, 1e-6);
  EXPECT_NEAR(d[0].xmax, 0.35f + 0.125f, 1e-6);
  EXPECT_NEAR(d[0].ymin, 0.45f - 0.25f, 1e-6);
  EXPECT_NEAR(d[0].ymax, 0.45f + 0.25f, 1e-6);
  ASSERT_EQ(d[0].keypoints.size(), 1u);
  EXPECT_NEAR(d[0].keypoints[0].first, 0.25f, 1e-6);
  EXPECT_NEAR(d[0].keypoints[0].second, 0.6f, 1e-6);
  // Clipping keeps huge logits finite.
  scores = {1e9f, -1e9f};
  d = decode(boxes.data(), scores.data(), anchors, o);
  ASSERT_EQ(d.size(), 1u);
  EXPECT_NEAR(d[0].score, 1.f, 1e-6);
}

Detection box(float score, float x0, float y0, float x1, float y1) {
  Detection d;
  d.score = score;
  d.xmin = x0, d.ymin = y0, d.xmax = x1, d.ymax = y1;
  return d;
}

TEST(SsdNms, HardAndWeighted) {
  std::vector<Detection> d = {box(0.6f, 0.1f, 0.1f, 0.3f, 0.3f), box(0.9f, 0.1f, 0.1f, 0.3f, 0.3f),
                              box(0.8f, 0.12f, 0.1f, 0.32f, 0.3f),
                              box(0.7f, 0.6f, 0.6f, 0.8f, 0.8f)};
  EXPECT_NEAR(iou(d[0], d[1]), 1.f, 1e-6);
  auto hard = nms(d, 0.3f, NmsMode::kHard);
  ASSERT_EQ(hard.size(), 2u);
  EXPECT_FLOAT_EQ(hard[0].score, 0.9f);
  EXPECT_FLOAT_EQ(hard[0].xmin, 0.1f);
  EXPECT_FLOAT_EQ(hard[1].score, 0.7f);
  auto w = nms(d, 0.3f, NmsMode::kWeighted);
  ASSERT_EQ(w.size(), 2u);
  EXPECT_FLOAT_EQ(w[0].score, 0.9f);
  EXPECT_NEAR(w[0].xmin, (0.1f * 0.9f + 0.12f * 0.8f + 0.1f * 0.6f) / 2.3f, 1e-6);
  EXPECT_EQ(nms(d, 0.3f, NmsMode::kHard, 1).size(), 1u);
  EXPECT_TRUE(nms({}, 0.3f, NmsMode::kHard).empty());
}

}  // namespace
}  // namespace nns::ssd

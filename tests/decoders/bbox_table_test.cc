// SPDX-License-Identifier: LGPL-2.1-only
// Scheme table and NMS shared by every bounding_boxes scheme.
#include <gtest/gtest.h>

#include "box_scheme.h"

using nns::bbox::Box;

namespace {
Box box(float x, float y, float w, float h, float score, int cls = 0) {
  Box b;
  b.x = x, b.y = y, b.w = w, b.h = h, b.score = score, b.class_id = cls;
  return b;
}
}  // namespace

TEST(BboxTable, IouOfKnownBoxes) {
  EXPECT_FLOAT_EQ(nns::bbox::iou(box(0, 0, 10, 10, 1), box(0, 0, 10, 10, 1)), 1.f);
  EXPECT_FLOAT_EQ(nns::bbox::iou(box(0, 0, 10, 10, 1), box(5, 0, 10, 10, 1)), 50.f / 150.f);
  EXPECT_FLOAT_EQ(nns::bbox::iou(box(0, 0, 10, 10, 1), box(20, 20, 5, 5, 1)), 0.f);
}

TEST(BboxTable, NmsKeepsBestOfOverlappingGroup) {
  std::vector<Box> v{box(0, 0, 10, 10, 0.6f), box(1, 0, 10, 10, 0.9f), box(50, 50, 10, 10, 0.7f),
                     box(0, 1, 10, 10, 0.8f, 1)};
  auto all = v;
  nns::bbox::nms(all, 0.5f, false);
  ASSERT_EQ(all.size(), 2u);
  EXPECT_FLOAT_EQ(all[0].score, 0.9f);
  EXPECT_FLOAT_EQ(all[1].score, 0.7f);
  nns::bbox::nms(v, 0.5f, true);  // class 1 survives next to class 0
  ASSERT_EQ(v.size(), 3u);
  EXPECT_FLOAT_EQ(v[0].score, 0.9f);
  EXPECT_FLOAT_EQ(v[1].score, 0.8f);
  EXPECT_EQ(v[1].class_id, 1);
}

TEST(BboxTable, AliasesResolveToCanonicalNames) {
  nns::bbox::SchemeTable t;
  t.add("a", [] { return std::unique_ptr<nns::bbox::Scheme>(); });
  t.add(
      "old-a", [] { return std::unique_ptr<nns::bbox::Scheme>(); }, "a");
  EXPECT_EQ(t.canonical("old-a"), "a");
  EXPECT_EQ(t.canonical("a"), "a");
  EXPECT_EQ(t.canonical("b"), "");
  EXPECT_EQ(t.names(), (std::vector<std::string>{"a", "old-a"}));
}

// SPDX-License-Identifier: LGPL-2.1-only
// Drawing and tracking helpers of tensor_decoder mode=bounding_boxes (nns_bbox).
#include <gtest/gtest.h>

#include <vector>

#include "draw.h"
#include "tracker.h"

using nns::bbox::Box;
using nns::bbox::Canvas;

namespace {
struct Frame {
  std::vector<uint32_t> px;
  Canvas c;
  Frame(int w, int h) : px(static_cast<std::size_t>(w) * h, 0), c{px.data(), w, h} {}
  bool on(int x, int y) const { return px[static_cast<std::size_t>(y) * c.width + x] != 0; }
  int count() const {
    int n = 0;
    for (auto v : px) n += v != 0;
    return n;
  }
};
Box box(float x, float y, float w, float h) {
  Box b;
  b.x = x, b.y = y, b.w = w, b.h = h;
  return b;
}
}  // namespace

TEST(BboxDraw, RectangleIsOnePixelOutline) {
  Frame f(20, 10);
  nns::bbox::draw_rect(f.c, 2, 1, 7, 5, nns::bbox::box_colour());
  EXPECT_TRUE(f.on(2, 1) && f.on(7, 1) && f.on(2, 5) && f.on(7, 5) && f.on(2, 3) && f.on(7, 3));
  EXPECT_FALSE(f.on(4, 3));
  EXPECT_EQ(f.count(), 6 * 2 + 3 * 2);
  const auto *rgba = reinterpret_cast<const uint8_t *>(&f.px[1 * 20 + 2]);
  EXPECT_EQ(rgba[0], 255);
  EXPECT_EQ(rgba[1], 0);
  EXPECT_EQ(rgba[2], 0);
  EXPECT_EQ(rgba[3], 255);
}

TEST(BboxDraw, RectangleClipsToCanvas) {
  Frame f(10, 10);
  nns::bbox::draw_rect(f.c, -5, -5, 50, 50, 1);
  EXPECT_TRUE(f.on(0, 0) && f.on(9, 9) && f.on(0, 9) && f.on(9, 0));
  EXPECT_EQ(f.count(), 36);
}

TEST(BboxDraw, LineReachesBothEnds) {
  Frame f(20, 20);
  nns::bbox::draw_line(f.c, 1, 2, 15, 9, 1);
  EXPECT_TRUE(f.on(1, 2));
  EXPECT_TRUE(f.on(15, 9));
  EXPECT_EQ(f.count(), 15);                        // one pixel per column of the longer axis
  nns::bbox::draw_line(f.c, -10, -10, 30, 30, 1);  // clipped, no crash
  EXPECT_TRUE(f.on(19, 19));
}

TEST(BboxDraw, TextStaysInCellsAndStopsAtEdge) {
  Frame f(30, 20);
  nns::bbox::draw_text(f.c, 0, 0, "tv", 1);
  int inside = 0;
  for (int y = 0; y < 13; ++y)
    for (int x = 0; x < 17; ++x) inside += f.on(x, y);
  EXPECT_EQ(inside, f.count());
  EXPECT_GT(inside, 10);
  Frame g(30, 20);
  nns::bbox::draw_text(g.c, 0, 0, "person", 1);  // only 3 cells fit in 30 px
  for (int y = 0; y < 20; ++y)
    for (int x = 26; x < 30; ++x) EXPECT_FALSE(g.on(x, y));
}

TEST(BboxTracker, IdsFollowNearestCentroid) {
  nns::bbox::CentroidTracker t;
  std::vector<Box> a{box(0, 0, 10, 10), box(100, 100, 10, 10)};
  t.update(a);
  EXPECT_EQ(a[0].track_id, 1);
  EXPECT_EQ(a[1].track_id, 2);
  std::vector<Box> b{box(98, 101, 10, 10), box(200, 0, 10, 10), box(2, 1, 10, 10)};
  t.update(b);
  EXPECT_EQ(b[0].track_id, 2);
  EXPECT_EQ(b[1].track_id, 3);
  EXPECT_EQ(b[2].track_id, 1);
  std::vector<Box> none;
  t.update(none);
  std::vector<Box> c{box(1, 1, 10, 10)};
  t.update(c);
  EXPECT_EQ(c[0].track_id, 1);
}

TEST(BboxDraw, AxisAlignedBoxScaledLikeUpstream) {
  Frame f(160, 120);
  // mobilenet-ssd frame 0, first person: 300x300 input -> 160x120.
  auto p = nns::bbox::draw_box(f.c, box(91, 174, 79, 121), 300, 300, 1);
  EXPECT_EQ(p.x, 48);  // 160 * 91 / 300
  EXPECT_EQ(p.y, 69);  // 120 * 174 / 300
  EXPECT_EQ(p.w, 42);  // 160 * 170 / 300 - 48
  EXPECT_EQ(p.h, 49);  // min(119, 120 * 295 / 300) - 69
  EXPECT_TRUE(f.on(48, 69) && f.on(90, 118));
}

// As NNStreamer's integer boxes: x and w are truncated separately, so the right edge of
// x = 10.7, w = 20.6 is at 10 + 20 = 30, not floor(31.3) = 31.
TEST(BboxDraw, FractionalBoxTruncatedLikeUpstream) {
  Frame f(100, 100);
  auto p = nns::bbox::draw_box(f.c, box(10.7f, 5.9f, 20.6f, 10.6f), 100, 100, 1);
  EXPECT_EQ(p.x, 10);
  EXPECT_EQ(p.y, 5);
  EXPECT_EQ(p.w, 20);
  EXPECT_EQ(p.h, 10);
  EXPECT_TRUE(f.on(30, 10));
  EXPECT_FALSE(f.on(31, 10));
  EXPECT_TRUE(f.on(20, 15));
  EXPECT_FALSE(f.on(20, 16));
}

// Each character writes its whole 8x13 cell: the glyph of the X11 misc-fixed 8x13 bold font in
// the colour, every other pixel cleared (a box line under the cell is erased, as upstream).
TEST(BboxDraw, TextCellsHoldMiscFixedGlyphsAndClearTheRest) {
  Frame f(40, 20);
  nns::bbox::draw_rect(f.c, 0, 5, 39, 5, 7);  // a line through the cells
  nns::bbox::draw_text(f.c, 1, 0, "b\x01", 9);
  // 'b' of 8x13B: rows 1-3 "##......", row 4 "##.###..", rows 11-12 empty.
  const char *b[13] = {"........", "##......", "##......", "##......", "##.###..",
                       "###..##.", "##...##.", "##...##.", "##...##.", "###..##.",
                       "##.###..", "........", "........"};
  for (int y = 0; y < 13; ++y)
    for (int x = 0; x < 8; ++x)
      EXPECT_EQ(f.px[static_cast<std::size_t>(y) * 40 + 1 + x], b[y][x] == '#' ? 9u : 0u)
          << x << "," << y;
  EXPECT_EQ(f.px[5 * 40 + 0], 7u);  // the line left of the cell stays
  EXPECT_EQ(f.px[5 * 40 + 9], 7u);  // so does the column between cells
  // A non-printable character shows as '*' (row 5 of its cell: "#######.").
  for (int x = 0; x < 8; ++x) EXPECT_EQ(f.px[5 * 40 + 10 + x], x < 7 ? 9u : 0u) << x;
}

TEST(BboxDraw, RotatedBoxDrawnAsFourLines) {
  Frame f(100, 100);
  Box b = box(30, 40, 40, 20);  // centre (50, 50)
  b.angle = 3.14159265f / 2;    // a quarter turn: 20 wide, 40 high
  auto p = nns::bbox::draw_box(f.c, b, 100, 100, 1);
  EXPECT_NEAR(p.x, 40, 1);
  EXPECT_NEAR(p.y, 30, 1);
  EXPECT_NEAR(p.w, 20, 1);
  EXPECT_NEAR(p.h, 40, 1);
  EXPECT_TRUE(f.on(40, 50) || f.on(39, 50));  // left side at mid height
  EXPECT_TRUE(f.on(60, 50) || f.on(59, 50));  // right side
  EXPECT_FALSE(f.on(50, 50));                 // hollow
  EXPECT_FALSE(f.on(30, 45));                 // the unrotated corner area stays empty
  Box c = box(30, 40, 40, 20);
  c.angle = 0.5f;
  Frame g(100, 100);
  nns::bbox::draw_box(g.c, c, 100, 100, 1);
  EXPECT_GT(g.count(), 100);
  EXPECT_FALSE(g.on(30, 40));  // the axis-aligned corner is not drawn
}

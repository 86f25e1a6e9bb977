// SPDX-License-Identifier: LGPL-2.1-only
// Drawing on an RGBA frame for tensor_decoder mode=bounding_boxes: axis-aligned rectangles
// the way NNStreamer draws them (1 px, inclusive corners, the same pixels), lines (rotated
// boxes), and label text in NNStreamer's 8x13 character cells (9 px advance, the whole cell
// written) with glyphs of the public-domain X11 misc-fixed 8x13 bold font (font_8x13.h).
#pragma once

#include <cstdint>
#include <string_view>

#include "box_scheme.h"

namespace nns::bbox {

struct Canvas {
  uint32_t *px = nullptr;  // width * height RGBA pixels (byte order R, G, B, A)
  int width = 0, height = 0;
};

// Opaque red, as NNStreamer draws boxes (R=255, G=0, B=0, A=255 in memory order).
uint32_t box_colour();

// Rectangle with corners (x1, y1) and (x2, y2) inclusive; clipped to the canvas.
void draw_rect(Canvas &c, int x1, int y1, int x2, int y2, uint32_t colour);
// Line between two points (Bresenham), clipped per pixel.
void draw_line(Canvas &c, int x0, int y0, int x1, int y1, uint32_t colour);
// Text with its top-left cell corner at (x, y): each character's whole 8x13 cell is written
// (glyph pixels in `colour`, the rest transparent 0), as NNStreamer does; drawing stops at the
// first character that would cross the right edge; characters outside 32..126 show as '*'.
void draw_text(Canvas &c, int x, int y, std::string_view text, uint32_t colour);

// Output rectangle of a drawn box (for rotated boxes: their bounding rectangle, clipped).
struct Placed {
  int x = 0, y = 0, w = 0, h = 0;
};
// Draws `b` (model-input pixels of an in_w x in_h input) scaled to the canvas as NNStreamer
// does: axis-aligned with x, y, w, h truncated to int (x1 = W*x/in_w, x2 = min(W-1,
// W*(x+w)/in_w), integer division), or, when b.angle != 0, its four sides rotated by the angle
// about the box centre (float corners, scaled, truncated).
Placed draw_box(Canvas &c, const Box &b, unsigned in_w, unsigned in_h, uint32_t colour);

inline constexpr int kCellW = 8, kCellH = 13, kAdvance = 9;

}  // namespace nns::bbox

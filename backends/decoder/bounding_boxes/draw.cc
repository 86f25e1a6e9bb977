// SPDX-License-Identifier: LGPL-2.1-only
#include "draw.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

#include "font_8x13.h"

namespace nns::bbox {
namespace {

inline void put(Canvas &c, int x, int y, uint32_t colour) {
  if (x >= 0 && x < c.width && y >= 0 && y < c.height) c.px[y * c.width + x] = colour;
}

}  // namespace

uint32_t box_colour() {
  const uint8_t rgba[4] = {255, 0, 0, 255};
  uint32_t v;
  std::memcpy(&v, rgba, 4);
  return v;
}

void draw_rect(Canvas &c, int x1, int y1, int x2, int y2, uint32_t colour) {
  if (c.width <= 0 || c.height <= 0) return;
  x1 = std::clamp(x1, 0, c.width - 1), x2 = std::clamp(x2, 0, c.width - 1);
  y1 = std::clamp(y1, 0, c.height - 1), y2 = std::clamp(y2, 0, c.height - 1);
  if (x2 < x1 || y2 < y1) return;
  uint32_t *top = c.px + static_cast<std::ptrdiff_t>(y1) * c.width;
  uint32_t *bottom = c.px + static_cast<std::ptrdiff_t>(y2) * c.width;
  std::fill(top + x1, top + x2 + 1, colour);
  std::fill(bottom + x1, bottom + x2 + 1, colour);
  for (int y = y1 + 1; y < y2; ++y) {
    c.px[static_cast<std::ptrdiff_t>(y) * c.width + x1] = colour;
    c.px[static_cast<std::ptrdiff_t>(y) * c.width + x2] = colour;
  }
}

void draw_line(Canvas &c, int x0, int y0, int x1, int y1, uint32_t colour) {
  const int dx = std::abs(x1 - x0), sx = x0 < x1 ? 1 : -1;
  const int dy = -std::abs(y1 - y0), sy = y0 < y1 ? 1 : -1;
  int err = dx + dy;
  for (int guard = 0; guard < 1 << 20; ++guard) {
    put(c, x0, y0, colour);
    if (x0 == x1 && y0 == y1) break;
    const int e2 = 2 * err;
    if (e2 >= dy) err += dy, x0 += sx;
    if (e2 <= dx) err += dx, y0 += sy;
  }
}

void draw_text(Canvas &c, int x, int y, std::string_view text, uint32_t colour) {
  for (char ch : text) {
    if (x + kCellW > c.width) break;
    auto u = static_cast<unsigned char>(ch);
    if (u < 32 || u >= 127) u = '*';  // as NNStreamer: non-printable characters show as '*'
    const uint8_t *rows = kFont8x13[u - 32];
    // The whole cell is written: glyph pixels in `colour`, the others transparent (0).
    for (int r = 0; r < kCellH; ++r)
      for (int col = 0; col < kCellW; ++col)
        put(c, x + col, y + r, (rows[r] & (0x80 >> col)) ? colour : 0u);
    x += kAdvance;
  }
}

Placed draw_box(Canvas &cv, const Box &b, unsigned in_w, unsigned in_h, uint32_t colour) {
  Placed o;
  if (cv.width <= 0 || cv.height <= 0 || in_w == 0 || in_h == 0) return o;
  if (b.angle != 0) {
    // As NNStreamer: float corners about the centre, scaled to the frame, truncated to int.
    const float cx = b.x + b.w / 2, cy = b.y + b.h / 2;
    const float co = std::cos(b.angle), si = std::sin(b.angle);
    const float hw = b.w / 2, hh = b.h / 2;
    const float dx[4] = {-hw, hw, hw, -hw};
    const float dy[4] = {-hh, -hh, hh, hh};
    const float W = static_cast<float>(cv.width), H = static_cast<float>(cv.height);
    const float iw = static_cast<float>(in_w), ih = static_cast<float>(in_h);
    int px[4], py[4];
    for (int k = 0; k < 4; ++k) {
      const float x = cx + dx[k] * co - dy[k] * si;
      const float y = cy + dx[k] * si + dy[k] * co;
      px[k] = static_cast<int>(W * x / iw);
      py[k] = static_cast<int>(H * y / ih);
    }
    for (int k = 0; k < 4; ++k)
      draw_line(cv, px[k], py[k], px[(k + 1) % 4], py[(k + 1) % 4], colour);
    const int minx = std::clamp(*std::min_element(px, px + 4), 0, cv.width - 1);
    const int maxx = std::clamp(*std::max_element(px, px + 4), 0, cv.width - 1);
    const int miny = std::clamp(*std::min_element(py, py + 4), 0, cv.height - 1);
    const int maxy = std::clamp(*std::max_element(py, py + 4), 0, cv.height - 1);
    o.x = minx, o.y = miny, o.w = maxx - minx, o.h = maxy - miny;
    return o;
  }
  // As NNStreamer: the box in whole model-input pixels (truncated), scaled with integer
  // arithmetic; the right/bottom edge is x + w scaled, kept inside the frame.
  const int64_t bx = static_cast<int64_t>(b.x), by = static_cast<int64_t>(b.y);
  const int64_t bw = static_cast<int64_t>(b.w), bh = static_cast<int64_t>(b.h);
  const int64_t W = cv.width, H = cv.height;
  int x1 = static_cast<int>(W * bx / in_w), y1 = static_cast<int>(H * by / in_h);
  const int x2 = static_cast<int>(std::min<int64_t>(W - 1, W * (bx + bw) / in_w));
  const int y2 = static_cast<int>(std::min<int64_t>(H - 1, H * (by + bh) / in_h));
  x1 = std::clamp(x1, 0, cv.width - 1), y1 = std::clamp(y1, 0, cv.height - 1);
  draw_rect(cv, x1, y1, x2, y2, colour);
  o.x = x1, o.y = y1, o.w = std::max(0, x2 - x1), o.h = std::max(0, y2 - y1);
  return o;
}

}  // namespace nns::bbox

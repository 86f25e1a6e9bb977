// SPDX-License-Identifier: LGPL-2.1-only
#include "draw.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>

namespace nns::bbox {
namespace {

// Our 5x7 font: 7 rows per glyph, bit 4 = leftmost column. Drawn from scratch for this
// project (capitals, digits and common punctuation).
struct Glyph {
  char ch;
  uint8_t rows[7];
};
constexpr Glyph kFont[] = {
    {'A', {0x0E, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'B', {0x1E, 0x11, 0x11, 0x1E, 0x11, 0x11, 0x1E}},
    {'C', {0x0E, 0x11, 0x10, 0x10, 0x10, 0x11, 0x0E}},
    {'D', {0x1C, 0x12, 0x11, 0x11, 0x11, 0x12, 0x1C}},
    {'E', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x1F}},
    {'F', {0x1F, 0x10, 0x10, 0x1E, 0x10, 0x10, 0x10}},
    {'G', {0x0E, 0x11, 0x10, 0x17, 0x11, 0x11, 0x0F}},
    {'H', {0x11, 0x11, 0x11, 0x1F, 0x11, 0x11, 0x11}},
    {'I', {0x0E, 0x04, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'J', {0x07, 0x02, 0x02, 0x02, 0x02, 0x12, 0x0C}},
    {'K', {0x11, 0x12, 0x14, 0x18, 0x14, 0x12, 0x11}},
    {'L', {0x10, 0x10, 0x10, 0x10, 0x10, 0x10, 0x1F}},
    {'M', {0x11, 0x1B, 0x15, 0x15, 0x11, 0x11, 0x11}},
    {'N', {0x11, 0x11, 0x19, 0x15, 0x13, 0x11, 0x11}},
    {'O', {0x0E, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'P', {0x1E, 0x11, 0x11, 0x1E, 0x10, 0x10, 0x10}},
    {'Q', {0x0E, 0x11, 0x11, 0x11, 0x15, 0x12, 0x0D}},
    {'R', {0x1E, 0x11, 0x11, 0x1E, 0x14, 0x12, 0x11}},
    {'S', {0x0F, 0x10, 0x10, 0x0E, 0x01, 0x01, 0x1E}},
    {'T', {0x1F, 0x04, 0x04, 0x04, 0x04, 0x04, 0x04}},
    {'U', {0x11, 0x11, 0x11, 0x11, 0x11, 0x11, 0x0E}},
    {'V', {0x11, 0x11, 0x11, 0x11, 0x11, 0x0A, 0x04}},
    {'W', {0x11, 0x11, 0x11, 0x15, 0x15, 0x15, 0x0A}},
    {'X', {0x11, 0x11, 0x0A, 0x04, 0x0A, 0x11, 0x11}},
    {'Y', {0x11, 0x11, 0x0A, 0x04, 0x04, 0x04, 0x04}},
    {'Z', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x10, 0x1F}},
    {'0', {0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E}},
    {'1', {0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E}},
    {'2', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F}},
    {'3', {0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E}},
    {'4', {0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02}},
    {'5', {0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E}},
    {'6', {0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E}},
    {'7', {0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08}},
    {'8', {0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E}},
    {'9', {0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C}},
    {'-', {0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00}},
    {'_', {0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x1F}},
    {'.', {0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C}},
    {',', {0x00, 0x00, 0x00, 0x00, 0x0C, 0x04, 0x08}},
    {':', {0x00, 0x0C, 0x0C, 0x00, 0x0C, 0x0C, 0x00}},
    {'/', {0x01, 0x01, 0x02, 0x04, 0x08, 0x10, 0x10}},
    {'(', {0x02, 0x04, 0x08, 0x08, 0x08, 0x04, 0x02}},
    {')', {0x08, 0x04, 0x02, 0x02, 0x02, 0x04, 0x08}},
    {'?', {0x0E, 0x11, 0x01, 0x02, 0x04, 0x00, 0x04}},
    {'!', {0x04, 0x04, 0x04, 0x04, 0x04, 0x00, 0x04}},
    {'\'', {0x04, 0x04, 0x08, 0x00, 0x00, 0x00, 0x00}},
    {'+', {0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00}},
    {'#', {0x0A, 0x0A, 0x1F, 0x0A, 0x1F, 0x0A, 0x0A}},
    {'%', {0x18, 0x19, 0x02, 0x04, 0x08, 0x13, 0x03}},
    {'&', {0x0C, 0x12, 0x14, 0x08, 0x15, 0x12, 0x0D}},
};
constexpr uint8_t kUnknown[7] = {0x1F, 0x11, 0x11, 0x11, 0x11, 0x11, 0x1F};

// 128-entry lookup from ASCII to glyph rows, built once.
struct FontTable {
  const uint8_t *rows[128];
  FontTable() {
    for (auto &r : rows) r = kUnknown;
    for (const auto &g : kFont) rows[static_cast<unsigned char>(g.ch)] = g.rows;
    for (char c = 'a'; c <= 'z'; ++c) rows[static_cast<int>(c)] = rows[c - 'a' + 'A'];
    static constexpr uint8_t kSpace[7] = {};
    rows[static_cast<int>(' ')] = kSpace;
  }
};
const FontTable &font() {
  static const FontTable t;
  return t;
}

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
  const FontTable &f = font();
  for (char ch : text) {
    if (x + kCellW > c.width) break;
    const auto u = static_cast<unsigned char>(ch);
    const uint8_t *rows = u < 128 ? f.rows[u] : kUnknown;
    // The 5x7 glyph sits in the 8x13 cell one column in and three rows down.
    for (int r = 0; r < 7; ++r)
      for (int col = 0; col < 5; ++col)
        if (rows[r] & (0x10 >> col)) put(c, x + 1 + col, y + 3 + r, colour);
    x += kAdvance;
  }
}

Placed draw_box(Canvas &cv, const Box &b, unsigned in_w, unsigned in_h, uint32_t colour) {
  Placed o;
  if (cv.width <= 0 || cv.height <= 0 || in_w == 0 || in_h == 0) return o;
  const double W = cv.width, H = cv.height, iw = in_w, ih = in_h;
  if (b.angle != 0) {
    const double cx = b.x + b.w / 2.0, cy = b.y + b.h / 2.0;
    const double c = std::cos(b.angle), s = std::sin(b.angle);
    const double dx[4] = {-b.w / 2.0, b.w / 2.0, b.w / 2.0, -b.w / 2.0};
    const double dy[4] = {-b.h / 2.0, -b.h / 2.0, b.h / 2.0, b.h / 2.0};
    int px[4], py[4];
    for (int k = 0; k < 4; ++k) {
      px[k] = static_cast<int>(std::floor(W * (cx + dx[k] * c - dy[k] * s) / iw));
      py[k] = static_cast<int>(std::floor(H * (cy + dx[k] * s + dy[k] * c) / ih));
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
  int x1 = static_cast<int>(std::floor(W * b.x / iw));
  int y1 = static_cast<int>(std::floor(H * b.y / ih));
  const int x2 = std::min(cv.width - 1, static_cast<int>(std::floor(W * (b.x + b.w) / iw)));
  const int y2 = std::min(cv.height - 1, static_cast<int>(std::floor(H * (b.y + b.h) / ih)));
  x1 = std::clamp(x1, 0, cv.width - 1), y1 = std::clamp(y1, 0, cv.height - 1);
  draw_rect(cv, x1, y1, x2, y2, colour);
  o.x = x1, o.y = y1, o.w = std::max(0, x2 - x1), o.h = std::max(0, y2 - y1);
  return o;
}

}  // namespace nns::bbox

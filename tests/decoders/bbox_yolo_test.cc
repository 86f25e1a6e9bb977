// SPDX-License-Identifier: LGPL-2.1-only
// YOLO schemes of tensor_decoder mode=bounding_boxes (backends/decoder/bounding_boxes/schemes/
// yolo.cc), called directly: the captured upstream decoder inputs are decoded with the options
// of upstream's tests/nnstreamer_decoder_boundingbox/runTest.sh and checked against the box
// outlines of upstream's golden RGBA frames; layouts, options and error texts.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "box_scheme.h"
#include "support/harness.h"

using nns::bbox::Box;

namespace {

constexpr const char *kDir = "/decoder/nnstreamer_decoder_boundingbox/";

template <typename T>
std::vector<T> load(const std::string &name) {
  std::ifstream f(nns::test::shared_models_dir() + kDir + name, std::ios::binary);
  std::vector<char> bytes((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::vector<T> v(bytes.size() / sizeof(T));
  std::memcpy(v.data(), bytes.data(), v.size() * sizeof(T));
  return v;
}

nns::TensorsInfo info_of(const std::string &dims, nns::TensorType type = nns::TensorType::kFloat32) {
  nns::TensorsInfo in;
  nns::TensorInfo t;
  t.type = type;
  t.dims = nns::parse_dims(dims);
  in.tensors.push_back(t);
  return in;
}

struct Run {
  std::unique_ptr<nns::bbox::Scheme> scheme;
  nns::TensorsInfo info;
  nns::bbox::Context ctx;
};

Run prepare(const std::string &name, const std::string &option3, const std::string &dims,
            unsigned in_w, unsigned in_h, std::size_t labels) {
  Run r{nns::bbox::schemes().make(name), info_of(dims), {}};
  EXPECT_TRUE(r.scheme) << name;
  r.ctx.in_w = in_w;
  r.ctx.in_h = in_h;
  r.ctx.num_labels = labels;
  r.scheme->set_option3(option3);
  r.scheme->check_input(r.info, r.ctx);
  return r;
}

std::vector<Box> decode(Run &r, const std::vector<float> &data) {
  nns::bbox::TensorView v{data.data(), data.size() * sizeof(float), &r.info[0]};
  std::vector<Box> out;
  r.scheme->decode(std::span<const nns::bbox::TensorView>(&v, 1), r.ctx, out);
  return out;
}

std::vector<Box> decode_file(const std::string &name, const std::string &option3,
                             const std::string &dims, unsigned in_w, unsigned in_h,
                             std::size_t labels, const std::string &file) {
  Run r = prepare(name, option3, dims, in_w, in_h, labels);
  return decode(r, load<float>(file));
}

// Transposes a rows x cols row-major matrix.
[[maybe_unused]] std::vector<float> transpose(const std::vector<float> &v, std::size_t rows, std::size_t cols) {
  std::vector<float> t(v.size());
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) t[c * rows + r] = v[r * cols + c];
  return t;
}

// ---- golden frames ----------------------------------------------------------------------------

// Opaque pixels of an upstream golden RGBA frame (boxes and labels are drawn opaque).
struct Mask {
  int w = 0, h = 0;
  std::vector<uint8_t> on;
  bool at(int x, int y) const { return x >= 0 && y >= 0 && x < w && y < h && on[y * w + x]; }
  // Any set pixel within 1 px (8-neighbourhood).
  bool near(int x, int y) const {
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx)
        if (at(x + dx, y + dy)) return true;
    return false;
  }
};

Mask golden(const std::string &file, int w, int h) {
  const auto rgba = load<uint8_t>(file);
  Mask m{w, h, std::vector<uint8_t>(static_cast<std::size_t>(w) * h)};
  EXPECT_EQ(rgba.size(), m.on.size() * 4) << file;
  for (std::size_t i = 0; i < m.on.size() && i * 4 + 3 < rgba.size(); ++i)
    m.on[i] = rgba[i * 4 + 3] != 0;
  return m;
}

// Fraction of the pixels of the outline of the axis-aligned rectangle [x1, x2] x [y1, y2]
// (inclusive, clipped to the frame) that are set in the golden frame. Upstream draws label glyph
// cells opaque-or-clear, so labels of other boxes may erase a few outline pixels.
double outline_fraction(const Mask &m, int x1, int y1, int x2, int y2) {
  int set = 0, all = 0;
  const auto probe = [&](int x, int y) {
    if (x < 0 || y < 0 || x >= m.w || y >= m.h) return;
    ++all;
    set += m.at(x, y);
  };
  for (int x = x1; x <= x2; ++x) probe(x, y1), probe(x, y2);
  for (int y = y1; y <= y2; ++y) probe(x1, y), probe(x2, y);
  return all > 0 ? static_cast<double>(set) / all : 0.0;
}

struct Found {
  int x1, y1, x2, y2;
};

// Every box of ours (model-input pixels, scaled to the frame) must have a golden outline within
// 1 px of each side; every opaque golden pixel must lie on one of those outlines or in the label
// band above one (so the golden frame has no box we lack). Returns the matched outlines.
std::vector<Found> match_axis_aligned(const std::vector<Box> &boxes, const Mask &m, unsigned in_w,
                                      unsigned in_h) {
  std::vector<Found> found;
  const float sx = static_cast<float>(m.w) / in_w, sy = static_cast<float>(m.h) / in_h;
  for (const Box &b : boxes) {
    const int x1 = static_cast<int>(b.x * sx), y1 = static_cast<int>(b.y * sy);
    const int x2 = static_cast<int>((b.x + b.w) * sx), y2 = static_cast<int>((b.y + b.h) * sy);
    double best = 0;
    Found at{};
    for (int a = -1; a <= 1; ++a)
      for (int c = -1; c <= 1; ++c)
        for (int e = -1; e <= 1; ++e)
          for (int f = -1; f <= 1; ++f) {
            const auto cx = [&](int v) { return std::clamp(v, 0, m.w - 1); };
            const auto cy = [&](int v) { return std::clamp(v, 0, m.h - 1); };
            const Found r{cx(x1 + a), cy(y1 + c), cx(x2 + e), cy(y2 + f)};
            const double q = outline_fraction(m, r.x1, r.y1, r.x2, r.y2);
            if (q > best) best = q, at = r;
          }
    const bool ok = best >= 0.9;
    if (ok) found.push_back(at);
    EXPECT_TRUE(ok) << "best outline fraction " << best << ": " << "no golden outline within 1 px of box x=" << b.x << " y=" << b.y
                    << " w=" << b.w << " h=" << b.h << " class=" << b.class_id;
  }
  int unexplained = 0;
  std::string where;
  for (int y = 0; y < m.h; ++y)
    for (int x = 0; x < m.w; ++x) {
      if (!m.at(x, y)) continue;
      bool ok = false;
      for (const Found &f : found) {
        const bool on_h = (y == f.y1 || y == f.y2) && x >= f.x1 && x <= f.x2;
        const bool on_v = (x == f.x1 || x == f.x2) && y >= f.y1 && y <= f.y2;
        // Label glyphs: a text line above the box's top-left corner (or inside it at y = 0).
        const bool label = x >= f.x1 && x < f.x1 + 60 && y >= f.y1 - 14 && y <= f.y1 + 14;
        if (on_h || on_v || label) {
          ok = true;
          break;
        }
      }
      if (!ok && unexplained < 12) where += " " + std::to_string(x) + "," + std::to_string(y);
      unexplained += !ok;
    }
  EXPECT_EQ(unexplained, 0) << "opaque golden pixels on no box of ours, e.g." << where;
  return found;
}

struct Expect {
  int x1, y1, class_id;  // top-left in frame pixels (read off the golden frame), label class
};

[[maybe_unused]] void expect_classes(const std::vector<Box> &boxes, const std::vector<Expect> &want) {
  ASSERT_EQ(boxes.size(), want.size());
  for (const Expect &e : want) {
    const auto it = std::find_if(boxes.begin(), boxes.end(), [&](const Box &b) {
      return std::abs(b.x - e.x1) <= 3 && std::abs(b.y - e.y1) <= 3;
    });
    ASSERT_NE(it, boxes.end()) << "no box at " << e.x1 << "," << e.y1;
    EXPECT_EQ(it->class_id, e.class_id) << "box at " << e.x1 << "," << e.y1;
  }
}

void dump(const std::vector<Box> &v) {
  for (const Box &b : v)
    std::printf("  x=%.1f y=%.1f w=%.1f h=%.1f a=%.3f class=%d score=%.3f\n", b.x, b.y, b.w, b.h,
                b.angle, b.class_id, b.score);
}

}  // namespace

// ---- goldens ----------------------------------------------------------------------------------

TEST(BboxYolo, Yolov5MatchesGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto boxes = decode_file("yolov5", "0:0.25:0.45", "85:6300:1", 320, 320, 80,
                                 "yolov5_decoder_input.raw");
  dump(boxes);
  match_axis_aligned(boxes, golden("yolov5_result_golden.raw", 320, 320), 320, 320);
}

TEST(BboxYolo, Yolov8MatchesGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto boxes = decode_file("yolov8", "0:0.25:0.45", "84:2100:1", 320, 320, 80,
                                 "yolov8_decoder_input.raw");
  dump(boxes);
  match_axis_aligned(boxes, golden("yolov8_result_golden.raw", 320, 320), 320, 320);
}

TEST(BboxYolo, Yolov10MatchesGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto boxes = decode_file("yolov10", "0:0.25", "6:300:1", 320, 320, 80,
                                 "yolov10_decoder_input.raw");
  dump(boxes);
  match_axis_aligned(boxes, golden("yolov10_result_golden.raw", 320, 320), 320, 320);
}

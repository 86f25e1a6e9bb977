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
#include <functional>
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

nns::TensorsInfo info_of(const std::string &dims,
                         nns::TensorType type = nns::TensorType::kFloat32) {
  nns::TensorsInfo in;
  nns::TensorInfo t;
  t.type = type;
  t.dims = nns::parse_dims(dims);
  in.tensors.push_back(t);
  return in;
}

struct Decoding {
  std::unique_ptr<nns::bbox::Scheme> scheme;
  nns::TensorsInfo info;
  nns::bbox::Context ctx;
};

Decoding prepare(const std::string &name, const std::string &option3, const std::string &dims,
                 unsigned in_w, unsigned in_h, std::size_t labels) {
  Decoding r{nns::bbox::schemes().make(name), info_of(dims), {}};
  EXPECT_TRUE(r.scheme) << name;
  r.ctx.in_w = in_w;
  r.ctx.in_h = in_h;
  r.ctx.num_labels = labels;
  r.scheme->set_option3(option3);
  r.scheme->check_input(r.info, r.ctx);
  return r;
}

std::vector<Box> decode(Decoding &r, const std::vector<float> &data) {
  nns::bbox::TensorView v{data.data(), data.size() * sizeof(float), &r.info[0]};
  std::vector<Box> out;
  r.scheme->decode(std::span<const nns::bbox::TensorView>(&v, 1), r.ctx, out);
  return out;
}

std::vector<Box> decode_file(const std::string &name, const std::string &option3,
                             const std::string &dims, unsigned in_w, unsigned in_h,
                             std::size_t labels, const std::string &file) {
  Decoding r = prepare(name, option3, dims, in_w, in_h, labels);
  return decode(r, load<float>(file));
}

// Transposes a rows x cols row-major matrix.
std::vector<float> transpose(const std::vector<float> &v, std::size_t rows, std::size_t cols) {
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
    EXPECT_TRUE(ok) << "best outline fraction " << best << ": "
                    << "no golden outline within 1 px of box x=" << b.x << " y=" << b.y
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

void expect_classes(const std::vector<Box> &boxes, const std::vector<Expect> &want) {
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
  const auto boxes =
      decode_file("yolov5", "0:0.25:0.45", "85:6300:1", 320, 320, 80, "yolov5_decoder_input.raw");
  dump(boxes);
  match_axis_aligned(boxes, golden("yolov5_result_golden.raw", 320, 320), 320, 320);
}

TEST(BboxYolo, Yolov8MatchesGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto boxes =
      decode_file("yolov8", "0:0.25:0.45", "84:2100:1", 320, 320, 80, "yolov8_decoder_input.raw");
  dump(boxes);
  match_axis_aligned(boxes, golden("yolov8_result_golden.raw", 320, 320), 320, 320);
}

TEST(BboxYolo, Yolov10MatchesGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto boxes =
      decode_file("yolov10", "0:0.25", "6:300:1", 320, 320, 80, "yolov10_decoder_input.raw");
  dump(boxes);
  match_axis_aligned(boxes, golden("yolov10_result_golden.raw", 320, 320), 320, 320);
}

// yolov8-obb: upstream draws rotated outlines without labels. Every golden pixel must lie within
// 1 px of one of our rotated outlines and every outline of ours must run along golden pixels.
TEST(BboxYolo, Yolov8ObbMatchesGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto boxes = decode_file("yolov8-obb", "0:0.25:0.45", "20:8400:1", 640, 640, 15,
                                 "yolov8_obb_decoder_input.raw");
  const Mask g = golden("yolov8_obb_decoder_result_golden.raw", 640, 640);
  Mask ours{g.w, g.h, std::vector<uint8_t>(g.on.size())};
  int poor = 0;
  for (const Box &b : boxes) {
    const float cx = b.x + b.w / 2, cy = b.y + b.h / 2, co = std::cos(b.angle),
                si = std::sin(b.angle);
    const float ux = b.w / 2 * co, uy = b.w / 2 * si, vx = -b.h / 2 * si, vy = b.h / 2 * co;
    const float px[4] = {cx - ux - vx, cx + ux - vx, cx + ux + vx, cx - ux + vx};
    const float py[4] = {cy - uy - vy, cy + uy - vy, cy + uy + vy, cy - uy + vy};
    int along = 0, all = 0;
    for (int e = 0; e < 4; ++e) {
      const float dx = px[(e + 1) % 4] - px[e], dy = py[(e + 1) % 4] - py[e];
      const int steps = static_cast<int>(std::hypot(dx, dy) * 2) + 2;
      for (int s = 0; s <= steps; ++s) {
        const int x = static_cast<int>(px[e] + dx * s / steps),
                  y = static_cast<int>(py[e] + dy * s / steps);
        if (x < 0 || y < 0 || x >= g.w || y >= g.h) continue;
        ours.on[y * g.w + x] = 1;
        ++all;
        along += g.near(x, y);
      }
    }
    if (all > 0 && along < 0.8 * all) ++poor;
  }
  int golden_px = 0, explained = 0;
  for (int y = 0; y < g.h; ++y)
    for (int x = 0; x < g.w; ++x)
      if (g.at(x, y)) ++golden_px, explained += ours.near(x, y);
  EXPECT_EQ(boxes.size(), 117u);
  EXPECT_GE(explained, 0.98 * golden_px) << explained << " of " << golden_px;
  // The oriented NMS estimates IoU as upstream's does (a 6x6 point grid in the smaller box), so
  // the same boxes survive: every outline of ours runs along the reference (the whole frame is
  // compared pixel for pixel in BboxYoloPipeline.Yolov8ObbGolden).
  EXPECT_EQ(poor, 0);
  for (const Box &b : boxes) EXPECT_TRUE(b.class_id == 9 || b.class_id == 10);  // vehicles
}

TEST(BboxYolo, GoldenClassesReadOffTheFrames) {
  NNS_REQUIRE_SHARED_MODELS();
  // coco-80.txt: 0 person, 5 bus, 16 dog.
  expect_classes(
      decode_file("yolov5", "0:0.25:0.45", "85:6300:1", 320, 320, 80, "yolov5_decoder_input.raw"),
      {{43, 67, 5}, {54, 116, 0}, {105, 119, 0}, {240, 111, 0}});
  expect_classes(
      decode_file("yolov8", "0:0.25:0.45", "84:2100:1", 320, 320, 80, "yolov8_decoder_input.raw"),
      {{5, 13, 16}, {99, 0, 0}, {126, 34, 16}});
  expect_classes(
      decode_file("yolov10", "0:0.25", "6:300:1", 320, 320, 80, "yolov10_decoder_input.raw"),
      {{2, 68, 5}, {20, 116, 0}, {0, 162, 0}, {89, 120, 0}, {264, 118, 0}});
}

// ---- layouts ----------------------------------------------------------------------------------

void expect_same(const std::vector<Box> &a, const std::vector<Box> &b) {
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].x, b[i].x);
    EXPECT_EQ(a[i].y, b[i].y);
    EXPECT_EQ(a[i].w, b[i].w);
    EXPECT_EQ(a[i].h, b[i].h);
    EXPECT_EQ(a[i].angle, b[i].angle);
    EXPECT_EQ(a[i].class_id, b[i].class_id);
    EXPECT_EQ(a[i].score, b[i].score);
  }
}

TEST(BboxYolo, Yolov8ModelLayoutNeedsNoTranspose) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto data = load<float>("yolov8_decoder_input.raw");  // 2100 boxes x 84 values
  Decoding up = prepare("yolov8", "", "84:2100:1", 320, 320, 80);
  Decoding raw = prepare("yolov8", "", "2100:84:1", 320, 320, 80);
  const auto a = decode(up, data);
  const auto b = decode(raw, transpose(data, 2100, 84));
  EXPECT_EQ(a.size(), 3u);
  expect_same(a, b);
  // Without a label file the classes come from the tensor (84 - 4), either layout.
  Decoding nolabels = prepare("yolov8", "", "2100:84:1", 320, 320, 0);
  expect_same(a, decode(nolabels, transpose(data, 2100, 84)));
}

TEST(BboxYolo, Yolov8ObbModelLayoutNeedsNoTranspose) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto data = load<float>("yolov8_obb_decoder_input.raw");  // 8400 x 20
  Decoding up = prepare("yolov8-obb", "", "20:8400:1", 640, 640, 15);
  Decoding raw = prepare("yolov8-obb", "", "8400:20:1", 640, 640, 15);
  expect_same(decode(up, data), decode(raw, transpose(data, 8400, 20)));
}

// Square case: with C == A both readings fit; the upstream (box-major) one is taken.
TEST(BboxYolo, SquareShapeReadsBoxMajor) {
  // option5 32:32 gives 1 + 4 + 16 = 21 anchors; 17 labels make C = 21 too.
  std::vector<float> d(21 * 21, 0.f);
  float *row = d.data() + 3 * 21;  // box 3, box-major
  row[0] = 0.5f, row[1] = 0.5f, row[2] = 0.25f, row[3] = 0.5f, row[4 + 7] = 0.9f;
  Decoding r = prepare("yolov8", "", "21:21:1", 32, 32, 17);
  const auto boxes = decode(r, d);
  ASSERT_EQ(boxes.size(), 1u);
  EXPECT_EQ(boxes[0].class_id, 7);
  EXPECT_FLOAT_EQ(boxes[0].x, 12.f);
  EXPECT_FLOAT_EQ(boxes[0].y, 8.f);
  EXPECT_FLOAT_EQ(boxes[0].w, 8.f);
  EXPECT_FLOAT_EQ(boxes[0].h, 16.f);
}

// ---- option3 ----------------------------------------------------------------------------------

TEST(BboxYolo, ConfidenceAndIouThresholds) {
  NNS_REQUIRE_SHARED_MODELS();
  const auto data = load<float>("yolov8_decoder_input.raw");
  Decoding strict = prepare("yolov8", "0:0.9:0.45", "84:2100:1", 320, 320, 80);
  const auto s = decode(strict, data);
  ASSERT_EQ(s.size(), 1u);  // only the dog at 0.936
  EXPECT_GT(s[0].score, 0.9f);
  // iou 1: upstream's IoU counts the intersection in inclusive pixels (x2 - x1 + 1) but not the
  // areas, so boxes that (nearly) coincide score above 1 and are still dropped: 9 of the 29
  // candidates above 0.25 stay, as with NNStreamer.
  Decoding keep = prepare("yolov8", "0:0.25:1", "84:2100:1", 320, 320, 80);
  const auto k = decode(keep, data);
  EXPECT_EQ(k.size(), 9u);
  for (std::size_t i = 1; i < k.size(); ++i) EXPECT_GE(k[i - 1].score, k[i].score);
  // yolov10 conf: 0.9 keeps the two above it.
  Decoding v10 = prepare("yolov10", "x:0.9", "6:300:1", 320, 320, 80);
  EXPECT_EQ(decode(v10, load<float>("yolov10_decoder_input.raw")).size(), 2u);
}

TEST(BboxYolo, ScaledCoordinatesAreModelPixels) {
  std::vector<float> d(84 * 2100, 0.f);
  float *row = d.data() + 10 * 84;
  row[0] = 100, row[1] = 50, row[2] = 40, row[3] = 20, row[4 + 2] = 0.8f;
  Decoding r = prepare("yolov8", "1", "84:2100:1", 320, 320, 80);
  const auto b = decode(r, d);
  ASSERT_EQ(b.size(), 1u);
  EXPECT_FLOAT_EQ(b[0].x, 80.f);
  EXPECT_FLOAT_EQ(b[0].y, 40.f);
  EXPECT_FLOAT_EQ(b[0].w, 40.f);
  EXPECT_FLOAT_EQ(b[0].h, 20.f);
  EXPECT_EQ(b[0].class_id, 2);
}

TEST(BboxYolo, ObbOrientedZeroGivesAxisAlignedBoxes) {
  NNS_REQUIRE_SHARED_MODELS();
  Decoding r = prepare("yolov8-obb", "0:0.25:0.45:0", "20:8400:1", 640, 640, 15);
  const auto b = decode(r, load<float>("yolov8_obb_decoder_input.raw"));
  ASSERT_FALSE(b.empty());
  for (const Box &x : b) EXPECT_EQ(x.angle, 0.f);
}

std::string error_of(const std::function<void()> &f) {
  try {
    f();
  } catch (const nns::Error &e) {
    return e.what();
  }
  return "no error";
}

TEST(BboxYolo, BadOption3NamesFieldAndGrammar) {
  auto s = nns::bbox::schemes().make("yolov8");
  EXPECT_EQ(error_of([&] { s->set_option3("0:abc"); }),
            "option3 of scheme yolov8: field 2 (conf) expects a number in [0, 1], got 'abc'; "
            "grammar: scaled(0/1):conf(0.25):iou(0.45)");
  EXPECT_EQ(error_of([&] { s->set_option3("2"); }),
            "option3 of scheme yolov8: field 1 (scaled) expects 0 or 1, got '2'; grammar: "
            "scaled(0/1):conf(0.25):iou(0.45)");
  EXPECT_EQ(error_of([&] { s->set_option3("0:0.25:1.5"); }),
            "option3 of scheme yolov8: field 3 (iou) expects a number in [0, 1], got '1.5'; "
            "grammar: scaled(0/1):conf(0.25):iou(0.45)");
  EXPECT_EQ(error_of([&] { s->set_option3("0:0.25:0.45:1"); }),
            "option3 of scheme yolov8: field 4 (extra) expects at most 3 fields, got "
            "'0:0.25:0.45:1'; grammar: scaled(0/1):conf(0.25):iou(0.45)");
  auto obb = nns::bbox::schemes().make("yolov8-obb");
  EXPECT_EQ(error_of([&] { obb->set_option3("0:0.25:0.45:yes"); }),
            "option3 of scheme yolov8-obb: field 4 (oriented) expects 0 or 1, got 'yes'; "
            "grammar: scaled(0/1):conf(0.25):iou(0.45):oriented(0/1, 1)");
  auto v10 = nns::bbox::schemes().make("yolov10");
  EXPECT_EQ(error_of([&] { v10->set_option3("0:-1"); }),
            "option3 of scheme yolov10: field 2 (conf) expects a number in [0, 1], got '-1'; "
            "grammar: <ignored>:conf(0.25)");
  EXPECT_EQ(error_of([&] { v10->set_option3("anything:0.5:0.45"); }), "no error");
}

// ---- input checks -----------------------------------------------------------------------------

std::string check_error(const std::string &scheme, const std::string &dims, nns::TensorType type,
                        unsigned w, unsigned h, std::size_t labels) {
  auto s = nns::bbox::schemes().make(scheme);
  nns::bbox::Context ctx;
  ctx.in_w = w, ctx.in_h = h, ctx.num_labels = labels;
  try {
    s->check_input(info_of(dims, type), ctx);
  } catch (const nns::Error &e) {
    EXPECT_EQ(e.kind(), nns::ErrorKind::kNegotiation);
    return e.what();
  }
  return "no error";
}

TEST(BboxYolo, WrongInputsAreRejectedWithShapes) {
  using nns::TensorType;
  // runTest.sh 8 yolov8 decoder_n: 84:8400 with option5 320:320.
  EXPECT_EQ(check_error("yolov8", "84:8400:1", TensorType::kFloat32, 320, 320, 80),
            "scheme yolov8 expects float32 84:2100:1 (4+#classes : anchors, as after "
            "tensor_transform mode=transpose option=1:0:2:3) or 2100:84:1 (the model's own "
            "layout) for option5 320:320 and 80 labels, got float32 84:8400:1");
  // runTest.sh 6 yolov5 decoder_n: 85:10647 with option5 320:320.
  EXPECT_EQ(check_error("yolov5", "85:10647:1", TensorType::kFloat32, 320, 320, 80),
            "scheme yolov5 expects float32 85:6300:1 (5+#classes : 3*anchors, for option5 "
            "320:320), got float32 85:10647:1");
  // runTest.sh 10 yolov8-obb inputdim_n / inputtype_n.
  EXPECT_EQ(check_error("yolov8-obb", "22:8400:1", TensorType::kFloat32, 640, 640, 15),
            "scheme yolov8-obb expects float32 20:8400:1 (4+#classes+1 : anchors, as after "
            "tensor_transform mode=transpose option=1:0:2:3) or 8400:20:1 (the model's own "
            "layout) for option5 640:640 and 15 labels, got float32 22:8400:1");
  EXPECT_EQ(check_error("yolov8-obb", "20:8400:1", TensorType::kUInt8, 640, 640, 15),
            "scheme yolov8-obb expects float32 20:8400:1 (4+#classes+1 : anchors, as after "
            "tensor_transform mode=transpose option=1:0:2:3) or 8400:20:1 (the model's own "
            "layout) for option5 640:640 and 15 labels, got uint8 20:8400:1");
  // runTest.sh 9 yolov10 dim_n / type_n.
  EXPECT_EQ(check_error("yolov10", "4:300:1", TensorType::kFloat32, 320, 320, 80),
            "scheme yolov10 expects float32 6:#MAX_DET:1 (x1 y1 x2 y2 score class per "
            "detection), got float32 4:300:1");
  EXPECT_EQ(check_error("yolov10", "6:300:1", TensorType::kInt32, 320, 320, 80),
            "scheme yolov10 expects float32 6:#MAX_DET:1 (x1 y1 x2 y2 score class per "
            "detection), got int32 6:300:1");
  // Rank 3.
  EXPECT_NE(check_error("yolov8", "84:2100:2", TensorType::kFloat32, 320, 320, 80)
                .find("got float32 84:2100:2"),
            std::string::npos);
  EXPECT_EQ(check_error("yolov8", "2100:84:1", TensorType::kFloat32, 320, 320, 80), "no error");
}

TEST(BboxYolo, ShortBufferIsAStreamError) {
  Decoding r = prepare("yolov8", "", "84:2100:1", 320, 320, 80);
  std::vector<float> small(100);
  try {
    decode(r, small);
    FAIL() << "no error";
  } catch (const nns::Error &e) {
    EXPECT_EQ(e.kind(), nns::ErrorKind::kStream);
    EXPECT_STREQ(e.what(), "scheme yolov8: input tensor holds 400 bytes, expected 705600");
  }
}

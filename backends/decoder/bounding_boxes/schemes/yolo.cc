// SPDX-License-Identifier: LGPL-2.1-only
// YOLO schemes of tensor_decoder mode=bounding_boxes: yolov5, yolov8, yolov8-obb, yolov10.
//
//   ... ! tensor_filter model=yolov8n.tflite
//       ! tensor_decoder mode=bounding_boxes option1=yolov8 option2=coco-80.txt
//         option3=0:0.25:0.45 option4=640:480 option5=320:320 ! videoconvert ! autovideosink
//
// Layouts (NNStreamer dims, innermost first; B = boxes, C = values per box):
//   yolov5      5+#classes : 3*A : 1  (cx cy w h objectness classes...), score = obj * best class
//   yolov8      4+#classes : A : 1    (cx cy w h classes...), score = best class
//               or the model's own A : 4+#classes : 1 (no tensor_transform transpose needed)
//   yolov8-obb  4+#classes+1 : A : 1  (cx cy w h classes... angle) or A : 4+#classes+1 : 1
//   yolov10     6 : #MAX_DET : 1      (x1 y1 x2 y2 score class), sorted by score, NMS-free
// with A = (W/32)(H/32) + (W/16)(H/16) + (W/8)(H/8) for option5 W:H. Coordinates are 0..1 unless
// option3's `scaled` is 1 (already model-input pixels); yolov10's are always 0..1.
// See docs/decoders/bounding_boxes_yolo.md.
#include <algorithm>
#include <charconv>
#include <cmath>
#include <cstdint>
#include <string>
#include <vector>

#include "box_scheme.h"
#include "yolo_kernels.h"

namespace nns::bbox {
namespace {

constexpr float kDefaultConf = 0.25f;
constexpr float kDefaultIou = 0.45f;

// One box that passed the threshold, before NMS. `order` (the box index in the tensor) breaks
// score ties so results do not depend on the sort algorithm or the input layout.
struct Cand {
  float x, y, w, h, angle, score;
  int cls;
  uint32_t order;
};

// ---- option3 ----------------------------------------------------------------------------------

[[noreturn]] void bad_field(const std::string &scheme, const std::string &grammar, std::size_t pos,
                            const char *field, const char *expected, const std::string &got) {
  fail(ErrorKind::kSettings, "option3 of scheme " + scheme + ": field " + std::to_string(pos) +
                                 " (" + field + ") expects " + expected + ", got '" + got +
                                 "'; grammar: " + grammar);
}

float parse_unit(const std::string &scheme, const std::string &grammar, std::size_t pos,
                 const char *field, const std::string &s) {
  float v = 0;
  const auto r = std::from_chars(s.data(), s.data() + s.size(), v);
  if (r.ec != std::errc() || r.ptr != s.data() + s.size() || !(v >= 0.f && v <= 1.f))
    bad_field(scheme, grammar, pos, field, "a number in [0, 1]", s);
  return v;
}

bool parse_flag(const std::string &scheme, const std::string &grammar, std::size_t pos,
                const char *field, const std::string &s) {
  if (s != "0" && s != "1") bad_field(scheme, grammar, pos, field, "0 or 1", s);
  return s == "1";
}

// ---- shapes -----------------------------------------------------------------------------------

uint32_t anchors(unsigned w, unsigned h) {
  return (w / 32) * (h / 32) + (w / 16) * (h / 16) + (w / 8) * (h / 8);
}

uint32_t dim(const TensorInfo &t, std::size_t i) {
  return t.dims[i] == 0 ? 1 : t.dims[i];
}

bool rank2(const TensorInfo &t) {
  for (std::size_t i = 2; i < t.dims.size(); ++i)
    if (t.dims[i] > 1) return false;
  return true;
}

std::string got(const TensorsInfo &in) {
  if (in.size() == 0) return "no tensor";
  std::string s = in.size() == 1 ? "" : std::to_string(in.size()) + " tensors, first ";
  return s + std::string(type_name(in[0].type)) + " " + dims_to_string(in[0].dims);
}

// ---- NMS --------------------------------------------------------------------------------------

// IoU as NNStreamer's NMS computes it on its whole-pixel boxes: the intersection counts
// inclusive pixels (x2 - x1 + 1), the areas do not.
float iou_aligned(const Cand &a, const Cand &b) {
  const float x1 = std::max(a.x, b.x), y1 = std::max(a.y, b.y);
  const float x2 = std::min(a.x + a.w, b.x + b.w), y2 = std::min(a.y + a.h, b.y + b.h);
  const float inter = std::max(0.f, x2 - x1 + 1) * std::max(0.f, y2 - y1 + 1);
  const float o = inter / (a.w * a.h + b.w * b.h - inter);
  return o >= 0 ? o : 0.f;
}

struct Pt {
  float x, y;
};

// Corners of an oriented box, in order around it (clockwise on screen for angle 0).
void corners(const Cand &c, Pt p[4]) {
  const float cx = c.x + c.w / 2, cy = c.y + c.h / 2;
  const float co = std::cos(c.angle), si = std::sin(c.angle);
  const float ux = c.w / 2 * co, uy = c.w / 2 * si;   // half width along the box's x axis
  const float vx = -c.h / 2 * si, vy = c.h / 2 * co;  // half height along its y axis
  p[0] = {cx - ux - vx, cy - uy - vy};
  p[1] = {cx + ux - vx, cy + uy - vy};
  p[2] = {cx + ux + vx, cy + uy + vy};
  p[3] = {cx - ux + vx, cy - uy + vy};
}

// Whether `p` lies inside the polygon `poly` of `n` corners (even-odd crossing count along +x).
bool inside(Pt p, const Pt *poly, int n) {
  bool in = false;
  for (int i = 0; i < n; ++i) {
    const Pt a = poly[i], b = poly[(i + 1) % n];
    if ((a.y > p.y) != (b.y > p.y) && a.x + (p.y - a.y) * (b.x - a.x) / (b.y - a.y) > p.x) in = !in;
  }
  return in;
}

// Geometry of an oriented candidate, computed once per frame before NMS.
struct Quad {
  Pt p[4];
};

Quad quad_of(const Cand &c) {
  Quad q;
  corners(c, q.p);
  return q;
}

// IoU of two oriented boxes estimated the way NNStreamer's oriented NMS does it, so the same
// boxes survive: a 6x6 grid of points laid from the first corner of the smaller box along its
// axes (steps of size / 6, at half steps), the overlap being the share of those points inside
// both boxes times the smaller box's area.
float iou_oriented(const Cand &a, const Quad &qa, const Cand &b, const Quad &qb) {
  const float area_a = a.w * a.h, area_b = b.w * b.h;
  const bool a_small = area_a < area_b;
  const Cand &s = a_small ? a : b;
  const Pt origin = (a_small ? qa : qb).p[0];
  constexpr int kGrid = 5;
  const float step_x = s.w / (kGrid + 1), step_y = s.h / (kGrid + 1);
  const float co = std::cos(s.angle), si = std::sin(s.angle);
  int hit = 0, all = 0;
  for (int i = 0; i <= kGrid; ++i)
    for (int j = 0; j <= kGrid; ++j) {
      const double u = (i + 0.5) * step_x, v = (j + 0.5) * step_y;
      const Pt p{static_cast<float>(origin.x + u * co - v * si),
                 static_cast<float>(origin.y + u * si + v * co)};
      ++all;
      hit += inside(p, qa.p, 4) && inside(p, qb.p, 4);
    }
  const float overlap = static_cast<float>(hit) / all * s.w * s.h;
  return overlap / (area_a + area_b - overlap);
}

// ---- the schemes ------------------------------------------------------------------------------

class YoloScheme : public Scheme {
 protected:
  explicit YoloScheme(std::string name, std::string grammar)
      : name_(std::move(name)), grammar_(std::move(grammar)) {}

  [[noreturn]] void mismatch(const std::string &expected, const TensorsInfo &in) const {
    fail(ErrorKind::kNegotiation, "scheme " + name_ + " expects " + expected + ", got " + got(in));
  }

  // Common checks: one or more tensors (the first is decoded), float32, rank 2.
  void check_float_rank2(const TensorsInfo &in, const std::string &expected) const {
    if (in.size() == 0 || in[0].type != TensorType::kFloat32 || !rank2(in[0]))
      mismatch(expected, in);
  }

  const float *input(std::span<const TensorView> in, std::size_t values) const {
    if (in.empty() || in[0].data == nullptr || in[0].size < values * sizeof(float))
      fail(ErrorKind::kStream, "scheme " + name_ + ": input tensor holds " +
                                   std::to_string(in.empty() ? 0 : in[0].size) +
                                   " bytes, expected " + std::to_string(values * sizeof(float)));
    return static_cast<const float *>(in[0].data);
  }

  // Greedy NMS over cand_ (class-agnostic, as upstream), then the kept boxes into `out`.
  void nms_emit(std::vector<Box> &out, bool oriented) {
    std::sort(cand_.begin(), cand_.end(), [](const Cand &a, const Cand &b) {
      return a.score > b.score || (a.score == b.score && a.order < b.order);
    });
    std::size_t kept = 0;
    if (oriented) {
      quad_.clear();
      for (const Cand &c : cand_) quad_.push_back(quad_of(c));
    }
    for (std::size_t i = 0; i < cand_.size(); ++i) {
      bool drop = false;
      for (std::size_t k = 0; k < kept && !drop; ++k)
        drop = (oriented ? iou_oriented(cand_[k], quad_[k], cand_[i], quad_[i])
                         : iou_aligned(cand_[k], cand_[i])) > iou_;
      if (!drop) {
        if (oriented) quad_[kept] = quad_[i];
        cand_[kept++] = cand_[i];
      }
    }
    for (std::size_t i = 0; i < kept; ++i) {
      const Cand &c = cand_[i];
      Box &b = out.emplace_back();
      b.x = c.x;
      b.y = c.y;
      b.w = c.w;
      b.h = c.h;
      b.angle = c.angle;
      b.class_id = c.cls;
      b.score = c.score;
    }
  }

  // Centre/size box (0..1 unless scaled_) to a candidate, clamped as upstream for axis-aligned
  // boxes: top-left at >= 0, size <= the model input.
  void push(float cx, float cy, float w, float h, float angle, float score, int cls, uint32_t order,
            const Context &ctx, bool clamp) {
    const float iw = static_cast<float>(ctx.in_w), ih = static_cast<float>(ctx.in_h);
    if (!scaled_) {
      cx *= iw;
      cy *= ih;
      w *= iw;
      h *= ih;
    }
    // As upstream, boxes are whole model-input pixels (truncated) from here on: NMS and
    // drawing see the same numbers as NNStreamer's.
    const auto whole = [](float v) { return static_cast<float>(static_cast<int>(v)); };
    Cand c{cx - w / 2, cy - h / 2, w, h, angle, score, cls, order};
    if (clamp) {
      c.x = whole(std::max(0.f, c.x));
      c.y = whole(std::max(0.f, c.y));
      c.w = whole(std::min(iw, c.w));
      c.h = whole(std::min(ih, c.h));
    } else {  // oriented: the centre and the size are truncated
      c.w = whole(w);
      c.h = whole(h);
      c.x = whole(std::max(0.f, cx)) - c.w / 2;
      c.y = whole(std::max(0.f, cy)) - c.h / 2;
    }
    cand_.push_back(c);
  }

  std::string name_, grammar_;
  bool scaled_ = false;
  float conf_ = kDefaultConf;
  float iou_ = kDefaultIou;
  std::vector<uint32_t> idx_;  // reused per frame
  std::vector<float> best_;
  std::vector<Cand> cand_;
  std::vector<Quad> quad_;
};

// yolov5: 5+#classes : 3*A : 1, box-major.
class YoloV5 final : public YoloScheme {
 public:
  YoloV5() : YoloScheme("yolov5", "scaled(0/1):conf(0.25):iou(0.45)") {}

  void set_option3(const std::string &text) override {
    scaled_ = false;
    conf_ = kDefaultConf;
    iou_ = kDefaultIou;
    if (text.empty()) return;
    const auto f = split(text, ":", true);
    if (f.size() > 3) bad_field(name_, grammar_, 4, "extra", "at most 3 fields", text);
    if (f.size() > 0 && !f[0].empty()) scaled_ = parse_flag(name_, grammar_, 1, "scaled", f[0]);
    if (f.size() > 1 && !f[1].empty()) conf_ = parse_unit(name_, grammar_, 2, "conf", f[1]);
    if (f.size() > 2 && !f[2].empty()) iou_ = parse_unit(name_, grammar_, 3, "iou", f[2]);
  }

  void check_input(const TensorsInfo &in, const Context &ctx) override {
    const uint32_t n = 3 * anchors(ctx.in_w, ctx.in_h);
    const std::string what =
        ctx.num_labels > 0 ? std::to_string(ctx.num_labels + 5) : std::string("5+#classes");
    const std::string expected = "float32 " + what + ":" + std::to_string(n) +
                                 ":1 (5+#classes : 3*anchors, for option5 " +
                                 std::to_string(ctx.in_w) + ":" + std::to_string(ctx.in_h) + ")";
    check_float_rank2(in, expected);
    const uint32_t d0 = dim(in[0], 0), d1 = dim(in[0], 1);
    if (d1 != n || d0 <= 5 || (ctx.num_labels > 0 && d0 != ctx.num_labels + 5))
      mismatch(expected, in);
    boxes_ = n;
    stride_ = d0;
  }

  void decode(std::span<const TensorView> in, const Context &ctx, std::vector<Box> &out) override {
    out.clear();
    cand_.clear();
    const float *d = input(in, std::size_t{boxes_} * stride_);
    const std::size_t nc = stride_ - 5;
    for (uint32_t i = 0; i < boxes_; ++i) {
      const float *row = d + std::size_t{i} * stride_;
      const float obj = row[4];
      // obj * s > conf  <=>  s > conf / obj for obj > 0; the margin keeps rounding on the safe
      // side (the exact test follows).
      if (obj > 0 && !yolo_kernels::any_above(row + 5, nc, conf_ / obj * (1 - 1e-6f))) continue;
      std::size_t arg = 0;
      for (std::size_t c = 1; c < nc; ++c)
        if (row[5 + c] > row[5 + arg]) arg = c;
      const float score = row[5 + arg] * obj;
      if (!(score > conf_)) continue;
      push(row[0], row[1], row[2], row[3], 0.f, score, static_cast<int>(arg), i, ctx, true);
    }
    nms_emit(out, false);
  }

 private:
  uint32_t boxes_ = 0, stride_ = 0;
};

// yolov8 / yolov8-obb: 4+#classes(+1 angle) : A : 1 box-major, or A : 4+#classes(+1) : 1.
class YoloV8 final : public YoloScheme {
 public:
  explicit YoloV8(bool obb)
      : YoloScheme(obb ? "yolov8-obb" : "yolov8",
                   obb ? "scaled(0/1):conf(0.25):iou(0.45):oriented(0/1, 1)"
                       : "scaled(0/1):conf(0.25):iou(0.45)"),
        obb_(obb) {}

  void set_option3(const std::string &text) override {
    scaled_ = false;
    conf_ = kDefaultConf;
    iou_ = kDefaultIou;
    oriented_ = true;
    if (text.empty()) return;
    const auto f = split(text, ":", true);
    const std::size_t max_fields = obb_ ? 4 : 3;
    if (f.size() > max_fields)
      bad_field(name_, grammar_, max_fields + 1, "extra",
                obb_ ? "at most 4 fields" : "at most 3 fields", text);
    if (f.size() > 0 && !f[0].empty()) scaled_ = parse_flag(name_, grammar_, 1, "scaled", f[0]);
    if (f.size() > 1 && !f[1].empty()) conf_ = parse_unit(name_, grammar_, 2, "conf", f[1]);
    if (f.size() > 2 && !f[2].empty()) iou_ = parse_unit(name_, grammar_, 3, "iou", f[2]);
    if (f.size() > 3 && !f[3].empty()) oriented_ = parse_flag(name_, grammar_, 4, "oriented", f[3]);
  }

  // Layout rule: with option2 labels, C = #labels + 4 (+1): C:A is box-major (upstream), A:C is
  // the model's class-major layout. Without labels the classes are C - 4 (-1) for whichever dim
  // is not A. When both dims fit (C == A), the upstream box-major reading wins.
  void check_input(const TensorsInfo &in, const Context &ctx) override {
    const uint32_t extra = obb_ ? 5 : 4;
    const uint32_t n = anchors(ctx.in_w, ctx.in_h);
    const std::string c = ctx.num_labels > 0 ? std::to_string(ctx.num_labels + extra)
                                             : std::string(obb_ ? "5+#classes" : "4+#classes");
    const std::string expected =
        "float32 " + c + ":" + std::to_string(n) + ":1 (" + (obb_ ? "4+#classes+1" : "4+#classes") +
        " : anchors, as after tensor_transform mode=transpose option=1:0:2:3) or " +
        std::to_string(n) + ":" + c + ":1 (the model's own layout) for option5 " +
        std::to_string(ctx.in_w) + ":" + std::to_string(ctx.in_h) +
        (ctx.num_labels > 0 ? " and " + std::to_string(ctx.num_labels) + " labels" : "");
    check_float_rank2(in, expected);
    const uint32_t d0 = dim(in[0], 0), d1 = dim(in[0], 1);
    const auto fits = [&](uint32_t v) {
      return ctx.num_labels > 0 ? v == ctx.num_labels + extra : v > extra;
    };
    if (d1 == n && fits(d0)) {
      planes_ = false;
      stride_ = d0;
    } else if (d0 == n && fits(d1)) {
      planes_ = true;
      stride_ = d1;
    } else {
      mismatch(expected, in);
    }
    boxes_ = n;
    if (planes_) best_.resize(n);
    idx_.reserve(n);
  }

  void decode(std::span<const TensorView> in, const Context &ctx, std::vector<Box> &out) override {
    out.clear();
    cand_.clear();
    idx_.clear();
    const float *d = input(in, std::size_t{boxes_} * stride_);
    const std::size_t nc = stride_ - (obb_ ? 5 : 4);
    if (planes_)
      yolo_kernels::candidates_planes(d, boxes_, 4, nc, conf_, best_.data(), idx_);
    else
      yolo_kernels::candidates_rows(d, boxes_, stride_, 4, nc, conf_, idx_);
    // Element (box i, value v): box-major d[i * stride + v], class-major d[v * boxes + i].
    const std::size_t si = planes_ ? 1 : stride_, sv = planes_ ? boxes_ : 1;
    const bool oriented = obb_ && oriented_;
    for (const uint32_t i : idx_) {
      const float *p = d + i * si;
      std::size_t arg = 0;
      float best = p[4 * sv];
      for (std::size_t c = 1; c < nc; ++c) {
        const float v = p[(4 + c) * sv];
        if (v > best) {
          best = v;
          arg = c;
        }
      }
      const float angle = oriented ? p[(4 + nc) * sv] : 0.f;
      push(p[0], p[sv], p[2 * sv], p[3 * sv], angle, best, static_cast<int>(arg), i, ctx,
           !oriented);
    }
    nms_emit(out, oriented);
  }

 private:
  bool obb_;
  bool oriented_ = true;
  bool planes_ = false;
  uint32_t boxes_ = 0, stride_ = 0;
};

// yolov10: 6 : #MAX_DET : 1 (x1 y1 x2 y2 score class, 0..1), sorted by score; no NMS.
class YoloV10 final : public YoloScheme {
 public:
  YoloV10() : YoloScheme("yolov10", "<ignored>:conf(0.25)") {}

  // Field 1 is ignored and fields after conf are ignored, as upstream (whose own tests pass
  // yolov5-style 0:0.25:0.45 strings to yolov10).
  void set_option3(const std::string &text) override {
    conf_ = kDefaultConf;
    if (text.empty()) return;
    const auto f = split(text, ":", true);
    if (f.size() > 1 && !f[1].empty()) conf_ = parse_unit(name_, grammar_, 2, "conf", f[1]);
  }

  void check_input(const TensorsInfo &in, const Context &) override {
    const std::string expected = "float32 6:#MAX_DET:1 (x1 y1 x2 y2 score class per detection)";
    check_float_rank2(in, expected);
    if (dim(in[0], 0) != 6) mismatch(expected, in);
    max_det_ = dim(in[0], 1);
  }

  void decode(std::span<const TensorView> in, const Context &ctx, std::vector<Box> &out) override {
    out.clear();
    const float *d = input(in, std::size_t{max_det_} * 6);
    const float iw = static_cast<float>(ctx.in_w), ih = static_cast<float>(ctx.in_h);
    for (uint32_t i = 0; i < max_det_; ++i) {
      const float *r = d + std::size_t{i} * 6;
      if (!(r[4] >= conf_)) break;  // sorted: the rest scores lower
      const float cls = r[5];
      if (!(cls >= 0.f) || (ctx.num_labels > 0 && cls >= static_cast<float>(ctx.num_labels)))
        continue;  // a class the label file does not have
      const float x1 = r[0] * iw, y1 = r[1] * ih, x2 = r[2] * iw, y2 = r[3] * ih;
      Box &b = out.emplace_back();
      b.x = static_cast<float>(static_cast<int>(std::max(0.f, x1)));  // whole pixels, as upstream
      b.y = static_cast<float>(static_cast<int>(std::max(0.f, y1)));
      b.w = static_cast<float>(static_cast<int>(std::min(iw, x2 - x1)));
      b.h = static_cast<float>(static_cast<int>(std::min(ih, y2 - y1)));
      b.class_id = static_cast<int>(cls);
      b.score = r[4];
    }
  }

 private:
  uint32_t max_det_ = 0;
};

}  // namespace
}  // namespace nns::bbox

void nns_bbox_register_yolo(nns::bbox::SchemeTable &table) {
  using namespace nns::bbox;
  table.add("yolov5", [] { return std::make_unique<YoloV5>(); });
  table.add("yolov8", [] { return std::make_unique<YoloV8>(false); });
  table.add("yolov8-obb", [] { return std::make_unique<YoloV8>(true); });
  table.add("yolov10", [] { return std::make_unique<YoloV10>(); });
}

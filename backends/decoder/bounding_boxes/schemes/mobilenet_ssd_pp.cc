// SPDX-License-Identifier: LGPL-2.1-only
// Scheme mobilenet-ssd-postprocess (alias tf-ssd): the 4 outputs of TensorFlow's SSD
// post-processing op. option3 = LOC:CLASS:SCORE:NUM,THRESHOLD% (all five integers; default
// mapping 3:1:2:0, threshold: any score above 0):
//   NUM    1                     number of valid detections
//   CLASS  N                     class index per detection
//   SCORE  N                     score per detection
//   LOC    4:N                   ymin, xmin, ymax, xmax (normalised, clamped to [0,1])
// Boxes are truncated to whole model-input pixels; no NMS (the model did it).
#include <cmath>
#include <cstdio>
#include <limits>

#include "box_util.h"

namespace nns::bbox {
namespace {

const std::string kName = "mobilenet-ssd-postprocess";
constexpr std::size_t kMaxDetections = 100;

class MobilenetSsdPp final : public Scheme {
 public:
  void set_option3(const std::string &text) override {
    if (trim(text).empty()) return;
    int loc, cls, score, num, pct;
    char tail = 0;
    const int got =
        std::sscanf(text.c_str(), "%i:%i:%i:%i,%i%c", &loc, &cls, &score, &num, &pct, &tail);
    if (got != 5)
      fail(ErrorKind::kSettings, "option3 of scheme " + kName +
                                     " must be LOC:CLASS:SCORE:NUM,THRESHOLD (5 integers, e.g. "
                                     "3:1:2:0,50), got '" +
                                     text + "'");
    for (int v : {loc, cls, score, num})
      if (v < 0 || v > 15)
        fail(ErrorKind::kSettings, "option3 of scheme " + kName + ": tensor index " +
                                       std::to_string(v) + " is out of range 0..15");
    if (pct < 0 || pct > 100)
      fail(ErrorKind::kSettings, "option3 of scheme " + kName + ": threshold " +
                                     std::to_string(pct) + "% is out of range 0..100");
    loc_ = loc, cls_ = cls, score_ = score, num_ = num;
    threshold_ = static_cast<float>(pct) / 100.f;
  }

  void check_input(const TensorsInfo &in, const Context &) override {
    const std::string want =
        "4 tensors (option3 mapping LOC:CLASS:SCORE:NUM = " + std::to_string(loc_) + ":" +
        std::to_string(cls_) + ":" + std::to_string(score_) + ":" + std::to_string(num_) +
        "): NUM 1, CLASS N, SCORE N, LOC 4:N with N <= 100, all of one type";
    const std::size_t need = std::max({loc_, cls_, score_, num_}) + 1;
    if (in.size() < std::max<std::size_t>(need, 4)) reject_input(kName, want, in);
    for (std::size_t i = 1; i < in.size(); ++i)
      if (in[i].type != in[0].type) reject_input(kName, want + " (types differ)", in);
    const auto &n = in[num_].dims, &c = in[cls_].dims, &s = in[score_].dims, &l = in[loc_].dims;
    if (n[0] != 1 || !ones_from(n, 1)) reject_input(kName, want + " (NUM must be 1)", in);
    if (c[0] == 0 || s[0] != c[0] || !ones_from(c, 1) || !ones_from(s, 1))
      reject_input(kName, want + " (CLASS and SCORE must be N)", in);
    if (l[0] != 4 || l[1] != c[0] || !ones_from(l, 2))
      reject_input(kName, want + " (LOC must be 4:N)", in);
    if (c[0] > kMaxDetections) reject_input(kName, want + " (N too large)", in);
    n_ = c[0];
  }

  void decode(std::span<const TensorView> in, const Context &ctx, std::vector<Box> &out) override {
    out.clear();
    const float num_f = as_float(in[num_], 1, s_num_)[0];
    const float *cls = as_float(in[cls_], n_, s_cls_);
    const float *score = as_float(in[score_], n_, s_score_);
    const float *loc = as_float(in[loc_], 4 * n_, s_loc_);
    std::size_t num = num_f > 0 ? static_cast<std::size_t>(num_f) : 0;
    num = std::min(num, n_);
    const float iw = static_cast<float>(ctx.in_w), ih = static_cast<float>(ctx.in_h);
    auto clamp01 = [](float v) { return std::min(std::max(v, 0.f), 1.f); };
    for (std::size_t d = 0; d < num; ++d) {
      if (score[d] < threshold_) continue;
      const float *b = loc + 4 * d;
      const float y1 = clamp01(b[0]), x1 = clamp01(b[1]), y2 = clamp01(b[2]), x2 = clamp01(b[3]);
      Box box;
      box.x = static_cast<float>(static_cast<int>(x1 * iw));
      box.y = static_cast<float>(static_cast<int>(y1 * ih));
      box.w = static_cast<float>(static_cast<int>((x2 - x1) * iw));
      box.h = static_cast<float>(static_cast<int>((y2 - y1) * ih));
      box.class_id = static_cast<int>(cls[d]);
      box.score = score[d];
      out.push_back(std::move(box));
    }
  }

 private:
  std::size_t loc_ = 3, cls_ = 1, score_ = 2, num_ = 0, n_ = 0;
  float threshold_ = std::numeric_limits<float>::min();
  std::vector<float> s_num_, s_cls_, s_score_, s_loc_;
};

}  // namespace
}  // namespace nns::bbox

void nns_bbox_register_mobilenet_ssd_pp(nns::bbox::SchemeTable &table) {
  auto f = [] { return std::make_unique<nns::bbox::MobilenetSsdPp>(); };
  table.add("mobilenet-ssd-postprocess", f);
  table.add("tf-ssd", f, "mobilenet-ssd-postprocess");
}

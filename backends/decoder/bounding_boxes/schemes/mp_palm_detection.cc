// SPDX-License-Identifier: LGPL-2.1-only
// Scheme mp-palm-detection: MediaPipe SSD-style detectors with generated anchors (palm
// detector 18:2016 + 1:2016; BlazeFace 16:896 + 1:896; any 4+2k values per anchor).
//   tensor 0: K:N regressors, K = 4 + 2k: box centre/size then k keypoints (x, y)
//   tensor 1: 1:N score logits
// option3 = score_thr(0.5):num_layers(4):min_scale(1.0):max_scale(1.0):x_off(0.5):y_off(0.5)
//           :strides(8:16:16:16), one stride per layer.
// Anchors as NNStreamer generates them: layers sharing a stride share a square feature map of
// ceil(S / stride) cells with two anchors per layer (scales of layer and layer + 1). S is 192
// (the palm model, as NNStreamer); when that does not give N anchors, the option5 width is
// tried (128 for BlazeFace). Regressors are in option5 pixels. The first two regressor values
// are read as (y, x) and the size as (h, w) as NNStreamer reads them; our extension: a ninth
// option3 field after the strides is not possible, so the order is chosen by option3 prefix
// "xy/" (e.g. option3=xy/0.5:4:...) which reads MediaPipe's (x, y, w, h) order.
// NMS: pixel-inclusive IoU 0.05 (NNStreamer's value).
#include <cmath>

#include "box_util.h"
#include "core/ssd_decode.h"

namespace nns::bbox {
namespace {

const std::string kName = "mp-palm-detection";
constexpr std::size_t kMaxStrides = 7;

class MpPalmDetection final : public Scheme {
 public:
  void set_option3(const std::string &text_in) override {
    std::string text = text_in;
    xy_order_ = false;
    if (text.rfind("xy/", 0) == 0) {
      xy_order_ = true;
      text = text.substr(3);
    }
    auto f = split(text, ":", true);
    if (f.size() > 6 + kMaxStrides)
      fail(ErrorKind::kSettings,
           "option3 of scheme " + kName + " has " + std::to_string(f.size()) +
               " fields, at most 13 expected "
               "(score_thr:num_layers:min_scale:max_scale:x_off:y_off:strides...)");
    f.resize(6);
    auto all = split(text, ":", true);
    score_thr_ = opt_float(kName, "score_thr (field 1)", f[0], 0.5f);
    layers_ = opt_int(kName, "num_layers (field 2)", f[1], 4);
    min_scale_ = opt_float(kName, "min_scale (field 3)", f[2], 1.f);
    max_scale_ = opt_float(kName, "max_scale (field 4)", f[3], 1.f);
    off_x_ = opt_float(kName, "x_off (field 5)", f[4], 0.5f);
    off_y_ = opt_float(kName, "y_off (field 6)", f[5], 0.5f);
    if (layers_ < 1 || layers_ > static_cast<int>(kMaxStrides))
      fail(ErrorKind::kSettings, "option3 of scheme " + kName + ": num_layers must be 1.." +
                                     std::to_string(kMaxStrides) + ", got " +
                                     std::to_string(layers_));
    std::vector<int> strides = {8, 16, 16, 16};
    strides.resize(static_cast<std::size_t>(layers_), 16);
    for (std::size_t i = 6; i < all.size() && i - 6 < strides.size(); ++i)
      strides[i - 6] = opt_int(kName, "stride " + std::to_string(i - 5), all[i], strides[i - 6]);
    for (int s : strides)
      if (s <= 0)
        fail(ErrorKind::kSettings, "option3 of scheme " + kName + ": strides must be > 0");
    strides_ = strides;
  }

  void check_input(const TensorsInfo &in, const Context &ctx) override {
    const std::string want =
        "2 tensors of one type: regressors K:N (K = 4 + 2 x keypoints, e.g. 18:2016 palm, "
        "16:896 BlazeFace) and scores 1:N";
    if (in.size() < 2 || in[0].type != in[1].type) reject_input(kName, want, in);
    const auto &b = in[0].dims, &s = in[1].dims;
    if (b[0] < 4 || b[0] % 2 != 0 || b[1] == 0 || !ones_from(b, 2))
      reject_input(kName, want + " (tensor 0 must be K:N)", in);
    if (s[0] != 1 || s[1] != b[1] || !ones_from(s, 2))
      reject_input(kName, want + " (tensor 1 must be 1:N with the N of tensor 0)", in);
    coords_ = b[0];
    n_ = b[1];
    anchors_.clear();
    for (unsigned size : {192u, ctx.in_w, ctx.in_h, 128u, 256u}) {
      auto a = make_anchors(size);
      if (a.size() == n_) {
        anchors_ = std::move(a);
        break;
      }
    }
    if (anchors_.empty())
      fail(ErrorKind::kNegotiation,
           "scheme " + kName + ": option3 anchors (num_layers " + std::to_string(layers_) +
               ") give " + std::to_string(make_anchors(192).size()) +
               " anchors on a 192 px grid and " + std::to_string(make_anchors(ctx.in_w).size()) +
               " on the option5 " + std::to_string(ctx.in_w) +
               " px grid, the input has N=" + std::to_string(n_));
  }

  void decode(std::span<const TensorView> in, const Context &ctx, std::vector<Box> &out) override {
    out.clear();
    const float *reg = as_float(in[0], coords_ * n_, s_reg_);
    const float *sc = as_float(in[1], n_, s_sc_);
    const float iw = static_cast<float>(ctx.in_w), ih = static_cast<float>(ctx.in_h);
    const std::size_t kps = (coords_ - 4) / 2;
    for (std::size_t d = 0; d < n_; ++d) {
      const float raw = std::min(std::max(sc[d], -100.f), 100.f);
      const float score = 1.f / (1.f + std::exp(-raw));
      if (score < score_thr_) continue;
      const float *r = reg + d * coords_;
      const ssd::Anchor &a = anchors_[d];
      const float rx = xy_order_ ? r[0] : r[1], ry = xy_order_ ? r[1] : r[0];
      const float rw = xy_order_ ? r[2] : r[3], rh = xy_order_ ? r[3] : r[2];
      const float yc = ry / ih * a.h + a.cy, xc = rx / iw * a.w + a.cx;
      const float h = rh / ih * a.h, w = rw / iw * a.w;
      Box b;
      b.x = std::max(0.f, (xc - w / 2.f) * iw);
      b.y = std::max(0.f, (yc - h / 2.f) * ih);
      b.w = w * iw;
      b.h = h * ih;
      b.class_id = 0;
      b.score = score;
      b.keypoints.reserve(kps);
      for (std::size_t k = 0; k < kps; ++k) {
        const float kx = r[4 + 2 * k] / iw * a.w + a.cx, ky = r[5 + 2 * k] / ih * a.h + a.cy;
        b.keypoints.emplace_back(kx * iw, ky * ih);
      }
      out.push_back(std::move(b));
    }
    nms_pixels(out, 0.05f);
  }

 private:
  float scale_of(int i) const {
    if (layers_ == 1) return (min_scale_ + max_scale_) * 0.5f;
    return min_scale_ +
           (max_scale_ - min_scale_) * static_cast<float>(i) / (static_cast<float>(layers_) - 1.f);
  }

  std::vector<ssd::Anchor> make_anchors(unsigned size) const {
    std::vector<ssd::Anchor> out;
    if (size == 0) return out;
    int layer = 0;
    while (layer < layers_) {
      std::vector<float> scales;
      int last = layer;
      while (last < layers_ && strides_[static_cast<std::size_t>(last)] ==
                                   strides_[static_cast<std::size_t>(layer)]) {
        scales.push_back(scale_of(last));
        scales.push_back(scale_of(last + 1));
        ++last;
      }
      const int stride = strides_[static_cast<std::size_t>(layer)];
      const int fm = static_cast<int>(std::ceil(static_cast<float>(size) / stride));
      for (int y = 0; y < fm; ++y)
        for (int x = 0; x < fm; ++x)
          for (float s : scales)
            out.push_back(ssd::Anchor{(x + off_x_) / fm, (y + off_y_) / fm, s, s});
      layer = last;
    }
    return out;
  }

  float score_thr_ = 0.5f, min_scale_ = 1.f, max_scale_ = 1.f, off_x_ = 0.5f, off_y_ = 0.5f;
  int layers_ = 4;
  std::vector<int> strides_ = {8, 16, 16, 16};
  bool xy_order_ = false;
  std::size_t coords_ = 0, n_ = 0;
  std::vector<ssd::Anchor> anchors_;
  std::vector<float> s_reg_, s_sc_;
};

}  // namespace
}  // namespace nns::bbox

void nns_bbox_register_mp_palm_detection(nns::bbox::SchemeTable &table) {
  table.add("mp-palm-detection", [] { return std::make_unique<nns::bbox::MpPalmDetection>(); });
}

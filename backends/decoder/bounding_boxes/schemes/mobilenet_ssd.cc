// SPDX-License-Identifier: LGPL-2.1-only
// Scheme mobilenet-ssd (alias tflite-ssd): raw SSD output with box priors.
//   tensor 0: box regressors 4:1:N (y, x, h, w per prior), tensor 1: class logits C:N
//   (class 0 = background). option3 = priors-file:det_thr(0.5):Y(10):X(10):H(5):W(5):iou(0.5);
//   the priors file has 4 lines (ycenter, xcenter, h, w; normalised), N values each,
//   separated by spaces, tabs or commas.
// Box i: centre = reg/scale * prior_size + prior_centre, size = exp(reg/scale) * prior_size;
// score = sigmoid(logit) of the best class whose logit passes the threshold. Coordinates are
// truncated to whole model-input pixels as NNStreamer does, then NMS (pixel-inclusive IoU).
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>

#include "box_util.h"

namespace nns::bbox {
namespace {

constexpr std::size_t kMaxDetections = 2034;  // as NNStreamer (ssd_mobilenet v3 included)
const std::string kName = "mobilenet-ssd";

class MobilenetSsd final : public Scheme {
 public:
  void set_option3(const std::string &text) override {
    if (trim(text).empty()) return;  // check_input reports the missing priors file
    auto f = split(text, ":", true);
    if (f.empty() || f[0].empty())
      fail(ErrorKind::kSettings, "option3 of scheme " + kName +
                                     " needs the box priors file: "
                                     "priors.txt[:det_thr:Y:X:H:W:iou]");
    if (f.size() > 7)
      fail(ErrorKind::kSettings,
           "option3 of scheme " + kName + " has " + std::to_string(f.size()) +
               " fields, at most 7 expected (priors.txt:det_thr:Y:X:H:W:iou)");
    f.resize(7);
    load_priors(f[0]);
    threshold_ = opt_float(kName, "det_thr (field 2)", f[1], 0.5f);
    y_scale_ = opt_float(kName, "Y scale (field 3)", f[2], 10.f);
    x_scale_ = opt_float(kName, "X scale (field 4)", f[3], 10.f);
    h_scale_ = opt_float(kName, "H scale (field 5)", f[4], 5.f);
    w_scale_ = opt_float(kName, "W scale (field 6)", f[5], 5.f);
    iou_ = opt_float(kName, "iou threshold (field 7)", f[6], 0.5f);
    if (y_scale_ == 0 || x_scale_ == 0 || h_scale_ == 0 || w_scale_ == 0)
      fail(ErrorKind::kSettings, "option3 of scheme " + kName + ": box scales must not be 0");
    logit_threshold_ = threshold_ <= 0   ? -std::numeric_limits<float>::infinity()
                       : threshold_ >= 1 ? std::numeric_limits<float>::infinity()
                                         : std::log(threshold_ / (1.f - threshold_));
  }

  void check_input(const TensorsInfo &in, const Context &ctx) override {
    const std::string want =
        "2 tensors of one type: box regressors 4:1:N and class logits C:N (N <= 2034, C <= "
        "labels in option2)";
    if (priors_[0].empty())
      fail(ErrorKind::kSettings, "scheme " + kName + " needs option3=<box priors file>");
    if (in.size() < 2) reject_input(kName, want, in);
    const auto &b = in[0].dims, &c = in[1].dims;
    if (in[0].type != in[1].type) reject_input(kName, want + " (types differ)", in);
    if (b[0] != 4 || b[1] != 1 || b[2] == 0 || !ones_from(b, 3))
      reject_input(kName, want + " (tensor 0 must be 4:1:N)", in);
    if (c[0] == 0 || c[1] != b[2] || !ones_from(c, 2))
      reject_input(kName, want + " (tensor 1 must be C:N with the N of tensor 0)", in);
    if (b[2] > kMaxDetections) reject_input(kName, want + " (N too large)", in);
    if (b[2] > priors_[0].size())
      fail(ErrorKind::kNegotiation, "scheme " + kName + ": the priors file '" + priors_path_ +
                                        "' has " + std::to_string(priors_[0].size()) +
                                        " priors, the input has N=" + std::to_string(b[2]));
    if (c[0] > ctx.num_labels)
      fail(ErrorKind::kNegotiation,
           "scheme " + kName + ": the input has " + std::to_string(c[0]) +
               " classes but option2 gives " + std::to_string(ctx.num_labels) +
               " labels (a label file with at least " + std::to_string(c[0]) + " lines is needed)");
    n_ = b[2];
    classes_ = c[0];
  }

  void decode(std::span<const TensorView> in, const Context &ctx, std::vector<Box> &out) override {
    out.clear();
    const float *reg = as_float(in[0], 4 * n_, scratch_box_);
    const float *logits = as_float(in[1], classes_ * n_, scratch_cls_);
    const float iw = static_cast<float>(ctx.in_w), ih = static_cast<float>(ctx.in_h);
    for (std::size_t d = 0; d < n_; ++d) {
      const float *l = logits + d * classes_;
      int best = -1;
      float best_logit = 0;
      for (std::size_t k = 1; k < classes_; ++k) {
        if (l[k] >= logit_threshold_ && (best < 0 || l[k] > best_logit)) {
          best = static_cast<int>(k);
          best_logit = l[k];
        }
      }
      if (best < 0) continue;
      const float *r = reg + d * 4;
      const float py = priors_[0][d], px = priors_[1][d], ph = priors_[2][d], pw = priors_[3][d];
      const float yc = r[0] / y_scale_ * ph + py;
      const float xc = r[1] / x_scale_ * pw + px;
      const float h = std::exp(r[2] / h_scale_) * ph;
      const float w = std::exp(r[3] / w_scale_) * pw;
      Box box;
      box.x = static_cast<float>(std::max(0, static_cast<int>((xc - w / 2.f) * iw)));
      box.y = static_cast<float>(std::max(0, static_cast<int>((yc - h / 2.f) * ih)));
      box.w = static_cast<float>(static_cast<int>(w * iw));
      box.h = static_cast<float>(static_cast<int>(h * ih));
      box.class_id = best;
      box.score = 1.f / (1.f + std::exp(-best_logit));
      out.push_back(std::move(box));
    }
    nms_pixels(out, iou_);
  }

 private:
  void load_priors(const std::string &path) {
    std::ifstream f(path);
    if (!f)
      fail(ErrorKind::kNotFound,
           "option3 of scheme " + kName + ": cannot read box priors file '" + path + "'");
    std::array<std::vector<float>, 4> p;
    std::string line;
    std::size_t row = 0;
    while (row < 4 && std::getline(f, line)) {
      for (char &ch : line)
        if (ch == ',' || ch == '\t' || ch == '\r') ch = ' ';
      std::istringstream ss(line);
      std::string word;
      while (ss >> word) {
        char *end = nullptr;
        const float v = std::strtof(word.c_str(), &end);
        if (end == word.c_str() || *end)
          fail(ErrorKind::kSettings, "box priors file '" + path + "' line " +
                                         std::to_string(row + 1) + ": '" + word +
                                         "' is not a number");
        if (p[row].size() <= kMaxDetections) p[row].push_back(v);
      }
      ++row;
    }
    if (row < 4)
      fail(ErrorKind::kSettings, "box priors file '" + path + "' has " + std::to_string(row) +
                                     " lines, 4 expected (ycenter, xcenter, h, w)");
    for (std::size_t i = 1; i < 4; ++i)
      if (p[i].size() != p[0].size() || p[i].empty())
        fail(ErrorKind::kSettings, "box priors file '" + path + "' is not consistent: line 1 has " +
                                       std::to_string(p[0].size()) + " values, line " +
                                       std::to_string(i + 1) + " has " +
                                       std::to_string(p[i].size()));
    priors_ = std::move(p);
    priors_path_ = path;
  }

  std::array<std::vector<float>, 4> priors_;
  std::string priors_path_;
  float threshold_ = 0.5f, y_scale_ = 10, x_scale_ = 10, h_scale_ = 5, w_scale_ = 5, iou_ = 0.5f;
  float logit_threshold_ = 0;
  std::size_t n_ = 0, classes_ = 0;
  std::vector<float> scratch_box_, scratch_cls_;
};

}  // namespace
}  // namespace nns::bbox

void nns_bbox_register_mobilenet_ssd(nns::bbox::SchemeTable &table) {
  auto f = [] { return std::make_unique<nns::bbox::MobilenetSsd>(); };
  table.add("mobilenet-ssd", f);
  table.add("tflite-ssd", f, "mobilenet-ssd");
}

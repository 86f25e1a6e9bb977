// SPDX-License-Identifier: LGPL-2.1-only
// Scheme ov-person-detection: OpenVINO's DetectionOutput layout, one tensor 7:200 (any
// numeric type): per detection image_id, label, conf, x_min, y_min, x_max, y_max
// (normalised). A negative image_id ends the list; detections with conf < 0.8 are dropped.
// Boxes carry no class (class -1, score 1) as in NNStreamer; option3 is ignored.
#include "box_util.h"

namespace nns::bbox {
namespace {

const std::string kName = "ov-person-detection";
constexpr std::size_t kDesc = 7, kMax = 200;
constexpr float kConf = 0.8f;

class OvDetection final : public Scheme {
 public:
  void set_option3(const std::string &) override {}

  void check_input(const TensorsInfo &in, const Context &) override {
    if (in.size() < 1 || in[0].dims[0] != kDesc || in[0].dims[1] != kMax ||
        !ones_from(in[0].dims, 2))
      reject_input(kName, "1 tensor 7:200 (image_id, label, conf, x_min, y_min, x_max, y_max)", in);
  }

  void decode(std::span<const TensorView> in, const Context &ctx, std::vector<Box> &out) override {
    out.clear();
    const float *v = as_float(in[0], kDesc * kMax, scratch_);
    const float iw = static_cast<float>(ctx.in_w), ih = static_cast<float>(ctx.in_h);
    for (std::size_t d = 0; d < kMax; ++d) {
      const float *r = v + d * kDesc;
      if (static_cast<int>(r[0]) < 0) break;
      if (r[2] < kConf) continue;
      Box b;
      b.x = static_cast<float>(static_cast<int>(r[3] * iw));
      b.y = static_cast<float>(static_cast<int>(r[4] * ih));
      b.w = static_cast<float>(static_cast<int>((r[5] - r[3]) * iw));
      b.h = static_cast<float>(static_cast<int>((r[6] - r[4]) * ih));
      b.class_id = -1;
      b.score = 1.f;
      out.push_back(std::move(b));
    }
  }

 private:
  std::vector<float> scratch_;
};

}  // namespace
}  // namespace nns::bbox

void nns_bbox_register_ov_detection(nns::bbox::SchemeTable &table) {
  table.add("ov-person-detection", [] { return std::make_unique<nns::bbox::OvDetection>(); });
}

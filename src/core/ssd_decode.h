// SPDX-License-Identifier: LGPL-2.1-only
// SSD-style detector post-processing, GStreamer-free: MediaPipe-compatible anchor generation
// (SsdAnchorsCalculator semantics), decoding of raw box regressors against anchors (with
// keypoints, as BlazeFace/palm detectors emit them), sigmoid scores, and non-maximum
// suppression (hard or score-weighted). Coordinates are normalised to [0,1] of the model input,
// x to the right, y down.
#pragma once

#include <cstddef>
#include <cstdint>
#include <utility>
#include <vector>

namespace nns::ssd {

struct Anchor {
  float cx = 0, cy = 0, w = 1, h = 1;
};

struct AnchorOptions {
  int input_width = 128;
  int input_height = 128;
  float min_scale = 0.1484375f;
  float max_scale = 0.75f;
  float offset_x = 0.5f;
  float offset_y = 0.5f;
  std::vector<int> strides = {8, 16, 16, 16};  // one per layer; equal neighbours are merged
  std::vector<float> aspect_ratios = {1.0f};
  float interpolated_scale_aspect_ratio = 1.0f;  // <= 0: no interpolated anchor
  bool reduce_boxes_in_lowest_layer = false;
  bool fixed_anchor_size = true;  // w = h = 1 (the regressors carry the size)
};

// MediaPipe BlazeFace short-range ("front") detector: 128x128 input, 896 anchors
// (16x16 cells x 2 at stride 8, then 8x8 cells x 6 at stride 16).
AnchorOptions blazeface_front_options();

// Anchors in the order the model's outputs use: per layer group, rows, columns, anchors.
std::vector<Anchor> generate_anchors(const AnchorOptions &o);

struct Detection {
  float score = 0;
  float xmin = 0, ymin = 0, xmax = 0, ymax = 0;
  std::vector<std::pair<float, float>> keypoints;  // (x, y)

  float width() const { return xmax - xmin; }
  float height() const { return ymax - ymin; }
};

struct DecodeOptions {
  // Scale of the regressors (the model input size for BlazeFace).
  float x_scale = 128, y_scale = 128, w_scale = 128, h_scale = 128;
  std::size_t num_coords = 16;  // values per anchor in the box tensor
  std::size_t box_offset = 0;   // where x, y, w, h start
  std::size_t keypoint_offset = 4;
  std::size_t num_keypoints = 6;
  bool sigmoid_score = true;
  float score_clip = 100.f;  // raw scores are clipped to [-clip, clip] first (0: off)
  float min_score = 0.5f;    // after the sigmoid
};

float sigmoid(float x);

// boxes: anchors.size() * num_coords floats; scores: anchors.size() floats (raw logits when
// sigmoid_score). Returns the detections scoring at least min_score, unsorted.
std::vector<Detection> decode(const float *boxes, const float *scores,
                              const std::vector<Anchor> &anchors, const DecodeOptions &o);

float iou(const Detection &a, const Detection &b);

enum class NmsMode { kHard, kWeighted };
// Keeps the best detection of every group overlapping more than `iou_threshold`, best first.
// kWeighted replaces the kept box (and keypoints) by the score-weighted mean of its group, as
// MediaPipe does for faces. At most `max_detections` (0: no limit).
std::vector<Detection> nms(std::vector<Detection> dets, float iou_threshold, NmsMode mode,
                           std::size_t max_detections = 0);

}  // namespace nns::ssd

// SPDX-License-Identifier: LGPL-2.1-only
#include "core/ssd_decode.h"

#include <algorithm>
#include <cmath>

namespace nns::ssd {
namespace {

float layer_scale(float min_scale, float max_scale, std::size_t i, std::size_t n) {
  if (n == 1) return (min_scale + max_scale) / 2;
  return min_scale + (max_scale - min_scale) * static_cast<float>(i) / static_cast<float>(n - 1);
}

}  // namespace

AnchorOptions blazeface_front_options() {
  return AnchorOptions{};
}

std::vector<Anchor> generate_anchors(const AnchorOptions &o) {
  std::vector<Anchor> out;
  const std::size_t n = o.strides.size();
  std::size_t layer = 0;
  while (layer < n) {
    std::vector<float> ratios, scales;
    std::size_t last = layer;
    // Layers sharing a stride share the feature map: their anchors go into the same cells.
    while (last < n && o.strides[last] == o.strides[layer]) {
      float scale = layer_scale(o.min_scale, o.max_scale, last, n);
      if (last == 0 && o.reduce_boxes_in_lowest_layer) {
        ratios.insert(ratios.end(), {1.0f, 2.0f, 0.5f});
        scales.insert(scales.end(), {0.1f, scale, scale});
      } else {
        for (float r : o.aspect_ratios) {
          ratios.push_back(r);
          scales.push_back(scale);
        }
        if (o.interpolated_scale_aspect_ratio > 0) {
          float next = last == n - 1 ? 1.0f : layer_scale(o.min_scale, o.max_scale, last + 1, n);
          scales.push_back(std::sqrt(scale * next));
          ratios.push_back(o.interpolated_scale_aspect_ratio);
        }
      }
      ++last;
    }
    const int stride = o.strides[layer];
    const int rows = (o.input_height + stride - 1) / stride;
    const int cols = (o.input_width + stride - 1) / stride;
    for (int y = 0; y < rows; ++y)
      for (int x = 0; x < cols; ++x)
        for (std::size_t a = 0; a < ratios.size(); ++a) {
          Anchor an;
          an.cx = (x + o.offset_x) / cols;
          an.cy = (y + o.offset_y) / rows;
          if (!o.fixed_anchor_size) {
            float r = std::sqrt(ratios[a]);
            an.w = scales[a] * r;
            an.h = scales[a] / r;
          }
          out.push_back(an);
        }
    layer = last;
  }
  return out;
}

float sigmoid(float x) {
  return 1.f / (1.f + std::exp(-x));
}

std::vector<Detection> decode(const float *boxes, const float *scores,
                              const std::vector<Anchor> &anchors, const DecodeOptions &o) {
  std::vector<Detection> out;
  for (std::size_t i = 0; i < anchors.size(); ++i) {
    float s = scores[i];
    if (o.score_clip > 0) s = std::clamp(s, -o.score_clip, o.score_clip);
    if (o.sigmoid_score) s = sigmoid(s);
    if (!(s >= o.min_score)) continue;
    const Anchor &a = anchors[i];
    const float *r = boxes + i * o.num_coords;
    const float *b = r + o.box_offset;
    float cx = b[0] / o.x_scale * a.w + a.cx;
    float cy = b[1] / o.y_scale * a.h + a.cy;
    float w = b[2] / o.w_scale * a.w;
    float h = b[3] / o.h_scale * a.h;
    Detection d;
    d.score = s;
    d.xmin = cx - w / 2;
    d.xmax = cx + w / 2;
    d.ymin = cy - h / 2;
    d.ymax = cy + h / 2;
    for (std::size_t k = 0; k < o.num_keypoints; ++k) {
      const float *kp = r + o.keypoint_offset + 2 * k;
      d.keypoints.emplace_back(kp[0] / o.x_scale * a.w + a.cx, kp[1] / o.y_scale * a.h + a.cy);
    }
    out.push_back(std::move(d));
  }
  return out;
}

float iou(const Detection &a, const Detection &b) {
  float ix = std::max(0.f, std::min(a.xmax, b.xmax) - std::max(a.xmin, b.xmin));
  float iy = std::max(0.f, std::min(a.ymax, b.ymax) - std::max(a.ymin, b.ymin));
  float inter = ix * iy;
  float uni = a.width() * a.height() + b.width() * b.height() - inter;
  return uni > 0 ? inter / uni : 0.f;
}

std::vector<Detection> nms(std::vector<Detection> dets, float iou_threshold, NmsMode mode,
                           std::size_t max_detections) {
  std::stable_sort(dets.begin(), dets.end(),
                   [](const Detection &a, const Detection &b) { return a.score > b.score; });
  std::vector<Detection> kept;
  std::vector<bool> used(dets.size(), false);
  for (std::size_t i = 0; i < dets.size(); ++i) {
    if (used[i]) continue;
    if (max_detections && kept.size() == max_detections) break;
    // The group: this detection and every unused lower-scored one overlapping it.
    std::vector<std::size_t> group = {i};
    for (std::size_t j = i + 1; j < dets.size(); ++j)
      if (!used[j] && iou(dets[i], dets[j]) > iou_threshold) group.push_back(j);
    for (auto g : group) used[g] = true;
    Detection best = dets[i];
    if (mode == NmsMode::kWeighted && group.size() > 1) {
      float total = 0, xmin = 0, ymin = 0, xmax = 0, ymax = 0;
      std::vector<std::pair<float, float>> kps(best.keypoints.size(), {0.f, 0.f});
      for (auto g : group) {
        const Detection &d = dets[g];
        total += d.score;
        xmin += d.xmin * d.score;
        ymin += d.ymin * d.score;
        xmax += d.xmax * d.score;
        ymax += d.ymax * d.score;
        for (std::size_t k = 0; k < kps.size() && k < d.keypoints.size(); ++k) {
          kps[k].first += d.keypoints[k].first * d.score;
          kps[k].second += d.keypoints[k].second * d.score;
        }
      }
      best.xmin = xmin / total;
      best.ymin = ymin / total;
      best.xmax = xmax / total;
      best.ymax = ymax / total;
      for (std::size_t k = 0; k < kps.size(); ++k)
        best.keypoints[k] = {kps[k].first / total, kps[k].second / total};
    }
    kept.push_back(std::move(best));
  }
  return kept;
}

}  // namespace nns::ssd

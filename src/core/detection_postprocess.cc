// SPDX-License-Identifier: LGPL-2.1-only
// TFLite_Detection_PostProcess: see detection_postprocess.h for the semantics.
#include "core/detection_postprocess.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>
#include <vector>

namespace nns {
namespace {

struct Box {
  float ymin, xmin, ymax, xmax;
};

float iou(const Box &a, const Box &b) {
  const float area_a = (a.ymax - a.ymin) * (a.xmax - a.xmin);
  const float area_b = (b.ymax - b.ymin) * (b.xmax - b.xmin);
  if (area_a <= 0 || area_b <= 0) return 0.0f;
  const float ih = std::max(std::min(a.ymax, b.ymax) - std::max(a.ymin, b.ymin), 0.0f);
  const float iw = std::max(std::min(a.xmax, b.xmax) - std::max(a.xmin, b.xmin), 0.0f);
  const float inter = ih * iw;
  return inter / (area_a + area_b - inter);
}

// Indices of `score` (one per anchor, read with `stride`) kept by NMS, best first, at most
// `limit`.
std::vector<int> nms(const DetectionPostProcessOptions &o, const std::vector<Box> &boxes,
                     const float *score, int stride, int limit) {
  const int n = static_cast<int>(boxes.size());
  std::vector<int> cand;
  for (int i = 0; i < n; ++i)
    if (score[static_cast<size_t>(i) * stride] >= o.nms_score_threshold) cand.push_back(i);
  std::stable_sort(cand.begin(), cand.end(), [&](int a, int b) {
    return score[static_cast<size_t>(a) * stride] > score[static_cast<size_t>(b) * stride];
  });
  std::vector<int> kept;
  const int want = std::min<int>(limit, static_cast<int>(cand.size()));
  std::vector<char> alive(cand.size(), 1);
  for (size_t i = 0; i < cand.size() && static_cast<int>(kept.size()) < want; ++i) {
    if (!alive[i]) continue;
    kept.push_back(cand[i]);
    for (size_t j = i + 1; j < cand.size(); ++j)
      if (alive[j] && iou(boxes[cand[i]], boxes[cand[j]]) > o.nms_iou_threshold) alive[j] = 0;
  }
  return kept;
}

void put(const Box &b, int cls, float score, int slot, float *out_boxes, float *out_classes,
         float *out_scores) {
  out_boxes[4 * slot + 0] = b.ymin;
  out_boxes[4 * slot + 1] = b.xmin;
  out_boxes[4 * slot + 2] = b.ymax;
  out_boxes[4 * slot + 3] = b.xmax;
  out_classes[slot] = static_cast<float>(cls);
  out_scores[slot] = score;
}

bool valid(const DetectionPostProcessOptions &o) {
  return o.num_classes >= 1 && o.max_detections >= 0 && o.max_classes_per_detection >= 1 &&
         (!o.use_regular_nms || o.detections_per_class >= 1) && o.y_scale != 0 && o.x_scale != 0 &&
         o.h_scale != 0 && o.w_scale != 0;
}

}  // namespace

int detection_postprocess_slots(const DetectionPostProcessOptions &o) {
  if (!valid(o)) return 0;
  return o.use_regular_nms ? o.max_detections : o.max_detections * o.max_classes_per_detection;
}

int detection_postprocess(const DetectionPostProcessOptions &o, const float *boxes,
                          const float *scores, const float *anchors, int num_anchors,
                          float *out_boxes, float *out_classes, float *out_scores, float *out_num) {
  if (!valid(o) || num_anchors < 0) return -1;
  const int slots = detection_postprocess_slots(o);
  std::memset(out_boxes, 0, sizeof(float) * 4 * slots);
  std::memset(out_classes, 0, sizeof(float) * slots);
  std::memset(out_scores, 0, sizeof(float) * slots);

  std::vector<Box> decoded(num_anchors);
  for (int i = 0; i < num_anchors; ++i) {
    const float *e = boxes + 4 * static_cast<size_t>(i);
    const float *a = anchors + 4 * static_cast<size_t>(i);
    const float yc = e[0] / o.y_scale * a[2] + a[0];
    const float xc = e[1] / o.x_scale * a[3] + a[1];
    const float hh = 0.5f * std::exp(e[2] / o.h_scale) * a[2];
    const float hw = 0.5f * std::exp(e[3] / o.w_scale) * a[3];
    decoded[i] = {yc - hh, xc - hw, yc + hh, xc + hw};
  }
  const int row = o.num_classes + 1;  // score columns per anchor, background first
  int written = 0;

  if (!o.use_regular_nms) {
    const int per_anchor = std::min(o.max_classes_per_detection, o.num_classes);
    std::vector<int> top(static_cast<size_t>(num_anchors) * per_anchor);
    std::vector<float> best(num_anchors);
    std::vector<int> order(o.num_classes);
    for (int i = 0; i < num_anchors; ++i) {
      const float *s = scores + static_cast<size_t>(i) * row + 1;
      std::iota(order.begin(), order.end(), 0);
      std::partial_sort(order.begin(), order.begin() + per_anchor, order.end(),
                        [&](int a, int b) { return s[a] > s[b] || (s[a] == s[b] && a < b); });
      std::copy_n(order.begin(), per_anchor, top.begin() + static_cast<size_t>(i) * per_anchor);
      best[i] = s[order[0]];
    }
    for (int a : nms(o, decoded, best.data(), 1, o.max_detections)) {
      const float *s = scores + static_cast<size_t>(a) * row + 1;
      for (int c = 0; c < per_anchor; ++c) {
        const int cls = top[static_cast<size_t>(a) * per_anchor + c];
        put(decoded[a], cls, s[cls], written * o.max_classes_per_detection + c, out_boxes,
            out_classes, out_scores);
      }
      ++written;
    }
  } else {
    struct Det {
      float score;
      int anchor, cls;
    };
    std::vector<Det> all;
    for (int c = 0; c < o.num_classes; ++c)
      for (int a : nms(o, decoded, scores + 1 + c, row, o.detections_per_class))
        all.push_back({scores[static_cast<size_t>(a) * row + 1 + c], a, c});
    // Best first; ties: lower class, then the order NMS kept them in (score, then anchor).
    std::stable_sort(all.begin(), all.end(),
                     [](const Det &x, const Det &y) { return x.score > y.score; });
    for (const Det &d : all) {
      if (written >= o.max_detections) break;
      put(decoded[d.anchor], d.cls, d.score, written, out_boxes, out_classes, out_scores);
      ++written;
    }
  }
  *out_num = static_cast<float>(written);
  return written;
}

}  // namespace nns

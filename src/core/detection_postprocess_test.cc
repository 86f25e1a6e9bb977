// SPDX-License-Identifier: LGPL-2.1-only
// TFLite_Detection_PostProcess on 6 synthetic anchors and 3 classes. The golden values of the
// single-class-per-detection and regular-NMS cases were produced by Arm NN 20.08's
// DetectionPostProcess layer on CpuRef (a network of that one layer, same inputs). With
// max_classes_per_detection > 1 Arm NN does not follow TFLite (it runs NMS over anchor/class
// pairs), so that case is checked against values worked out by hand from TFLite's rules.
#include "core/detection_postprocess.h"

#include <gtest/gtest.h>

#include <array>
#include <vector>

namespace {

using nns::DetectionPostProcessOptions;

// anchors (ycenter, xcenter, h, w): three on one cell, two ten units lower, one far away.
const float kAnchors[6 * 4] = {0.5f,  0.5f, 1, 1, 0.5f,  0.5f, 1, 1, 0.5f,   0.5f, 1, 1,
                               10.5f, 0.5f, 1, 1, 10.5f, 0.5f, 1, 1, 100.5f, 0.5f, 1, 1};
// encodings (ty, tx, th, tw): tx = +-1 shifts x by 0.1 (x_scale 10); the last one uses all four.
const float kBoxes[6 * 4] = {0, 0, 0, 0, 0, 1, 0, 0, 0, -1, 0,    0,
                             0, 0, 0, 0, 0, 1, 0, 0, 1, 2,  1.5f, -0.5f};
// background + 3 classes per anchor.
const float kScores[6 * 4] = {0, .9f,  .8f,  .1f, 0, .75f, .72f, .2f,  0, .6f, .5f, .3f,
                              0, .93f, .95f, .4f, 0, .5f,  .4f,  .55f, 0, .3f, .2f, .1f};

struct Det {
  std::array<float, 4> box;
  float cls, score;
};

const std::array<float, 4> kA0 = {0, 0, 1, 1}, kA1 = {0, 0.100000024f, 1, 1.10000002f},
                           kA2 = {0, -0.099999994f, 1, 0.899999976f}, kA3 = {10, 0, 11, 1},
                           kA4 = {10, 0.100000024f, 11, 1.10000002f},
                           kA5 = {99.9250717f, 0.247581273f, 101.274925f, 1.15241873f};

DetectionPostProcessOptions opts(int max_det, int max_cls, int per_class, float score_thr,
                                 float iou_thr, bool regular) {
  DetectionPostProcessOptions o;
  o.max_detections = max_det;
  o.max_classes_per_detection = max_cls;
  o.detections_per_class = per_class;
  o.nms_score_threshold = score_thr;
  o.nms_iou_threshold = iou_thr;
  o.num_classes = 3;
  o.y_scale = o.x_scale = 10;
  o.h_scale = o.w_scale = 5;
  o.use_regular_nms = regular;
  return o;
}

void check(const DetectionPostProcessOptions &o, int want_num, const std::vector<Det> &want) {
  const int slots = nns::detection_postprocess_slots(o);
  ASSERT_EQ(slots, static_cast<int>(want.size()));
  std::vector<float> boxes(4 * slots, -7), cls(slots, -7), sc(slots, -7);
  float num = -7;
  ASSERT_EQ(nns::detection_postprocess(o, kBoxes, kScores, kAnchors, 6, boxes.data(), cls.data(),
                                       sc.data(), &num),
            want_num);
  EXPECT_EQ(num, static_cast<float>(want_num));
  for (int i = 0; i < slots; ++i) {
    for (int k = 0; k < 4; ++k)
      EXPECT_NEAR(boxes[4 * i + k], want[i].box[k], 1e-5f) << "slot " << i << " coord " << k;
    EXPECT_EQ(cls[i], want[i].cls) << "slot " << i;
    EXPECT_FLOAT_EQ(sc[i], want[i].score) << "slot " << i;
  }
}

const Det kEmpty = {{0, 0, 0, 0}, 0, 0};

TEST(DetectionPostProcess, FastNmsMatchesArmnn) {
  // Anchors 1, 2 overlap anchor 0 (IoU 0.82), anchor 4 overlaps 3: suppressed.
  check(opts(3, 1, 2, 0, 0.5f, false), 3, {{kA3, 1, .95f}, {kA0, 0, .9f}, {kA5, 0, .3f}});
  // Score threshold drops anchor 5; max_detections caps at 2.
  check(opts(2, 1, 2, 0.35f, 0.5f, false), 2, {{kA3, 1, .95f}, {kA0, 0, .9f}});
  // IoU threshold 0.9: nothing overlaps that much; the 0.25 threshold keeps all six.
  check(opts(10, 1, 100, 0.25f, 0.9f, false), 6,
        {{kA3, 1, .95f},
         {kA0, 0, .9f},
         {kA1, 0, .75f},
         {kA2, 0, .6f},
         {kA4, 2, .55f},
         {kA5, 0, .3f},
         kEmpty,
         kEmpty,
         kEmpty,
         kEmpty});
}

TEST(DetectionPostProcess, FastNmsSeveralClassesPerDetectionAsTflite) {
  // The anchors kept are those of max_classes_per_detection = 1; each fills two slots with its
  // two best classes; the count is of anchors.
  check(
      opts(3, 2, 2, 0, 0.5f, false), 3,
      {{kA3, 1, .95f}, {kA3, 0, .93f}, {kA0, 0, .9f}, {kA0, 1, .8f}, {kA5, 0, .3f}, {kA5, 1, .2f}});
  // max_classes_per_detection above num_classes: 3 classes written, slots stay 5 per anchor.
  DetectionPostProcessOptions o = opts(1, 5, 1, 0, 0.5f, false);
  check(o, 1, {{kA3, 1, .95f}, {kA3, 0, .93f}, {kA3, 2, .4f}, kEmpty, kEmpty});
}

TEST(DetectionPostProcess, RegularNmsMatchesArmnn) {
  check(opts(4, 1, 2, 0.35f, 0.5f, true), 4,
        {{kA3, 1, .95f}, {kA3, 0, .93f}, {kA0, 0, .9f}, {kA0, 1, .8f}});
  check(opts(5, 1, 3, 0, 0.5f, true), 5,
        {{kA3, 1, .95f}, {kA3, 0, .93f}, {kA0, 0, .9f}, {kA0, 1, .8f}, {kA4, 2, .55f}});
  // Ties (0.5 for anchor 4 class 0 and anchor 2 class 1): the lower class first.
  check(opts(10, 1, 100, 0.25f, 0.9f, true), 10,
        {{kA3, 1, .95f},
         {kA3, 0, .93f},
         {kA0, 0, .9f},
         {kA0, 1, .8f},
         {kA1, 0, .75f},
         {kA1, 1, .72f},
         {kA2, 0, .6f},
         {kA4, 2, .55f},
         {kA4, 0, .5f},
         {kA2, 1, .5f}});
}

TEST(DetectionPostProcess, NothingAboveThreshold) {
  check(opts(2, 1, 2, 0.99f, 0.5f, false), 0, {kEmpty, kEmpty});
  check(opts(2, 1, 2, 0.99f, 0.5f, true), 0, {kEmpty, kEmpty});
}

TEST(DetectionPostProcess, InvalidOptions) {
  float b[4], c[1], s[1], n = -7;
  DetectionPostProcessOptions o = opts(1, 1, 1, 0, 0.5f, false);
  o.num_classes = 0;
  EXPECT_EQ(nns::detection_postprocess(o, kBoxes, kScores, kAnchors, 6, b, c, s, &n), -1);
  EXPECT_EQ(nns::detection_postprocess_slots(o), 0);
  o = opts(1, 0, 1, 0, 0.5f, false);
  EXPECT_EQ(nns::detection_postprocess(o, kBoxes, kScores, kAnchors, 6, b, c, s, &n), -1);
  o = opts(1, 1, 0, 0, 0.5f, true);
  EXPECT_EQ(nns::detection_postprocess(o, kBoxes, kScores, kAnchors, 6, b, c, s, &n), -1);
  o = opts(1, 1, 1, 0, 0.5f, false);
  o.h_scale = 0;
  EXPECT_EQ(nns::detection_postprocess(o, kBoxes, kScores, kAnchors, 6, b, c, s, &n), -1);
  EXPECT_EQ(n, -7);  // untouched
  o = opts(1, 1, 1, 0, 0.5f, false);
  EXPECT_EQ(nns::detection_postprocess(o, kBoxes, kScores, kAnchors, 0, b, c, s, &n), 0);
  EXPECT_EQ(n, 0);
}

}  // namespace

// A box suppressed by a better one does not suppress others itself (TFLite). Arm NN 20.08's
// reference NMS lets it, and orders equal scores differently: on the real COCO SSD (orange.png,
// Arm NN's own pre-post-processing tensors) its first detection (class 54, score 0.75, box
// 0.2055 0.1965 0.9140 0.9050) equals ours, the later low-score ones differ for those reasons.
TEST(DetectionPostProcess, SuppressedBoxesDoNotSuppress) {
  // Along x: A [0,1], B [0.3,1.3], C [0.6,1.6]; IoU(A,B) = IoU(B,C) = 0.54, IoU(A,C) = 0.25.
  const float anchors[3 * 4] = {0.5f, 0.5f, 1, 1, 0.5f, 0.8f, 1, 1, 0.5f, 1.1f, 1, 1};
  const float boxes[3 * 4] = {};
  const float scores[3 * 2] = {0, .9f, 0, .8f, 0, .7f};
  DetectionPostProcessOptions o = opts(3, 1, 3, 0, 0.5f, false);
  o.num_classes = 1;
  for (bool regular : {false, true}) {
    o.use_regular_nms = regular;
    float b[12], c[3], s[3], n = -1;
    ASSERT_EQ(nns::detection_postprocess(o, boxes, scores, anchors, 3, b, c, s, &n), 2);
    EXPECT_FLOAT_EQ(s[0], .9f);
    EXPECT_FLOAT_EQ(s[1], .7f);  // C kept: only B, which A suppressed, overlaps it
    EXPECT_NEAR(b[4 + 1], 0.6f, 1e-6f);
    EXPECT_EQ(s[2], 0.f);
  }
}

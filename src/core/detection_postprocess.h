// SPDX-License-Identifier: LGPL-2.1-only
// TensorFlow Lite's custom operator TFLite_Detection_PostProcess (SSD box decoding against
// anchors + non-maximum suppression), GStreamer-free, float only (the TFLite back end
// dequantizes uint8 box encodings, scores and anchors before calling it).
//
// Boxes: decoded per anchor a (ycenter, xcenter, h, w) from the encoding (ty, tx, th, tw):
//   yc = ty / y_scale * a.h + a.yc, xc = tx / x_scale * a.w + a.xc,
//   h = exp(th / h_scale) * a.h, w = exp(tw / w_scale) * a.w,
//   box = (yc - h/2, xc - w/2, yc + h/2, xc + w/2)   (ymin, xmin, ymax, xmax)
// NMS of one score list: scores >= nms_score_threshold, by decreasing score (ties: lower anchor
// first); a box is dropped when its IoU with an already kept one is > nms_iou_threshold (IoU of
// a box with no area is 0).
// - use_regular_nms = false ("fast"): each anchor's best min(max_classes_per_detection,
//   num_classes) classes (background excluded); NMS on the anchors' best class scores keeps up
//   to max_detections anchors, each written with its max_classes_per_detection classes.
// - use_regular_nms = true: NMS per class (up to detections_per_class each), then the best
//   max_detections of all classes by score.
// Classes written exclude the background: score column c + 1 is written as class c.
#pragma once

namespace nns {

struct DetectionPostProcessOptions {
  int max_detections = 10;
  int max_classes_per_detection = 1;
  int detections_per_class = 100;
  float nms_score_threshold = 0.0f;
  float nms_iou_threshold = 0.5f;
  int num_classes = 90;
  float y_scale = 10.0f, x_scale = 10.0f, h_scale = 5.0f, w_scale = 5.0f;
  bool use_regular_nms = false;
};

// Number of detection slots the outputs need: max_detections * max_classes_per_detection for
// fast NMS (TFLite's output shape [1, that, 4]), max_detections for regular NMS. 0 when the
// options are invalid (see below).
int detection_postprocess_slots(const DetectionPostProcessOptions &o);

// boxes [num_anchors][4] encodings (ty,tx,th,tw); scores [num_anchors][num_classes+1]
// (index 0 background); anchors [num_anchors][4] (ycenter,xcenter,h,w).
// Outputs (slots = detection_postprocess_slots(o)): out_boxes [slots][4] (ymin,xmin,ymax,xmax),
// out_classes [slots], out_scores [slots], out_num [1]. Unused slots are zero.
// Returns the number of detections written (the value put in out_num: for fast NMS the number
// of anchors kept, each filling max_classes_per_detection slots), or -1 when the options are
// invalid (num_classes < 1, max_detections < 0, max_classes_per_detection < 1, regular NMS with
// detections_per_class < 1, a zero scale) or num_anchors < 0; outputs are then untouched.
int detection_postprocess(const DetectionPostProcessOptions &o, const float *boxes,
                          const float *scores, const float *anchors, int num_anchors,
                          float *out_boxes, float *out_classes, float *out_scores, float *out_num);

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
// Metadata that tensor_decoder mode=bounding_boxes attaches to each output frame (our
// extension; NNStreamer attaches none):
//  - one GstVideoRegionOfInterestMeta per box: roi_type = label (or "object"), x/y/w/h in
//    output pixels, id = track id (0 untracked), with a param structure "detection":
//    class-id (int), label (string), score (double), track-id (int), angle (double, radians),
//    keypoints (GstValueArray of doubles x0, y0, x1, y1, ... in output pixels; only if any);
//  - with option9 containing "json": a GstCustomMeta "NnsDetectionsMeta" whose structure has
//    a string field "json": {"width":W,"height":H,"boxes":[{"x":..,"y":..,"w":..,"h":..,
//    "class_id":..,"label":"..","score":..,"track_id":..,"angle":..,"keypoints":[..]}]}.
#pragma once

#include <gst/gst.h>

#include <string>
#include <vector>

#include "box_scheme.h"

namespace nns::bbox {

inline constexpr const char *kDetectionsMetaName = "NnsDetectionsMeta";

// One box as drawn: output pixels.
struct OutBox {
  const Box *box = nullptr;  // model-input box (class, score, track id, angle, keypoints)
  int x = 0, y = 0, w = 0, h = 0;
  float sx = 1, sy = 1;                // model-input to output scale (keypoints)
  const std::string *label = nullptr;  // nullptr: none
};

void add_roi_metas(GstBuffer *buf, const std::vector<OutBox> &boxes);
// Registers NnsDetectionsMeta once and attaches `json` (built by append_json).
void add_json_meta(GstBuffer *buf, const std::string &json);
void build_json(std::string &out, unsigned width, unsigned height,
                const std::vector<OutBox> &boxes);

}  // namespace nns::bbox

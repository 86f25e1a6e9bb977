// SPDX-License-Identifier: LGPL-2.1-only
// Naive centroid tracker of tensor_decoder mode=bounding_boxes option6=1, with NNStreamer's
// rules: ids start at 1; each frame, (centroid, box) pairs are matched greedily by increasing
// squared distance of integer centres (model-input pixels); unmatched boxes get new ids;
// a centroid unseen for 100 consecutive frames is dropped; frames with more than 100 boxes
// or centroids are not tracked (ids stay 0).
#pragma once

#include <cstdint>
#include <vector>

#include "box_scheme.h"

namespace nns::bbox {

class CentroidTracker {
 public:
  void update(std::vector<Box> &boxes);

 private:
  struct Centroid {
    int id = 0;
    int cx = 0, cy = 0;
    unsigned missed = 0;
    std::size_t matched = 0;
  };
  struct Pair {
    uint64_t dist;
    uint32_t c, b;
  };
  std::vector<Centroid> centroids_;
  std::vector<Pair> pairs_;
  int last_id_ = 0;
};

}  // namespace nns::bbox

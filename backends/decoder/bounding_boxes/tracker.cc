// SPDX-License-Identifier: LGPL-2.1-only
#include "tracker.h"

#include <algorithm>
#include <limits>

namespace nns::bbox {

namespace {
constexpr std::size_t kMaxCentroids = 100;
constexpr unsigned kDisappear = 100;
constexpr std::size_t kNone = std::numeric_limits<std::size_t>::max();

int centre_x(const Box &b) {
  return static_cast<int>(b.x) + static_cast<int>(b.w) / 2;
}
int centre_y(const Box &b) {
  return static_cast<int>(b.y) + static_cast<int>(b.h) / 2;
}
}  // namespace

void CentroidTracker::update(std::vector<Box> &boxes) {
  for (auto &b : boxes) b.track_id = 0;
  if (boxes.size() > kMaxCentroids) return;
  std::erase_if(centroids_, [](const Centroid &c) { return c.missed >= kDisappear; });
  if (centroids_.size() > kMaxCentroids) return;
  if (boxes.empty()) {
    for (auto &c : centroids_) ++c.missed;
    return;
  }
  auto add = [&](Box &b, std::size_t idx) {
    Centroid c;
    c.id = ++last_id_;
    c.cx = centre_x(b), c.cy = centre_y(b);
    c.matched = idx;
    centroids_.push_back(c);
    b.track_id = c.id;
  };
  if (centroids_.empty()) {
    for (std::size_t i = 0; i < boxes.size(); ++i) add(boxes[i], i);
    return;
  }
  pairs_.clear();
  for (uint32_t i = 0; i < centroids_.size(); ++i) {
    centroids_[i].matched = kNone;
    for (uint32_t j = 0; j < boxes.size(); ++j) {
      const int64_t dx = centroids_[i].cx - centre_x(boxes[j]);
      const int64_t dy = centroids_[i].cy - centre_y(boxes[j]);
      pairs_.push_back({static_cast<uint64_t>(dx * dx + dy * dy), i, j});
    }
  }
  std::stable_sort(pairs_.begin(), pairs_.end(),
                   [](const Pair &a, const Pair &b) { return a.dist < b.dist; });
  for (const Pair &p : pairs_) {
    Centroid &c = centroids_[p.c];
    Box &b = boxes[p.b];
    if (b.track_id != 0 || c.matched != kNone) continue;
    c.matched = p.b;
    b.track_id = c.id;
    c.missed = 0;
    // NNStreamer keeps the first centre of a centroid; so do we.
  }
  for (auto &c : centroids_)
    if (c.matched == kNone) ++c.missed;
  for (std::size_t j = 0; j < boxes.size(); ++j)
    if (boxes[j].track_id == 0) add(boxes[j], j);
}

}  // namespace nns::bbox

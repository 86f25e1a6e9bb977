// SPDX-License-Identifier: LGPL-2.1-only
#include "box_scheme.h"

#include <algorithm>
#include <mutex>

namespace nns::bbox {

void register_builtin_schemes(SchemeTable &table);  // generated from schemes/*.cc

void SchemeTable::add(const std::string &name, Factory f, const std::string &canonical) {
  Entry e{std::move(f), canonical.empty() ? name : canonical};
  for (auto &[n, old] : entries_) {
    if (n == name) {
      old = std::move(e);
      return;
    }
  }
  entries_.emplace_back(name, std::move(e));
}

std::unique_ptr<Scheme> SchemeTable::make(const std::string &name) const {
  for (const auto &[n, e] : entries_)
    if (n == name) return e.make();
  return nullptr;
}

std::string SchemeTable::canonical(const std::string &name) const {
  for (const auto &[n, e] : entries_)
    if (n == name) return e.canonical;
  return {};
}

std::vector<std::string> SchemeTable::names() const {
  std::vector<std::string> v;
  for (const auto &[n, e] : entries_) v.push_back(n);
  std::sort(v.begin(), v.end());
  return v;
}

const SchemeTable &schemes() {
  static const SchemeTable table = [] {
    SchemeTable t;
    register_builtin_schemes(t);
    return t;
  }();
  return table;
}

float iou(const Box &a, const Box &b) {
  const float x1 = std::max(a.x, b.x), y1 = std::max(a.y, b.y);
  const float x2 = std::min(a.x + a.w, b.x + b.w), y2 = std::min(a.y + a.h, b.y + b.h);
  const float inter = std::max(0.f, x2 - x1) * std::max(0.f, y2 - y1);
  const float uni = a.w * a.h + b.w * b.h - inter;
  return uni > 0 ? inter / uni : 0.f;
}

void nms(std::vector<Box> &boxes, float threshold, bool per_class) {
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const Box &a, const Box &b) { return a.score > b.score; });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    bool drop = false;
    for (std::size_t k = 0; k < kept && !drop; ++k) {
      if (per_class && boxes[k].class_id != boxes[i].class_id) continue;
      drop = iou(boxes[k], boxes[i]) > threshold;
    }
    if (!drop) {
      if (kept != i) boxes[kept] = std::move(boxes[i]);
      ++kept;
    }
  }
  boxes.resize(kept);
}

}  // namespace nns::bbox

// SPDX-License-Identifier: LGPL-2.1-only
// Hot loops of the YOLO schemes (schemes/yolo.cc): find the candidate boxes whose best class
// score passes the confidence threshold before any other work. Written with GCC/Clang vector
// extensions (4 x float, SSE2/NEON width) so they vectorise at any optimisation level; the scalar
// tails handle the remainder. Loads go through memcpy: tensor memories need not be 16-aligned.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstring>
#include <vector>

namespace nns::bbox::yolo_kernels {

typedef float f4 __attribute__((vector_size(16)));
typedef int32_t i4 __attribute__((vector_size(16)));

inline f4 load4(const float *p) {
  f4 v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

// True if any of p[0..n) is > thr.
inline bool any_above(const float *p, std::size_t n, float thr) {
  std::size_t i = 0;
  if (n >= 8) {
    const f4 t = f4{} + thr;
    i4 acc0{}, acc1{};
    for (; i + 8 <= n; i += 8) {
      acc0 |= load4(p + i) > t;
      acc1 |= load4(p + i + 4) > t;
    }
    const i4 acc = acc0 | acc1;
    if (acc[0] | acc[1] | acc[2] | acc[3]) return true;
  }
  for (; i < n; ++i)
    if (p[i] > thr) return true;
  return false;
}

// Box-major data ("#values : #boxes", each box's values contiguous): appends to `idx` every box
// i < n whose values [first, first + nc) hold one > thr. Rows are `stride` floats apart.
inline void candidates_rows(const float *d, std::size_t n, std::size_t stride, std::size_t first,
                            std::size_t nc, float thr, std::vector<uint32_t> &idx) {
  for (std::size_t i = 0; i < n; ++i)
    if (any_above(d + i * stride + first, nc, thr)) idx.push_back(static_cast<uint32_t>(i));
}

// Class-major data ("#boxes : #values", each value's plane of n boxes contiguous): best[i] =
// max over planes [first, first + nc) of plane[i]; then appends every i with best[i] > thr.
inline void candidates_planes(const float *d, std::size_t n, std::size_t first, std::size_t nc,
                              float thr, float *best, std::vector<uint32_t> &idx) {
  if (nc == 0) return;
  std::memcpy(best, d + first * n, n * sizeof(float));
  const std::size_t n4 = n & ~std::size_t{3};
  for (std::size_t c = first + 1; c < first + nc; ++c) {
    const float *plane = d + c * n;
    std::size_t i = 0;
    for (; i < n4; i += 4) {
      const f4 v = load4(plane + i);
      f4 b = load4(best + i);
      b = v > b ? v : b;
      std::memcpy(best + i, &b, sizeof b);
    }
    for (; i < n; ++i)
      if (plane[i] > best[i]) best[i] = plane[i];
  }
  for (std::size_t i = 0; i < n; ++i)
    if (best[i] > thr) idx.push_back(static_cast<uint32_t>(i));
}

}  // namespace nns::bbox::yolo_kernels

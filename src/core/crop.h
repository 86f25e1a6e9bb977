// SPDX-License-Identifier: LGPL-2.1-only
// tensor_crop logic (GStreamer-free): crop regions from an `info` tensor and NHWC cropping.
//
// The info tensor is NNStreamer's crop-info layout (tensor_decoder mode=tensor_region output):
// consecutive {x, y, w, h} quadruples of any numeric type (cast to uint32), at most 256.
// The raw tensor is NHWC: dimension[0] = channels, [1] = width, [2] = height (one frame).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "core/tensor_info.h"

namespace nns {

struct CropRegion {
  uint32_t x = 0, y = 0, w = 0, h = 0;
  std::string to_string() const;  // "(x=1, y=2, w=3, h=4)"
};

constexpr std::size_t kMaxCropRegions = 256;

// Regions from the payload (header removed) of an info tensor of `type`. Throws
// nns::Error(kStream) when the payload is not a whole number of quadruples.
std::vector<CropRegion> parse_crop_regions(TensorType type, const uint8_t *data, std::size_t size);

// Fits `r` to a width x height frame the way upstream does: w or h of 0 means "to the edge",
// a region reaching past the edge is clipped (*clipped set). A region that starts outside the
// frame throws nns::Error(kStream) naming region `index` and the frame size.
CropRegion fit_crop_region(const CropRegion &r, uint32_t width, uint32_t height, std::size_t index,
                           bool *clipped);

// Copies region `r` (already fitted) of an NHWC frame into `dst` (r.w * r.h * ch * esize bytes).
void crop_nhwc(const uint8_t *src, uint32_t channels, uint32_t width, std::size_t esize,
               const CropRegion &r, uint8_t *dst);

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
#include "core/crop.h"

#include <algorithm>
#include <cstring>
#include <type_traits>

#include "core/error.h"

namespace nns {
namespace {

template <typename T>
uint32_t as_u32(const uint8_t *p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  if constexpr (std::is_floating_point_v<T>) {
    return v <= 0 ? 0u : static_cast<uint32_t>(v);
  } else {
    return static_cast<uint32_t>(v);  // C cast, as upstream's typecast to uint32
  }
}

uint32_t read_u32(TensorType t, const uint8_t *p) {
  switch (t) {
    case TensorType::kInt32:
      return as_u32<int32_t>(p);
    case TensorType::kUInt32:
      return as_u32<uint32_t>(p);
    case TensorType::kInt16:
      return as_u32<int16_t>(p);
    case TensorType::kUInt16:
      return as_u32<uint16_t>(p);
    case TensorType::kInt8:
      return as_u32<int8_t>(p);
    case TensorType::kUInt8:
      return as_u32<uint8_t>(p);
    case TensorType::kFloat64:
      return as_u32<double>(p);
    case TensorType::kFloat32:
      return as_u32<float>(p);
    case TensorType::kInt64:
      return as_u32<int64_t>(p);
    case TensorType::kUInt64:
      return as_u32<uint64_t>(p);
    default:
      break;
  }
  fail(ErrorKind::kStream, "crop info of type " + std::string(type_name(t)) +
                               " is not supported (use an integer or float32/float64 type)");
}

}  // namespace

std::string CropRegion::to_string() const {
  return "(x=" + std::to_string(x) + ", y=" + std::to_string(y) + ", w=" + std::to_string(w) +
         ", h=" + std::to_string(h) + ")";
}

std::vector<CropRegion> parse_crop_regions(TensorType type, const uint8_t *data, std::size_t size) {
  std::size_t e = type_size(type);
  if (e == 0) fail(ErrorKind::kStream, "crop info has no element type");
  if (size % (4 * e) != 0)
    fail(ErrorKind::kStream, "crop info has " + std::to_string(size) + " bytes of " +
                                 std::string(type_name(type)) +
                                 ", not a whole number of {x,y,w,h} regions (" +
                                 std::to_string(4 * e) + " bytes each)");
  std::size_t n = size / (4 * e);
  if (n > kMaxCropRegions) n = kMaxCropRegions;
  std::vector<CropRegion> out(n);
  for (std::size_t i = 0; i < n; ++i) {
    const uint8_t *p = data + i * 4 * e;
    out[i] = {read_u32(type, p), read_u32(type, p + e), read_u32(type, p + 2 * e),
              read_u32(type, p + 3 * e)};
  }
  return out;
}

CropRegion fit_crop_region(const CropRegion &r, uint32_t width, uint32_t height, std::size_t index,
                           bool *clipped) {
  if (r.x >= width || r.y >= height)
    fail(ErrorKind::kStream, "crop region " + std::to_string(index) + " " + r.to_string() +
                                 " starts outside the " + std::to_string(width) + "x" +
                                 std::to_string(height) + " frame");
  CropRegion f = r;
  uint32_t room_w = width - r.x, room_h = height - r.y;
  f.w = r.w == 0 ? room_w : std::min(r.w, room_w);
  f.h = r.h == 0 ? room_h : std::min(r.h, room_h);
  *clipped = (r.w != 0 && r.w > room_w) || (r.h != 0 && r.h > room_h);
  return f;
}

void crop_nhwc(const uint8_t *src, uint32_t channels, uint32_t width, std::size_t esize,
               const CropRegion &r, uint8_t *dst) {
  const std::size_t px = std::size_t(channels) * esize;
  const std::size_t row = std::size_t(r.w) * px;
  for (uint32_t j = 0; j < r.h; ++j)
    std::memcpy(dst + j * row, src + (std::size_t(r.y + j) * width + r.x) * px, row);
}

}  // namespace nns

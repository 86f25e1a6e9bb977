// SPDX-License-Identifier: LGPL-2.1-only
#include "box_util.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace nns::bbox {

namespace {
template <typename T>
void convert(const void *src, std::size_t n, float *dst) {
  const T *s = static_cast<const T *>(src);
  for (std::size_t i = 0; i < n; ++i) dst[i] = static_cast<float>(s[i]);
}

float half_to_float(uint16_t h) {
  const uint32_t sign = (h >> 15) & 1, exp = (h >> 10) & 0x1f, mant = h & 0x3ff;
  float v;
  if (exp == 0)
    v = std::ldexp(static_cast<float>(mant), -24);
  else if (exp == 31)
    v = mant ? NAN : INFINITY;
  else
    v = std::ldexp(static_cast<float>(mant | 0x400), static_cast<int>(exp) - 25);
  return sign ? -v : v;
}
}  // namespace

const float *as_float(const TensorView &t, std::size_t count, std::vector<float> &scratch) {
  const TensorType type = t.info ? t.info->type : TensorType::kFloat32;
  const std::size_t need = count * type_size(type);
  if (!t.data || t.size < need)
    fail(ErrorKind::kStream,
         "tensor holds " + std::to_string(t.size) + " bytes, " + std::to_string(need) + " needed");
  if (type == TensorType::kFloat32) return static_cast<const float *>(t.data);
  if (scratch.size() < count) scratch.resize(count);
  float *d = scratch.data();
  switch (type) {
    case TensorType::kInt8:
      convert<int8_t>(t.data, count, d);
      break;
    case TensorType::kUInt8:
      convert<uint8_t>(t.data, count, d);
      break;
    case TensorType::kInt16:
      convert<int16_t>(t.data, count, d);
      break;
    case TensorType::kUInt16:
      convert<uint16_t>(t.data, count, d);
      break;
    case TensorType::kInt32:
      convert<int32_t>(t.data, count, d);
      break;
    case TensorType::kUInt32:
      convert<uint32_t>(t.data, count, d);
      break;
    case TensorType::kInt64:
      convert<int64_t>(t.data, count, d);
      break;
    case TensorType::kUInt64:
      convert<uint64_t>(t.data, count, d);
      break;
    case TensorType::kFloat64:
      convert<double>(t.data, count, d);
      break;
    case TensorType::kFloat16: {
      const auto *s = static_cast<const uint16_t *>(t.data);
      for (std::size_t i = 0; i < count; ++i) d[i] = half_to_float(s[i]);
      break;
    }
    default:
      fail(ErrorKind::kStream, "tensor type " + std::string(type_name(type)) + " is not numeric");
  }
  return d;
}

float opt_float(const std::string &scheme, const std::string &field_name, const std::string &text,
                float def) {
  const std::string s = trim(text);
  if (s.empty()) return def;
  char *end = nullptr;
  errno = 0;
  const double v = std::strtod(s.c_str(), &end);
  if (errno || end == s.c_str() || *end)
    fail(ErrorKind::kSettings,
         "option3 of scheme " + scheme + ": " + field_name + " must be a number, got '" + s + "'");
  return static_cast<float>(v);
}

int opt_int(const std::string &scheme, const std::string &field_name, const std::string &text,
            int def) {
  const std::string s = trim(text);
  if (s.empty()) return def;
  char *end = nullptr;
  errno = 0;
  const long v = std::strtol(s.c_str(), &end, 10);
  if (errno || end == s.c_str() || *end || v < -1000000 || v > 1000000)
    fail(ErrorKind::kSettings, "option3 of scheme " + scheme + ": " + field_name +
                                   " must be an integer, got '" + s + "'");
  return static_cast<int>(v);
}

bool ones_from(const Dims &d, std::size_t from) {
  for (std::size_t i = from; i < d.size(); ++i)
    if (d[i] > 1) return false;
  return true;
}

void reject_input(const std::string &scheme, const std::string &what, const TensorsInfo &in) {
  fail(ErrorKind::kNegotiation,
       "scheme " + scheme + " expects " + what + ", got " + in.to_string());
}

float iou_pixels(const Box &a, const Box &b) {
  const int ax = static_cast<int>(a.x), ay = static_cast<int>(a.y);
  const int aw = static_cast<int>(a.w), ah = static_cast<int>(a.h);
  const int bx = static_cast<int>(b.x), by = static_cast<int>(b.y);
  const int bw = static_cast<int>(b.w), bh = static_cast<int>(b.h);
  const int x1 = std::max(ax, bx), y1 = std::max(ay, by);
  const int x2 = std::min(ax + aw, bx + bw), y2 = std::min(ay + ah, by + bh);
  const int w = std::max(0, x2 - x1 + 1), h = std::max(0, y2 - y1 + 1);
  const float inter = static_cast<float>(w) * static_cast<float>(h);
  const float o = inter / (static_cast<float>(aw * ah + bw * bh) - inter);
  return o >= 0 ? o : 0;
}

void nms_pixels(std::vector<Box> &boxes, float threshold) {
  std::stable_sort(boxes.begin(), boxes.end(),
                   [](const Box &a, const Box &b) { return a.score > b.score; });
  std::size_t kept = 0;
  for (std::size_t i = 0; i < boxes.size(); ++i) {
    bool drop = false;
    for (std::size_t k = 0; k < kept && !drop; ++k)
      drop = iou_pixels(boxes[k], boxes[i]) > threshold;
    if (!drop) {
      if (kept != i) boxes[kept] = std::move(boxes[i]);
      ++kept;
    }
  }
  boxes.resize(kept);
}

}  // namespace nns::bbox

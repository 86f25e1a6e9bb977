// SPDX-License-Identifier: LGPL-2.1-only
#include "core/sparse.h"

#include <cstring>
#include <string>

#include "core/error.h"

namespace nns {
namespace {

// Zero test in the element's own type (float: -0.0 == 0, NaN != 0), as upstream.
template <typename T>
bool is_zero(const uint8_t *p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v == T(0);
}
bool is_zero_f16(const uint8_t *p) {
  uint16_t v;
  std::memcpy(&v, p, sizeof v);
  return (v & 0x7fffu) == 0;  // +0 and -0
}

using ZeroFn = bool (*)(const uint8_t *);

ZeroFn zero_fn(TensorType t) {
  switch (t) {
    case TensorType::kInt32:
      return is_zero<int32_t>;
    case TensorType::kUInt32:
      return is_zero<uint32_t>;
    case TensorType::kInt16:
      return is_zero<int16_t>;
    case TensorType::kUInt16:
      return is_zero<uint16_t>;
    case TensorType::kInt8:
      return is_zero<int8_t>;
    case TensorType::kUInt8:
      return is_zero<uint8_t>;
    case TensorType::kFloat64:
      return is_zero<double>;
    case TensorType::kFloat32:
      return is_zero<float>;
    case TensorType::kInt64:
      return is_zero<int64_t>;
    case TensorType::kUInt64:
      return is_zero<uint64_t>;
    case TensorType::kFloat16:
      return is_zero_f16;
    case TensorType::kEnd:
      break;
  }
  fail(ErrorKind::kStream, "sparse tensor has no valid element type");
}

void put32(uint8_t *p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
  p[2] = static_cast<uint8_t>(v >> 16);
  p[3] = static_cast<uint8_t>(v >> 24);
}
uint32_t get32(const uint8_t *p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

}  // namespace

std::size_t sparse_count_nonzero(const TensorInfo &info, const uint8_t *data) {
  ZeroFn zero = zero_fn(info.type);
  std::size_t n = info.element_count();
  std::size_t e = type_size(info.type);
  std::size_t nnz = 0;
  for (std::size_t i = 0; i < n; ++i) nnz += !zero(data + i * e);
  return nnz;
}

std::size_t sparse_encoded_size(TensorType type, std::size_t nnz) {
  return kMetaHeaderSize + nnz * (type_size(type) + sizeof(uint32_t));
}

std::size_t sparse_encode(const TensorInfo &info, const uint8_t *src, uint8_t *dst,
                          MediaType media) {
  ZeroFn zero = zero_fn(info.type);
  const std::size_t n = info.element_count();
  if (n > UINT32_MAX)
    fail(ErrorKind::kStream, "tensor " + info.to_string() +
                                 " has more elements than a uint32 sparse index can address");
  const std::size_t e = type_size(info.type);
  const std::size_t nnz = sparse_count_nonzero(info, src);
  MetaHeader h;
  h.type = info.type;
  h.dims = info.dims;
  h.format = TensorFormat::kSparse;
  h.media_type = media;
  h.nnz = static_cast<uint32_t>(nnz);
  write_meta_header(h, dst);
  uint8_t *values = dst + kMetaHeaderSize;
  uint8_t *indices = values + nnz * e;
  std::size_t k = 0;
  for (std::size_t i = 0; i < n; ++i) {
    const uint8_t *p = src + i * e;
    if (zero(p)) continue;
    std::memcpy(values + k * e, p, e);
    put32(indices + k * 4, static_cast<uint32_t>(i));
    ++k;
  }
  return sparse_encoded_size(info.type, nnz);
}

std::vector<uint8_t> sparse_encode(const TensorInfo &info, const uint8_t *src) {
  std::vector<uint8_t> out(sparse_encoded_size(info.type, sparse_count_nonzero(info, src)));
  sparse_encode(info, src, out.data());
  return out;
}

MetaHeader sparse_parse(const uint8_t *src, std::size_t size) {
  MetaHeader h = parse_meta_header(src, size);
  if (h.format != TensorFormat::kSparse)
    fail(ErrorKind::kStream, std::string("tensor memory header has format=") +
                                 std::string(format_name(h.format)) + ", expected sparse");
  if (rank_of(h.dims) == 0) fail(ErrorKind::kStream, "sparse tensor header has no dimension");
  std::size_t expect = sparse_encoded_size(h.type, h.nnz);
  if (size != expect)
    fail(ErrorKind::kStream, "sparse tensor memory has " + std::to_string(size) +
                                 " bytes, expected " + std::to_string(expect) + " for nnz " +
                                 std::to_string(h.nnz) + " of " + h.info().to_string());
  const std::size_t n = element_count(h.dims);
  const uint8_t *indices = src + kMetaHeaderSize + h.nnz * type_size(h.type);
  for (std::size_t k = 0; k < h.nnz; ++k) {
    uint32_t idx = get32(indices + 4 * k);
    if (idx >= n)
      fail(ErrorKind::kStream, "sparse tensor index " + std::to_string(idx) + " (entry " +
                                   std::to_string(k) + ") is outside the " + std::to_string(n) +
                                   " elements of " + h.info().to_string());
  }
  return h;
}

void sparse_decode(const MetaHeader &h, const uint8_t *src, uint8_t *dst) {
  const std::size_t e = type_size(h.type);
  std::memset(dst, 0, element_count(h.dims) * e);
  const uint8_t *values = src + kMetaHeaderSize;
  const uint8_t *indices = values + h.nnz * e;
  for (std::size_t k = 0; k < h.nnz; ++k)
    std::memcpy(dst + std::size_t(get32(indices + 4 * k)) * e, values + k * e, e);
}

}  // namespace nns

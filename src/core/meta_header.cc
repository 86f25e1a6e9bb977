// SPDX-License-Identifier: LGPL-2.1-only
#include "core/meta_header.h"

#include <cstring>
#include <sstream>

#include "core/error.h"

namespace nns {
namespace {

void put32(uint8_t *p, uint32_t v) {
  p[0] = static_cast<uint8_t>(v);
  p[1] = static_cast<uint8_t>(v >> 8);
  p[2] = static_cast<uint8_t>(v >> 16);
  p[3] = static_cast<uint8_t>(v >> 24);
}

uint32_t get32(const uint8_t *p) {
  return uint32_t(p[0]) | uint32_t(p[1]) << 8 | uint32_t(p[2]) << 16 | uint32_t(p[3]) << 24;
}

std::string hex(uint32_t v) {
  std::ostringstream os;
  os << "0x" << std::hex << v;
  return os.str();
}

}  // namespace

std::size_t MetaHeader::payload_size() const {
  if (format == TensorFormat::kSparse) return nnz * (type_size(type) + sizeof(uint32_t));
  return element_count(dims) * type_size(type);
}

MetaHeader flexible_header(TensorType type, const Dims &dims, MediaType media,
                           FlexHeaderKind kind) {
  MetaHeader h;
  h.type = type;
  h.dims = dims;
  h.format =
      kind == FlexHeaderKind::kMarkedFlexible ? TensorFormat::kFlexible : TensorFormat::kStatic;
  h.media_type = media;
  return h;
}

void write_meta_header(const MetaHeader &h, uint8_t *dst) {
  std::memset(dst, 0, kMetaHeaderSize);
  put32(dst, kMetaMagic);
  put32(dst + 4, kMetaVersion);
  put32(dst + 8, static_cast<uint32_t>(h.type));
  for (std::size_t i = 0; i < kRankLimit; ++i) put32(dst + 12 + 4 * i, h.dims[i]);
  put32(dst + 76, static_cast<uint32_t>(h.format));
  put32(dst + 80, static_cast<uint32_t>(h.media_type));
  put32(dst + 84, h.nnz);
}

bool has_meta_header(const uint8_t *src, std::size_t size) {
  return size >= kMetaHeaderSize && get32(src) == kMetaMagic &&
         (get32(src + 4) & 0xFFFF0000u) == (kMetaVersion & 0xFFFF0000u);
}

MetaHeader parse_meta_header(const uint8_t *src, std::size_t size) {
  if (size < kMetaHeaderSize)
    fail(ErrorKind::kStream, "flexible tensor memory of " + std::to_string(size) +
                                 " bytes is shorter than the 128-byte header");
  if (get32(src) != kMetaMagic)
    fail(ErrorKind::kStream,
         "flexible tensor header has magic " + hex(get32(src)) + ", expected " + hex(kMetaMagic));
  if ((get32(src + 4) & 0xFFFF0000u) != (kMetaVersion & 0xFFFF0000u))
    fail(ErrorKind::kStream, "flexible tensor header has version " + hex(get32(src + 4)) +
                                 ", expected " + hex(kMetaVersion));
  MetaHeader h;
  uint32_t type = get32(src + 8);
  if (type >= kNumTypes)
    fail(ErrorKind::kStream, "flexible tensor header has type " + std::to_string(type) +
                                 ", expected 0.." + std::to_string(kNumTypes - 1));
  h.type = static_cast<TensorType>(type);
  for (std::size_t i = 0; i < kRankLimit; ++i) h.dims[i] = get32(src + 12 + 4 * i);
  // Validate rank: zeros only after the last non-zero entry.
  std::size_t r = rank_of(h.dims);
  for (std::size_t i = r; i < kRankLimit; ++i)
    if (h.dims[i] != 0)
      fail(ErrorKind::kStream, "flexible tensor header has dimension " + dims_to_string(h.dims) +
                                   " with a 0 inside the rank");
  // The byte size must be representable (crafted dimensions overflowed size_t and made
  // payload_size() tiny; found by fuzz/meta_header_fuzz.cc).
  {
    std::size_t bytes = type_size(h.type);
    for (std::size_t i = 0; i < r; ++i)
      if (__builtin_mul_overflow(bytes, std::size_t{h.dims[i]}, &bytes))
        fail(ErrorKind::kStream, "flexible tensor header has dimension " + dims_to_string(h.dims) +
                                     " whose size overflows");
  }
  uint32_t fmt = get32(src + 76);
  if (fmt >= static_cast<uint32_t>(TensorFormat::kEnd))
    fail(ErrorKind::kStream, "flexible tensor header has format " + std::to_string(fmt) +
                                 ", expected 0 (static), 1 (flexible) or 2 (sparse)");
  h.format = static_cast<TensorFormat>(fmt);
  h.media_type = static_cast<MediaType>(static_cast<int32_t>(get32(src + 80)));
  h.nnz = get32(src + 84);
  if (h.format == TensorFormat::kSparse && h.nnz > element_count(h.dims))
    fail(ErrorKind::kStream, "sparse tensor header has nnz " + std::to_string(h.nnz) +
                                 " larger than its " + std::to_string(element_count(h.dims)) +
                                 " elements");
  std::size_t sparse_bytes;
  if (h.format == TensorFormat::kSparse &&
      __builtin_mul_overflow(std::size_t{h.nnz}, type_size(h.type) + sizeof(uint32_t),
                             &sparse_bytes))
    fail(ErrorKind::kStream,
         "sparse tensor header has nnz " + std::to_string(h.nnz) + " whose size overflows");
  return h;
}

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
// The 128-byte header that starts each memory of a flexible or sparse tensor stream,
// byte-compatible with NNStreamer's GstTensorMetaInfo (v1): little-endian uint32 words
// magic, version, type, dimension[16], format, media_type, nnz; the rest is zero.
#pragma once

#include <cstddef>
#include <cstdint>

#include "core/tensor_info.h"

namespace nns {

constexpr uint32_t kMetaMagic = 0xfeedcced;
constexpr uint32_t kMetaVersion = 0xDE001000;  // major 1, minor 0
constexpr std::size_t kMetaHeaderSize = 128;

struct MetaHeader {
  TensorType type = TensorType::kEnd;
  Dims dims{};
  TensorFormat format = TensorFormat::kStatic;
  MediaType media_type = MediaType::kTensor;
  uint32_t nnz = 0;  // sparse only

  TensorInfo info() const { return TensorInfo{"", type, dims}; }
  // Bytes of payload after the header: dense size, or nnz values + nnz uint32 indices.
  std::size_t payload_size() const;
};

// The `format` word a flexible tensor's header carries, as NNStreamer 2.x writes it. Most of its
// writers fill the header from the tensor's info and leave the initial value, static (0):
// tensor_converter, tensor_transform, tensor_mux, tensor_filter's negotiated flexible output and
// every static-to-flexible conversion. tensor_crop and tensor_filter with invoke-dynamic (also
// through the async dispatch) mark it flexible (1). Only sparse (2) changes the layout, so
// readers must take 0 and 1 alike (older nnstreamer-cpp wrote 1 everywhere).
enum class FlexHeaderKind { kFromInfo, kMarkedFlexible };

// The header of one flexible tensor; every writer of flexible headers goes through here.
MetaHeader flexible_header(TensorType type, const Dims &dims, MediaType media = MediaType::kTensor,
                           FlexHeaderKind kind = FlexHeaderKind::kFromInfo);

void write_meta_header(const MetaHeader &h, uint8_t *dst);  // writes kMetaHeaderSize bytes
// True when `src` starts with a header (magic and version match).
bool has_meta_header(const uint8_t *src, std::size_t size);
// Parses and validates a header; throws nns::Error(kStream) saying what is wrong.
MetaHeader parse_meta_header(const uint8_t *src, std::size_t size);

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
// Sparse tensor memories, byte-compatible with NNStreamer's tensor_sparse_enc/dec: the
// 128-byte meta header (format=sparse, nnz) followed by nnz values of the tensor's type and
// nnz uint32 flat indices (little-endian, innermost dimension fastest). An element is stored
// when it compares unequal to zero in its own type (so -0.0 is not stored and decodes as +0.0,
// NaN is stored), as upstream does.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/meta_header.h"
#include "core/tensor_info.h"

namespace nns {

// Number of non-zero elements of a dense tensor (`data` holds info.byte_size() bytes).
std::size_t sparse_count_nonzero(const TensorInfo &info, const uint8_t *data);
// Bytes of the sparse memory for `nnz` stored elements of `type` (header included).
std::size_t sparse_encoded_size(TensorType type, std::size_t nnz);
// Writes the sparse memory of a dense tensor into `dst`, which must hold
// sparse_encoded_size(info.type, sparse_count_nonzero(info, src)) bytes. `media` goes into the
// header. Returns the bytes written.
std::size_t sparse_encode(const TensorInfo &info, const uint8_t *src, uint8_t *dst,
                          MediaType media = MediaType::kTensor);
// Convenience: encode into a new vector.
std::vector<uint8_t> sparse_encode(const TensorInfo &info, const uint8_t *src);

// Parses and validates a sparse memory (header format=sparse, size = header + nnz * (esize+4),
// every index < element count). Throws nns::Error(kStream) saying what is wrong.
MetaHeader sparse_parse(const uint8_t *src, std::size_t size);
// Writes the dense tensor of a validated sparse memory into `dst` (h.info().byte_size() bytes,
// zero-filled here first).
void sparse_decode(const MetaHeader &h, const uint8_t *src, uint8_t *dst);

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
// Shared by the built-in decoders. Their private data starts with DecoderErrorSlot so that
// tensor_decoder can show *why* a decoder refused an option or an input (the NNStreamer table
// has no error channel): the element recognises the magic and appends `message` to its bus
// error. Decoders written by others are unaffected (their data lacks the magic).
#pragma once

#include <cstdarg>
#include <cstdio>
#include <cstring>

#include "tensor_typedef.h"

namespace nns::dec {

inline constexpr char kErrorMagic[8] = {'N', 'N', 'S', 'D', 'E', 'R', 'R', '\0'};

struct DecoderErrorSlot {
  char magic[8];
  char message[512];
  DecoderErrorSlot() {
    std::memcpy(magic, kErrorMagic, sizeof magic);
    message[0] = '\0';
  }
  void set(const char *fmt, ...) __attribute__((format(printf, 2, 3))) {
    va_list ap;
    va_start(ap, fmt);
    std::vsnprintf(message, sizeof message, fmt, ap);
    va_end(ap);
  }
};

// Number of dims in use (0 marks the end) and element count of a C tensor description.
inline unsigned c_rank(const GstTensorInfo &t) {
  unsigned r = 0;
  while (r < NNS_TENSOR_RANK_LIMIT && t.dimension[r]) ++r;
  return r;
}
inline size_t c_elements(const GstTensorInfo &t) {
  unsigned r = c_rank(t);
  size_t n = r ? 1 : 0;
  for (unsigned i = 0; i < r; ++i) n *= t.dimension[i];
  return n;
}

// Bytes of one element of a C tensor type (0 for an invalid type).
inline unsigned c_element_size(tensor_type t) {
  switch (t) {
    case _NNS_INT64:
    case _NNS_UINT64:
    case _NNS_FLOAT64:
      return 8;
    case _NNS_INT32:
    case _NNS_UINT32:
    case _NNS_FLOAT32:
      return 4;
    case _NNS_INT16:
    case _NNS_UINT16:
    case _NNS_FLOAT16:
      return 2;
    case _NNS_INT8:
    case _NNS_UINT8:
      return 1;
    default:
      return 0;
  }
}

}  // namespace nns::dec

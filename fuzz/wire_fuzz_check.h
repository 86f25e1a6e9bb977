// SPDX-License-Identifier: LGPL-2.1-only
// Properties every wire decoder must keep for *any* input (fuzz/*_fuzz.cc):
//   - it returns a frame or throws nns::wire::WireError; nothing else escapes, nothing crashes;
//   - a returned frame passes validate(); zero-copy tensors lie inside the input;
//   - every tensor byte is readable (ASan checks the reads);
//   - re-encoding the frame and decoding it again gives the same frame.
// A broken property aborts (libFuzzer records the input as a crash).
#pragma once

#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "wire.h"

namespace nns::fuzz {

[[noreturn]] inline void broken(const char *what) {
  std::fprintf(stderr, "fuzz property broken: %s\n", what);
  std::abort();
}

inline void same_frames(const wire::Frame &a, const wire::Frame &b) {
  if (a.format != b.format || a.rate_n != b.rate_n || a.rate_d != b.rate_d)
    broken("re-decoded frame header differs");
  if (a.tensors.size() != b.tensors.size()) broken("re-decoded tensor count differs");
  for (std::size_t i = 0; i < a.tensors.size(); ++i) {
    const wire::Tensor &x = a.tensors[i], &y = b.tensors[i];
    if (x.name != y.name || x.type != y.type || x.dims != y.dims || x.size != y.size)
      broken("re-decoded tensor description differs");
    if (x.size && std::memcmp(x.data, y.data, x.size) != 0) broken("re-decoded data differs");
  }
}

inline void check_wire(wire::Format fmt, const uint8_t *data, std::size_t size) {
  wire::Frame f;
  try {
    f = wire::decode(fmt, data, size);
  } catch (const wire::WireError &) {
    return;  // refused with a reason: fine
  }
  try {
    wire::validate(f);
  } catch (const wire::WireError &) {
    broken("decode returned a frame that validate() refuses");
  }
  unsigned sum = 0;
  for (const wire::Tensor &t : f.tensors) {
    if (!f.owner && t.size && (t.data < data || t.data + t.size > data + size))
      broken("zero-copy tensor data outside the input");
    for (std::size_t k = 0; k < t.size; ++k) sum += t.data[k];
  }
  volatile unsigned sink = sum;
  (void)sink;
  std::vector<uint8_t> again;
  try {
    wire::encode(fmt, f, again);
    same_frames(f, wire::decode(fmt, again.data(), again.size()));
  } catch (const wire::WireError &e) {
    std::fprintf(stderr, "%s\n", e.what());
    broken("a decoded frame does not survive encode + decode");
  }
}

}  // namespace nns::fuzz

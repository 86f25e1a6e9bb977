// SPDX-License-Identifier: LGPL-2.1-only
// libFuzzer target: the 128-byte flexible/sparse tensor header (nns::parse_meta_header), as
// tensor_converter, tensor_decoder, tensor_sparse_dec and the filters run it on each memory.
// Properties: parse returns or throws nns::Error; has_meta_header agrees with the magic and
// version check; an accepted header has sizes that do not overflow (payload_size() and
// info().byte_size() equal the exact 128-bit products) and survives write + parse unchanged.
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "core/error.h"
#include "core/meta_header.h"

namespace {

[[noreturn]] void broken(const char *what) {
  std::fprintf(stderr, "fuzz property broken: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  nns::MetaHeader h;
  try {
    h = nns::parse_meta_header(data, size);
  } catch (const nns::Error &) {
    return 0;
  }
  if (!nns::has_meta_header(data, size)) broken("parsed a header has_meta_header() refuses");
  // Exact sizes: the element count must fit (the parser refuses what does not).
  std::size_t r = nns::rank_of(h.dims);
  unsigned __int128 n = r ? 1 : 0;
  for (std::size_t i = 0; i < r; ++i) {
    n *= h.dims[i];
    if (n > SIZE_MAX) broken("accepted dimensions whose element count overflows size_t");
  }
  const unsigned __int128 es = nns::type_size(h.type);
  const unsigned __int128 dense = n * es;
  if (dense > SIZE_MAX) broken("accepted dimensions whose byte size overflows size_t");
  if (h.info().byte_size() != static_cast<std::size_t>(dense)) broken("byte_size() is wrong");
  unsigned __int128 want = h.format == nns::TensorFormat::kSparse
                               ? static_cast<unsigned __int128>(h.nnz) * (es + 4)
                               : dense;
  if (want > SIZE_MAX || h.payload_size() != static_cast<std::size_t>(want))
    broken("payload_size() overflowed");
  uint8_t again[nns::kMetaHeaderSize];
  nns::write_meta_header(h, again);
  nns::MetaHeader g = nns::parse_meta_header(again, sizeof again);
  if (g.type != h.type || g.dims != h.dims || g.format != h.format || g.nnz != h.nnz ||
      g.media_type != h.media_type)
    broken("header does not survive write + parse");
  return 0;
}

// SPDX-License-Identifier: LGPL-2.1-only
// libFuzzer target: nnstreamer-edge's serialized edge data, the payload of connect-type MQTT
// messages (src/edge/edge_data.cc parse_data), fed exactly as edgesrc gets an MQTT message.
// Properties: parse_data never crashes; it refuses with a reason or accepts; nothing is
// allocated before every size was checked against the message (the allocator checks each
// request against what is left of the input); an accepted message has the memory sizes its
// header announced, and serializing it again gives back the same bytes (but the version key,
// padding and the 4-byte zero-count spelling of empty metadata, which is written as nothing).
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "edge/edge_data.h"

namespace {

[[noreturn]] void broken(const char *what) {
  std::fprintf(stderr, "fuzz property broken: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  nns::edge::Limits limits;
  std::size_t allocated = 0;
  const nns::edge::Allocator alloc = [&](std::size_t n) {
    allocated += n;
    if (allocated > size) broken("allocated more than the message holds");
    return nns::edge::heap_payload(n);
  };
  nns::edge::Message m;
  std::string why;
  if (!nns::edge::parse_data(data, size, limits, alloc, &m, &why)) {
    if (why.empty()) broken("a refusal without a reason");
    if (allocated) broken("allocated before refusing");
    return 0;
  }
  if (m.mems.size() != m.header.mem_sizes.size()) broken("memory count differs from header");
  nns::edge::OutFrame f;
  for (std::size_t i = 0; i < m.mems.size(); ++i) {
    if (m.mems[i]->size() != m.header.mem_sizes[i]) broken("memory size differs from header");
    f.mems.push_back({m.mems[i]->data(), m.mems[i]->size()});
  }
  f.meta = m.meta;
  // Empty metadata has two spellings: no bytes (what nnstreamer-edge and we write) and a 4-byte
  // zero count (what nnstreamer-edge's reader accepts too). Compare with the written one.
  std::vector<uint8_t> want(data, data + size);
  if (m.meta.empty() && m.header.meta_size != 0) {
    if (m.header.meta_size != 4) broken("empty metadata from a block other than a zero count");
    want.resize(size - 4);
    std::memset(&want[nns::edge::kDataOffMetaLen], 0, 8);
  }
  const auto again = nns::edge::serialize_data(f);
  if (again.size() != want.size()) broken("re-serialized size differs");
  // Bytes 8..15 are the version key (ours on re-serialization); the rest must match, padding
  // included only where the C struct has none (4..7 and 20..23 are padding).
  for (std::size_t i = 0; i < want.size(); ++i) {
    if ((i >= 4 && i < 16) || (i >= 20 && i < 24)) continue;
    if (i >= nns::edge::kDataOffLen + 8 * m.mems.size() && i < nns::edge::kDataOffMetaLen)
      continue;  // unused size slots
    if (again[i] != want[i]) broken("re-serialized bytes differ");
  }
  return 0;
}

// SPDX-License-Identifier: LGPL-2.1-only
// libFuzzer target: nnstreamer-edge TCP frames (src/edge/edge_io.cc read_frame), read through a
// real socket pair exactly as the elements read a peer. The input is written into one end,
// which is then shut down, and frames are read from the other until the stream ends.
// Properties: read_frame never crashes; no memory larger than the limit is ever allocated
// (the allocator checks every request); an accepted frame has exactly the memory sizes its
// header announced, and its metadata serializes back to bytes that parse to the same pairs.
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <cstdlib>

#include "edge/edge_io.h"

namespace {

[[noreturn]] void broken(const char *what) {
  std::fprintf(stderr, "fuzz property broken: %s\n", what);
  std::abort();
}

constexpr uint64_t kLimit = 1 << 20;

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  int sv[2];
  if (socketpair(AF_UNIX, SOCK_STREAM | SOCK_CLOEXEC, 0, sv) != 0) return 0;
  nns::edge::Fd rd(sv[0]), wr(sv[1]);
  std::size_t off = 0;
  while (off < size) {
    const ssize_t w = ::send(wr.get(), data + off, size - off, MSG_NOSIGNAL);
    if (w <= 0) break;
    off += static_cast<std::size_t>(w);
  }
  ::shutdown(wr.get(), SHUT_WR);
  nns::edge::Limits limits;
  limits.max_frame_bytes = kLimit;
  limits.max_meta_bytes = kLimit;
  const nns::edge::Allocator alloc = [](std::size_t n) {
    if (n > kLimit) broken("allocated more than the frame limit");
    return nns::edge::heap_payload(n);
  };
  std::atomic<bool> stop{false};
  for (int frames = 0; frames < 64; ++frames) {
    nns::edge::Message m;
    std::string why;
    const auto st = nns::edge::read_frame(rd.get(), limits, alloc, stop, 0, &m, &why);
    if (st != nns::edge::IoStatus::kOk) {
      if ((st == nns::edge::IoStatus::kError || st == nns::edge::IoStatus::kProtocol) &&
          why.empty())
        broken("an error without a reason");
      break;
    }
    if (m.mems.size() != m.header.mem_sizes.size()) broken("memory count differs from header");
    for (std::size_t i = 0; i < m.mems.size(); ++i)
      if (m.mems[i]->size() != m.header.mem_sizes[i]) broken("memory size differs from header");
    const auto bytes = m.meta.serialize();
    auto again = nns::edge::Metadata::parse(bytes.data(), bytes.size(), &why);
    if (!again || again->items() != m.meta.items()) broken("metadata does not round-trip");
  }
  return 0;
}

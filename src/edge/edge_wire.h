// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer-edge's TCP wire format (docs/wire-edge-tcp.md): a fixed 2088-byte command header
// followed by the bytes of each memory and then the serialized metadata. Everything here is
// GStreamer-free and does no I/O; decoding checks every size against explicit limits before
// anything is allocated, so a peer claiming a 4 GiB memory costs us nothing.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace nns::edge {

// Little-endian field access (nnstreamer-edge's structs as laid out on its platforms).
inline void put_u32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
inline void put_u64(uint8_t *p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
inline uint32_t get_u32(const uint8_t *p) {
  uint32_t v = 0;
  for (int i = 3; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
inline uint64_t get_u64(const uint8_t *p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}

inline constexpr uint32_t kMagic = 0xfeedfeedU;
inline constexpr std::size_t kMaxMemories = 256;  // NNS_EDGE_DATA_LIMIT
inline constexpr std::size_t kHeaderSize = 2088;  // 4+4+8+8+4(+4 pad)+256*8+8
// Offsets of the header fields (little-endian, the C struct as laid out on LP64 hosts).
inline constexpr std::size_t kOffMagic = 0, kOffCmd = 4, kOffVersion = 8, kOffClientId = 16,
                             kOffNum = 24, kOffMemSize = 32, kOffMetaSize = 2080;

// Version key: 0xefdd in the top 16 bits, then micro<<24 | major<<12 | minor.
inline constexpr uint64_t kVersionTag = 0xefdd000000000000ULL;
// We announce the nnstreamer-edge release whose protocol we implement.
inline constexpr unsigned kVersionMajor = 0, kVersionMinor = 2, kVersionMicro = 6;
uint64_t version_key(unsigned major = kVersionMajor, unsigned minor = kVersionMinor,
                     unsigned micro = kVersionMicro);
bool version_key_valid(uint64_t key);

enum class Cmd : uint32_t { kError = 0, kTransferData = 1, kHostInfo = 2, kCapability = 3 };
inline constexpr uint32_t kCmdEnd = 4;
const char *cmd_name(Cmd c);

struct Header {
  Cmd cmd = Cmd::kError;
  uint64_t version = version_key();
  int64_t client_id = 0;
  std::vector<uint64_t> mem_sizes;  // at most kMaxMemories
  uint64_t meta_size = 0;
};

// Limits a receiver applies before allocating. Defaults: 255 memories (the sender side of
// nnstreamer-edge rejects 256 on receive), 1 GiB per frame, 1 MiB of metadata.
struct Limits {
  std::size_t max_memories = kMaxMemories - 1;
  uint64_t max_frame_bytes = 1ULL << 30;
  uint64_t max_meta_bytes = 1ULL << 20;
};

std::array<uint8_t, kHeaderSize> encode_header(const Header &h);

// Decodes and validates a header; on failure returns nullopt and sets `why` to what was wrong
// (bad magic, unknown command, version key, memory count, a size over the limits).
std::optional<Header> decode_header(const uint8_t *bytes, const Limits &limits, std::string *why);

// Key/value metadata of a data frame (nns_edge_metadata): case-insensitive keys, setting an
// existing key replaces its value, new keys go first (serialization order = newest first).
class Metadata {
 public:
  void set(std::string_view key, std::string_view value);
  std::optional<std::string> get(std::string_view key) const;
  bool empty() const { return items_.empty(); }
  std::size_t size() const { return items_.size(); }
  const std::vector<std::pair<std::string, std::string>> &items() const { return items_; }

  // u32 count, then key '\0' value '\0' per pair. Empty metadata serializes to nothing.
  std::vector<uint8_t> serialize() const;
  // Strict: every pair NUL-terminated inside `len`, count matching, no empty key or value, no
  // key twice. Empty metadata is 0 bytes (what nnstreamer-edge writes) or a 4-byte zero count
  // (what its reader also accepts); both parse to no pairs.
  static std::optional<Metadata> parse(const uint8_t *data, std::size_t len, std::string *why);

 private:
  std::vector<std::pair<std::string, std::string>> items_;  // newest first
};

// "host:port" as sent in HOST_INFO (NUL-terminated on the wire).
std::string host_string(std::string_view host, uint16_t port);
bool parse_host_string(std::string_view s, std::string *host, uint16_t *port);

// Capability string helpers: "@key@value@key@value..." (query server: query_server_src_caps /
// query_server_sink_caps; edgesink: edge_sink_caps).
std::optional<std::string> caps_field(std::string_view caps, std::string_view key);

}  // namespace nns::edge

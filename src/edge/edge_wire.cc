// SPDX-License-Identifier: LGPL-2.1-only
#include "edge/edge_wire.h"

#include <strings.h>

#include <cctype>
#include <cstdio>
#include <cstring>
#include <unordered_set>

namespace nns::edge {

namespace {

bool iequal(std::string_view a, std::string_view b) {
  if (a.size() != b.size()) return false;
  for (std::size_t i = 0; i < a.size(); ++i) {
    char x = a[i], y = b[i];
    if (x >= 'A' && x <= 'Z') x = static_cast<char>(x - 'A' + 'a');
    if (y >= 'A' && y <= 'Z') y = static_cast<char>(y - 'A' + 'a');
    if (x != y) return false;
  }
  return true;
}

}  // namespace

uint64_t version_key(unsigned major, unsigned minor, unsigned micro) {
  return kVersionTag | (static_cast<uint64_t>(micro & 0xfff) << 24) |
         (static_cast<uint64_t>(major & 0xfff) << 12) | (minor & 0xfff);
}

bool version_key_valid(uint64_t key) {
  return (key & 0xffff000000000000ULL) == kVersionTag;
}

const char *cmd_name(Cmd c) {
  switch (c) {
    case Cmd::kError:
      return "ERROR";
    case Cmd::kTransferData:
      return "TRANSFER_DATA";
    case Cmd::kHostInfo:
      return "HOST_INFO";
    case Cmd::kCapability:
      return "CAPABILITY";
  }
  return "?";
}

std::array<uint8_t, kHeaderSize> encode_header(const Header &h) {
  std::array<uint8_t, kHeaderSize> out{};
  put_u32(&out[kOffMagic], kMagic);
  put_u32(&out[kOffCmd], static_cast<uint32_t>(h.cmd));
  put_u64(&out[kOffVersion], h.version);
  put_u64(&out[kOffClientId], static_cast<uint64_t>(h.client_id));
  const std::size_t n = h.mem_sizes.size() < kMaxMemories ? h.mem_sizes.size() : kMaxMemories;
  put_u32(&out[kOffNum], static_cast<uint32_t>(n));
  for (std::size_t i = 0; i < n; ++i) put_u64(&out[kOffMemSize + 8 * i], h.mem_sizes[i]);
  put_u64(&out[kOffMetaSize], h.meta_size);
  return out;
}

std::optional<Header> decode_header(const uint8_t *b, const Limits &limits, std::string *why) {
  auto bad = [&](std::string s) -> std::optional<Header> {
    if (why) *why = std::move(s);
    return std::nullopt;
  };
  char tmp[96];
  const uint32_t magic = get_u32(b + kOffMagic);
  if (magic != kMagic) {
    std::snprintf(tmp, sizeof tmp, "bad magic 0x%08x (expected 0xfeedfeed)", magic);
    return bad(tmp);
  }
  const uint32_t cmd = get_u32(b + kOffCmd);
  if (cmd >= kCmdEnd) return bad("unknown command " + std::to_string(cmd));
  Header h;
  h.cmd = static_cast<Cmd>(cmd);
  h.version = get_u64(b + kOffVersion);
  if (!version_key_valid(h.version)) {
    std::snprintf(tmp, sizeof tmp, "bad version key 0x%016llx (expected 0xefdd...)",
                  static_cast<unsigned long long>(h.version));
    return bad(tmp);
  }
  h.client_id = static_cast<int64_t>(get_u64(b + kOffClientId));
  const uint32_t num = get_u32(b + kOffNum);
  if (num > limits.max_memories)
    return bad("memory count " + std::to_string(num) + " exceeds the limit " +
               std::to_string(limits.max_memories));
  uint64_t total = 0;
  h.mem_sizes.resize(num);
  for (uint32_t i = 0; i < num; ++i) {
    const uint64_t s = get_u64(b + kOffMemSize + 8 * i);
    if (s > limits.max_frame_bytes || total + s > limits.max_frame_bytes)
      return bad("memory " + std::to_string(i) + " claims " + std::to_string(s) +
                 " bytes, over the frame limit of " + std::to_string(limits.max_frame_bytes));
    total += s;
    h.mem_sizes[i] = s;
  }
  h.meta_size = get_u64(b + kOffMetaSize);
  if (h.meta_size > limits.max_meta_bytes)
    return bad("metadata claims " + std::to_string(h.meta_size) + " bytes, over the limit of " +
               std::to_string(limits.max_meta_bytes));
  return h;
}

void Metadata::set(std::string_view key, std::string_view value) {
  for (auto &kv : items_) {
    if (iequal(kv.first, key)) {
      kv.second = std::string(value);
      return;
    }
  }
  items_.insert(items_.begin(), {std::string(key), std::string(value)});
}

std::optional<std::string> Metadata::get(std::string_view key) const {
  for (const auto &kv : items_)
    if (iequal(kv.first, key)) return kv.second;
  return std::nullopt;
}

std::vector<uint8_t> Metadata::serialize() const {
  std::vector<uint8_t> out;
  if (items_.empty()) return out;
  std::size_t total = 4;
  for (const auto &kv : items_) total += kv.first.size() + kv.second.size() + 2;
  out.resize(total);
  put_u32(out.data(), static_cast<uint32_t>(items_.size()));
  std::size_t pos = 4;
  for (const auto &kv : items_) {
    std::memcpy(&out[pos], kv.first.data(), kv.first.size());
    pos += kv.first.size();
    out[pos++] = 0;
    std::memcpy(&out[pos], kv.second.data(), kv.second.size());
    pos += kv.second.size();
    out[pos++] = 0;
  }
  return out;
}

std::optional<Metadata> Metadata::parse(const uint8_t *data, std::size_t len, std::string *why) {
  auto bad = [&](std::string s) -> std::optional<Metadata> {
    if (why) *why = "metadata: " + std::move(s);
    return std::nullopt;
  };
  Metadata m;
  if (len == 0) return m;
  if (len < 4) return bad(std::to_string(len) + " bytes, shorter than its 4-byte count");
  const uint32_t count = get_u32(data);
  std::size_t pos = 4;
  std::vector<std::pair<std::string, std::string>> pairs;
  std::unordered_set<std::string> seen;
  auto take = [&](std::string *out) {
    const void *nul = std::memchr(data + pos, 0, len - pos);
    if (!nul) return false;
    const std::size_t n = static_cast<const uint8_t *>(nul) - (data + pos);
    out->assign(reinterpret_cast<const char *>(data + pos), n);
    pos += n + 1;
    return true;
  };
  while (pos < len) {
    std::string k, v;
    if (!take(&k) || !take(&v))
      return bad("pair " + std::to_string(pairs.size()) + " is not NUL-terminated");
    if (k.empty() || v.empty()) return bad("pair " + std::to_string(pairs.size()) + " is empty");
    // nnstreamer-edge's reader replaces a repeated key and then, one pair short of the count,
    // reads on past the block; its writer never repeats a key. Refused.
    // A set, not a scan: 1 MiB of metadata holds up to 2^18 pairs.
    std::string folded = k;
    for (char &c : folded) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (!seen.insert(std::move(folded)).second)
      return bad("pair " + std::to_string(pairs.size()) + " repeats the key '" + k +
                 "' (keys are case-insensitive)");
    pairs.emplace_back(std::move(k), std::move(v));
  }
  if (pairs.size() != count)
    return bad("count says " + std::to_string(count) + " pairs, found " +
               std::to_string(pairs.size()));
  // Wire order is newest first, as items_ (keys are distinct: no set() needed).
  m.items_ = std::move(pairs);
  return m;
}

std::string host_string(std::string_view host, uint16_t port) {
  return std::string(host) + ":" + std::to_string(port);
}

bool parse_host_string(std::string_view s, std::string *host, uint16_t *port) {
  const auto colon = s.rfind(':');
  if (colon == std::string_view::npos || colon == 0 || colon + 1 >= s.size()) return false;
  unsigned long v = 0;
  for (std::size_t i = colon + 1; i < s.size(); ++i) {
    if (s[i] < '0' || s[i] > '9') return false;
    v = v * 10 + static_cast<unsigned long>(s[i] - '0');
    if (v > 65535) return false;
  }
  if (v == 0) return false;
  *host = std::string(s.substr(0, colon));
  *port = static_cast<uint16_t>(v);
  return true;
}

std::optional<std::string> caps_field(std::string_view caps, std::string_view key) {
  // Split on '@': fields 1, 3, ... are keys, the next field their value.
  std::vector<std::string_view> parts;
  std::size_t start = 0;
  for (;;) {
    const auto at = caps.find('@', start);
    parts.push_back(caps.substr(start, at == std::string_view::npos ? caps.npos : at - start));
    if (at == std::string_view::npos) break;
    start = at + 1;
  }
  for (std::size_t i = 1; i + 1 < parts.size(); i += 2)
    if (parts[i] == key) return std::string(parts[i + 1]);
  return std::nullopt;
}

}  // namespace nns::edge

// SPDX-License-Identifier: LGPL-2.1-only
#include "edge/edge_data.h"

#include <cstdio>
#include <cstring>

#include "core/error.h"

namespace nns::edge {

std::vector<uint8_t> serialize_data(const OutFrame &frame) {
  if (frame.mems.size() > kMaxMemories)
    fail(ErrorKind::kStream, "a buffer of " + std::to_string(frame.mems.size()) +
                                 " memories cannot be sent (nnstreamer-edge carries at most " +
                                 std::to_string(kMaxMemories) + ")");
  const std::vector<uint8_t> meta = frame.meta.serialize();
  std::size_t total = kDataHeaderSize + meta.size();
  for (const auto &m : frame.mems) total += m.size;
  std::vector<uint8_t> out(total, 0);
  put_u32(&out[kDataOffKey], kDataKey);
  put_u64(&out[kDataOffVersion], version_key());
  put_u32(&out[kDataOffNum], static_cast<uint32_t>(frame.mems.size()));
  std::size_t pos = kDataHeaderSize;
  for (std::size_t i = 0; i < frame.mems.size(); ++i) {
    put_u64(&out[kDataOffLen + 8 * i], frame.mems[i].size);
    if (frame.mems[i].size) std::memcpy(&out[pos], frame.mems[i].data, frame.mems[i].size);
    pos += frame.mems[i].size;
  }
  put_u64(&out[kDataOffMetaLen], meta.size());
  if (!meta.empty()) std::memcpy(&out[pos], meta.data(), meta.size());
  return out;
}

bool parse_data(const uint8_t *data, std::size_t len, const Limits &limits, const Allocator &alloc,
                Message *out, std::string *why) {
  auto bad = [&](std::string s) {
    if (why) *why = std::move(s);
    return false;
  };
  if (len < kDataHeaderSize)
    return bad(std::to_string(len) + " bytes, shorter than the " + std::to_string(kDataHeaderSize) +
               "-byte edge data header");
  char tmp[112];
  const uint32_t key = get_u32(data + kDataOffKey);
  if (key != kDataKey) {
    std::snprintf(tmp, sizeof tmp, "bad edge data key 0x%08x (expected 0xeddaedda)", key);
    return bad(tmp);
  }
  const uint64_t version = get_u64(data + kDataOffVersion);
  if (!version_key_valid(version)) {
    std::snprintf(tmp, sizeof tmp, "bad version key 0x%016llx (expected 0xefdd...)",
                  static_cast<unsigned long long>(version));
    return bad(tmp);
  }
  const uint32_t num = get_u32(data + kDataOffNum);
  if (num > kMaxMemories || num > limits.max_memories + 1)
    return bad("memory count " + std::to_string(num) + " exceeds the limit " +
               std::to_string(kMaxMemories));
  // Sum with overflow checks: every size must fit in what is left of the message.
  const uint64_t body = len - kDataHeaderSize;
  uint64_t total = 0;
  std::vector<uint64_t> sizes(num);
  for (uint32_t i = 0; i < num; ++i) {
    const uint64_t s = get_u64(data + kDataOffLen + 8 * i);
    if (s > limits.max_frame_bytes || total + s > limits.max_frame_bytes)
      return bad("memory " + std::to_string(i) + " claims " + std::to_string(s) +
                 " bytes, over the frame limit of " + std::to_string(limits.max_frame_bytes));
    if (s > body - total)
      return bad("memory " + std::to_string(i) + " claims " + std::to_string(s) +
                 " bytes but only " + std::to_string(body - total) + " are left in the " +
                 std::to_string(len) + "-byte message (truncated)");
    total += s;
    sizes[i] = s;
  }
  const uint64_t meta_len = get_u64(data + kDataOffMetaLen);
  if (meta_len > limits.max_meta_bytes)
    return bad("metadata claims " + std::to_string(meta_len) + " bytes, over the limit of " +
               std::to_string(limits.max_meta_bytes));
  if (meta_len != body - total)
    return bad("header sizes add up to " + std::to_string(kDataHeaderSize + total + meta_len) +
               " bytes but the message has " + std::to_string(len));
  const uint8_t *meta_at = data + kDataHeaderSize + total;
  std::string mwhy;
  auto meta = Metadata::parse(meta_at, meta_len, &mwhy);
  if (!meta) return bad(mwhy);
  Message m;
  m.header.cmd = Cmd::kTransferData;
  m.header.version = version;
  m.header.mem_sizes = sizes;
  m.header.meta_size = meta_len;
  m.meta = std::move(*meta);
  const uint8_t *p = data + kDataHeaderSize;
  for (uint32_t i = 0; i < num; ++i) {
    PayloadPtr mem = alloc ? alloc(sizes[i]) : heap_payload(sizes[i]);
    if (!mem) return bad("cannot allocate memory " + std::to_string(i));
    if (sizes[i]) std::memcpy(mem->data(), p, sizes[i]);
    p += sizes[i];
    m.mems.push_back(std::move(mem));
  }
  *out = std::move(m);
  return true;
}

}  // namespace nns::edge

// SPDX-License-Identifier: LGPL-2.1-only
#include "mqtt/mqtt_message.h"

#include <cstring>

#include "core/error.h"

namespace nns::mqtt {

namespace {

void put_u64(uint8_t *p, uint64_t v) {
  for (int i = 0; i < 8; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint64_t get_u64(const uint8_t *p) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | p[i];
  return v;
}
void put_u32(uint8_t *p, uint32_t v) {
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(v >> (8 * i));
}
uint32_t get_u32(const uint8_t *p) {
  return static_cast<uint32_t>(p[0]) | static_cast<uint32_t>(p[1]) << 8 |
         static_cast<uint32_t>(p[2]) << 16 | static_cast<uint32_t>(p[3]) << 24;
}

[[noreturn]] void bad(const std::string &what) {
  fail(ErrorKind::kStream, what);
}

}  // namespace

uint64_t MessageHeader::payload_size() const {
  uint64_t total = 0;
  for (uint64_t s : mem_sizes) total += s;
  return total;
}

void write_header(const MessageHeader &h, uint8_t *out) {
  if (h.mem_sizes.size() > kMaxMems)
    fail(ErrorKind::kStream, "a buffer of " + std::to_string(h.mem_sizes.size()) +
                                 " memories does not fit the MQTT header (at most 16)");
  if (h.caps.size() >= kMaxCapsLen)
    fail(ErrorKind::kNegotiation, "the caps string is " + std::to_string(h.caps.size()) +
                                      " bytes; the MQTT header holds at most 511: " + h.caps);
  std::memset(out, 0, kHeaderSize);
  put_u32(out + kOffNumMems, static_cast<uint32_t>(h.mem_sizes.size()));
  for (std::size_t i = 0; i < h.mem_sizes.size(); ++i)
    put_u64(out + kOffSizes + 8 * i, h.mem_sizes[i]);
  put_u64(out + kOffBaseEpoch, static_cast<uint64_t>(h.base_time_epoch));
  put_u64(out + kOffSentEpoch, static_cast<uint64_t>(h.sent_time_epoch));
  put_u64(out + kOffDuration, h.duration);
  put_u64(out + kOffDts, h.dts);
  put_u64(out + kOffPts, h.pts);
  std::memcpy(out + kOffCaps, h.caps.data(), h.caps.size());
}

MessageHeader parse_message(const uint8_t *data, std::size_t size) {
  if (size < kHeaderSize)
    bad("message of " + std::to_string(size) + " bytes is shorter than the 1024-byte header");
  MessageHeader h;
  const uint32_t n = get_u32(data + kOffNumMems);
  if (n > kMaxMems) bad("header claims " + std::to_string(n) + " memories (at most 16)");
  const uint64_t body = size - kHeaderSize;
  uint64_t total = 0;
  h.mem_sizes.reserve(n);
  for (uint32_t i = 0; i < n; ++i) {
    const uint64_t s = get_u64(data + kOffSizes + 8 * i);
    if (s > body - total)
      bad("memory " + std::to_string(i) + " claims " + std::to_string(s) + " bytes but only " +
          std::to_string(body - total) + " bytes follow the header");
    total += s;
    h.mem_sizes.push_back(s);
  }
  if (total != body)
    bad("the memory sizes add up to " + std::to_string(total) + " bytes but " +
        std::to_string(body) + " bytes follow the header");
  h.base_time_epoch = static_cast<int64_t>(get_u64(data + kOffBaseEpoch));
  h.sent_time_epoch = static_cast<int64_t>(get_u64(data + kOffSentEpoch));
  h.duration = get_u64(data + kOffDuration);
  h.dts = get_u64(data + kOffDts);
  h.pts = get_u64(data + kOffPts);
  const char *caps = reinterpret_cast<const char *>(data + kOffCaps);
  const void *nul = std::memchr(caps, '\0', kMaxCapsLen);
  if (!nul) bad("the caps string is not terminated within its 512 bytes");
  h.caps.assign(caps, static_cast<const char *>(nul));
  return h;
}

Rebased rebase(const MessageHeader &h, int64_t receiver_base_epoch) {
  Rebased r;
  // Wrapping arithmetic as NNStreamer's mqttsrc does it (its quirks included: a message
  // without pts whose sender started earlier gets no timestamps).
  const int64_t diff = static_cast<int64_t>(static_cast<uint64_t>(h.base_time_epoch) -
                                            static_cast<uint64_t>(receiver_base_epoch));
  if (h.sent_time_epoch < receiver_base_epoch) {
    r.drop = Rebased::Drop::kSentBeforeBase;
    return r;
  }
  const int64_t landed = static_cast<int64_t>(h.pts + static_cast<uint64_t>(diff));
  if (landed < 0) {
    r.drop = Rebased::Drop::kBeforeRunningZero;
    r.landed = landed;
    return r;
  }
  if (h.pts != kNoTime) r.pts = h.pts + static_cast<uint64_t>(diff);
  if (h.dts != kNoTime) {
    const uint64_t d = h.dts + static_cast<uint64_t>(diff);
    if (static_cast<int64_t>(d) >= 0) r.dts = d;
  }
  r.duration = h.duration;
  if (r.pts != kNoTime || r.dts != kNoTime || r.duration != kNoTime) r.drop = Rebased::Drop::kNone;
  return r;
}

int64_t base_time_epoch(int64_t now_epoch_ns, uint64_t clock_now, uint64_t base_time) {
  return now_epoch_ns - static_cast<int64_t>(clock_now - base_time);
}

}  // namespace nns::mqtt

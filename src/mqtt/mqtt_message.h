// SPDX-License-Identifier: LGPL-2.1-only
// The payload NNStreamer's mqttsink publishes and mqttsrc reads (GStreamer-free).
//
// Every MQTT message is a fixed 1024-byte header followed by the buffer's memories, back to
// back. The header is NNStreamer's GstMQTTMessageHdr as laid out by a 64-bit little-endian
// build (the struct is sent raw upstream):
//   offset   0  u32  number of memories (0..16), then 4 bytes of padding
//   offset   8  u64  size of memory i, 16 slots
//   offset 136  i64  base time of the sender's pipeline, as Unix epoch ns
//   offset 144  i64  time the message was sent, as Unix epoch ns
//   offset 152  u64  duration   (GST_CLOCK_TIME_NONE = all ones)
//   offset 160  u64  dts
//   offset 168  u64  pts
//   offset 176  char caps string, NUL-terminated, 512 bytes
//   offset 688  zero up to 1024
// See docs/wire-mqtt.md.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace nns::mqtt {

inline constexpr std::size_t kHeaderSize = 1024;
inline constexpr std::size_t kMaxCapsLen = 512;  // including the terminating NUL
inline constexpr std::size_t kMaxMems = 16;
inline constexpr uint64_t kNoTime = UINT64_MAX;  // GST_CLOCK_TIME_NONE

inline constexpr std::size_t kOffNumMems = 0;
inline constexpr std::size_t kOffSizes = 8;
inline constexpr std::size_t kOffBaseEpoch = 136;
inline constexpr std::size_t kOffSentEpoch = 144;
inline constexpr std::size_t kOffDuration = 152;
inline constexpr std::size_t kOffDts = 160;
inline constexpr std::size_t kOffPts = 168;
inline constexpr std::size_t kOffCaps = 176;

struct MessageHeader {
  std::vector<uint64_t> mem_sizes;  // at most kMaxMems
  int64_t base_time_epoch = 0;      // ns since 1970
  int64_t sent_time_epoch = 0;      // ns since 1970
  uint64_t duration = kNoTime;
  uint64_t dts = kNoTime;
  uint64_t pts = kNoTime;
  std::string caps;  // shorter than kMaxCapsLen

  uint64_t payload_size() const;
};

// Writes `h` into out[0..kHeaderSize). Throws nns::Error when there are more than kMaxMems
// memories or the caps string does not fit.
void write_header(const MessageHeader &h, uint8_t *out);

// Reads and checks a whole message of `size` bytes: the header is there, the memory count is
// at most kMaxMems, the memory sizes add up to exactly the bytes after the header (no
// overflow), and the caps string ends within its 512 bytes. Throws nns::Error(kStream) saying
// what is wrong otherwise. Never allocates more than the caps string.
MessageHeader parse_message(const uint8_t *data, std::size_t size);

// The header's timestamps moved onto the receiving pipeline's running time, as NNStreamer's
// mqttsrc does: add (sender base epoch - receiver base epoch). A message sent before the
// receiver's base time, or whose pts would become negative, gets no timestamps at all
// (valid() false; mqttsrc drops such buffers), and `drop` says which check refused it.
struct Rebased {
  enum class Drop {
    kNone,               // valid
    kSentBeforeBase,     // sent_time_epoch < the receiver's base epoch
    kBeforeRunningZero,  // pts + (sender base - receiver base) < 0; a missing pts counts as -1
    kNoTimestamps,       // nothing left: no pts, dts or duration
  };
  Drop drop = Drop::kNoTimestamps;
  int64_t landed = 0;  // kBeforeRunningZero: where the pts landed (negative, ns)
  uint64_t pts = kNoTime;
  uint64_t dts = kNoTime;
  uint64_t duration = kNoTime;
  bool valid() const { return drop == Drop::kNone; }
};
Rebased rebase(const MessageHeader &h, int64_t receiver_base_epoch);

// The sender's base time as an epoch: now_epoch - (clock_now - base_time), all in ns.
int64_t base_time_epoch(int64_t now_epoch_ns, uint64_t clock_now, uint64_t base_time);

}  // namespace nns::mqtt

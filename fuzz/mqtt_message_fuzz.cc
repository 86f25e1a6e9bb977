// SPDX-License-Identifier: LGPL-2.1-only
// libFuzzer target: NNStreamer's MQTT message (nns::mqtt::parse_message), what mqttsrc runs on
// every message of its topic. Properties: parse returns or throws nns::Error; an accepted
// message has at most 16 memories whose sizes add up exactly to the bytes after the 1024-byte
// header, a caps string shorter than 512 bytes, and survives write + parse unchanged.
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "core/error.h"
#include "mqtt/mqtt_message.h"

namespace {

[[noreturn]] void broken(const char *what) {
  std::fprintf(stderr, "fuzz property broken: %s\n", what);
  std::abort();
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  nns::mqtt::MessageHeader h;
  try {
    h = nns::mqtt::parse_message(data, size);
  } catch (const nns::Error &) {
    return 0;
  }
  if (size < nns::mqtt::kHeaderSize) broken("accepted a message shorter than the header");
  if (h.mem_sizes.size() > nns::mqtt::kMaxMems) broken("accepted more than 16 memories");
  unsigned __int128 total = 0;
  for (uint64_t s : h.mem_sizes) total += s;
  if (total != size - nns::mqtt::kHeaderSize) broken("memory sizes do not match the payload");
  if (h.caps.size() >= nns::mqtt::kMaxCapsLen) broken("caps string longer than its field");
  if (h.caps.find('\0') != std::string::npos) broken("caps string holds a NUL");
  std::vector<uint8_t> again(size);
  nns::mqtt::write_header(h, again.data());
  std::memcpy(again.data() + nns::mqtt::kHeaderSize, data + nns::mqtt::kHeaderSize,
              size - nns::mqtt::kHeaderSize);
  const nns::mqtt::MessageHeader g = nns::mqtt::parse_message(again.data(), again.size());
  if (g.mem_sizes != h.mem_sizes || g.caps != h.caps || g.pts != h.pts || g.dts != h.dts ||
      g.duration != h.duration || g.base_time_epoch != h.base_time_epoch ||
      g.sent_time_epoch != h.sent_time_epoch)
    broken("write + parse changed the header");
  nns::mqtt::rebase(h, 0);
  nns::mqtt::rebase(h, h.base_time_epoch);
  return 0;
}

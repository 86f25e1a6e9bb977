// SPDX-License-Identifier: LGPL-2.1-only
// One channel of a Linux IIO buffered device: its scan_elements type string
// ("le:s12/16>>4"), where its sample sits in a scan, and the conversion of a stored sample to
// float32 ((value + offset) * scale). GStreamer-free; tensor_src_iio uses it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace nns::iio {

// The kernel's "[be|le]:[s|u]<bits>/<storagebits>>><shift>" (scan_elements/<channel>_type).
struct ChannelType {
  bool big_endian = false;
  bool is_signed = false;
  unsigned used_bits = 0;     // 1..64
  unsigned storage_bits = 0;  // used_bits..64
  unsigned shift = 0;         // < storage_bits
  unsigned storage_bytes() const { return (storage_bits + 7) / 8; }
};

// Throws nns::Error(kSettings) quoting `text` and naming `file` when it does not parse.
ChannelType parse_channel_type(std::string_view text, const std::string &file);

struct Channel {
  std::string name;  // "in_accel_x" (the scan_elements file prefix)
  unsigned index = 0;
  ChannelType type;
  float scale = 1.0f;
  float offset = 0.0f;
  bool enabled = false;      // enabled while streaming
  bool was_enabled = false;  // as found, restored at stop
  bool timestamp = false;    // the "timestamp" channel: laid out, never output
  std::size_t location = 0;  // byte offset in one scan
};

// Converts the stored sample at `scan + ch.location` (exactly storage_bytes bytes are read) to
// float: endianness, storage masking, shift, used-bits mask, sign extension, then
// ((float)value + offset) * scale, in float arithmetic as NNStreamer's tensor_src_iio does.
float decode_sample(const Channel &ch, const uint8_t *scan);

// Lays out enabled channels (sorted by index) the way the kernel fills its buffer: each sample
// aligned to its own storage size, the scan padded to the largest one. Returns the scan size in
// bytes (0 when nothing is enabled) and sets each enabled channel's location.
std::size_t layout_scan(std::vector<Channel> &channels);

}  // namespace nns::iio

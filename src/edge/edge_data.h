// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer-edge's serialized edge data (nns_edge_data_serialize): the payload of every MQTT
// message of connect-type MQTT (docs/wire-edge-mqtt.md). A fixed 2080-byte header, then the
// bytes of each memory, then the serialized metadata (the same key/value format as the TCP
// frames). GStreamer-free, no I/O; parsing checks every size against the message length and the
// limits before anything is allocated, so a claimed 4 GiB memory costs nothing.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "edge/edge_io.h"

namespace nns::edge {

inline constexpr uint32_t kDataKey = 0xeddaeddaU;
inline constexpr std::size_t kDataHeaderSize = 2080;  // 4(+4 pad)+8+4(+4 pad)+256*8+8
// Offsets of the header fields (little-endian, the C struct as laid out on LP64 hosts).
inline constexpr std::size_t kDataOffKey = 0, kDataOffVersion = 8, kDataOffNum = 16,
                             kDataOffLen = 24, kDataOffMetaLen = 2072;

// Header + memories + metadata in one buffer (MQTT publishes one contiguous payload).
// More than 256 memories cannot be expressed: throws nns::Error(kStream).
std::vector<uint8_t> serialize_data(const OutFrame &frame);

// Parses one serialized edge data. On failure returns false and sets `why` (bad key, version
// key, memory count, sizes that do not add up to `len`, a size over the limits, bad metadata).
// The memories are allocated through `alloc` only after every size was checked. Up to
// kMaxMemories (256) memories are accepted, as nnstreamer-edge's receiver does.
bool parse_data(const uint8_t *data, std::size_t len, const Limits &limits, const Allocator &alloc,
                Message *out, std::string *why);

}  // namespace nns::edge

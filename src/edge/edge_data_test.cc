// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer-edge's serialized edge data (MQTT payload): golden layout, round trip, and the
// reasons a malformed message is refused before anything is allocated.
#include "edge/edge_data.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace nns::edge;

namespace {

uint64_t u64_at(const std::vector<uint8_t> &b, std::size_t off) {
  uint64_t v = 0;
  for (int i = 7; i >= 0; --i) v = (v << 8) | b[off + i];
  return v;
}

std::vector<uint8_t> sample() {
  static const uint8_t a[3] = {1, 2, 3}, b[2] = {0xaa, 0xbb};
  OutFrame f;
  f.mems = {{a, 3}, {b, 2}};
  f.meta.set("caps", "x/y");
  return serialize_data(f);
}

std::string refuse(std::vector<uint8_t> bytes, Limits limits = {}) {
  Message m;
  std::string why;
  std::size_t allocated = 0;
  Allocator alloc = [&](std::size_t n) {
    allocated += n;
    return heap_payload(n);
  };
  EXPECT_FALSE(parse_data(bytes.data(), bytes.size(), limits, alloc, &m, &why));
  EXPECT_EQ(allocated, 0u);
  return why;
}

}  // namespace

TEST(EdgeData, GoldenLayout) {
  const auto b = sample();
  // header 2080 + 3 + 2 + metadata (u32 count + "caps\0x/y\0" = 4 + 9).
  ASSERT_EQ(b.size(), 2080u + 5 + 13);
  EXPECT_EQ(std::vector<uint8_t>(b.begin(), b.begin() + 4),
            (std::vector<uint8_t>{0xda, 0xed, 0xda, 0xed}));
  EXPECT_EQ(u64_at(b, 8), 0xefdd000006000002ULL);  // 0.2.6
  EXPECT_EQ(b[16], 2);
  EXPECT_EQ(u64_at(b, 24), 3u);
  EXPECT_EQ(u64_at(b, 32), 2u);
  EXPECT_EQ(u64_at(b, 40), 0u);
  EXPECT_EQ(u64_at(b, 2072), 13u);
  EXPECT_EQ(std::vector<uint8_t>(b.begin() + 2080, b.begin() + 2085),
            (std::vector<uint8_t>{1, 2, 3, 0xaa, 0xbb}));
  EXPECT_EQ(std::memcmp(&b[2085], "\x01\0\0\0caps\0x/y\0", 13), 0);
}

TEST(EdgeData, RoundTrip) {
  const auto b = sample();
  Message m;
  std::string why;
  ASSERT_TRUE(parse_data(b.data(), b.size(), Limits{}, {}, &m, &why)) << why;
  ASSERT_EQ(m.mems.size(), 2u);
  EXPECT_EQ(m.mems[0]->size(), 3u);
  EXPECT_EQ(m.mems[1]->data()[1], 0xbb);
  EXPECT_EQ(m.meta.get("caps"), "x/y");
}

TEST(EdgeData, RefusesMalformedBeforeAllocating) {
  EXPECT_EQ(refuse({'h', 'i'}), "2 bytes, shorter than the 2080-byte edge data header");
  auto b = sample();
  b[0] = 0;
  EXPECT_NE(refuse(b).find("bad edge data key 0xeddaed00"), std::string::npos);
  b = sample();
  b[15] = 0;
  EXPECT_NE(refuse(b).find("bad version key"), std::string::npos);
  b = sample();
  b[16] = 0x01;
  b[17] = 0x01;  // 257 memories
  EXPECT_EQ(refuse(b), "memory count 257 exceeds the limit 256");
  b = sample();
  b[24 + 4] = 1;  // memory 0 claims 4 GiB + 3
  EXPECT_NE(refuse(b).find("memory 0 claims 4294967299 bytes, over the frame limit"),
            std::string::npos);
  Limits big;
  big.max_frame_bytes = 1ULL << 40;
  EXPECT_NE(refuse(b, big).find("memory 0 claims 4294967299 bytes but only 18 are left in the "
                                "2098-byte message (truncated)"),
            std::string::npos);
  b = sample();
  b.pop_back();
  EXPECT_EQ(refuse(b), "header sizes add up to 2098 bytes but the message has 2097");
  b = sample();
  b[2072] = 12;
  b.pop_back();
  EXPECT_NE(refuse(b).find("metadata: pair 0 is not NUL-terminated"), std::string::npos);
}

// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer-edge's serialized edge data (MQTT payload): golden layout, round trip, and the
// reasons a malformed message is refused before anything is allocated.
#include "edge/edge_data.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>

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

// parse_data with an allocator that adds up what it is asked for into *allocated.
bool parse_counted(const std::vector<uint8_t> &bytes, const Limits &limits, Message *m,
                   std::string *why, std::size_t *allocated) {
  *allocated = 0;
  Allocator alloc = [allocated](std::size_t n) {
    *allocated += n;
    return heap_payload(n);
  };
  return parse_data(bytes.data(), bytes.size(), limits, alloc, m, why);
}

std::string refuse(std::vector<uint8_t> bytes, Limits limits = {}) {
  Message m;
  std::string why;
  std::size_t allocated = 0;
  EXPECT_FALSE(parse_counted(bytes, limits, &m, &why, &allocated));
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

namespace {

// nnstreamer-edge's data header for `num` memories of `sizes`, then `meta` as metadata block.
std::vector<uint8_t> with_meta(uint32_t num, std::vector<uint8_t> meta) {
  OutFrame f;
  static const uint8_t none = 0;
  for (uint32_t i = 0; i < num; ++i) f.mems.push_back({&none, 0});
  auto b = serialize_data(f);
  for (int i = 0; i < 8; ++i) b[kDataOffMetaLen + i] = static_cast<uint8_t>(meta.size() >> 8 * i);
  b.insert(b.end(), meta.begin(), meta.end());
  return b;
}

}  // namespace

// Fuzz finding (edge_data, issue 22): metadata given as a 4-byte block holding a zero count.
// nnstreamer-edge's writer sends empty metadata as 0 bytes, but its reader
// (nns_edge_metadata_deserialize) takes the zero-count block as empty metadata too: the message
// is well-formed and carries nothing more, so it is accepted, and written back as 0 bytes.
TEST(EdgeData, FuzzRegressionZeroCountMetadataIsEmpty) {
  const auto b = with_meta(7, {0, 0, 0, 0});
  ASSERT_EQ(b.size(), 2084u);
  Message m;
  std::string why;
  ASSERT_TRUE(parse_data(b.data(), b.size(), Limits{}, {}, &m, &why)) << why;
  EXPECT_EQ(m.mems.size(), 7u);
  EXPECT_TRUE(m.meta.empty());
  EXPECT_EQ(m.header.meta_size, 4u);
  OutFrame f;
  for (const auto &mem : m.mems) f.mems.push_back({mem->data(), mem->size()});
  const auto again = serialize_data(f);
  ASSERT_EQ(again.size(), 2080u);
  EXPECT_EQ(u64_at(again, kDataOffMetaLen), 0u);
  // A count without its pairs, or pairs beyond the count, stays refused.
  EXPECT_EQ(refuse(with_meta(0, {1, 0, 0, 0})), "metadata: count says 1 pairs, found 0");
  EXPECT_EQ(refuse(with_meta(0, {0, 0, 0, 0, 'k', 0, 'v', 0})),
            "metadata: count says 0 pairs, found 1");
}

// The next step of the same finding: a key given twice. nnstreamer-edge's reader replaces the
// first value and, one pair short of the count, reads on past the block; refused here.
TEST(EdgeData, RepeatedMetadataKeyRefused) {
  EXPECT_EQ(refuse(with_meta(0, {2, 0, 0, 0, 'a', 0, '1', 0, 'A', 0, '2', 0})),
            "metadata: pair 1 repeats the key 'A' (keys are case-insensitive)");
}

// Every input in fuzz/regressions/edge_data/ is refused with a reason before anything is
// allocated, or accepted and written back to the same bytes (but the version key and the
// 4-byte spelling of empty metadata).
TEST(EdgeData, FuzzRegressionsReplay) {
  namespace fs = std::filesystem;
  const fs::path dir = fs::path(NNS_SOURCE_DIR) / "fuzz" / "regressions" / "edge_data";
  int seen = 0;
  for (const auto &e : fs::directory_iterator(dir)) {
    SCOPED_TRACE(e.path().string());
    std::ifstream in(e.path(), std::ios::binary);
    const std::vector<uint8_t> raw((std::istreambuf_iterator<char>(in)), {});
    Message m;
    std::string why;
    std::size_t allocated = 0;
    ++seen;
    if (!parse_counted(raw, Limits{}, &m, &why, &allocated)) {
      EXPECT_FALSE(why.empty());
      EXPECT_EQ(allocated, 0u);
      continue;
    }
    OutFrame f;
    for (const auto &mem : m.mems) f.mems.push_back({mem->data(), mem->size()});
    f.meta = m.meta;
    const auto again = serialize_data(f);
    const std::size_t dropped = m.meta.empty() ? m.header.meta_size : 0;
    EXPECT_EQ(again.size() + dropped, raw.size());
    EXPECT_TRUE(
        std::equal(again.begin() + kDataHeaderSize, again.end(), raw.begin() + kDataHeaderSize));
  }
  EXPECT_GE(seen, 2);
}

// SPDX-License-Identifier: LGPL-2.1-only
#include "edge/edge_wire.h"

#include <gtest/gtest.h>

#include <cstring>

using namespace nns::edge;

TEST(EdgeWire, HeaderGoldenBytes) {
  Header h;
  h.cmd = Cmd::kTransferData;
  h.version = version_key(0, 2, 6);
  h.client_id = 0x0102030405060708LL;
  h.mem_sizes = {150528, 4};
  h.meta_size = 22;
  const auto b = encode_header(h);
  ASSERT_EQ(b.size(), 2088u);
  const uint8_t head[] = {0xed, 0xfe, 0xed, 0xfe, 0x01, 0x00, 0x00, 0x00,   // magic, cmd
                          0x02, 0x00, 0x00, 0x06, 0x00, 0x00, 0xdd, 0xef,   // version key
                          0x08, 0x07, 0x06, 0x05, 0x04, 0x03, 0x02, 0x01,   // client id
                          0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00,   // num + padding
                          0x00, 0x4c, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00,   // mem_size[0]
                          0x04, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};  // mem_size[1]
  EXPECT_EQ(0, std::memcmp(b.data(), head, sizeof head));
  for (std::size_t i = sizeof head; i < 2080; ++i) ASSERT_EQ(b[i], 0) << i;
  EXPECT_EQ(b[2080], 22);
  EXPECT_EQ(version_key(0, 2, 6), 0xefdd000006000002ULL);

  std::string why;
  auto d = decode_header(b.data(), Limits{}, &why);
  ASSERT_TRUE(d) << why;
  EXPECT_EQ(d->cmd, Cmd::kTransferData);
  EXPECT_EQ(d->client_id, h.client_id);
  EXPECT_EQ(d->mem_sizes, h.mem_sizes);
  EXPECT_EQ(d->meta_size, 22u);
}

TEST(EdgeWire, DecodeRejectsWithReason) {
  Header h;
  h.cmd = Cmd::kTransferData;
  auto b = encode_header(h);
  std::string why;
  auto bad = b;
  bad[0] = 0;
  EXPECT_FALSE(decode_header(bad.data(), Limits{}, &why));
  EXPECT_EQ(why, "bad magic 0xfeedfe00 (expected 0xfeedfeed)");
  bad = b;
  bad[4] = 9;
  EXPECT_FALSE(decode_header(bad.data(), Limits{}, &why));
  EXPECT_EQ(why, "unknown command 9");
  bad = b;
  bad[15] = 0;
  EXPECT_FALSE(decode_header(bad.data(), Limits{}, &why));
  EXPECT_NE(why.find("bad version key"), std::string::npos);
  // 4 GiB claimed: rejected from the header alone.
  h.mem_sizes = {4294967296ULL};
  b = encode_header(h);
  EXPECT_FALSE(decode_header(b.data(), Limits{}, &why));
  EXPECT_EQ(why, "memory 0 claims 4294967296 bytes, over the frame limit of 1073741824");
  // Sum over the limit.
  h.mem_sizes = {600u << 20, 600u << 20};
  b = encode_header(h);
  EXPECT_FALSE(decode_header(b.data(), Limits{}, &why));
  EXPECT_NE(why.find("memory 1 claims"), std::string::npos);
  h.mem_sizes.clear();
  b = encode_header(h);
  b[24] = 0;
  b[25] = 1;  // 256 memories
  EXPECT_FALSE(decode_header(b.data(), Limits{}, &why));
  EXPECT_EQ(why, "memory count 256 exceeds the limit 255");
  h.meta_size = 1ULL << 40;
  b = encode_header(h);
  EXPECT_FALSE(decode_header(b.data(), Limits{}, &why));
  EXPECT_NE(why.find("metadata claims 1099511627776 bytes"), std::string::npos);
}

TEST(EdgeWire, MetadataRoundTripAndOrder) {
  Metadata m;
  m.set("client_id", "42");
  m.set("a", "b");
  m.set("CLIENT_ID", "43");  // replaces, case-insensitive
  EXPECT_EQ(m.size(), 2u);
  EXPECT_EQ(*m.get("client_id"), "43");
  const auto s = m.serialize();
  const uint8_t want[] = {2,   0,   0,   0,   'a', 0,   'b', 0,   'c', 'l', 'i',
                          'e', 'n', 't', '_', 'i', 'd', 0,   '4', '3', 0};
  ASSERT_EQ(s.size(), sizeof want);
  EXPECT_EQ(0, std::memcmp(s.data(), want, sizeof want));
  std::string why;
  auto p = Metadata::parse(s.data(), s.size(), &why);
  ASSERT_TRUE(p) << why;
  EXPECT_EQ(p->items(), m.items());
  EXPECT_TRUE(Metadata().serialize().empty());
}

TEST(EdgeWire, MetadataRejectsBadInput) {
  std::string why;
  const uint8_t unterminated[] = {1, 0, 0, 0, 'k', 0, 'v'};
  EXPECT_FALSE(Metadata::parse(unterminated, sizeof unterminated, &why));
  EXPECT_EQ(why, "metadata: pair 0 is not NUL-terminated");
  const uint8_t wrong_count[] = {3, 0, 0, 0, 'k', 0, 'v', 0};
  EXPECT_FALSE(Metadata::parse(wrong_count, sizeof wrong_count, &why));
  EXPECT_EQ(why, "metadata: count says 3 pairs, found 1");
  const uint8_t shorty[] = {1, 0};
  EXPECT_FALSE(Metadata::parse(shorty, sizeof shorty, &why));
  const uint8_t twice[] = {2, 0, 0, 0, 'K', 0, 'v', 0, 'k', 0, 'w', 0};
  EXPECT_FALSE(Metadata::parse(twice, sizeof twice, &why));
  EXPECT_EQ(why, "metadata: pair 1 repeats the key 'k' (keys are case-insensitive)");
  const uint8_t zero_count[] = {0, 0, 0, 0};  // nnstreamer-edge's reader takes it as empty
  auto empty = Metadata::parse(zero_count, sizeof zero_count, &why);
  ASSERT_TRUE(empty) << why;
  EXPECT_TRUE(empty->empty());
}

TEST(EdgeWire, HostStringAndCapsFields) {
  std::string host;
  uint16_t port = 0;
  EXPECT_EQ(host_string("localhost", 3001), "localhost:3001");
  ASSERT_TRUE(parse_host_string("127.0.0.1:3001", &host, &port));
  EXPECT_EQ(host, "127.0.0.1");
  EXPECT_EQ(port, 3001);
  EXPECT_FALSE(parse_host_string("nohost", &host, &port));
  EXPECT_FALSE(parse_host_string("h:70000", &host, &port));
  EXPECT_FALSE(parse_host_string("h:0", &host, &port));
  const std::string caps =
      "@query_server_sink_caps@other/tensors,format=static@query_server_src_caps@ANY";
  EXPECT_EQ(*caps_field(caps, "query_server_src_caps"), "ANY");
  EXPECT_EQ(*caps_field(caps, "query_server_sink_caps"), "other/tensors,format=static");
  EXPECT_FALSE(caps_field(caps, "edge_sink_caps"));
}

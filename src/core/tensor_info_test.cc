// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_info.h"

#include <gtest/gtest.h>

#include "core/error.h"
#include "core/meta_header.h"

namespace nns {
namespace {

TEST(TensorType, NamesSizesAndNumbering) {
  EXPECT_EQ(static_cast<int>(TensorType::kInt32), 0);
  EXPECT_EQ(static_cast<int>(TensorType::kFloat16), 10);
  EXPECT_EQ(type_size(TensorType::kFloat64), 8u);
  EXPECT_EQ(type_size(TensorType::kFloat16), 2u);
  EXPECT_EQ(type_size(TensorType::kUInt8), 1u);
  EXPECT_EQ(type_name(TensorType::kUInt16), "uint16");
  for (std::size_t i = 0; i < kNumTypes; ++i) {
    auto t = static_cast<TensorType>(i);
    EXPECT_EQ(parse_type(type_name(t)), t);
  }
}

TEST(TensorType, RejectsUnknownQuotingToken) {
  try {
    parse_type("float8");
    FAIL() << "no exception";
  } catch (const Error &e) {
    EXPECT_EQ(e.kind(), ErrorKind::kSettings);
    EXPECT_NE(std::string(e.what()).find("'float8'"), std::string::npos);
  }
}

TEST(Dims, ParseRankAndCount) {
  Dims d = parse_dims("3:224:224:1");
  EXPECT_EQ(rank_of(d), 4u);
  EXPECT_EQ(element_count(d), 3u * 224 * 224);
  EXPECT_EQ(dims_to_string(d), "3:224:224:1");
  EXPECT_EQ(rank_of(parse_dims("10:20:0:0")), 2u);
  Dims full = parse_dims("1:2:3:4:5:6:7:8:9:10:11:12:13:14:15:16");
  EXPECT_EQ(rank_of(full), 16u);
}

TEST(Dims, TrailingOnesCompareEqual) {
  EXPECT_TRUE(dims_equal(parse_dims("3:224:224"), parse_dims("3:224:224:1")));
  EXPECT_TRUE(dims_equal(parse_dims("1"), parse_dims("1:1:1:1")));
  EXPECT_TRUE(dims_equal(parse_dims("10:20:0:0"), parse_dims("10:20")));
  EXPECT_FALSE(dims_equal(parse_dims("3:224:224:2"), parse_dims("3:224:224")));
  EXPECT_FALSE(dims_equal(parse_dims("224:3"), parse_dims("3:224")));
}

TEST(Dims, RejectsMalformed) {
  for (const char *bad : {"", "3::4", "3:a:4", "3:-1", "0:3", "3:0:4", "4294967296",
                          "1:2:3:4:5:6:7:8:9:10:11:12:13:14:15:16:17", "3:4x"}) {
    EXPECT_THROW(parse_dims(bad), Error) << bad;
  }
  try {
    parse_dims("3:x:4");
  } catch (const Error &e) {
    EXPECT_NE(std::string(e.what()).find("'x'"), std::string::npos) << e.what();
  }
}

TEST(Dims, ListsSplitOnCommaAndDot) {
  auto l = parse_dims_list("3:224:224:1,10:1.5", "input-dim");
  ASSERT_EQ(l.size(), 3u);
  EXPECT_EQ(element_count(l[2]), 5u);
  auto t = parse_types_list("uint8.float32,int16");
  ASSERT_EQ(t.size(), 3u);
  EXPECT_EQ(t[1], TensorType::kFloat32);
  try {
    parse_types_list("uint8,bogus", "input-type");
    FAIL();
  } catch (const Error &e) {
    std::string m = e.what();
    EXPECT_NE(m.find("input-type"), std::string::npos);
    EXPECT_NE(m.find("'bogus'"), std::string::npos);
  }
}

TEST(TensorsInfo, SizesAndStrings) {
  TensorsInfo info;
  info.tensors.push_back({"a", TensorType::kUInt8, parse_dims("3:4:4:1")});
  info.tensors.push_back({"b", TensorType::kFloat32, parse_dims("10")});
  EXPECT_TRUE(info.valid());
  EXPECT_EQ(info.total_bytes(), 48u + 40u);
  EXPECT_EQ(info.dims_string(), "3:4:4:1,10");
  EXPECT_EQ(info.types_string(), "uint8,float32");
  TensorsInfo other = info;
  other.tensors[1].dims = parse_dims("10:1:1");
  EXPECT_TRUE(info.same_as(other));
  other.tensors[1].type = TensorType::kFloat64;
  EXPECT_FALSE(info.same_as(other));
}

TEST(MetaHeader, ByteLayoutMatchesNNStreamer) {
  MetaHeader h;
  h.type = TensorType::kFloat32;
  h.dims = parse_dims("3:224:224:1");
  h.format = TensorFormat::kFlexible;
  h.media_type = MediaType::kVideo;
  uint8_t buf[kMetaHeaderSize];
  write_meta_header(h, buf);
  auto u32 = [&](int word) {
    return uint32_t(buf[word * 4]) | uint32_t(buf[word * 4 + 1]) << 8 |
           uint32_t(buf[word * 4 + 2]) << 16 | uint32_t(buf[word * 4 + 3]) << 24;
  };
  EXPECT_EQ(u32(0), 0xfeedccedu);
  EXPECT_EQ(u32(1), 0xDE001000u);
  EXPECT_EQ(u32(2), 7u);  // float32
  EXPECT_EQ(u32(3), 3u);
  EXPECT_EQ(u32(4), 224u);
  EXPECT_EQ(u32(6), 1u);
  EXPECT_EQ(u32(7), 0u);
  EXPECT_EQ(u32(19), 1u);  // flexible
  EXPECT_EQ(u32(20), 0u);  // video
  for (std::size_t i = 88; i < kMetaHeaderSize; ++i) EXPECT_EQ(buf[i], 0);
  MetaHeader p = parse_meta_header(buf, sizeof buf);
  EXPECT_EQ(p.type, TensorType::kFloat32);
  EXPECT_TRUE(dims_equal(p.dims, h.dims));
  EXPECT_EQ(p.format, TensorFormat::kFlexible);
  EXPECT_EQ(p.payload_size(), 3u * 224 * 224 * 4);
}

TEST(MetaHeader, RejectsCorruptHeaders) {
  MetaHeader h;
  h.type = TensorType::kUInt8;
  h.dims = parse_dims("4");
  uint8_t buf[kMetaHeaderSize];
  write_meta_header(h, buf);
  EXPECT_THROW(parse_meta_header(buf, 64), Error);
  uint8_t bad[kMetaHeaderSize];
  std::copy(buf, buf + kMetaHeaderSize, bad);
  bad[0] ^= 1;
  EXPECT_THROW(parse_meta_header(bad, sizeof bad), Error);
  std::copy(buf, buf + kMetaHeaderSize, bad);
  bad[8] = 42;  // type
  EXPECT_THROW(parse_meta_header(bad, sizeof bad), Error);
  std::copy(buf, buf + kMetaHeaderSize, bad);
  bad[76] = 9;  // format
  EXPECT_THROW(parse_meta_header(bad, sizeof bad), Error);
  std::copy(buf, buf + kMetaHeaderSize, bad);
  bad[20] = 5;  // dims[2] non-zero after dims[1] == 0
  EXPECT_THROW(parse_meta_header(bad, sizeof bad), Error);
}

TEST(Strings, SplitTrimsAndJoinPutsTheSeparatorBetween) {
  EXPECT_EQ(split(" a, b ,c", ","), (std::vector<std::string>{"a", "b", "c"}));
  EXPECT_EQ(join({"a", "b", "c"}, ","), "a,b,c");
  EXPECT_EQ(join({"onnxruntime", "opencv"}, ", "), "onnxruntime, opencv");
  EXPECT_EQ(join({"only"}, ", "), "only");
  EXPECT_EQ(join({}, ","), "");
}

}  // namespace
}  // namespace nns

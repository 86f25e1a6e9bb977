// SPDX-License-Identifier: LGPL-2.1-only
#include "core/iio/iio_channel.h"

#include <gtest/gtest.h>

#include <cstring>

#include "core/error.h"

using nns::iio::Channel;
using nns::iio::ChannelType;
using nns::iio::decode_sample;
using nns::iio::layout_scan;
using nns::iio::parse_channel_type;

TEST(IioChannelType, ParsesKernelStrings) {
  ChannelType t = parse_channel_type("le:s12/16>>4\n", "f");
  EXPECT_FALSE(t.big_endian);
  EXPECT_TRUE(t.is_signed);
  EXPECT_EQ(t.used_bits, 12u);
  EXPECT_EQ(t.storage_bits, 16u);
  EXPECT_EQ(t.shift, 4u);
  EXPECT_EQ(t.storage_bytes(), 2u);
  t = parse_channel_type("be:u24/32>>0", "f");
  EXPECT_TRUE(t.big_endian);
  EXPECT_FALSE(t.is_signed);
  EXPECT_EQ(t.storage_bytes(), 4u);
  EXPECT_EQ(parse_channel_type("le:s64/64>>0", "f").storage_bytes(), 8u);
}

TEST(IioChannelType, RejectsMalformedNamingTheFile) {
  for (const char *bad :
       {"xx:s12/16>>4", "le:q12/16>>4", "le:s12/16", "le:s17/16>>0", "le:s12/16X2>>4",
        "le:s12/16>>16", "le:s0/16>>0", "le:s12/16>>8", "le:s12-16>>4", "", "le:s12/16>>4junk"}) {
    try {
      parse_channel_type(bad, "/sys/x/scan_elements/in_accel_x_type");
      ADD_FAILURE() << "accepted '" << bad << "'";
    } catch (const nns::Error &e) {
      EXPECT_NE(std::string(e.what()).find("/sys/x/scan_elements/in_accel_x_type"),
                std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find(std::string("'") + bad), std::string::npos) << e.what();
    }
  }
}

namespace {

Channel make(const char *type, float scale = 1.0f, float offset = 0.0f, std::size_t loc = 0) {
  Channel c;
  c.name = "ch";
  c.type = parse_channel_type(type, "t");
  c.scale = scale;
  c.offset = offset;
  c.location = loc;
  c.enabled = true;
  return c;
}

}  // namespace

TEST(IioDecode, SignedLittleEndianShifted) {
  // -5 in 12 bits, shifted left by 4, stored little-endian in 16 bits; low nibble is noise.
  uint16_t stored = static_cast<uint16_t>(((-5 & 0xFFF) << 4) | 0xA);
  uint8_t scan[2] = {static_cast<uint8_t>(stored & 0xFF), static_cast<uint8_t>(stored >> 8)};
  Channel c = make("le:s12/16>>4", 0.5f, 1.0f);
  EXPECT_EQ(decode_sample(c, scan), (-5.0f + 1.0f) * 0.5f);
}

TEST(IioDecode, UnsignedBigEndianShifted) {
  // 1000 in 10 bits, shifted by 6, big-endian.
  uint16_t stored = static_cast<uint16_t>(1000u << 6 | 0x3F);
  uint8_t scan[2] = {static_cast<uint8_t>(stored >> 8), static_cast<uint8_t>(stored & 0xFF)};
  Channel c = make("be:u10/16>>6");
  EXPECT_EQ(decode_sample(c, scan), 1000.0f);
}

TEST(IioDecode, SingleByte) {
  uint8_t scan[1] = {0xF6};  // -10 as int8, 246 as uint8
  EXPECT_EQ(decode_sample(make("le:s8/8>>0"), scan), -10.0f);
  EXPECT_EQ(decode_sample(make("be:u8/8>>0"), scan), 246.0f);
  // 3 signed bits at bit 2: 0xF6 = 1111 0110 -> >>2 = 0011 1101 -> low 3 bits 101 = -3
  EXPECT_EQ(decode_sample(make("le:s3/8>>2"), scan), -3.0f);
}

TEST(IioDecode, ThirtyTwoAndThreeByteStorage) {
  int32_t v = -123456;
  uint32_t stored = static_cast<uint32_t>(v & 0xFFFFFF) << 8;
  uint8_t le[4];
  std::memcpy(le, &stored, 4);  // this test machine is little-endian (x86_64)
  EXPECT_EQ(decode_sample(make("le:s24/32>>8", 0.001f), le), -123456.0f * 0.001f);
  uint8_t be[4] = {static_cast<uint8_t>(stored >> 24), static_cast<uint8_t>(stored >> 16),
                   static_cast<uint8_t>(stored >> 8), static_cast<uint8_t>(stored)};
  EXPECT_EQ(decode_sample(make("be:s24/32>>8", 0.001f), be), -123456.0f * 0.001f);
  // 24-bit storage: exactly three bytes are read.
  uint8_t three_le[3] = {0x01, 0x02, 0x83};  // 0x830201 -> negative in 24 bits
  EXPECT_EQ(decode_sample(make("le:s24/24>>0"), three_le),
            static_cast<float>(static_cast<int32_t>(0x830201u << 8) >> 8));
  uint8_t three_be[3] = {0x83, 0x02, 0x01};
  EXPECT_EQ(decode_sample(make("be:u24/24>>0"), three_be), static_cast<float>(0x830201));
}

TEST(IioDecode, SixtyFourBit) {
  int64_t v = -(int64_t{1} << 40) - 7;
  uint8_t scan[8];
  std::memcpy(scan, &v, 8);
  EXPECT_EQ(decode_sample(make("le:s64/64>>0"), scan), static_cast<float>(v));
  uint64_t u = ~uint64_t{0};
  std::memcpy(scan, &u, 8);
  EXPECT_EQ(decode_sample(make("le:u64/64>>0"), scan), static_cast<float>(u));
}

TEST(IioDecode, UsesLocation) {
  uint8_t scan[6] = {0, 0, 0, 0, 0x34, 0x12};
  Channel c = make("le:u16/16>>0", 1.0f, 0.0f, 4);
  EXPECT_EQ(decode_sample(c, scan), static_cast<float>(0x1234));
}

TEST(IioLayout, AlignsEachSampleAndPadsTheScan) {
  std::vector<Channel> chs = {make("le:u8/8>>0"), make("le:u16/16>>0"), make("le:u32/32>>0"),
                              make("le:s16/16>>0")};
  chs[0].index = 2;
  chs[1].index = 0;
  chs[2].index = 1;
  chs[3].index = 3;
  chs[3].enabled = false;
  EXPECT_EQ(layout_scan(chs), 12u);  // u16@0, u32@4, u8@8, padded to 12
  EXPECT_EQ(chs[0].index, 0u);
  EXPECT_EQ(chs[0].location, 0u);
  EXPECT_EQ(chs[1].location, 4u);
  EXPECT_EQ(chs[2].location, 8u);
  std::vector<Channel> none = {make("le:u8/8>>0")};
  none[0].enabled = false;
  EXPECT_EQ(layout_scan(none), 0u);
  std::vector<Channel> ts = {make("le:s16/16>>0"), make("le:s64/64>>0")};
  ts[0].index = 0;
  ts[1].index = 1;
  EXPECT_EQ(layout_scan(ts), 16u);  // the timestamp is 8-aligned: s16@0, s64@8
  EXPECT_EQ(ts[1].location, 8u);
}

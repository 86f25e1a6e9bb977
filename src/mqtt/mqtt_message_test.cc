// SPDX-License-Identifier: LGPL-2.1-only
#include "mqtt/mqtt_message.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "core/error.h"

using namespace nns::mqtt;

namespace {

std::vector<uint8_t> message(const MessageHeader &h) {
  std::vector<uint8_t> m(kHeaderSize + h.payload_size(), 0xAB);
  write_header(h, m.data());
  return m;
}

std::string error_of(const std::vector<uint8_t> &m) {
  try {
    parse_message(m.data(), m.size());
  } catch (const nns::Error &e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(MqttMessage, LayoutIsUpstreamStructOn64BitLittleEndian) {
  MessageHeader h;
  h.mem_sizes = {12, 0x0102030405060708ULL >> 40};
  h.base_time_epoch = 0x1122334455667788LL;
  h.sent_time_epoch = 0x0A0B0C0D0E0F1011LL;
  h.duration = 33333333;
  h.dts = kNoTime;
  h.pts = 1000;
  h.caps = "video/x-raw";
  std::vector<uint8_t> out(kHeaderSize);
  write_header(h, out.data());
  const uint8_t golden_start[] = {2, 0, 0, 0, 0,    0,    0,    0, 12, 0, 0, 0,
                                  0, 0, 0, 0, 0x03, 0x02, 0x01, 0, 0,  0, 0, 0};
  EXPECT_EQ(0, std::memcmp(out.data(), golden_start, sizeof golden_start));
  const uint8_t base[] = {0x88, 0x77, 0x66, 0x55, 0x44, 0x33, 0x22, 0x11};
  EXPECT_EQ(0, std::memcmp(out.data() + 136, base, 8));
  const uint8_t pts[] = {0xE8, 0x03, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(0, std::memcmp(out.data() + 168, pts, 8));
  for (int i = 0; i < 8; ++i) EXPECT_EQ(out[160 + i], 0xFF);
  EXPECT_EQ(0, std::memcmp(out.data() + 176, "video/x-raw\0", 12));
  for (std::size_t i = 176 + 11; i < kHeaderSize; ++i) ASSERT_EQ(out[i], 0) << i;
}

TEST(MqttMessage, RoundTrip) {
  MessageHeader h;
  h.mem_sizes = {4, 0, 6};
  h.base_time_epoch = 5;
  h.sent_time_epoch = 7;
  h.pts = 9;
  h.caps = "other/tensors,num_tensors=(int)3";
  const auto m = message(h);
  const MessageHeader g = parse_message(m.data(), m.size());
  EXPECT_EQ(g.mem_sizes, h.mem_sizes);
  EXPECT_EQ(g.base_time_epoch, 5);
  EXPECT_EQ(g.sent_time_epoch, 7);
  EXPECT_EQ(g.pts, 9u);
  EXPECT_EQ(g.dts, kNoTime);
  EXPECT_EQ(g.duration, kNoTime);
  EXPECT_EQ(g.caps, h.caps);
}

TEST(MqttMessage, RefusesBadMessages) {
  std::vector<uint8_t> small(100, 0);
  EXPECT_NE(error_of(small).find("shorter than the 1024-byte header"), std::string::npos);

  MessageHeader h;
  h.mem_sizes = {8};
  auto m = message(h);
  m[0] = 17;
  EXPECT_NE(error_of(m).find("claims 17 memories"), std::string::npos);

  m = message(h);
  // A 4 GiB size field with 8 bytes of data.
  const uint64_t huge = 4ULL << 30;
  for (int i = 0; i < 8; ++i) m[8 + i] = static_cast<uint8_t>(huge >> (8 * i));
  EXPECT_NE(error_of(m).find("claims 4294967296 bytes but only 8 bytes follow"), std::string::npos);

  m = message(h);
  m.pop_back();  // truncated
  EXPECT_NE(error_of(m).find("claims 8 bytes but only 7"), std::string::npos);

  m = message(h);
  m.push_back(0);  // trailing bytes
  EXPECT_NE(error_of(m).find("add up to 8 bytes but 9 bytes follow"), std::string::npos);

  m = message(h);
  std::memset(m.data() + kOffCaps, 'x', kMaxCapsLen);
  EXPECT_NE(error_of(m).find("not terminated"), std::string::npos);

  // Sizes that wrap around 2^64 together.
  h.mem_sizes = {8, 8};
  m = message(h);
  const uint64_t wrap = ~0ULL - 3;
  for (int i = 0; i < 8; ++i) m[8 + i] = static_cast<uint8_t>(wrap >> (8 * i));
  EXPECT_NE(error_of(m).find("memory 0 claims"), std::string::npos);
}

TEST(MqttMessage, WriteRefusesWhatDoesNotFit) {
  MessageHeader h;
  h.mem_sizes.assign(17, 1);
  std::vector<uint8_t> out(kHeaderSize);
  EXPECT_THROW(write_header(h, out.data()), nns::Error);
  h.mem_sizes = {1};
  h.caps.assign(512, 'c');
  EXPECT_THROW(write_header(h, out.data()), nns::Error);
  h.caps.assign(511, 'c');
  EXPECT_NO_THROW(write_header(h, out.data()));
}

TEST(MqttMessage, RebaseMovesTimestampsOntoTheReceiverBase) {
  MessageHeader h;
  h.base_time_epoch = 1000000;  // sender started 300 ns after the receiver
  h.sent_time_epoch = 2000000;
  h.pts = 500;
  h.dts = 400;
  h.duration = 10;
  Rebased r = rebase(h, 999700);
  ASSERT_TRUE(r.valid());
  EXPECT_EQ(r.pts, 800u);
  EXPECT_EQ(r.dts, 700u);
  EXPECT_EQ(r.duration, 10u);
  // Receiver started 300 ns after the sender: timestamps move back.
  r = rebase(h, 1000300);
  EXPECT_EQ(r.pts, 200u);
  EXPECT_EQ(r.dts, 100u);
  // Would become negative: no timestamps.
  r = rebase(h, 1000600);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.pts, kNoTime);
  EXPECT_EQ(r.drop, Rebased::Drop::kBeforeRunningZero);
  EXPECT_EQ(r.landed, -100);
  // Sent before the receiver started: no timestamps.
  r = rebase(h, 2000001);
  EXPECT_FALSE(r.valid());
  EXPECT_EQ(r.drop, Rebased::Drop::kSentBeforeBase);
  // No timestamps at all in the message: nothing valid.
  MessageHeader none;
  none.base_time_epoch = 10;
  none.sent_time_epoch = 20;
  EXPECT_FALSE(rebase(none, 5).valid());
  EXPECT_EQ(rebase(none, 5).drop, Rebased::Drop::kNoTimestamps);
  // No pts from a sender that started first: the missing pts counts as -1 (upstream's quirk).
  EXPECT_EQ(rebase(none, 15).drop, Rebased::Drop::kBeforeRunningZero);
  EXPECT_EQ(rebase(h, 999700).drop, Rebased::Drop::kNone);
}

TEST(MqttMessage, BaseTimeEpoch) {
  EXPECT_EQ(base_time_epoch(1'000'000'000'000LL, 5000, 2000), 1'000'000'000'000LL - 3000);
}

// The hex example of docs/wire-mqtt.md.
TEST(MqttMessage, WireDocExample) {
  MessageHeader h;
  h.mem_sizes = {4};
  h.base_time_epoch = 1700000000000000000LL;
  h.sent_time_epoch = h.base_time_epoch + 5000000;
  h.duration = 33000000;
  h.pts = 1000000;
  h.caps = "application/octet-stream";
  std::vector<uint8_t> m(kHeaderSize + 4);
  write_header(h, m.data());
  const uint8_t data[] = {0xde, 0xad, 0xbe, 0xef};
  std::memcpy(m.data() + kHeaderSize, data, 4);
  auto hex = [&](std::size_t off) {
    std::string s;
    char b[4];
    for (std::size_t i = 0; i < 16 && off + i < m.size(); ++i) {
      std::snprintf(b, sizeof b, "%02x ", m[off + i]);
      s += b;
    }
    return s;
  };
  EXPECT_EQ(hex(0x00), "01 00 00 00 00 00 00 00 04 00 00 00 00 00 00 00 ");
  EXPECT_EQ(hex(0x10), "00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 00 ");
  EXPECT_EQ(hex(0x80), "00 00 00 00 00 00 00 00 00 00 2a 36 fe 9c 97 17 ");
  EXPECT_EQ(hex(0x90), "40 4b 76 36 fe 9c 97 17 40 8a f7 01 00 00 00 00 ");
  EXPECT_EQ(hex(0xa0), "ff ff ff ff ff ff ff ff 40 42 0f 00 00 00 00 00 ");
  EXPECT_EQ(hex(0xb0), "61 70 70 6c 69 63 61 74 69 6f 6e 2f 6f 63 74 65 ");
  EXPECT_EQ(hex(0xc0), "74 2d 73 74 72 65 61 6d 00 00 00 00 00 00 00 00 ");
  EXPECT_EQ(hex(0x400), "de ad be ef ");
  for (std::size_t i = 0xc9; i < kHeaderSize; ++i) ASSERT_EQ(m[i], 0) << i;
  EXPECT_EQ(parse_message(m.data(), m.size()).caps, "application/octet-stream");
}

// A message captured on the wire from NNStreamer 2.7.0's mqttsink (nnstreamer 5b13ea6, built
// from source; docs/interop.md): `videotestsrc pattern=ball ! video/x-raw,format=RGB,width=8,
// height=6,framerate=10/1 ! tensor_converter ! mqttsink`, second buffer. Bytes 0x134..0x3ff
// are zero; the payload is 144 bytes of 0xff. Ours must read every field of it, and write the
// same 1024 header bytes from those fields.
TEST(MqttMessage, MessageCapturedFromNNStreamer270) {
  const std::string head_hex =
      "0100000000000000900000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000000000000000000000000000000000000"
      "0000000000000000000000000000000000000000000000000000000000000000"
      "000000000000000092dfbd732ca7eb18b836c0732ca7eb1800e1f50500000000"
      "ffffffffffffffff00e1f505000000006f746865722f74656e736f72732c2066"
      "6f726d61743d28737472696e67297374617469632c206e756d5f74656e736f72"
      "733d28696e7429312c206672616d65726174653d286672616374696f6e293130"
      "2f312c2064696d656e73696f6e733d28737472696e6729333a383a363a312c20"
      "74797065733d28737472696e672975696e743800";
  std::vector<uint8_t> wire(kHeaderSize + 144, 0xff);
  std::fill(wire.begin(), wire.begin() + kHeaderSize, 0);
  for (std::size_t i = 0; i < head_hex.size() / 2; ++i)
    wire[i] = static_cast<uint8_t>(std::stoi(head_hex.substr(2 * i, 2), nullptr, 16));

  const MessageHeader h = parse_message(wire.data(), wire.size());
  ASSERT_EQ(h.mem_sizes, std::vector<uint64_t>{144});
  EXPECT_EQ(h.base_time_epoch, 0x18eba72c73bddf92LL);
  EXPECT_EQ(h.sent_time_epoch, 0x18eba72c73c036b8LL);
  EXPECT_EQ(h.sent_time_epoch - h.base_time_epoch, 153382);  // sync=false: sent at once
  EXPECT_EQ(h.duration, 100000000u);
  EXPECT_EQ(h.dts, kNoTime);
  EXPECT_EQ(h.pts, 100000000u);
  EXPECT_EQ(h.caps,
            "other/tensors, format=(string)static, num_tensors=(int)1, framerate=(fraction)10/1, "
            "dimensions=(string)3:8:6:1, types=(string)uint8");
  // Rebased onto a receiver whose pipeline started 1.5 s after the sender's.
  const Rebased r = rebase(h, h.base_time_epoch + 1500000000LL);
  EXPECT_FALSE(r.valid());  // sent before that receiver's base time: dropped, as upstream
  const Rebased r2 = rebase(h, h.base_time_epoch - 1500000000LL);
  ASSERT_TRUE(r2.valid());
  EXPECT_EQ(r2.pts, 1600000000u);
  EXPECT_EQ(r2.dts, kNoTime);
  EXPECT_EQ(r2.duration, 100000000u);

  std::vector<uint8_t> ours(kHeaderSize);
  write_header(h, ours.data());
  for (std::size_t i = 0; i < kHeaderSize; ++i) ASSERT_EQ(ours[i], wire[i]) << "byte " << i;
}

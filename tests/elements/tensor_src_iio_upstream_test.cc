// SPDX-License-Identifier: LGPL-2.1-only
// tensor_src_iio on the fake device tree NNStreamer's tests/nnstreamer_source/unittest_src_iio.cc
// builds (rebuilt here by our own code, same files and contents): sys/bus/iio/devices/iio:device0
// named "test-device-1" with 8 in_voltageN channels in every endianness/sign/bit width, a
// timestamp channel, in_voltage_scale 10.1 and in_voltage_offset 1.1, empty buffer/enable,
// buffer/length, trigger/current_trigger and sampling_frequency files, sampling frequencies
// "1000 2000 3000", a trigger iio:trigger0 named "test-trigger-1", and the data file
// dev/iio:device0. The frames are checked value by value.
//
// Where upstream's data differs from what the kernel writes: its scans leave out the enabled
// timestamp channel (index 8, 64 bits) that the kernel appends, 8-byte aligned, to every scan.
// Ours reads the kernel layout (docs/elements/tensor_src_iio.md), so the data written here
// carries the timestamp; everything else is upstream's tree unchanged.
#include <fcntl.h>
#include <gst/app/gstappsink.h>
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>

#include "elements/stream_util.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

namespace fs = std::filesystem;
using nns::test::Pipe;

namespace {

constexpr int kChannels = 8;
constexpr int kData = 98;
constexpr int kFrames = 5;

void put(const fs::path &p, const std::string &text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;  // no newline, as g_file_set_contents writes it
}

std::string get(const fs::path &p) {
  std::ifstream f(p);
  return std::string((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
}

// One channel of upstream's layout: channel idx of an 8-channel device with `bits` data bits.
struct ChannelType {
  char endian, sign;
  int used, storage, shift;
};

// Bytes per sample: bits rounded up to 1, 2, 4 or 8 bytes.
int storage_bytes(int bits) {
  int b = (bits + 7) / 8;
  int p = 1;
  while (p < b) p <<= 1;
  return p;
}

ChannelType channel_type(int idx, int bits) {
  ChannelType t{'b', 's', 0, 0, 0};
  switch (idx % (kChannels / 2)) {
    case 1:
      t.endian = 'l';
      t.sign = 'u';
      break;
    case 2:
      t.sign = 'u';
      break;
    case 3:
      t.endian = 'l';
      break;
  }
  t.storage = storage_bytes(bits) * 8;
  t.used = std::max(1, bits - 2 * (idx / (kChannels / 2)));
  t.shift = t.storage - t.used;
  return t;
}

// The raw value the element must decode from `data` written as upstream writes it.
double decoded(int64_t data, const ChannelType &t) {
  const uint64_t smask = t.storage == 64 ? ~0ull : ((1ull << t.storage) - 1);
  const uint64_t stored = (static_cast<uint64_t>(data) << t.shift) & smask;
  const uint64_t umask = t.used == 64 ? ~0ull : ((1ull << t.used) - 1);
  uint64_t v = (stored >> t.shift) & umask;
  if (t.sign == 's' && t.used < 64 && ((v >> (t.used - 1)) & 1)) {
    return static_cast<double>(static_cast<int64_t>(v) - static_cast<int64_t>(1ull << t.used));
  }
  return t.sign == 's' ? static_cast<double>(static_cast<int64_t>(v)) : static_cast<double>(v);
}

struct UpstreamIioTree {
  fs::path root = nns::test::make_temp_dir();
  fs::path base = root / "sys" / "bus" / "iio" / "devices";  // iio-base-dir
  fs::path dev_dir = root / "dev";
  fs::path dev = base / "iio:device0";
  fs::path scan = dev / "scan_elements";
  int bits;
  int skip;

  UpstreamIioTree(int data_bits, bool trigger = true, int alternate = 1)
      : bits(data_bits), skip(alternate) {
    put(dev / "name", "test-device-1");
    put(base / "iio:trigger0" / "name", "test-trigger-1");
    if (trigger) put(dev / "trigger" / "current_trigger", "");
    put(dev / "buffer" / "enable", "");
    put(dev / "buffer" / "length", "");
    for (int i = 0; i < kChannels; ++i) {
      const ChannelType t = channel_type(i, bits);
      put(scan / ("in_voltage" + std::to_string(i) + "_en"), i % skip == 0 ? "1" : "0");
      put(scan / ("in_voltage" + std::to_string(i) + "_index"), std::to_string(i));
      char type[64];
      std::snprintf(type, sizeof type, "%ce:%c%d/%d>>%d", t.endian, t.sign, t.used, t.storage,
                    t.shift);
      put(scan / ("in_voltage" + std::to_string(i) + "_type"), type);
      put(dev / ("in_voltage" + std::to_string(i) + "_raw"), std::to_string(kData));
    }
    put(scan / "timestamp_en", "1");
    put(scan / "timestamp_index", std::to_string(kChannels));
    put(scan / "timestamp_type", "be:s64/64>>0");
    put(dev / "sampling_frequency", "");
    put(dev / "sampling_frequency_available", "1000 2000 3000");
    char num[32];
    std::snprintf(num, sizeof num, "%f", 10.1f);
    put(dev / "in_voltage_scale", num);
    std::snprintf(num, sizeof num, "%f", 1.1f);
    put(dev / "in_voltage_offset", num);
    fs::create_directories(dev_dir);
  }
  ~UpstreamIioTree() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }

  // kFrames scans with data kData, kData + 1, ... (upstream increments the value per frame).
  // Each scan: the enabled channels as upstream writes them, then the 8-byte timestamp the
  // kernel adds (see the note at the top).
  void write_scans(const std::vector<int> &enabled) {
    std::string bytes;
    const int nb = storage_bytes(bits);
    for (int f = 0; f < kFrames; ++f) {
      std::string s;
      for (int i : enabled) {
        const ChannelType t = channel_type(i, bits);
        uint64_t w = static_cast<uint64_t>(static_cast<int64_t>(kData + f)) << t.shift;
        for (int b = 0; b < nb; ++b) {
          const int k = t.endian == 'l' ? b : nb - 1 - b;
          s.push_back(static_cast<char>((w >> (8 * k)) & 0xFF));
        }
      }
      while (s.size() % 8) s.push_back('\0');
      for (int b = 0; b < 8; ++b) s.push_back(static_cast<char>(0x10 + f));  // timestamp
      bytes += s;
    }
    std::ofstream(dev_dir / "iio:device0", std::ios::binary) << bytes;
  }
  std::string props() const {
    return "iio-base-dir=" + base.string() + " dev-dir=" + dev_dir.string() + " ";
  }
};

std::vector<float> floats_of(GstBuffer *b, guint idx) {
  auto bytes = nns::test::tensor_bytes(b, idx);
  std::vector<float> f(bytes.size() / 4);
  std::memcpy(f.data(), bytes.data(), f.size() * 4);
  return f;
}

std::string two_decimals(double v) {
  char s[64];
  std::snprintf(s, sizeof s, "%.2f", v);
  return s;
}

// The value upstream expects: (raw + offset) * scale, compared with two decimals.
std::string expected(int frame, int channel, int bits) {
  return two_decimals((decoded(kData + frame, channel_type(channel, bits)) + 1.1f) * 10.1f);
}

// dataVerifyNoTriggerBits<N>alternate<S>: every bit width, all channels or every other one.
class UpstreamIioData : public ::testing::TestWithParam<std::pair<int, int>> {};

TEST_P(UpstreamIioData, FramesMatchValueByValue) {
  const auto [bits, skip] = GetParam();
  UpstreamIioTree t(bits, false, skip);
  std::vector<int> enabled;
  for (int i = 0; i < kChannels; i += skip) enabled.push_back(i);
  t.write_scans(enabled);
  Pipe p("tensor_src_iio device=test-device-1 silent=FALSE " + t.props() +
         "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), static_cast<std::size_t>(kFrames));
  for (int f = 0; f < kFrames; ++f) {
    auto v = floats_of(p.out()[f], 0);
    ASSERT_EQ(v.size(), enabled.size());
    for (std::size_t c = 0; c < enabled.size(); ++c)
      EXPECT_EQ(two_decimals(v[c]), expected(f, enabled[c], bits))
          << "frame " << f << " channel " << enabled[c];
  }
}

INSTANTIATE_TEST_SUITE_P(Bits, UpstreamIioData,
                         ::testing::Values(std::pair{4, 1}, std::pair{8, 2}, std::pair{12, 1},
                                           std::pair{16, 2}, std::pair{24, 1}, std::pair{32, 2},
                                           std::pair{40, 1}, std::pair{48, 2}, std::pair{56, 1},
                                           std::pair{64, 2}));

// dataVerifyTrigger: device-number and trigger by name; merged channels give one float32 tensor
// of 8 values per scan at the first available frequency (sampling_frequency is empty).
TEST(TensorSrcIioUpstream, TriggerByNameMergedCaps) {
  UpstreamIioTree t(16);
  t.write_scans({0, 1, 2, 3, 4, 5, 6, 7});
  Pipe p("tensor_src_iio device-number=0 trigger=test-trigger-1 silent=FALSE name=my-src-iio " +
         t.props() + "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), static_cast<std::size_t>(kFrames));
  for (int f = 0; f < kFrames; ++f) {
    auto v = floats_of(p.out()[f], 0);
    ASSERT_EQ(v.size(), 8u);
    for (int c = 0; c < 8; ++c) EXPECT_EQ(two_decimals(v[c]), expected(f, c, 16));
  }
}

TEST(TensorSrcIioUpstream, CapsWhilePlaying) {
  // The caps upstream's tests read while PLAYING (other/tensor, float32 8:1, 1000/1), and with
  // merge-channels-data=false other/tensors of 8 float32 1:1 tensors. A FIFO keeps the stream
  // open, as upstream's fake device does.
  for (bool merged : {true, false}) {
    SCOPED_TRACE(merged);
    UpstreamIioTree t(16);
    const fs::path fifo = t.dev_dir / "iio:device0";
    ASSERT_EQ(mkfifo(fifo.c_str(), 0600), 0);
    // Read-write: opening does not wait for the element, which then finds a writer.
    const int fd = open(fifo.c_str(), O_RDWR);
    ASSERT_GE(fd, 0);
    // One scan (8 x 16 bits, then the timestamp) so caps are set.
    const std::string scan(16 + 8, '\0');
    ASSERT_EQ(write(fd, scan.data(), scan.size()), static_cast<ssize_t>(scan.size()));
    Pipe p("tensor_src_iio device-number=0 trigger=test-trigger-1 name=my-src-iio " +
           std::string(merged ? "" : "merge-channels-data=false ") + t.props() +
           "! appsink name=out sync=false");
    gst_element_set_state(p.pipeline(), GST_STATE_PLAYING);
    GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(p.get("out")), 5 * GST_SECOND);
    ASSERT_TRUE(s);
    GstCaps *caps = gst_sample_get_caps(s);
    const GstStructure *st = gst_caps_get_structure(caps, 0);
    nns::TensorsConfig cfg = nns::gst::config_from_caps(caps);
    EXPECT_EQ(cfg.rate_n, 1000);
    EXPECT_EQ(cfg.rate_d, 1);
    if (merged) {
      EXPECT_STREQ(gst_structure_get_name(st), "other/tensor") << nns::gst::caps_to_string(caps);
      ASSERT_EQ(cfg.info.size(), 1u);
      EXPECT_EQ(cfg.info[0].type, nns::TensorType::kFloat32);
      EXPECT_EQ(cfg.info[0].dims[0], 8u);
      EXPECT_EQ(cfg.info[0].dims[1], 1u);
    } else {
      EXPECT_STREQ(gst_structure_get_name(st), "other/tensors");
      ASSERT_EQ(cfg.info.size(), 8u);
      for (std::size_t i = 0; i < 8; ++i) {
        EXPECT_EQ(cfg.info[i].type, nns::TensorType::kFloat32);
        EXPECT_EQ(cfg.info[i].dims[0], 1u);
      }
    }
    gst_sample_unref(s);
    gst_element_set_state(p.pipeline(), GST_STATE_NULL);
    close(fd);
  }
}

// dataVerifyCustomChannels: channels=1,3 gives 2 values per scan.
TEST(TensorSrcIioUpstream, CustomChannels) {
  UpstreamIioTree t(16);
  t.write_scans({1, 3});
  Pipe p("tensor_src_iio device-number=0 trigger=test-trigger-1 channels=1,3 name=my-src-iio " +
         t.props() + "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), static_cast<std::size_t>(kFrames));
  for (int f = 0; f < kFrames; ++f) {
    auto v = floats_of(p.out()[f], 0);
    ASSERT_EQ(v.size(), 2u);
    EXPECT_EQ(two_decimals(v[0]), expected(f, 1, 16));
    EXPECT_EQ(two_decimals(v[1]), expected(f, 3, 16));
  }
}

// dataVerifyFreqGenericType: channel 1's type only in the generic in_voltage_type, every channel
// disabled (channels=auto then enables all), sampling_frequency 3000 and buffer/length 3 before;
// frequency=2000, one tensor per channel; the files are put back after the stream.
TEST(TensorSrcIioUpstream, FrequencyGenericTypeAndRestore) {
  UpstreamIioTree t(16);
  fs::rename(t.scan / "in_voltage1_type", t.scan / "in_voltage_type");
  for (int i = 0; i < kChannels; ++i) put(t.scan / ("in_voltage" + std::to_string(i) + "_en"), "0");
  put(t.dev / "sampling_frequency", "3000");
  put(t.dev / "buffer" / "length", "3");
  t.write_scans({0, 1, 2, 3, 4, 5, 6, 7});
  Pipe p(
      "tensor_src_iio device-number=0 trigger-number=0 frequency=2000 "
      "merge-channels-data=False name=my-src-iio " +
      t.props() + "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), static_cast<std::size_t>(kFrames));
  for (int f = 0; f < kFrames; ++f) {
    ASSERT_EQ(gst_buffer_n_memory(p.out()[f]), 8u);
    for (int c = 0; c < 8; ++c) {
      auto v = floats_of(p.out()[f], c);
      ASSERT_EQ(v.size(), 1u);
      // Channel 1 takes the generic type, which is its own (le:u16/16>>0) moved there.
      EXPECT_EQ(two_decimals(v[0]), expected(f, c, 16)) << "frame " << f << " channel " << c;
    }
  }
  EXPECT_EQ(get(t.dev / "sampling_frequency"), "3000");
  EXPECT_EQ(get(t.dev / "buffer" / "length"), "3");
  for (int i = 0; i < kChannels; ++i)
    EXPECT_EQ(get(t.scan / ("in_voltage" + std::to_string(i) + "_en")), "0") << i;
}

}  // namespace

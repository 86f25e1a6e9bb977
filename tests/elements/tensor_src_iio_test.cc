// SPDX-License-Identifier: LGPL-2.1-only
// tensor_src_iio against a fake IIO device: a sysfs tree in a temp folder (name, scan_elements
// *_en/_index/_type, scale/offset, sampling frequency, buffer, trigger) and a plain file standing
// in for the buffered character device, holding known scans of several channel types.
#include <gst/app/gstappsink.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "elements/stream_util.h"
#include "support/harness.h"

namespace fs = std::filesystem;
using nns::test::Pipe;
using nns::test::run_pipeline;

namespace {

void put(const fs::path &p, const std::string &text) {
  fs::create_directories(p.parent_path());
  std::ofstream(p) << text;
}

std::string get(const fs::path &p) {
  std::ifstream f(p);
  std::string s((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  while (!s.empty() && s.back() == '\n') s.pop_back();
  return s;
}

// Sample k of each channel (raw integers before scale/offset).
int16_t x_raw(int k) {
  return static_cast<int16_t>(-5 - k);
}
uint16_t y_raw(int k) {
  return static_cast<uint16_t>(1000 - k);
}
int32_t v_raw(int k) {
  return -123456 + 1000 * k;
}
float x_val(int k) {
  return static_cast<float>(x_raw(k)) * 0.5f;
}
float y_val(int k) {
  return static_cast<float>(y_raw(k)) * 0.5f;
}
float v_val(int k) {
  return (static_cast<float>(v_raw(k)) + 10.0f) * 0.25f;
}

struct FakeIio {
  fs::path root = nns::test::make_temp_dir();
  fs::path base = root / "sys";
  fs::path dev = root / "dev";
  fs::path d = base / "iio:device0";
  fs::path scan = d / "scan_elements";

  FakeIio() {
    put(d / "name", "fake_accel\n");
    channel("in_accel_x", 0, "le:s12/16>>4", false);
    channel("in_accel_y", 1, "be:u10/16>>6", false);
    channel("in_voltage2", 2, "le:s24/32>>8", false);
    channel("in_timestamp", 3, "le:s64/64>>0", false);
    put(d / "in_accel_scale", "0.5\n");
    put(d / "in_voltage_scale", "0.25\n");
    put(d / "in_voltage2_offset", "10\n");
    put(d / "sampling_frequency", "100\n");
    put(d / "sampling_frequency_available", "100 200 1000\n");
    put(d / "buffer" / "length", "2\n");
    put(d / "buffer" / "enable", "0\n");
    put(d / "trigger" / "current_trigger", "\n");
    put(base / "trigger0" / "name", "fake-trig\n");
    put(base / "iio:device1" / "name", "other\n");
    fs::create_directories(dev);
  }
  ~FakeIio() {
    std::error_code ec;
    fs::remove_all(root, ec);
  }
  void channel(const std::string &n, int idx, const std::string &type, bool en) {
    put(scan / (n + "_en"), en ? "1\n" : "0\n");
    put(scan / (n + "_index"), std::to_string(idx) + "\n");
    put(scan / (n + "_type"), type + "\n");
  }
  // Writes `count` scans to the buffer file: x (and/or y) and v as the kernel lays them out.
  void scans(int count, bool x, bool y, bool v, bool ts = false, std::size_t extra = 0) {
    std::string bytes;
    for (int k = 0; k < count; ++k) {
      std::string s;
      auto pad_to = [&](std::size_t a) {
        while (s.size() % a) s.push_back('\xEE');
      };
      if (x) {
        uint16_t w = static_cast<uint16_t>(((x_raw(k) & 0xFFF) << 4) | 0xA);
        s.push_back(static_cast<char>(w & 0xFF));
        s.push_back(static_cast<char>(w >> 8));
      }
      if (y) {
        pad_to(2);
        uint16_t w = static_cast<uint16_t>((y_raw(k) << 6) | 0x3F);
        s.push_back(static_cast<char>(w >> 8));
        s.push_back(static_cast<char>(w & 0xFF));
      }
      if (v) {
        pad_to(4);
        uint32_t w = (static_cast<uint32_t>(v_raw(k)) & 0xFFFFFF) << 8 | 0x55;
        for (int i = 0; i < 4; ++i) s.push_back(static_cast<char>(w >> (8 * i)));
      }
      if (ts) {
        pad_to(8);
        for (int i = 0; i < 8; ++i) s.push_back(static_cast<char>(k + i));
      }
      pad_to(ts ? 8 : (v ? 4 : 2));
      bytes += s;
    }
    bytes.append(extra, '\x01');
    std::ofstream(dev / "iio:device0", std::ios::binary) << bytes;
  }
  std::string props() const {
    return "iio-base-dir=" + base.string() + " dev-dir=" + dev.string() + " ";
  }
};

std::vector<float> floats(GstBuffer *b, guint idx) {
  auto bytes = nns::test::tensor_bytes(b, idx);
  std::vector<float> f(bytes.size() / 4);
  std::memcpy(f.data(), bytes.data(), f.size() * 4);
  return f;
}

std::string caps_of(Pipe &p, const char *sink) {
  GstPad *pad = gst_element_get_static_pad(p.get(sink), "sink");
  GstCaps *c = gst_pad_get_current_caps(pad);
  std::string s;
  if (c) {
    gchar *str = gst_caps_to_string(c);
    s = str;
    g_free(str);
    gst_caps_unref(c);
  }
  gst_object_unref(pad);
  return s;
}

}  // namespace

TEST(TensorSrcIio, MergedChannelsBitExact) {
  FakeIio f;
  f.scans(6, true, true, true);  // 3 buffers of 2 scans, then the file ends
  Pipe p("tensor_src_iio device=fake_accel channels=all buffer-capacity=2 frequency=1000 " +
         f.props() + "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), 3u);
  for (int b = 0; b < 3; ++b) {
    GstBuffer *buf = p.out()[b];
    ASSERT_EQ(gst_buffer_n_memory(buf), 1u);
    auto v = floats(buf, 0);
    ASSERT_EQ(v.size(), 6u);  // 3 channels x 2 scans, channel innermost
    for (int s = 0; s < 2; ++s) {
      int k = b * 2 + s;
      EXPECT_EQ(v[s * 3 + 0], x_val(k)) << "buffer " << b << " scan " << s;
      EXPECT_EQ(v[s * 3 + 1], y_val(k));
      EXPECT_EQ(v[s * 3 + 2], v_val(k));
    }
    EXPECT_TRUE(GST_BUFFER_PTS_IS_VALID(buf));
    EXPECT_EQ(GST_BUFFER_DURATION(buf), 2 * GST_MSECOND);
    if (b > 0) {
      EXPECT_GE(GST_BUFFER_PTS(buf), GST_BUFFER_PTS(p.out()[b - 1]));
    }
  }
  // Spot-check against hand-computed values too.
  EXPECT_EQ(floats(p.out()[0], 0)[0], -2.5f);
  EXPECT_EQ(floats(p.out()[0], 0)[1], 500.0f);
  EXPECT_EQ(floats(p.out()[0], 0)[2], (-123456.0f + 10.0f) * 0.25f);
  // Every setting is put back once the pipeline is in NULL.
  for (const char *c : {"in_accel_x", "in_accel_y", "in_voltage2"})
    EXPECT_EQ(get(f.scan / (std::string(c) + "_en")), "0") << c;
  EXPECT_EQ(get(f.d / "sampling_frequency"), "100");
  EXPECT_EQ(get(f.d / "buffer" / "length"), "2");
}

TEST(TensorSrcIio, CapsAndSettingsWhilePlaying) {
  FakeIio f;
  f.scans(8, true, true, true);
  Pipe p(
      "tensor_src_iio name=src device-number=0 channels=all buffer-capacity=4 "
      "frequency=200 trigger=fake-trig " +
      f.props() + "! appsink name=out sync=false max-buffers=1");
  ASSERT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_PLAYING), GST_STATE_CHANGE_ASYNC);
  GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(p.get("out")), 5 * GST_SECOND);
  ASSERT_NE(s, nullptr);
  gst_sample_unref(s);
  std::string caps = caps_of(p, "out");
  EXPECT_NE(caps.find("3:4"), std::string::npos) << caps;
  EXPECT_NE(caps.find("float32"), std::string::npos) << caps;
  EXPECT_NE(caps.find("50/1"), std::string::npos) << caps;  // 200 Hz / 4 samples per buffer
  EXPECT_EQ(get(f.scan / "in_accel_y_en"), "1");
  EXPECT_EQ(get(f.d / "sampling_frequency"), "200");
  EXPECT_EQ(get(f.d / "buffer" / "length"), "4");
  EXPECT_EQ(get(f.d / "buffer" / "enable"), "1");
  EXPECT_EQ(get(f.d / "trigger" / "current_trigger"), "fake-trig");
  gst_element_set_state(p.pipeline(), GST_STATE_NULL);
  EXPECT_EQ(get(f.scan / "in_accel_y_en"), "0");
  EXPECT_EQ(get(f.d / "sampling_frequency"), "100");
  EXPECT_EQ(get(f.d / "buffer" / "length"), "2");
  EXPECT_EQ(get(f.d / "buffer" / "enable"), "0");
  EXPECT_EQ(get(f.d / "trigger" / "current_trigger"), "");
}

TEST(TensorSrcIio, OneTensorPerChannelAndChannelList) {
  FakeIio f;
  f.scans(4, true, false, true);  // channels 0 and 2 only: x@0, v@4, 8-byte scans
  Pipe p(
      "tensor_src_iio device=fake_accel channels=0,2 merge-channels-data=false "
      "buffer-capacity=2 frequency=1000 " +
      f.props() + "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), 2u);
  for (int b = 0; b < 2; ++b) {
    ASSERT_EQ(gst_buffer_n_memory(p.out()[b]), 2u);
    auto x = floats(p.out()[b], 0), v = floats(p.out()[b], 1);
    ASSERT_EQ(x.size(), 2u);
    for (int s = 0; s < 2; ++s) {
      EXPECT_EQ(x[s], x_val(b * 2 + s));
      EXPECT_EQ(v[s], v_val(b * 2 + s));
    }
  }
}

TEST(TensorSrcIio, AutoKeepsEnabledChannelsAndLaysOutTheTimestamp) {
  FakeIio f;
  f.channel("in_accel_x", 0, "le:s12/16>>4", true);
  f.channel("in_accel_y", 1, "be:u10/16>>6", true);
  f.channel("in_timestamp", 3, "le:s64/64>>0", true);
  f.scans(2, true, true, false, true);  // x@0, y@2, timestamp@8: 16-byte scans
  Pipe p("tensor_src_iio device=fake_accel buffer-capacity=1 frequency=1000 " + f.props() +
         "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), 2u);
  for (int k = 0; k < 2; ++k) {
    auto v = floats(p.out()[k], 0);
    ASSERT_EQ(v.size(), 2u);  // the timestamp channel is not output
    EXPECT_EQ(v[0], x_val(k));
    EXPECT_EQ(v[1], y_val(k));
  }
  EXPECT_EQ(get(f.scan / "in_voltage2_en"), "0");  // auto did not enable it
}

TEST(TensorSrcIio, OneShotReadsRawAttributes) {
  FakeIio f;
  put(f.d / "in_accel_x_raw", "-7\n");
  put(f.d / "in_accel_y_raw", "12\n");
  put(f.d / "in_voltage2_raw", "90\n");
  Pipe p(
      "tensor_src_iio mode=one-shot device=fake_accel channels=all buffer-capacity=2 "
      "frequency=1000 num-buffers=2 " +
      f.props() + "! appsink name=out sync=false");
  p.collect("out");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out().size(), 2u);
  auto v = floats(p.out()[1], 0);
  ASSERT_EQ(v.size(), 6u);
  EXPECT_EQ(v[0], -3.5f);
  EXPECT_EQ(v[1], 6.0f);
  EXPECT_EQ(v[2], (90.0f + 10.0f) * 0.25f);
  EXPECT_EQ(v[3], -3.5f);
}

namespace {

void expect_error(const std::string &desc, std::initializer_list<std::string> parts) {
  auto r = run_pipeline(desc, 10);
  ASSERT_TRUE(r.error) << "no error for: " << desc;
  EXPECT_NE(r.error_source.find("tensorsrciio"), std::string::npos) << r.error_source;
  for (const auto &part : parts)
    EXPECT_NE(r.error_text.find(part), std::string::npos) << r.error_text;
}

}  // namespace

TEST(TensorSrcIioErrors, MissingDeviceNamesIt) {
  FakeIio f;
  f.scans(2, true, true, true);
  expect_error("tensor_src_iio device=no_such_sensor " + f.props() + "! fakesink",
               {"no_such_sensor", f.base.string()});
  expect_error("tensor_src_iio device-number=7 " + f.props() + "! fakesink",
               {(f.base / "iio:device7" / "name").string()});
  expect_error("tensor_src_iio " + f.props() + "! fakesink", {"device-number"});
}

TEST(TensorSrcIioErrors, BadTreeNamesTheFile) {
  {
    FakeIio f;
    f.channel("in_accel_y", 1, "le:x10/16>>6", false);
    expect_error("tensor_src_iio device=fake_accel " + f.props() + "! fakesink",
                 {(f.scan / "in_accel_y_type").string(), "le:x10/16>>6"});
  }
  {
    FakeIio f;
    fs::remove(f.scan / "in_voltage2_index");
    expect_error("tensor_src_iio device=fake_accel " + f.props() + "! fakesink",
                 {(f.scan / "in_voltage2_index").string()});
  }
  {
    FakeIio f;
    put(f.d / "in_accel_scale", "fast\n");
    expect_error("tensor_src_iio device=fake_accel " + f.props() + "! fakesink",
                 {(f.d / "in_accel_scale").string(), "fast"});
  }
  {
    FakeIio f;  // the character device vanished
    expect_error(
        "tensor_src_iio device=fake_accel channels=all frequency=100 " + f.props() + "! fakesink",
        {(f.dev / "iio:device0").string()});
    // and the settings were put back when start failed
    EXPECT_EQ(get(f.scan / "in_accel_x_en"), "0");
    EXPECT_EQ(get(f.d / "buffer" / "length"), "2");
  }
  {
    FakeIio f;
    fs::remove_all(f.scan);
    expect_error("tensor_src_iio device=fake_accel " + f.props() + "! fakesink",
                 {f.scan.string(), "not a buffered device"});
  }
}

TEST(TensorSrcIioErrors, BadSettingsAndTruncatedData) {
  FakeIio f;
  f.scans(2, true, true, true);
  expect_error("tensor_src_iio device=fake_accel frequency=300 " + f.props() + "! fakesink",
               {"frequency 300", "100 200 1000"});
  expect_error("tensor_src_iio device=fake_accel channels=0,9 " + f.props() + "! fakesink",
               {"channel index 9", "0,1,2,3"});
  expect_error("tensor_src_iio device=fake_accel trigger=nope " + f.props() + "! fakesink",
               {"nope"});
  expect_error(
      "tensor_src_iio device=fake_accel mode=one-shot channels=all " + f.props() + "! fakesink",
      {"in_accel_x_raw"});
  f.scans(3, true, true, true, false, 3);  // one full buffer of 2 scans, then 1 scan + 3 bytes
  expect_error("tensor_src_iio device=fake_accel channels=all buffer-capacity=2 frequency=1000 " +
                   f.props() + "! fakesink",
               {"ended inside a buffer", "11 of 16 bytes"});
}

TEST(TensorSrcIio, PropertyDefaultsAsUpstream) {
  GstElement *e = gst_element_factory_make("tensor_src_iio", nullptr);
  ASSERT_NE(e, nullptr);
  gchar *mode = nullptr, *base = nullptr, *dev = nullptr, *channels = nullptr, *device = nullptr;
  gint devnum = 0, trignum = 0, poll = 0;
  guint cap = 0;
  gulong freq = 1;
  gboolean merge = FALSE, silent = FALSE;
  g_object_get(e, "mode", &mode, "iio-base-dir", &base, "dev-dir", &dev, "channels", &channels,
               "device", &device, "device-number", &devnum, "trigger-number", &trignum,
               "poll-timeout", &poll, "buffer-capacity", &cap, "frequency", &freq,
               "merge-channels-data", &merge, "silent", &silent, nullptr);
  EXPECT_STREQ(mode, "continuous");
  EXPECT_STREQ(base, "/sys/bus/iio/devices");
  EXPECT_STREQ(dev, "/dev");
  EXPECT_STREQ(channels, "auto");
  EXPECT_EQ(device, nullptr);
  EXPECT_EQ(devnum, -1);
  EXPECT_EQ(trignum, -1);
  EXPECT_EQ(poll, 10000);
  EXPECT_EQ(cap, 1u);
  EXPECT_EQ(freq, 0u);
  EXPECT_TRUE(merge);
  EXPECT_TRUE(silent);
  g_object_set(e, "channels", "3;1,1", nullptr);
  g_free(channels);
  g_object_get(e, "channels", &channels, nullptr);
  EXPECT_STREQ(channels, "1,3");
  g_free(mode);
  g_free(base);
  g_free(dev);
  g_free(channels);
  g_free(device);
  gst_object_unref(e);
}

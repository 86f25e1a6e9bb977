// SPDX-License-Identifier: LGPL-2.1-only
// tensor_crop: static and flexible raw input, crop info of several types, clipping (warning),
// regions outside the frame (bus error), lateness, output layout (flexible headers).
#include <gtest/gtest.h>

#include "core/meta_header.h"
#include "elements/cycle_check.h"
#include "elements/flow_harness.h"

namespace {

using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::Frame;
using nns::test::static_caps;

const char *kFlex = "other/tensors,format=flexible,framerate=(fraction)30/1";

// 3-channel uint8 frame of width 6, height 4: value = 10*y + x + 100*c (as uint8).
Bytes raw_frame() {
  Bytes b(3 * 6 * 4);
  for (int y = 0; y < 4; ++y)
    for (int x = 0; x < 6; ++x)
      for (int c = 0; c < 3; ++c)
        b[(y * 6 + x) * 3 + c] = static_cast<uint8_t>(10 * y + x + 100 * c);
  return b;
}

Bytes expected_crop(int x0, int y0, int w, int h) {
  Bytes full = raw_frame(), out;
  for (int y = y0; y < y0 + h; ++y)
    for (int x = x0; x < x0 + w; ++x)
      for (int c = 0; c < 3; ++c) out.push_back(full[(y * 6 + x) * 3 + c]);
  return out;
}

Bytes with_header(nns::TensorType type, std::initializer_list<uint32_t> dims, const Bytes &p) {
  nns::MetaHeader h;
  h.type = type;
  h.dims = nns::make_dims(dims);
  h.format = nns::TensorFormat::kFlexible;
  Bytes b(nns::kMetaHeaderSize + p.size());
  nns::write_meta_header(h, b.data());
  std::copy(p.begin(), p.end(), b.begin() + nns::kMetaHeaderSize);
  return b;
}

template <typename T>
Bytes info_of(const std::vector<T> &regions) {
  return with_header(sizeof(T) == 4 ? nns::TensorType::kUInt32 : nns::TensorType::kUInt16,
                     {4, static_cast<uint32_t>(regions.size() / 4)}, nns::test::bytes_of(regions));
}

struct CropRun {
  nns::test::RunResult r;
  std::vector<Frame> out;
};

CropRun run_crop(const std::string &raw_caps, const std::vector<Frame> &raw,
                 const std::vector<Frame> &info, const std::string &props = "") {
  AppPipeline p("appsrc name=raw ! crop.raw appsrc name=info ! crop.info tensor_crop name=crop " +
                props + " ! appsink name=out");
  p.set_caps("raw", raw_caps);
  p.set_caps("info", kFlex);
  for (const auto &f : raw) p.push("raw", f);
  for (const auto &f : info) p.push("info", f);
  p.eos("raw");
  p.eos("info");
  CropRun c;
  c.r = p.run(10);
  c.out = p.frames("out");
  return c;
}

void expect_region(const Bytes &mem, int x, int y, int w, int h) {
  ASSERT_GE(mem.size(), nns::kMetaHeaderSize);
  auto hd = nns::parse_meta_header(mem.data(), mem.size());
  EXPECT_EQ(hd.format, nns::TensorFormat::kFlexible);
  EXPECT_EQ(hd.type, nns::TensorType::kUInt8);
  EXPECT_EQ(nns::dims_to_string(hd.dims),
            "3:" + std::to_string(w) + ":" + std::to_string(h) + ":1");
  EXPECT_EQ(Bytes(mem.begin() + nns::kMetaHeaderSize, mem.end()), expected_crop(x, y, w, h));
}

TEST(TensorCrop, StaticRawUint32Regions) {
  auto c = run_crop(static_caps("3:6:4:1", "uint8", "30/1"),
                    {Frame({raw_frame()}, 0), Frame({raw_frame()}, 33 * GST_MSECOND)},
                    {Frame({info_of<uint32_t>({1, 1, 2, 2, 0, 0, 6, 4})}, 0),
                     Frame({info_of<uint32_t>({4, 2, 2, 1})}, 33 * GST_MSECOND)});
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(c.out.size(), 2u);
  ASSERT_EQ(c.out[0].mems.size(), 2u);
  expect_region(c.out[0].mems[0], 1, 1, 2, 2);
  expect_region(c.out[0].mems[1], 0, 0, 6, 4);
  ASSERT_EQ(c.out[1].mems.size(), 1u);
  expect_region(c.out[1].mems[0], 4, 2, 2, 1);
  EXPECT_EQ(c.out[1].pts, 33 * GST_MSECOND);
  EXPECT_NE(c.out[0].caps.find("format=(string)flexible"), std::string::npos) << c.out[0].caps;
  EXPECT_NE(c.out[0].caps.find("framerate=(fraction)30/1"), std::string::npos) << c.out[0].caps;
}

TEST(TensorCrop, FlexibleRawUint16RegionsAndZeroSizeMeansToTheEdge) {
  auto c =
      run_crop(kFlex, {Frame({with_header(nns::TensorType::kUInt8, {3, 6, 4, 1}, raw_frame())}, 0)},
               {Frame({info_of<uint16_t>({2, 1, 0, 0})}, 0)});
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(c.out.size(), 1u);
  expect_region(c.out[0].mems[0], 2, 1, 4, 3);
}

TEST(TensorCrop, RegionPastTheEdgeIsClipped) {
  auto c = run_crop(static_caps("3:6:4:1", "uint8"), {Frame({raw_frame()}, 0)},
                    {Frame({info_of<uint32_t>({4, 3, 5, 5})}, 0)});
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(c.out.size(), 1u);
  expect_region(c.out[0].mems[0], 4, 3, 2, 1);
}

TEST(TensorCrop, RegionOutsideTheFrameIsABusError) {
  auto c = run_crop(static_caps("3:6:4:1", "uint8"), {Frame({raw_frame()}, 0)},
                    {Frame({info_of<uint32_t>({0, 0, 1, 1, 6, 0, 2, 2})}, 0)});
  ASSERT_TRUE(c.r.error);
  EXPECT_NE(
      c.r.error_text.find("crop: crop region 1 (x=6, y=0, w=2, h=2) starts outside the 6x4 frame"),
      std::string::npos)
      << c.r.error_text;
}

TEST(TensorCrop, MalformedInfoAndRawAreBusErrors) {
  Bytes bad_info = with_header(nns::TensorType::kUInt32, {3}, Bytes(12, 0));
  auto c =
      run_crop(static_caps("3:6:4:1", "uint8"), {Frame({raw_frame()}, 0)}, {Frame({bad_info}, 0)});
  ASSERT_TRUE(c.r.error);
  EXPECT_NE(c.r.error_text.find("crop info has 12 bytes of uint32, not a whole number"),
            std::string::npos)
      << c.r.error_text;
  c = run_crop(static_caps("3:6:4:1", "uint8"), {Frame({raw_frame()}, 0)},
               {Frame({Bytes(16, 1)}, 0)});
  ASSERT_TRUE(c.r.error);
  EXPECT_NE(c.r.error_text.find("info pad: flexible tensor memory of 16 bytes"), std::string::npos)
      << c.r.error_text;
  // raw caps for two frames (144 bytes), buffer of one (72)
  c = run_crop(static_caps("3:6:4:2", "uint8"), {Frame({raw_frame()}, 0)},
               {Frame({info_of<uint32_t>({0, 0, 1, 1})}, 0)});
  ASSERT_TRUE(c.r.error);
  EXPECT_NE(c.r.error_text.find("crop: raw tensor has 72 bytes, expected 144 for uint8 3:6:4:2"),
            std::string::npos)
      << c.r.error_text;
  // right size, but not one NHWC frame
  Bytes two = raw_frame();
  two.insert(two.end(), two.begin(), two.end());
  c = run_crop(static_caps("3:6:4:2", "uint8"), {Frame({two}, 0)},
               {Frame({info_of<uint32_t>({0, 0, 1, 1})}, 0)});
  ASSERT_TRUE(c.r.error);
  EXPECT_NE(c.r.error_text.find("crop: raw tensor uint8 3:6:4:2 is not one NHWC frame "
                                "(channel:width:height:1)"),
            std::string::npos)
      << c.r.error_text;
}

// Regions {i, 0, 1, 1} for frame i (i = 0..n-1), raw and info at the same PTS.
std::vector<Frame> raw_frames(int n) {
  std::vector<Frame> v;
  for (int i = 0; i < n; ++i) v.push_back(Frame({raw_frame()}, i * 10 * GST_MSECOND));
  return v;
}
std::vector<Frame> info_frames(int n) {
  std::vector<Frame> v;
  for (int i = 0; i < n; ++i)
    v.push_back(Frame({info_of<uint32_t>({uint32_t(i), 0, 1, 1})}, i * 10 * GST_MSECOND));
  return v;
}

void expect_first_pairs(const std::vector<Frame> &out, std::size_t n) {
  ASSERT_EQ(out.size(), n);
  for (std::size_t i = 0; i < n; ++i) {
    EXPECT_EQ(out[i].pts, i * 10 * GST_MSECOND);
    ASSERT_EQ(out[i].mems.size(), 1u);
    expect_region(out[i].mems[0], int(i), 0, 1, 1);
  }
}

// EOS on info after 2 regions while raw still has 20 frames: the 2 pairs are cropped, then the
// stream ends (raw's producer gets EOS back) instead of waiting for info forever.
TEST(TensorCrop, EosOnInfoWhileRawFlowsEndsTheStream) {
  auto c = run_crop(static_caps("3:6:4:1", "uint8", "100/1"), raw_frames(20), info_frames(2));
  ASSERT_TRUE(c.r.eos) << (c.r.timed_out ? "timed out" : c.r.error_text);
  expect_first_pairs(c.out, 2);
}

TEST(TensorCrop, EosOnRawWhileInfoFlowsEndsTheStream) {
  auto c = run_crop(static_caps("3:6:4:1", "uint8", "100/1"), raw_frames(3), info_frames(20));
  ASSERT_TRUE(c.r.eos) << (c.r.timed_out ? "timed out" : c.r.error_text);
  expect_first_pairs(c.out, 3);
}

// 100 PLAYING<->NULL cycles: two pairs cropped; raw without info (stop while waiting); EOS on
// info while raw flows; EOS on raw while info flows. No hang, nothing left alive.
TEST(TensorCrop, HundredPlayingNullCyclesNoHangNoLeak) {
  AppPipeline p(
      "appsrc name=raw ! crop.raw appsrc name=info ! crop.info tensor_crop name=crop "
      "! fakesink name=out");
  p.set_caps("raw", static_caps("3:6:4:1", "uint8", "100/1"));
  p.set_caps("info", kFlex);
  nns::test::state_cycles(p.pipeline(), 100, [&](int i, nns::test::LiveObjects &live) {
    std::size_t before = live.delivered("out");
    auto raw = raw_frames(3), info = info_frames(3);
    std::string err;
    switch (i % 4) {
      case 0:
        for (int k = 0; k < 2; ++k) p.push("raw", raw[k]), p.push("info", info[k]);
        EXPECT_TRUE(live.wait_delivered("out", before + 2)) << "cycle " << i;
        break;
      case 1:
        for (const auto &f : raw) p.push("raw", f);
        break;
      case 2:
        for (const auto &f : raw) p.push("raw", f);
        p.push("info", info[0]);
        p.eos("info");
        EXPECT_TRUE(nns::test::wait_eos(p.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
        EXPECT_EQ(live.delivered("out"), before + 1) << "cycle " << i;
        break;
      case 3:
        p.push("raw", raw[0]);
        p.eos("raw");
        for (const auto &f : info) p.push("info", f);
        EXPECT_TRUE(nns::test::wait_eos(p.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
        EXPECT_EQ(live.delivered("out"), before + 1) << "cycle " << i;
        break;
    }
  });
}

TEST(TensorCrop, LatenessDropsTheOlderBuffer) {
  // raw at 0, 100 ms; info at 100 ms only: with lateness 20 ms raw@0 is dropped.
  auto c = run_crop(static_caps("3:6:4:1", "uint8"),
                    {Frame({raw_frame()}, 0), Frame({raw_frame()}, 100 * GST_MSECOND)},
                    {Frame({info_of<uint32_t>({0, 0, 1, 1})}, 100 * GST_MSECOND)}, "lateness=20");
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(c.out.size(), 1u);
  EXPECT_EQ(c.out[0].pts, 100 * GST_MSECOND);
  // lateness off: the first pair is cropped whatever the timestamps
  c = run_crop(static_caps("3:6:4:1", "uint8"),
               {Frame({raw_frame()}, 0), Frame({raw_frame()}, 100 * GST_MSECOND)},
               {Frame({info_of<uint32_t>({0, 0, 1, 1})}, 100 * GST_MSECOND)});
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(c.out.size(), 1u);
  EXPECT_EQ(c.out[0].pts, 0u);
}

TEST(TensorCrop, PadsAndPropertiesAsUpstream) {
  GstElement *e = gst_element_factory_make("tensor_crop", nullptr);
  ASSERT_NE(e, nullptr);
  gint lateness = 0;
  g_object_get(e, "lateness", &lateness, nullptr);
  EXPECT_EQ(lateness, -1);
  for (const char *pad : {"raw", "info", "src"}) {
    GstPad *p = gst_element_get_static_pad(e, pad);
    EXPECT_NE(p, nullptr) << pad;
    if (p) gst_object_unref(p);
  }
  gst_object_unref(e);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// End-to-end pipeline tests of tensor_converter and tensor_transform against goldens and
// references computed from stock-GStreamer output (see golden_util.h for the mechanism).
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "pipelines/golden_util.h"

namespace {

using nns::test::floats_near;
using nns::test::matches_golden;
using nns::test::run_to_bytes;

// Stock GStreamer only: pins down the videotestsrc frames the references below start from.
TEST(PipelineGolden, StockVideotestsrcGray8MatchesGolden) {
  auto out = run_to_bytes(
      "videotestsrc num-buffers=2 pattern=gradient ! "
      "video/x-raw,format=GRAY8,width=5,height=3,framerate=0/1 ! filesink location=@OUT@");
  ASSERT_TRUE(out.run.eos) << out.run.error_text;
  ASSERT_EQ(out.bytes.size(), 2u * 8 * 3) << "GRAY8 rows are padded to 4 bytes";
  // The padding bytes are not initialised by videotestsrc: compare the pixels only.
  std::vector<uint8_t> pixels;
  for (int f = 0; f < 2; ++f)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 5; ++x) pixels.push_back(out.bytes[f * 24 + y * 8 + x]);
  EXPECT_TRUE(matches_golden("stock_gradient_gray8_5x3_x2", pixels));
}

// orange.png decoded by stock elements is byte-identical to orange.raw (../shared/models says
// so); the converter must hand those bytes on unchanged.
TEST(PipelineGolden, ConverterOrangeRgbIsTheRawFrame) {
  NNS_REQUIRE_SHARED_MODELS();
  NNS_REQUIRE_ELEMENTS("tensor_converter");
  auto out = run_to_bytes(
      "filesrc location=@SHARED@/data/orange.png ! pngdec ! videoconvert ! "
      "video/x-raw,format=RGB ! tensor_converter ! filesink location=@OUT@");
  ASSERT_TRUE(out.run.eos) << out.run.error_text;
  auto raw = nns::test::read_file(nns::test::shared_models_dir() + "/data/orange.raw");
  ASSERT_EQ(raw.size(), 224u * 224 * 3);
  EXPECT_EQ(out.bytes.size(), raw.size());
  EXPECT_TRUE(out.bytes == raw) << "converter output differs from orange.raw";
  EXPECT_TRUE(matches_golden("orange_rgb_u8", out.bytes));
}

// The demo's normalisation: typecast:float32,add:-127.5,div:127.5 computed in float32 in that
// order, as NNStreamer does.
TEST(PipelineGolden, TransformNormalisesOrangeToMinusOneOne) {
  NNS_REQUIRE_SHARED_MODELS();
  NNS_REQUIRE_ELEMENTS("tensor_converter", "tensor_transform");
  auto out = run_to_bytes(
      "filesrc location=@SHARED@/data/orange.png ! pngdec ! videoconvert ! videoscale ! "
      "video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! "
      "tensor_transform mode=arithmetic option=typecast:float32,add:-127.5,div:127.5 ! "
      "filesink location=@OUT@");
  ASSERT_TRUE(out.run.eos) << out.run.error_text;
  auto raw = nns::test::read_file(nns::test::shared_models_dir() + "/data/orange.raw");
  std::vector<float> want(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) {
    float v = static_cast<float>(raw[i]);
    v = v + -127.5f;
    want[i] = v / 127.5f;
  }
  // Exact with true division; within one float32 ulp of 1.0 if a kernel multiplies by 1/127.5.
  auto r = floats_near(out.bytes, want, 2.5e-7f);
  EXPECT_TRUE(r);
  std::printf("  %s\n", r.message());
  // The golden is numpy's (orange.astype(float32) + float32(-127.5)) / float32(127.5): the same
  // float32 operations in the same order give the same bits.
  EXPECT_TRUE(matches_golden("orange_rgb_f32_normalised", out.bytes));
}

// Row padding: GRAY8 rows of 5 pixels are 8 bytes in video buffers; tensors are dense.
TEST(PipelineGolden, ConverterDropsVideoRowPadding) {
  NNS_REQUIRE_ELEMENTS("tensor_converter");
  const char *src =
      "videotestsrc num-buffers=2 pattern=gradient ! "
      "video/x-raw,format=GRAY8,width=5,height=3,framerate=0/1 ! ";
  auto ref = run_to_bytes(std::string(src) + "filesink location=@OUT@");
  ASSERT_TRUE(ref.run.eos) << ref.run.error_text;
  ASSERT_EQ(ref.bytes.size(), 2u * 8 * 3);
  std::vector<uint8_t> want;
  for (int f = 0; f < 2; ++f)
    for (int y = 0; y < 3; ++y)
      for (int x = 0; x < 5; ++x) want.push_back(ref.bytes[f * 24 + y * 8 + x]);
  auto out = run_to_bytes(std::string(src) + "tensor_converter ! filesink location=@OUT@");
  ASSERT_TRUE(out.run.eos) << out.run.error_text;
  EXPECT_EQ(out.bytes, want);
}

// The benchmark's tiny frames: typecast only, integers are exact in float32.
TEST(PipelineGolden, TransformTypecastGray8ToFloat32IsExact) {
  NNS_REQUIRE_ELEMENTS("tensor_converter", "tensor_transform");
  const char *src =
      "videotestsrc num-buffers=3 pattern=gradient ! "
      "video/x-raw,format=GRAY8,width=4,height=4,framerate=0/1 ! ";
  auto ref = run_to_bytes(std::string(src) + "filesink location=@OUT@");
  ASSERT_TRUE(ref.run.eos) << ref.run.error_text;
  ASSERT_EQ(ref.bytes.size(), 3u * 16);
  std::vector<float> want(ref.bytes.begin(), ref.bytes.end());
  auto out = run_to_bytes(std::string(src) +
                          "tensor_converter ! tensor_transform mode=typecast option=float32 ! "
                          "filesink location=@OUT@");
  ASSERT_TRUE(out.run.eos) << out.run.error_text;
  EXPECT_TRUE(floats_near(out.bytes, want, 0.0f));
}

}  // namespace

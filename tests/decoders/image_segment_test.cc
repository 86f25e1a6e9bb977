// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=image_segment: tflite-deeplab / snpe-deeplab / snpe-depth on small
// synthetic maps (exact RGBA), option and input errors (bus text).
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "decoders/decoder_test_util.h"
#include "support/harness.h"

using nns::test::HarnessPtr;
using nns::test::run_pipeline;
using nns::test::decoder::expect_error;
using nns::test::decoder::tensor_file_src;

namespace {

template <typename T>
GstBuffer *buffer_of(const std::vector<T> &v) {
  GstBuffer *b = gst_buffer_new_allocate(nullptr, v.size() * sizeof(T), nullptr);
  gst_buffer_fill(b, 0, v.data(), v.size() * sizeof(T));
  return b;
}

struct Out {
  std::vector<uint8_t> px;
  std::string caps;
};

template <typename T>
Out decode(const std::string &props, const std::string &type, const std::string &dims,
           const std::vector<T> &data) {
  Out o;
  HarnessPtr h(gst_harness_new_parse(("tensor_decoder mode=image_segment " + props).c_str()));
  gst_harness_set_src_caps_str(h.get(), ("other/tensors,format=static,num_tensors=1,types=" + type +
                                         ",dimensions=(string)" + dims + ",framerate=0/1")
                                            .c_str());
  EXPECT_EQ(gst_harness_push(h.get(), buffer_of(data)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  EXPECT_NE(out, nullptr);
  if (!out) return o;
  o.px.resize(gst_buffer_get_size(out));
  gst_buffer_extract(out, 0, o.px.data(), o.px.size());
  gst_buffer_unref(out);
  GstCaps *c = gst_pad_get_current_caps(h->sinkpad);
  gchar *s = gst_caps_to_string(c);
  o.caps = s;
  g_free(s);
  gst_caps_unref(c);
  return o;
}

std::vector<uint8_t> px(const Out &o, size_t i) {
  return {o.px[4 * i], o.px[4 * i + 1], o.px[4 * i + 2], o.px[4 * i + 3]};
}

const std::vector<uint8_t> kClear = {0, 0, 0, 0};
// PASCAL VOC palette: 1 = (128,0,0), 2 = (0,128,0), 3 = (128,128,0), 15 (person) = (192,128,128).
const std::vector<uint8_t> kC1 = {128, 0, 0, 255}, kC2 = {0, 128, 0, 255}, kC3 = {128, 128, 0, 255},
                           kC15 = {192, 128, 128, 255};

}  // namespace

TEST(ImageSegment, TfliteDeeplabArgmaxAboveHalf) {
  // 3 classes (option2=2), 2x2 pixels; class scores innermost.
  std::vector<float> s = {
      0.9f, 0.05f, 0.05f,  // (0,0) background
      0.1f, 0.8f,  0.1f,   // (1,0) class 1
      0.2f, 0.2f,  0.6f,   // (0,1) class 2
      0.3f, 0.4f,  0.3f,   // (1,1) class 1 best but 0.4 <= 0.5 -> background
  };
  Out o = decode("option1=tflite-deeplab option2=2", "float32", "3:2:2:1", s);
  ASSERT_EQ(o.px.size(), 16u);
  EXPECT_NE(o.caps.find("format=(string)RGBA"), std::string::npos) << o.caps;
  EXPECT_NE(o.caps.find("width=(int)2"), std::string::npos) << o.caps;
  EXPECT_NE(o.caps.find("height=(int)2"), std::string::npos) << o.caps;
  EXPECT_EQ(px(o, 0), kClear);
  EXPECT_EQ(px(o, 1), kC1);
  EXPECT_EQ(px(o, 2), kC2);
  EXPECT_EQ(px(o, 3), kClear);
}

TEST(ImageSegment, TfliteDeeplabDefault21ClassesPerson) {
  std::vector<float> s(21 * 3 * 1, 0.0f);
  s[0 * 21 + 0] = 1.0f;   // background
  s[1 * 21 + 15] = 0.7f;  // person
  s[2 * 21 + 20] = 0.9f;  // class 20 (tvmonitor)
  Out o = decode("option1=tflite-deeplab", "float32", "21:3:1:1", s);
  ASSERT_EQ(o.px.size(), 12u);
  EXPECT_EQ(px(o, 0), kClear);
  EXPECT_EQ(px(o, 1), kC15);
  EXPECT_EQ(px(o, 2), (std::vector<uint8_t>{0, 64, 128, 255}));
}

TEST(ImageSegment, SnpeDeeplabIndicesFloatAndUint8) {
  // W:H:1 map of class indices; 7 > option2=3 stays transparent, 2.7 truncates to 2.
  Out f = decode("option1=snpe-deeplab option2=3", "float32", "3:2:1:1",
                 std::vector<float>{0.f, 1.f, 2.7f, 3.f, 7.f, -1.f});
  ASSERT_EQ(f.px.size(), 24u);
  EXPECT_NE(f.caps.find("width=(int)3"), std::string::npos) << f.caps;
  EXPECT_NE(f.caps.find("height=(int)2"), std::string::npos) << f.caps;
  EXPECT_EQ(px(f, 0), kClear);
  EXPECT_EQ(px(f, 1), kC1);
  EXPECT_EQ(px(f, 2), kC2);
  EXPECT_EQ(px(f, 3), kC3);
  EXPECT_EQ(px(f, 4), kClear);
  EXPECT_EQ(px(f, 5), kClear);
  Out u = decode("option1=snpe-deeplab", "uint8", "2:1:1:1", std::vector<uint8_t>{15, 0});
  ASSERT_EQ(u.px.size(), 8u);
  EXPECT_EQ(px(u, 0), kC15);
  EXPECT_EQ(px(u, 1), kClear);
}

TEST(ImageSegment, SnpeDepthGrayScaledToMax) {
  Out o =
      decode("option1=snpe-depth", "float32", "1:4:1:1", std::vector<float>{0.f, 1.f, 2.f, 4.f});
  ASSERT_EQ(o.px.size(), 16u);
  EXPECT_EQ(px(o, 0), (std::vector<uint8_t>{0, 0, 0, 255}));
  EXPECT_EQ(px(o, 1), (std::vector<uint8_t>{63, 63, 63, 255}));
  EXPECT_EQ(px(o, 2), (std::vector<uint8_t>{127, 127, 127, 255}));
  EXPECT_EQ(px(o, 3), (std::vector<uint8_t>{255, 255, 255, 255}));
  Out z = decode("option1=snpe-depth", "float32", "1:2:1:1", std::vector<float>{0.f, 0.f});
  EXPECT_EQ(z.px, std::vector<uint8_t>(8, 0));
}

// ---- errors: the bus text names the option or tensor, expected vs got --------------------------

TEST(ImageSegmentErrors, UnknownOption1) {
  expect_error(tensor_file_src("21:2:2:1", 21 * 4 * 4, "float32") +
                   "tensor_decoder mode=image_segment option1=yolo-deeplab ! fakesink",
               "unknown image_segment mode 'yolo-deeplab'");
}

TEST(ImageSegmentErrors, MissingOption1) {
  expect_error(tensor_file_src("21:2:2:1", 21 * 4 * 4, "float32") +
                   "tensor_decoder mode=image_segment ! fakesink",
               "image_segment needs option1=");
}

TEST(ImageSegmentErrors, Option2NotANumber) {
  expect_error(tensor_file_src("21:2:2:1", 21 * 4 * 4, "float32") +
                   "tensor_decoder mode=image_segment option1=tflite-deeplab option2=many ! "
                   "fakesink",
               "option2: max labels must be an integer in 1..65535, got 'many'");
}

TEST(ImageSegmentErrors, WrongTypeForTflite) {
  expect_error(tensor_file_src("21:2:2:1", 21 * 4, "uint8") +
                   "tensor_decoder mode=image_segment option1=tflite-deeplab ! fakesink",
               "tflite-deeplab expects a float32 tensor, got type uint8");
}

TEST(ImageSegmentErrors, ClassCountDiffersFromOption2) {
  expect_error(tensor_file_src("5:2:2:1", 5 * 4 * 4, "float32") +
                   "tensor_decoder mode=image_segment option1=tflite-deeplab ! fakesink",
               "tflite-deeplab expects dim0 = option2 + 1 = 21 classes, got 5 (set option2=4)");
}

TEST(ImageSegmentErrors, DepthNeedsOneChannel) {
  expect_error(tensor_file_src("2:4:4:1", 2 * 16 * 4, "float32") +
                   "tensor_decoder mode=image_segment option1=snpe-depth ! fakesink",
               "snpe-depth expects dims 1:W:H:1 (one depth channel), got dim0 = 2");
}

TEST(ImageSegmentErrors, BatchDimensionRejected) {
  expect_error(tensor_file_src("4:4:1:2", 32 * 4, "float32") +
                   "tensor_decoder mode=image_segment option1=snpe-deeplab ! fakesink",
               "snpe-deeplab expects dims W:H:1:1, got dim3 = 2");
}

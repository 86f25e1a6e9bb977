// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=bounding_boxes with the YOLO schemes in whole pipelines: upstream's
// runTest.sh cases (captured decoder inputs through tensor_converter) drawn by our sub-plugin and
// compared with upstream's golden RGBA frames (box pixels within 1 px, label glyphs excluded);
// the model's own yolov8 layout; bus errors.
#include <gtest/gtest.h>

#include "decoders/bbox_test_util.h"

using nns::test::bbox::collect;
using nns::test::bbox::compare_boxes;
using nns::test::bbox::text_areas;

namespace {

std::string data_dir() {
  return nns::test::shared_models_dir() + "/decoder/nnstreamer_decoder_boundingbox";
}

std::string yolo(const std::string &file, const std::string &dims, const std::string &opts,
                 const std::string &between = "") {
  return "multifilesrc location=" + file +
         " start-index=0 stop-index=0 caps=application/octet-stream ! tensor_converter "
         "input-dim=" + dims + " input-type=float32 ! " + between +
         "tensor_decoder mode=bounding_boxes " + opts + " ! appsink name=out";
}

void expect_golden(const std::string &desc, const std::string &golden, int w, int h,
                   std::size_t boxes) {
  auto c = collect(desc, data_dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 1u);
  EXPECT_EQ(c.frames[0].rois.size(), boxes);
  const auto ref = nns::test::read_file(data_dir() + "/" + golden);
  EXPECT_EQ(compare_boxes(c.frames[0].data, ref, false, w, h, text_areas(c.frames[0].rois)), "");
}

const std::string k320 = " option4=320:320 option5=320:320 option6=0 option7=1";

}  // namespace

TEST(BboxYoloPipeline, Yolov5Golden) {
  NNS_REQUIRE_SHARED_MODELS();
  expect_golden(yolo("yolov5_decoder_input.raw", "85:6300:1",
                     "option1=yolov5 option2=coco-80.txt option3=0:0.25:0.45" + k320),
                "yolov5_result_golden.raw", 320, 320, 4);
}

TEST(BboxYoloPipeline, Yolov8Golden) {
  NNS_REQUIRE_SHARED_MODELS();
  expect_golden(yolo("yolov8_decoder_input.raw", "84:2100:1",
                     "option1=yolov8 option2=coco-80.txt option3=0:0.25:0.45" + k320),
                "yolov8_result_golden.raw", 320, 320, 3);
}

// The model's own layout (2100:84, what a yolov8 tflite/onnx model emits before upstream's
// required transpose) gives the same frame.
TEST(BboxYoloPipeline, Yolov8ModelLayoutGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  expect_golden(yolo("yolov8_decoder_input.raw", "84:2100:1",
                     "option1=yolov8 option2=coco-80.txt option3=0:0.25:0.45" + k320,
                     "tensor_transform mode=transpose option=1:0:2:3 ! "),
                "yolov8_result_golden.raw", 320, 320, 3);
}

TEST(BboxYoloPipeline, Yolov10Golden) {
  NNS_REQUIRE_SHARED_MODELS();
  expect_golden(yolo("yolov10_decoder_input.raw", "6:300:1",
                     "option1=yolov10 option2=coco-80.txt option3=0:0.25" + k320),
                "yolov10_result_golden.raw", 320, 320, 5);
}

TEST(BboxYoloPipeline, WrongDimsPostError) {
  NNS_REQUIRE_SHARED_MODELS();
  // runTest.sh "8 yolov8 decoder_n".
  auto c = collect(yolo("yolov8_decoder_input.raw", "84:8400:1",
                        "option1=yolov8 option2=coco-80.txt option3=0:0.25:0.45" + k320),
                   data_dir());
  EXPECT_NE(c.error.find("scheme yolov8 expects float32 84:2100:1"), std::string::npos)
      << c.error;
  EXPECT_NE(c.error.find("got float32 84:8400:1"), std::string::npos) << c.error;
}

TEST(BboxYoloPipeline, BadOption3PostsError) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect(yolo("yolov8_decoder_input.raw", "84:2100:1",
                        "option1=yolov8 option2=coco-80.txt option3=0:high" + k320),
                   data_dir());
  EXPECT_NE(c.error.find("option3 of scheme yolov8: field 2 (conf) expects a number in [0, 1], "
                         "got 'high'"),
            std::string::npos)
      << c.error;
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=bounding_boxes with the YOLO schemes in whole pipelines: upstream's
// runTest.sh cases (captured decoder inputs through tensor_converter) drawn by our sub-plugin and
// compared with upstream's golden RGBA frames pixel for pixel (the label glyphs excepted: ours
// are the X11 misc-fixed font, in the same cells);
// the model's own yolov8 layout; bus errors.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

#include "decoders/bbox_test_util.h"

using nns::test::bbox::collect;
using nns::test::bbox::compare_exact;
using nns::test::bbox::data_dir;
using nns::test::bbox::label_cells;

namespace {

std::string yolo(const std::string &file, const std::string &dims, const std::string &opts,
                 const std::string &between = "") {
  return "multifilesrc location=" + file +
         " start-index=0 stop-index=0 caps=application/octet-stream ! tensor_converter "
         "input-dim=" +
         dims + " input-type=float32 ! " + between + "tensor_decoder mode=bounding_boxes " + opts +
         " ! appsink name=out";
}

void expect_golden(const std::string &desc, const std::string &golden, int w, int h,
                   std::size_t boxes) {
  auto c = collect(desc, data_dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 1u);
  EXPECT_EQ(c.frames[0].rois.size(), boxes);
  const auto ref = nns::test::read_file(data_dir() + "/" + golden);
  EXPECT_EQ(compare_exact(c.frames[0].data, ref, false, w, h, label_cells(c.frames[0].rois, w)),
            "");
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
  EXPECT_NE(c.error.find("scheme yolov8 expects float32 84:2100:1"), std::string::npos) << c.error;
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

// yolov8-obb (runTest.sh case 10): rotated outlines, no labels: the frame is upstream's, pixel
// for pixel (same truncated boxes, same sampled oriented NMS, same rasterization).
TEST(BboxYoloPipeline, Yolov8ObbGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  const std::string dir = nns::test::make_temp_dir();
  const std::string labels = dir + "/dota8-obb-label.txt";
  {
    std::ofstream f(labels);
    f << "plane\nship\nstorage tank\nbaseball diamond\ntennis court\nbasketball court\n"
         "ground track field\nharbor\nbridge\nlarge vehicle\nsmall vehicle\nhelicopter\n"
         "roundabout\nsoccer ball field\nswimming pool\n";
  }
  auto c = collect(yolo("yolov8_obb_decoder_input.raw", "20:8400:1",
                        "option1=yolov8-obb option2=" + labels +
                            " option3=0:0.25:0.45 option4=640:640 option5=640:640"),
                   data_dir());
  std::filesystem::remove_all(dir);
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 1u);
  EXPECT_EQ(c.frames[0].rois.size(), 117u);
  const auto ref = nns::test::read_file(data_dir() + "/yolov8_obb_decoder_result_golden.raw");
  EXPECT_EQ(c.frames[0].data, ref) << compare_exact(c.frames[0].data, ref, false, 640, 640, {});
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=tensor_region: crop regions from mobilenet-ssd output as a flexible
// uint32 4:N tensor, and upstream's pipeline into tensor_crop compared with its reference
// crop (tensor_region_orange.txt, RGBx bytes of the orange cropped from the 300x300 photo).
#include <gtest/gtest.h>

#include <cstring>

#include "core/meta_header.h"
#include "decoders/bbox_test_util.h"

using nns::test::bbox::collect;

namespace {

std::string dir() {
  return nns::test::shared_models_dir() + "/decoder/nnstreamer_decoder_tensor_region";
}

std::string inputs() {
  return " filesrc location=mobilenet_ssd_tensor.0 blocksize=-1 ! application/octet-stream ! "
         "tensor_converter input-dim=4:1:1917:1 input-type=float32 ! mux.sink_0 filesrc "
         "location=mobilenet_ssd_tensor.1 blocksize=-1 ! application/octet-stream ! "
         "tensor_converter input-dim=91:1917:1 input-type=float32 ! mux.sink_1";
}

const std::string kLabelsPriors =
    " option2=../nnstreamer_decoder_boundingbox/coco_labels_list.txt "
    "option3=../nnstreamer_decoder_boundingbox/box_priors.txt";

}  // namespace

TEST(TensorRegion, RegionsAsFlexibleTensor) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect(
      "tensor_mux name=mux ! other/tensors,format=static ! tensor_decoder "
      "mode=tensor_region option1=3" +
          kLabelsPriors + " ! appsink name=out" + inputs(),
      dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 1u);
  const auto &d = c.frames[0].data;
  ASSERT_EQ(d.size(), nns::kMetaHeaderSize + 3 * 4 * 4);
  auto h = nns::parse_meta_header(d.data(), d.size());
  EXPECT_EQ(h.type, nns::TensorType::kUInt32);
  EXPECT_EQ(h.dims[0], 4u);
  EXPECT_EQ(h.dims[1], 3u);
  uint32_t r[12];
  std::memcpy(r, d.data() + nns::kMetaHeaderSize, sizeof r);
  // The best region is the orange; its crop has the size of upstream's reference crop
  // (184836 bytes of RGBx).
  EXPECT_GT(r[2], 0u);
  EXPECT_EQ(static_cast<std::size_t>(r[2]) * r[3] * 4, 184836u)
      << r[0] << "," << r[1] << " " << r[2] << "x" << r[3];
  // Only one detection: the other slots are zero.
  for (int i = 4; i < 12; ++i) EXPECT_EQ(r[i], 0u) << i;
}

TEST(TensorRegion, CropMatchesUpstreamReference) {
  NNS_REQUIRE_SHARED_MODELS();
  const std::string photo = nns::test::shared_models_dir() + "/data/orange.png";
  auto c = collect(
      "filesrc location=" + photo +
          " ! pngdec ! videoconvert ! videoscale ! "
          "video/x-raw,width=300,height=300,format=RGB,framerate=0/1 ! tensor_converter ! "
          "crop.raw tensor_mux name=mux ! other/tensors,format=static ! tensor_decoder "
          "mode=tensor_region option1=1" +
          kLabelsPriors +
          " ! crop.info tensor_crop name=crop ! other/tensors,format=flexible ! tensor_converter "
          "! tensor_decoder mode=direct_video ! videoconvert ! video/x-raw,format=RGBx ! "
          "appsink name=out" +
          inputs(),
      dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 1u);
  auto ref = nns::test::read_file(dir() + "/tensor_region_orange.txt");
  ASSERT_EQ(c.frames[0].data.size(), ref.size());
  EXPECT_TRUE(c.frames[0].data == std::vector<uint8_t>(ref.begin(), ref.end()));
}

TEST(TensorRegion, Errors) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect("tensor_mux name=mux ! tensor_decoder mode=tensor_region option1=0" +
                       kLabelsPriors + " ! appsink name=out" + inputs(),
                   dir());
  EXPECT_NE(c.error.find("option1: number of regions must be an integer 1..1024, got '0'"),
            std::string::npos)
      << c.error;
  c = collect(
      "tensor_mux name=mux ! tensor_decoder mode=tensor_region option1=1 "
      "option2=../nnstreamer_decoder_boundingbox/coco-80.txt "
      "option3=../nnstreamer_decoder_boundingbox/box_priors.txt ! appsink name=out" +
          inputs(),
      dir());
  EXPECT_NE(c.error.find("91 classes but option2 gives 80 labels"), std::string::npos) << c.error;
  c = collect("tensor_mux name=mux ! tensor_decoder mode=tensor_region option1=1" + kLabelsPriors +
                  " option4=abc ! appsink name=out" + inputs(),
              dir());
  EXPECT_NE(c.error.find("option4: input video size must be WIDTH:HEIGHT"), std::string::npos)
      << c.error;
}

// Upstream's second case: more regions than detections; the zero slots make tensor_crop crop
// the whole 300x300 frame, so the output holds at least two whole-frame crops.
TEST(TensorRegion, ZeroSlotsCropWholeFrame) {
  NNS_REQUIRE_SHARED_MODELS();
  const std::string photo = nns::test::shared_models_dir() + "/data/orange.png";
  auto c = collect("filesrc location=" + photo +
                       " ! pngdec ! videoconvert ! videoscale ! "
                       "video/x-raw,width=300,height=300,format=RGB,framerate=0/1 ! "
                       "tensor_converter ! crop.raw tensor_mux name=mux ! "
                       "other/tensors,format=static ! tensor_decoder mode=tensor_region option1=3" +
                       kLabelsPriors +
                       " ! crop.info tensor_crop name=crop ! other/tensors,format=flexible ! "
                       "appsink name=out" +
                       inputs(),
                   dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  std::size_t total = 0;
  for (const auto &f : c.frames) total += f.data.size();
  EXPECT_GE(total, 2u * (128 + 300 * 300 * 3));
}

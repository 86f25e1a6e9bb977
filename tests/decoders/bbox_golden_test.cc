// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=bounding_boxes against NNStreamer's captured detector tensors and
// reference frames (../shared/models/upstream/decoder/nnstreamer_decoder_boundingbox, the
// pipelines of upstream's runTest.sh): the same frames pixel for pixel, the label glyphs excepted
// (ours are the X11 misc-fixed font; the cells they fill are the same), the same number of boxes,
// and the classes read from the reference images.
#include <gtest/gtest.h>

#include "decoders/bbox_test_util.h"

using nns::test::bbox::collect;
using nns::test::bbox::compare_exact;
using nns::test::bbox::data_dir;
using nns::test::bbox::kSsdInputs;
using nns::test::bbox::label_cells;

namespace {

const std::string kPpInputs =
    " multifilesrc location=mobilenetssd_postprocess_tensors.0.%d start-index=0 stop-index=1 "
    "caps=application/octet-stream ! tensor_converter input-dim=1 input-type=float32 ! mux.sink_0"
    " multifilesrc location=mobilenetssd_postprocess_tensors.1.%d start-index=0 stop-index=1 "
    "caps=application/octet-stream ! tensor_converter input-dim=100:1 input-type=float32 ! "
    "mux.sink_1 multifilesrc location=mobilenetssd_postprocess_tensors.2.%d start-index=0 "
    "stop-index=1 caps=application/octet-stream ! tensor_converter input-dim=100:1 "
    "input-type=float32 ! mux.sink_2 multifilesrc location=mobilenetssd_postprocess_tensors.3.%d "
    "start-index=0 stop-index=1 caps=application/octet-stream ! tensor_converter "
    "input-dim=4:100:1 input-type=float32 ! mux.sink_3";

const std::string kPalmInputs =
    " multifilesrc location=palm_detection_input_0.%d start-index=0 stop-index=1 "
    "caps=application/octet-stream ! tensor_converter input-dim=18:2016:1:1 input-type=float32 ! "
    "mux.sink_0 multifilesrc location=palm_detection_input_1.%d start-index=0 stop-index=1 "
    "caps=application/octet-stream ! tensor_converter input-dim=1:2016:1:1 input-type=float32 ! "
    "mux.sink_1";

std::vector<std::string> labels_of(const nns::test::bbox::Frame &f) {
  std::vector<std::string> v;
  for (const auto &r : f.rois) v.push_back(r.label);
  return v;
}

// Runs `decoder` (tensor_decoder ...) on `inputs` and compares both frames with
// <golden>.0/.1; `classes[i]` are the labels seen in reference frame i, best score first.
void check_golden(const std::string &decoder, const std::string &inputs, const std::string &golden,
                  bool bgrx, const std::vector<std::vector<std::string>> &classes) {
  const std::string desc =
      "tensor_mux name=mux ! " + decoder + " ! appsink name=out sync=false" + inputs;
  auto c = collect(desc, data_dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_TRUE(c.eos);
  ASSERT_EQ(c.frames.size(), 2u);
  for (std::size_t i = 0; i < 2; ++i) {
    SCOPED_TRACE("frame " + std::to_string(i));
    const auto &f = c.frames[i];
    auto ref = nns::test::read_file(data_dir() + "/" + golden + "." + std::to_string(i));
    EXPECT_EQ(compare_exact(f.data, ref, bgrx, 160, 120, label_cells(f.rois, 160)), "");
    EXPECT_EQ(labels_of(f), classes[i]);
  }
}

const std::vector<std::vector<std::string>> kSsdClasses = {{"person", "person", "tv"},
                                                           {"person", "person", "chair", "tv"}};

}  // namespace

TEST(BboxGolden, MobilenetSsd) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden(
      "tensor_decoder mode=bounding_boxes option1=mobilenet-ssd option2=coco_labels_list.txt "
      "option3=box_priors.txt option4=160:120 option5=300:300",
      kSsdInputs, "mobilenetssd_golden", true, kSsdClasses);
}

TEST(BboxGolden, MobilenetSsdConfigFile) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden("tensor_decoder option1=mobilenet-ssd config-file=config_file.0", kSsdInputs,
               "mobilenetssd_golden", true, kSsdClasses);
}

TEST(BboxGolden, TfliteSsdAlias) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden(
      "tensor_decoder mode=bounding_boxes option1=tflite-ssd option2=coco_labels_list.txt "
      "option3=box_priors.txt option4=160:120 option5=300:300",
      kSsdInputs, "mobilenetssd_golden", true, kSsdClasses);
}

const std::vector<std::vector<std::string>> kPpClasses = {{"person", "tv", "tv", "chair"},
                                                          {"person", "person", "tv"}};

TEST(BboxGolden, MobilenetSsdPostprocess) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden(
      "tensor_decoder mode=bounding_boxes option1=mobilenet-ssd-postprocess "
      "option2=coco_labels_list.txt option4=160:120 option5=640:480",
      kPpInputs, "mobilenetssd_postprocess_golden", true, kPpClasses);
}

TEST(BboxGolden, MobilenetSsdPostprocessConfigFile) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden("tensor_decoder option1=mobilenet-ssd-postprocess config-file=config_file.1",
               kPpInputs, "mobilenetssd_postprocess_golden", true, kPpClasses);
}

TEST(BboxGolden, TfSsdAliasConfigFile) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden("tensor_decoder option1=tf-ssd config-file=config_file.1", kPpInputs,
               "mobilenetssd_postprocess_golden", true, kPpClasses);
}

// Palm detection has no labels: one unlabeled box per frame.
TEST(BboxGolden, MpPalmDetection) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden(
      "tensor_decoder mode=bounding_boxes option1=mp-palm-detection "
      "option3=0.5:4:1.0:1.0:0.5:0.5:8:16:16:16 option4=160:120 option5=300:300",
      kPalmInputs, "palm_detection_result_golden", false, {{""}, {""}});
}

TEST(BboxGolden, MpPalmDetectionConfigFile) {
  NNS_REQUIRE_SHARED_MODELS();
  check_golden("tensor_decoder config-file=config_file.2", kPalmInputs,
               "palm_detection_result_golden", false, {{""}, {""}});
}

// The comparison can fail: the SSD frames against the post-process references.
TEST(BboxGolden, ComparisonDetectsOtherBoxes) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect(
      "tensor_mux name=mux ! tensor_decoder mode=bounding_boxes option1=mobilenet-ssd "
      "option2=coco_labels_list.txt option3=box_priors.txt option4=160:120 option5=300:300 ! "
      "appsink name=out sync=false" +
          kSsdInputs,
      data_dir());
  ASSERT_EQ(c.frames.size(), 2u);
  auto ref = nns::test::read_file(data_dir() + "/mobilenetssd_postprocess_golden.0");
  EXPECT_NE(
      compare_exact(c.frames[0].data, ref, true, 160, 120, label_cells(c.frames[0].rois, 160)), "");
}

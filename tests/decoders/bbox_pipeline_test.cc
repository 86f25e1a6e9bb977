// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=bounding_boxes: metadata (ROI metas, JSON custom meta), tracking ids,
// oriented-box drawing free of crashes, and bus errors for bad options and inputs.
#include <gtest/gtest.h>

#include "decoders/bbox_test_util.h"

using nns::test::run_pipeline;
using nns::test::bbox::collect;
using nns::test::bbox::data_dir;
using nns::test::bbox::kSsdInputs;

namespace {

std::string ssd(const std::string &opts, const std::string &sink = "appsink name=out") {
  return "tensor_mux name=mux ! tensor_decoder mode=bounding_boxes " + opts + " ! " + sink +
         kSsdInputs;
}

const std::string kSsdOpts =
    "option1=mobilenet-ssd option2=coco_labels_list.txt option3=box_priors.txt option4=160:120 "
    "option5=300:300";

// Runs in the data folder and returns the bus error text ("" if none).
std::string error_of(const std::string &desc) {
  auto c = collect(desc, data_dir());
  return c.error;
}

}  // namespace

TEST(BboxPipeline, RoiMetaPerBox) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect(ssd(kSsdOpts), data_dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 2u);
  const auto &rois = c.frames[0].rois;
  ASSERT_EQ(rois.size(), 3u);
  // Frame 0, best first: person (x 91 y 174 w 79 h 121 in 300x300) scaled to 160x120.
  EXPECT_EQ(rois[0].type, "person");
  EXPECT_EQ(rois[0].label, "person");
  EXPECT_EQ(rois[0].class_id, 1);
  EXPECT_EQ(rois[0].x, 48);
  EXPECT_EQ(rois[0].y, 69);
  EXPECT_EQ(rois[0].w, 42);
  EXPECT_EQ(rois[0].h, 49);
  EXPECT_NEAR(rois[0].score, 0.9372, 1e-3);
  EXPECT_EQ(rois[0].id, 0);
  EXPECT_EQ(rois[2].label, "tv");
  EXPECT_GT(rois[0].score, rois[1].score);
  EXPECT_FALSE(c.frames[0].has_json);  // only with option9=json
}

TEST(BboxPipeline, JsonMetaWithOption9) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect(ssd(kSsdOpts + " option9=json"), data_dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 2u);
  ASSERT_TRUE(c.frames[1].has_json);
  const std::string &j = c.frames[1].json;
  EXPECT_EQ(j.rfind("{\"width\":160,\"height\":120,\"boxes\":[{\"x\":48,\"y\":69,", 0), 0u) << j;
  EXPECT_NE(j.find("\"label\":\"chair\""), std::string::npos) << j;
  EXPECT_EQ(std::count(j.begin(), j.end(), '{'), 5) << j;  // object + 4 boxes
}

TEST(BboxPipeline, TrackingIdsStayWithObjects) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect(ssd(kSsdOpts + " option6=1"), data_dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 2u);
  const auto &a = c.frames[0].rois, &b = c.frames[1].rois;
  ASSERT_EQ(a.size(), 3u);
  ASSERT_EQ(b.size(), 4u);
  EXPECT_EQ(a[0].id, 1);
  EXPECT_EQ(a[1].id, 2);
  EXPECT_EQ(a[2].id, 3);
  EXPECT_EQ(b[0].id, 1);  // the same person, barely moved
  EXPECT_EQ(b[0].track_id, 1);
  EXPECT_EQ(b[3].id, 3);  // the tv
  EXPECT_EQ(b[2].id, 4);  // the chair is new
}

TEST(BboxPipeline, LogsBoxesWithOption7) {
  NNS_REQUIRE_SHARED_MODELS();
  testing::internal::CaptureStdout();
  auto c = collect(ssd(kSsdOpts + " option7=1"), data_dir());
  const std::string out = testing::internal::GetCapturedStdout();
  ASSERT_TRUE(c.error.empty()) << c.error;
  EXPECT_NE(out.find("Detect 3 boxes in 300 x 300 input image"), std::string::npos) << out;
  EXPECT_NE(out.find("[person] x:91 y:174 w:79 h:121 prob:0.937"), std::string::npos) << out;
}

TEST(BboxPipeline, UnknownSchemeListsValidOnes) {
  NNS_REQUIRE_SHARED_MODELS();
  auto e = error_of(ssd("option1=no-such-net option4=160:120"));
  EXPECT_NE(e.find("unknown bounding-box scheme 'no-such-net'"), std::string::npos) << e;
  EXPECT_NE(e.find("mobilenet-ssd, mobilenet-ssd-postprocess"), std::string::npos) << e;
  EXPECT_NE(e.find("mp-palm-detection"), std::string::npos) << e;
}

TEST(BboxPipeline, MissingPriorsFile) {
  NNS_REQUIRE_SHARED_MODELS();
  auto e = error_of(ssd("option1=mobilenet-ssd option2=coco_labels_list.txt option3=nope.txt"));
  EXPECT_NE(e.find("cannot read box priors file 'nope.txt'"), std::string::npos) << e;
  e = error_of(ssd("option1=mobilenet-ssd option2=coco_labels_list.txt"));
  EXPECT_NE(e.find("needs option3=<box priors file>"), std::string::npos) << e;
}

TEST(BboxPipeline, MalformedPriorsFile) {
  NNS_REQUIRE_SHARED_MODELS();
  const std::string dir = nns::test::make_temp_dir();
  {
    std::ofstream f(dir + "/bad_priors.txt");
    f << "0.1 0.2 0.3\n0.1 0.2\n0.1 0.2 0.3\n0.1 0.2 0.3\n";
    std::ofstream g(dir + "/short_priors.txt");
    g << "0.1 0.2\n0.1 x\n";
  }
  auto e = error_of(
      ssd("option1=mobilenet-ssd option2=coco_labels_list.txt option3=" + dir + "/bad_priors.txt"));
  EXPECT_NE(e.find("is not consistent: line 1 has 3 values, line 2 has 2"), std::string::npos) << e;
  e = error_of(ssd("option1=mobilenet-ssd option2=coco_labels_list.txt option3=" + dir +
                   "/short_priors.txt"));
  EXPECT_NE(e.find("'x' is not a number"), std::string::npos) << e;
  e =
      error_of(ssd("option1=mobilenet-ssd option2=coco_labels_list.txt "
                   "option3=box_priors.txt:abc"));
  EXPECT_NE(e.find("det_thr (field 2) must be a number, got 'abc'"), std::string::npos) << e;
  std::filesystem::remove_all(dir);
}

TEST(BboxPipeline, PriorsFewerThanDetections) {
  NNS_REQUIRE_SHARED_MODELS();
  const std::string dir = nns::test::make_temp_dir();
  {
    std::ofstream f(dir + "/p.txt");
    for (int i = 0; i < 4; ++i) f << "0.1 0.2 0.3\n";
  }
  auto e = error_of(ssd("option1=mobilenet-ssd option2=coco_labels_list.txt option3=" + dir +
                        "/p.txt option4=160:120"));
  EXPECT_NE(e.find("has 3 priors, the input has N=1917"), std::string::npos) << e;
  std::filesystem::remove_all(dir);
}

TEST(BboxPipeline, LabelFileMissingOrShort) {
  NNS_REQUIRE_SHARED_MODELS();
  auto e = error_of(ssd("option1=mobilenet-ssd option2=no_labels.txt option3=box_priors.txt"));
  EXPECT_NE(e.find("option2: cannot read label file 'no_labels.txt'"), std::string::npos) << e;
  e =
      error_of(ssd("option1=mobilenet-ssd option2=coco-80.txt option3=box_priors.txt "
                   "option4=160:120"));
  EXPECT_NE(e.find("the input has 91 classes but option2 gives 80 labels"), std::string::npos) << e;
}

TEST(BboxPipeline, BadSizes) {
  NNS_REQUIRE_SHARED_MODELS();
  auto e = error_of(ssd(kSsdOpts + " option4=160x120"));
  EXPECT_NE(e.find("option4: output size must be WIDTH:HEIGHT (e.g. 640:480), got '160x120'"),
            std::string::npos)
      << e;
  e = error_of(ssd(kSsdOpts + " option5=0:300"));
  EXPECT_NE(e.find("option5: model input size must be WIDTH:HEIGHT"), std::string::npos) << e;
}

TEST(BboxPipeline, TensorsNotFittingScheme) {
  NNS_REQUIRE_SHARED_MODELS();
  // One tensor only.
  auto e = error_of(
      "multifilesrc location=mobilenetssd_tensors.0.%d start-index=0 stop-index=0 "
      "caps=application/octet-stream ! tensor_converter input-dim=4:1:1917:1 input-type=float32 "
      "! tensor_decoder mode=bounding_boxes " +
      kSsdOpts + " ! appsink name=out");
  EXPECT_NE(e.find("scheme mobilenet-ssd expects 2 tensors of one type"), std::string::npos) << e;
  // Wrong dims for the SSD boxes.
  e = error_of("tensor_mux name=mux ! tensor_decoder mode=bounding_boxes " + kSsdOpts +
               " ! appsink name=out multifilesrc location=mobilenetssd_tensors.0.%d start-index=0 "
               "stop-index=0 caps=application/octet-stream ! tensor_converter input-dim=2:2:1917:1 "
               "input-type=float32 ! mux.sink_0 multifilesrc location=mobilenetssd_tensors.1.%d "
               "start-index=0 stop-index=0 caps=application/octet-stream ! tensor_converter "
               "input-dim=91:1917:1 input-type=float32 ! mux.sink_1");
  EXPECT_NE(e.find("(tensor 0 must be 4:1:N)"), std::string::npos) << e;
  // Types differ.
  e = error_of("tensor_mux name=mux ! tensor_decoder mode=bounding_boxes " + kSsdOpts +
               " ! appsink name=out multifilesrc location=mobilenetssd_tensors.0.%d start-index=0 "
               "stop-index=0 caps=application/octet-stream ! tensor_converter input-dim=4:1:1917:1 "
               "input-type=int32 ! mux.sink_0 multifilesrc location=mobilenetssd_tensors.1.%d "
               "start-index=0 stop-index=0 caps=application/octet-stream ! tensor_converter "
               "input-dim=91:1917:1 input-type=float32 ! mux.sink_1");
  EXPECT_NE(e.find("(types differ)"), std::string::npos) << e;
  // Palm: scores tensor of another N.
  e = error_of(
      "tensor_mux name=mux ! tensor_decoder mode=bounding_boxes option1=mp-palm-detection "
      "option3=0.5 option4=160:120 ! appsink name=out multifilesrc "
      "location=palm_detection_input_0.%d start-index=0 stop-index=0 "
      "caps=application/octet-stream ! tensor_converter input-dim=18:2016:1:1 "
      "input-type=float32 ! mux.sink_0 multifilesrc location=palm_detection_input_0.%d "
      "start-index=0 stop-index=0 caps=application/octet-stream ! tensor_converter "
      "input-dim=2:18144:1:1 input-type=float32 ! mux.sink_1");
  EXPECT_NE(e.find("scheme mp-palm-detection expects"), std::string::npos) << e;
  EXPECT_NE(e.find("tensor 1 must be 1:N"), std::string::npos) << e;
}

TEST(BboxPipeline, PostprocessOption3Malformed) {
  NNS_REQUIRE_SHARED_MODELS();
  auto e = error_of(ssd("option1=mobilenet-ssd-postprocess option3=3:1:2"));
  EXPECT_NE(e.find("must be LOC:CLASS:SCORE:NUM,THRESHOLD"), std::string::npos) << e;
}

TEST(BboxPipeline, PalmKeypointsInRoiMeta) {
  NNS_REQUIRE_SHARED_MODELS();
  auto c = collect(
      "tensor_mux name=mux ! tensor_decoder mode=bounding_boxes option1=mp-palm-detection "
      "option3=0.5:4:1.0:1.0:0.5:0.5:8:16:16:16 option4=160:120 option5=300:300 option9=json ! "
      "appsink name=out multifilesrc location=palm_detection_input_0.%d start-index=0 "
      "stop-index=0 caps=application/octet-stream ! tensor_converter input-dim=18:2016:1:1 "
      "input-type=float32 ! mux.sink_0 multifilesrc location=palm_detection_input_1.%d "
      "start-index=0 stop-index=0 caps=application/octet-stream ! tensor_converter "
      "input-dim=1:2016:1:1 input-type=float32 ! mux.sink_1",
      data_dir());
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 1u);
  ASSERT_EQ(c.frames[0].rois.size(), 1u);
  const auto &r = c.frames[0].rois[0];
  EXPECT_EQ(r.type, "object");  // no labels
  EXPECT_EQ(r.x, 51);
  EXPECT_EQ(r.y, 62);
  ASSERT_EQ(r.keypoints.size(), 14u);  // 7 palm keypoints
  for (std::size_t i = 0; i < 14; i += 2) {
    EXPECT_GE(r.keypoints[i], 0);
    EXPECT_LT(r.keypoints[i], 160);
    EXPECT_GE(r.keypoints[i + 1], 0);
    EXPECT_LT(r.keypoints[i + 1], 120);
  }
  EXPECT_NE(c.frames[0].json.find("\"keypoints\":[["), std::string::npos) << c.frames[0].json;
}

// OpenVINO person detection: a synthetic 7:200 tensor with two detections above 0.8 and one
// below, then the end marker.
TEST(BboxPipeline, OvPersonDetection) {
  const std::string dir = nns::test::make_temp_dir();
  {
    std::vector<float> v(7 * 200, 0.f);
    const float rows[4][7] = {{0, 1, 0.95f, 0.1f, 0.2f, 0.4f, 0.6f},
                              {0, 1, 0.50f, 0.5f, 0.5f, 0.6f, 0.6f},
                              {0, 1, 0.85f, 0.5f, 0.1f, 0.9f, 0.3f},
                              {-1, 0, 0, 0, 0, 0, 0}};
    for (int r = 0; r < 4; ++r)
      for (int k = 0; k < 7; ++k) v[static_cast<std::size_t>(r) * 7 + k] = rows[r][k];
    std::ofstream f(dir + "/ov.raw", std::ios::binary);
    f.write(reinterpret_cast<const char *>(v.data()), static_cast<std::streamsize>(v.size() * 4));
  }
  auto c = collect("filesrc location=" + dir +
                   "/ov.raw blocksize=-1 ! application/octet-stream ! tensor_converter "
                   "input-dim=7:200 input-type=float32 ! tensor_decoder mode=bounding_boxes "
                   "option1=ov-person-detection option4=200:100 option5=200:100 ! "
                   "appsink name=out");
  ASSERT_TRUE(c.error.empty()) << c.error;
  ASSERT_EQ(c.frames.size(), 1u);
  ASSERT_EQ(c.frames[0].rois.size(), 2u);
  const auto &a = c.frames[0].rois[0], &b = c.frames[0].rois[1];
  EXPECT_EQ(a.type, "object");
  EXPECT_EQ(a.class_id, -1);
  EXPECT_EQ(a.x, 20);
  EXPECT_EQ(a.y, 20);
  EXPECT_EQ(a.w, 60);
  EXPECT_EQ(a.h, 40);
  EXPECT_EQ(b.x, 100);
  EXPECT_EQ(b.y, 10);
  // The same bytes as two 7:100 frames do not fit the scheme.
  auto e = collect("filesrc location=" + dir +
                   "/ov.raw blocksize=2800 ! application/octet-stream ! tensor_converter "
                   "input-dim=7:100 input-type=float32 ! tensor_decoder mode=bounding_boxes "
                   "option1=ov-person-detection ! appsink name=out");
  std::filesystem::remove_all(dir);
  EXPECT_NE(e.error.find("scheme ov-person-detection expects 1 tensor 7:200"), std::string::npos)
      << e.error;
}

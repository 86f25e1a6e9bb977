// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=pose_estimation: synthetic heatmaps with known peaks -> exact keypoint
// pixels, skeleton lines and the "pose" region-of-interest meta; heatmap-offset with known
// offsets; option and input errors (bus text).
#include <gst/gst.h>
#include <gst/video/gstvideometa.h>
#include <gtest/gtest.h>

#include <cmath>
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

std::string write_temp(const std::string &name, const std::string &text) {
  std::string path = nns::test::make_temp_dir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

GstMemory *mem_of(const std::vector<float> &v) {
  GstMemory *m = gst_allocator_alloc(nullptr, v.size() * 4, nullptr);
  GstMapInfo map;
  gst_memory_map(m, &map, GST_MAP_WRITE);
  memcpy(map.data, v.data(), v.size() * 4);
  gst_memory_unmap(m, &map);
  return m;
}

// heat[(y * W + x) * K + k]
struct Heat {
  unsigned k, w, h;
  std::vector<float> v;
  Heat(unsigned k_, unsigned w_, unsigned h_, float fill = 0.0f)
      : k(k_), w(w_), h(h_), v(static_cast<size_t>(k_) * w_ * h_, fill) {}
  float &at(unsigned kp, unsigned x, unsigned y) {
    return v[(static_cast<size_t>(y) * w + x) * k + kp];
  }
};

struct Keypt {
  std::string name;
  int x, y;
  double score;
  bool found;
};

struct Result {
  int w = 0, h = 0;
  std::vector<uint8_t> px;
  bool has_meta = false;
  guint rx = 0, ry = 0, rw = 0, rh = 0;
  std::vector<Keypt> kps;
  std::vector<uint8_t> at(int x, int y) const {
    size_t i = (static_cast<size_t>(y) * w + x) * 4;
    return {px[i], px[i + 1], px[i + 2], px[i + 3]};
  }
};

Result run(const std::string &props, const std::vector<std::vector<float>> &tensors,
           const std::string &dims) {
  Result r;
  HarnessPtr h(gst_harness_new_parse(("tensor_decoder mode=pose_estimation " + props).c_str()));
  std::string types = "float32";
  for (size_t i = 1; i < tensors.size(); ++i) types += ",float32";
  gst_harness_set_src_caps_str(
      h.get(),
      ("other/tensors,format=static,num_tensors=" + std::to_string(tensors.size()) +
       ",types=(string)\"" + types + "\",dimensions=(string)\"" + dims + "\",framerate=0/1")
          .c_str());
  GstBuffer *in = gst_buffer_new();
  for (const auto &t : tensors) gst_buffer_append_memory(in, mem_of(t));
  EXPECT_EQ(gst_harness_push(h.get(), in), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  EXPECT_NE(out, nullptr);
  if (!out) return r;
  GstCaps *c = gst_pad_get_current_caps(h->sinkpad);
  GstStructure *s = gst_caps_get_structure(c, 0);
  gst_structure_get_int(s, "width", &r.w);
  gst_structure_get_int(s, "height", &r.h);
  EXPECT_STREQ(gst_structure_get_string(s, "format"), "RGBA");
  gst_caps_unref(c);
  r.px.resize(gst_buffer_get_size(out));
  gst_buffer_extract(out, 0, r.px.data(), r.px.size());
  auto *m = gst_buffer_get_video_region_of_interest_meta_id(out, 0);
  if (m) {
    r.has_meta = true;
    EXPECT_EQ(m->roi_type, g_quark_from_string("pose"));
    r.rx = m->x, r.ry = m->y, r.rw = m->w, r.rh = m->h;
    GstStructure *p = gst_video_region_of_interest_meta_get_param(m, "pose");
    EXPECT_NE(p, nullptr);
    const GValue *list = p ? gst_structure_get_value(p, "keypoints") : nullptr;
    for (guint i = 0; list && i < gst_value_list_get_size(list); ++i) {
      const GstStructure *kp = gst_value_get_structure(gst_value_list_get_value(list, i));
      Keypt k;
      k.name = gst_structure_get_string(kp, "name");
      gboolean f = FALSE;
      gst_structure_get_int(kp, "x", &k.x);
      gst_structure_get_int(kp, "y", &k.y);
      gst_structure_get_double(kp, "score", &k.score);
      gst_structure_get_boolean(kp, "found", &f);
      k.found = f;
      r.kps.push_back(k);
    }
  }
  gst_buffer_unref(out);
  return r;
}

const std::vector<uint8_t> kWhite = {255, 255, 255, 255}, kYellow = {255, 255, 0, 255},
                           kClear = {0, 0, 0, 0};

}  // namespace

TEST(PoseEstimation, HeatmapOnlyPeaksLinesAndMeta) {
  // 3 keypoints on a 10x10 grid, output 100x50 -> x * 10, y * 5.
  std::string body = write_temp("body.txt", "head 1\nhand 0 2\nfoot\n");
  Heat hm(3, 10, 10);
  hm.at(0, 2, 2) = 0.9f;  // head -> (20,10)
  hm.at(1, 8, 2) = 0.8f;  // hand -> (80,10)
  hm.at(2, 5, 8) = 0.3f;  // foot: best score 0.3 < 0.5 -> not found
  Result r = run("option1=100:50 option2=10:10 option3=" + body, {hm.v}, "3:10:10:1");
  ASSERT_EQ(r.w, 100);
  ASSERT_EQ(r.h, 50);
  ASSERT_EQ(r.px.size(), 100u * 50 * 4);
  EXPECT_EQ(r.at(20, 10), kYellow);
  EXPECT_EQ(r.at(80, 10), kYellow);
  EXPECT_EQ(r.at(23, 10), kYellow);  // dot radius 3
  EXPECT_EQ(r.at(24, 10), kWhite);   // the head-hand line beyond the dot
  EXPECT_EQ(r.at(50, 10), kWhite);
  EXPECT_EQ(r.at(50, 11), kClear);
  EXPECT_EQ(r.at(50, 40), kClear);  // foot not drawn
  EXPECT_EQ(r.at(0, 0), kClear);
  ASSERT_TRUE(r.has_meta);
  EXPECT_EQ(r.rx, 20u);
  EXPECT_EQ(r.ry, 10u);
  EXPECT_EQ(r.rw, 61u);
  EXPECT_EQ(r.rh, 1u);
  ASSERT_EQ(r.kps.size(), 3u);
  EXPECT_EQ(r.kps[0].name, "head");
  EXPECT_EQ(r.kps[0].x, 20);
  EXPECT_EQ(r.kps[0].y, 10);
  EXPECT_NEAR(r.kps[0].score, 0.9, 1e-6);
  EXPECT_TRUE(r.kps[0].found);
  EXPECT_EQ(r.kps[1].name, "hand");
  EXPECT_EQ(r.kps[1].x, 80);
  EXPECT_EQ(r.kps[2].name, "foot");
  EXPECT_EQ(r.kps[2].x, 50);
  EXPECT_EQ(r.kps[2].y, 40);
  EXPECT_FALSE(r.kps[2].found);
}

// uint8 heatmaps (quantized models): read as value / 255, the same keypoints as float32.
TEST(PoseEstimation, Uint8HeatmapsAccepted) {
  std::string body = write_temp("body.txt", "head 1\nhand 0\n");
  std::vector<uint8_t> u8(2 * 4 * 4, 0);
  u8[(1 * 4 + 2) * 2 + 0] = 230;  // head at (2,1), score 230/255
  u8[(3 * 4 + 0) * 2 + 1] = 100;  // hand at (0,3): 100/255 < 0.5 -> not found
  HarnessPtr h(gst_harness_new_parse(
      ("tensor_decoder mode=pose_estimation option1=40:40 option3=" + body).c_str()));
  gst_harness_set_src_caps_str(h.get(),
                               "other/tensors,format=static,num_tensors=1,types=uint8,"
                               "dimensions=(string)2:4:4:1,framerate=0/1");
  GstBuffer *in = gst_buffer_new_memdup(u8.data(), u8.size());
  ASSERT_EQ(gst_harness_push(h.get(), in), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(out, nullptr);
  auto *m = gst_buffer_get_video_region_of_interest_meta_id(out, 0);
  ASSERT_NE(m, nullptr);
  GstStructure *p = gst_video_region_of_interest_meta_get_param(m, "pose");
  ASSERT_NE(p, nullptr);
  const GValue *list = gst_structure_get_value(p, "keypoints");
  ASSERT_EQ(gst_value_list_get_size(list), 2u);
  const GstStructure *head = gst_value_get_structure(gst_value_list_get_value(list, 0));
  const GstStructure *hand = gst_value_get_structure(gst_value_list_get_value(list, 1));
  int x = -1, y = -1;
  double score = 0;
  gboolean found = FALSE;
  gst_structure_get(head, "x", G_TYPE_INT, &x, "y", G_TYPE_INT, &y, "score", G_TYPE_DOUBLE, &score,
                    "found", G_TYPE_BOOLEAN, &found, nullptr);
  EXPECT_EQ(x, 20);
  EXPECT_EQ(y, 10);
  EXPECT_NEAR(score, 230.0 / 255, 1e-6);
  EXPECT_TRUE(found);
  gst_structure_get(hand, "found", G_TYPE_BOOLEAN, &found, nullptr);
  EXPECT_FALSE(found);
  std::vector<uint8_t> px(gst_buffer_get_size(out));
  gst_buffer_extract(out, 0, px.data(), px.size());
  EXPECT_EQ(std::vector<uint8_t>(px.begin() + (10 * 40 + 20) * 4, px.begin() + (10 * 40 + 21) * 4),
            kYellow);
  gst_buffer_unref(out);
}

TEST(PoseEstimation, Default17KeypointBodyAndGridScale) {
  // No option2: heatmap-only scales from the heatmap grid (9x9 -> 90x90).
  Heat hm(17, 9, 9);
  hm.at(5, 2, 3) = 1.0f;  // leftShoulder (20,30)
  hm.at(6, 6, 3) = 1.0f;  // rightShoulder (60,30)
  Result r = run("option1=90:90", {hm.v}, "17:9:9:1");
  ASSERT_EQ(r.kps.size(), 17u);
  EXPECT_EQ(r.kps[0].name, "nose");
  EXPECT_EQ(r.kps[16].name, "rightAnkle");
  EXPECT_EQ(r.kps[5].x, 20);
  EXPECT_EQ(r.kps[5].y, 30);
  EXPECT_EQ(r.kps[6].x, 60);
  EXPECT_EQ(r.at(40, 30), kWhite);  // shoulders are connected
  EXPECT_EQ(r.at(20, 30), kYellow);
  int found = 0;
  for (const auto &k : r.kps) found += k.found;
  EXPECT_EQ(found, 2);
}

TEST(PoseEstimation, HeatmapOffsetUsesSigmoidAndOffsets) {
  // 17 keypoints, 5x5 grid, model input 257x257, output 257x257 (no extra scaling).
  const unsigned k = 17, g = 5;
  Heat hm(k, g, g, -5.0f);  // sigmoid(-5) ~ 0.0067: not found
  Heat off(2 * k, g, g, 0.0f);
  hm.at(0, 1, 3) = 2.0f;        // nose: sigmoid(2) = 0.881
  off.at(0, 1, 3) = 6.0f;       // y offset
  off.at(k + 0, 1, 3) = -4.5f;  // x offset
  // x = 1/4 * 257 - 4.5 = 59.75 -> 59; y = 3/4 * 257 + 6 = 198.75 -> 198
  Result r = run("option1=257:257 option2=257:257 option4=heatmap-offset", {hm.v, off.v},
                 "17:5:5:1,34:5:5:1");
  ASSERT_EQ(r.kps.size(), 17u);
  EXPECT_EQ(r.kps[0].x, 59);
  EXPECT_EQ(r.kps[0].y, 198);
  EXPECT_NEAR(r.kps[0].score, 1.0 / (1.0 + std::exp(-2.0)), 1e-6);
  EXPECT_TRUE(r.kps[0].found);
  EXPECT_FALSE(r.kps[1].found);
  EXPECT_EQ(r.at(59, 198), kYellow);
  EXPECT_EQ(r.rx, 59u);
  EXPECT_EQ(r.ry, 198u);
  EXPECT_EQ(r.rw, 1u);
}

TEST(PoseEstimation, OffsetPositionsClampToTheFrame) {
  const unsigned k = 14, g = 3;
  Heat hm(k, g, g, -5.0f), off(2 * k, g, g, 0.0f);
  hm.at(0, 2, 2) = 3.0f;
  off.at(0, 2, 2) = 50.0f;
  off.at(k, 2, 2) = 50.0f;
  Result r =
      run("option1=64:48 option2=32:32 option4=heatmap-offset", {hm.v, off.v}, "14:3:3:1,28:3:3:1");
  ASSERT_EQ(r.kps.size(), 14u);
  EXPECT_EQ(r.kps[0].name, "top");
  EXPECT_EQ(r.kps[0].x, 63);
  EXPECT_EQ(r.kps[0].y, 47);
}

// ---- errors ----------------------------------------------------------------------------------

TEST(PoseEstimationErrors, BadOption1) {
  expect_error(tensor_file_src("17:9:9:1", 17 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=640x480 ! fakesink",
               "option1: output size must be WIDTH:HEIGHT (positive), got '640x480'");
}

TEST(PoseEstimationErrors, MissingOption1) {
  expect_error(
      tensor_file_src("17:9:9:1", 17 * 81 * 4) + "tensor_decoder mode=pose_estimation ! fakesink",
      "pose_estimation needs option1=<output WIDTH:HEIGHT>");
}

TEST(PoseEstimationErrors, UnknownOption4) {
  expect_error(tensor_file_src("17:9:9:1", 17 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option4=offsets ! fakesink",
               "option4: unknown mode 'offsets'");
}

TEST(PoseEstimationErrors, MissingKeypointFile) {
  expect_error(tensor_file_src("17:9:9:1", 17 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 "
                   "option3=/nonexistent/pose.txt ! fakesink",
               "option3: cannot read keypoint file '/nonexistent/pose.txt'");
}

TEST(PoseEstimationErrors, BadKeypointFileLink) {
  std::string f = write_temp("body.txt", "a 1\nb 5\n");
  expect_error(tensor_file_src("2:9:9:1", 2 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option3=" + f + " ! fakesink",
               "keypoint 'b' links to id 5, the file has 2 keypoints");
}

TEST(PoseEstimationErrors, KeypointCountDiffersFromFile) {
  std::string f = write_temp("body.txt", "a 1\nb 0\n");
  expect_error(tensor_file_src("3:9:9:1", 3 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option3=" + f + " ! fakesink",
               "the heatmaps have 3 keypoints, option3");
}

TEST(PoseEstimationErrors, UnknownDefaultBody) {
  expect_error(tensor_file_src("5:9:9:1", 5 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 ! fakesink",
               "the heatmaps have 5 keypoints; without option3 only 14 or 17 are known");
}

TEST(PoseEstimationErrors, HeatmapOffsetNeedsTwoTensors) {
  expect_error(tensor_file_src("17:9:9:1", 17 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option2=257:257 "
                   "option4=heatmap-offset ! fakesink",
               "heatmap-offset expects 2 tensors (heatmaps, offsets), got 1 tensor(s)");
}

TEST(PoseEstimationErrors, BatchDimensionRejected) {
  expect_error(tensor_file_src("17:9:9:2", 17 * 81 * 2 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 ! fakesink",
               "tensor 0 (heatmaps) must be C:W:H:1, got dim3 = 2");
}

TEST(PoseEstimationErrors, BadOption2) {
  expect_error(tensor_file_src("17:9:9:1", 17 * 81 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option2=0:257 ! fakesink",
               "option2: input size must be WIDTH:HEIGHT (positive), got '0:257'");
}

TEST(PoseEstimationErrors, HeatmapOffsetNeedsOption2) {
  expect_error(tensor_file_src("17:9:9:1,34:9:9:1", 17 * 81 * 4 * 3, "float32,float32") +
                   "tensor_decoder mode=pose_estimation option1=64:64 option4=heatmap-offset ! "
                   "fakesink",
               "heatmap-offset needs option2=<model input WIDTH:HEIGHT>");
}

// A real pipeline: decoder output composited over a video frame.
TEST(PoseEstimation, PipelineThroughCompositor) {
  auto r = run_pipeline(tensor_file_src("17:9:9:1", 17 * 81 * 4) +
                        "tensor_decoder mode=pose_estimation option1=64:48 ! mix.sink_1 "
                        "videotestsrc num-buffers=1 ! video/x-raw,width=64,height=48 ! mix.sink_0 "
                        "compositor name=mix sink_0::zorder=0 sink_1::zorder=1 ! videoconvert ! "
                        "fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

// NNStreamer's pose pipelines: tensor_split, then transpose, then the decoder. Before its input is
// known, tensor_transform asks the decoder with "other/tensors, format=static, framerate=30/1"
// (no tensors yet); that is no input to decode, so it must not fail ("0 tensor(s)").
TEST(PoseEstimation, AfterSplitAndTranspose) {
  auto r = run_pipeline(
      "videotestsrc num-buffers=2 ! video/x-raw,format=GRAY8,width=14,height=28 ! "
      "tensor_converter ! tensor_transform mode=typecast option=float32 ! "
      "tensor_split name=a tensorseg=1:14:14:1,1:14:14:1 a.src_0 ! queue ! "
      "tensor_transform mode=transpose option=1:2:0:3 ! "
      "tensor_decoder mode=pose_estimation option1=320:240 option2=14:14 ! "
      "video/x-raw,format=RGBA,width=320,height=240 ! fakesink a.src_1 ! queue ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

// option4=keypoints (MoveNet's [1,1,17,3] output: y, x, score normalized).
TEST(PoseEstimation, KeypointsModeMoveNetLayout) {
  std::vector<float> t(17 * 3, 0.0f);
  auto set = [&](int k, float y, float x, float s) {
    t[3 * k] = y;
    t[3 * k + 1] = x;
    t[3 * k + 2] = s;
  };
  set(0, 0.25f, 0.5f, 0.9f);     // nose -> (80, 30) in 160x120
  set(1, 0.2f, 0.55f, 0.6f);     // leftEye -> (88, 24)
  set(2, 0.2f, 0.4375f, 0.2f);   // rightEye (70, 24): score 0.2 -> not found
  set(5, 0.5f, 0.6875f, 0.45f);  // leftShoulder (110, 60): found only with option5=0.4
  set(16, 1.01f, -0.1f, 0.99f);  // rightAnkle outside: clamped to (0, 119)
  Result r = run("option1=160:120 option4=keypoints", {t}, "3:17:1:1");
  ASSERT_EQ(r.w, 160);
  ASSERT_EQ(r.h, 120);
  ASSERT_EQ(r.kps.size(), 17u);
  EXPECT_EQ(r.kps[0].name, "nose");
  EXPECT_EQ(r.kps[0].x, 80);
  EXPECT_EQ(r.kps[0].y, 30);
  EXPECT_TRUE(r.kps[0].found);
  EXPECT_NEAR(r.kps[0].score, 0.9, 1e-6);
  EXPECT_EQ(r.kps[1].x, 88);
  EXPECT_EQ(r.kps[1].y, 24);
  EXPECT_TRUE(r.kps[1].found);
  EXPECT_EQ(r.kps[2].x, 70);
  EXPECT_EQ(r.kps[2].y, 24);
  EXPECT_FALSE(r.kps[2].found);
  EXPECT_EQ(r.kps[5].x, 110);
  EXPECT_EQ(r.kps[5].y, 60);
  EXPECT_FALSE(r.kps[5].found);
  EXPECT_EQ(r.kps[16].x, 0);
  EXPECT_EQ(r.kps[16].y, 119);
  EXPECT_TRUE(r.kps[16].found);
  EXPECT_EQ(r.at(80, 30), kYellow);
  EXPECT_EQ(r.at(88, 24), kYellow);
  EXPECT_EQ(r.at(70, 24), kClear);  // not found: no dot
  EXPECT_EQ(r.at(110, 60), kClear);
  EXPECT_EQ(r.at(0, 119), kYellow);
  // nose - leftEye is a PoseNet-body connection, but it is inside the dots; the ROI box spans
  // the found keypoints.
  EXPECT_EQ(r.rx, 0u);
  EXPECT_EQ(r.ry, 24u);
  EXPECT_EQ(r.rw, 89u);
  EXPECT_EQ(r.rh, 96u);

  // option5 lowers the threshold: the shoulder is found (its PoseNet-body links, rightShoulder,
  // leftElbow and leftHip, are not: only its dot).
  Result r2 = run("option1=160:120 option4=keypoints option5=0.4", {t}, "3:17:1:1");
  ASSERT_EQ(r2.kps.size(), 17u);
  EXPECT_TRUE(r2.kps[5].found);
  EXPECT_FALSE(r2.kps[2].found);
  EXPECT_EQ(r2.at(110, 60), kYellow);
}

TEST(PoseEstimation, KeypointsModeDrawsLinesWithOption3) {
  std::string body = write_temp("body.txt", "a 1\nb\n");
  // Positions are floored: a (0.125 * 100, 0.125 * 50) = (12, 6), b (87, 6).
  std::vector<float> t = {0.125f, 0.125f, 0.8f, 0.125f, 0.875f, 0.7f};
  Result r = run("option1=100:50 option4=keypoints option3=" + body, {t}, "3:2:1:1");
  ASSERT_EQ(r.kps.size(), 2u);
  EXPECT_EQ(r.kps[0].x, 12);
  EXPECT_EQ(r.kps[0].y, 6);
  EXPECT_EQ(r.kps[1].x, 87);
  EXPECT_EQ(r.kps[1].y, 6);
  EXPECT_EQ(r.at(50, 6), kWhite);
  EXPECT_EQ(r.at(50, 7), kClear);
}

TEST(PoseEstimationErrors, KeypointsModeLayoutChecked) {
  expect_error(tensor_file_src("2:17:1:1", 2 * 17 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option4=keypoints ! fakesink",
               "tensor 0 (keypoints) must be 3:K:1:1 (y, x, score), got dim0 = 2");
  expect_error(tensor_file_src("3:5:1:1", 3 * 5 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option4=keypoints ! fakesink",
               "the tensor has 5 keypoints; without option3 only 14 or 17 are known");
  expect_error(tensor_file_src("3:17:2:1", 3 * 17 * 2 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option4=keypoints ! fakesink",
               "tensor 0 (keypoints) must be 3:K:1:1, got dim2 = 2");
}

TEST(PoseEstimationErrors, BadOption5) {
  expect_error(tensor_file_src("3:17:1:1", 3 * 17 * 4) +
                   "tensor_decoder mode=pose_estimation option1=64:64 option4=keypoints "
                   "option5=1.5 ! fakesink",
               "option5: score threshold must be a number in 0..1, got '1.5'");
}

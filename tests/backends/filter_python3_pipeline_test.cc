// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter framework=python3 in real pipelines: passthrough and scaler scripts against the
// unfiltered stream, framework=auto for .py, and the bus errors for broken scripts.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <string>
#include <vector>

#include "support/harness.h"

namespace {

using nns::test::run_pipeline;

std::string script(const std::string &name) {
  return std::string(NNS_SOURCE_DIR) + "/tests/data/python/" + name;
}

bool python3_filter_available() {
  GstElementFactory *f = gst_element_factory_find("tensor_filter");
  if (!f) return false;
  gst_object_unref(f);
  return std::filesystem::exists(std::string(NNS_BUILD_DIR) +
                                 "/subplugins/filters/libnnstreamer_filter_python3.so");
}

#define REQUIRE_PYTHON3_FILTER()                                            \
  do {                                                                      \
    if (!python3_filter_available())                                        \
      GTEST_SKIP() << "tensor_filter or the python3 back end is not built"; \
  } while (0)

// RGB frames of w x h from videotestsrc, through tensor_converter, teed: one branch through
// `filter`, one straight; both written to files. Returns {filtered, direct}.
std::pair<std::vector<uint8_t>, std::vector<uint8_t>> run_teed(const std::string &filter, int w,
                                                               int h, int frames) {
  std::string dir = nns::test::make_temp_dir();
  std::string desc = "videotestsrc num-buffers=" + std::to_string(frames) +
                     " pattern=smpte ! video/x-raw,format=RGB,width=" + std::to_string(w) +
                     ",height=" + std::to_string(h) +
                     ",framerate=30/1 ! tensor_converter ! tee name=t ! queue ! " + filter +
                     " ! filesink location=" + dir +
                     "/filtered t. ! queue ! filesink location=" + dir + "/direct";
  auto r = run_pipeline(desc);
  EXPECT_TRUE(r.eos) << r.error_text;
  return {nns::test::read_file(dir + "/filtered"), nns::test::read_file(dir + "/direct")};
}

TEST(FilterPython3Pipeline, PassthroughIsExact) {
  REQUIRE_PYTHON3_FILTER();
  auto [filtered, direct] =
      run_teed("tensor_filter framework=python3 model=" + script("passthrough.py"), 280, 40, 3);
  ASSERT_EQ(direct.size(), 3u * 3 * 280 * 40);
  EXPECT_EQ(filtered, direct);
}

TEST(FilterPython3Pipeline, FrameworkAutoPicksPython3ForPy) {
  REQUIRE_PYTHON3_FILTER();
  auto [filtered, direct] = run_teed("tensor_filter model=" + script("passthrough.py"), 280, 40, 2);
  ASSERT_EQ(direct.size(), 2u * 3 * 280 * 40);
  EXPECT_EQ(filtered, direct);
}

// scaler_shared_dims.py builds its output shape from the input shape's dims list itself (as
// NNStreamer's scaler example does) and edits it: TensorShape copies the list, so the input shape
// the script keeps for invoke() is unchanged.
TEST(FilterPython3Pipeline, ScalerDownAndUp) {
  REQUIRE_PYTHON3_FILTER();
  const int w = 64, h = 48, frames = 2;
  for (const char *py : {"scaler.py", "scaler_shared_dims.py"})
    for (auto [ow, oh] : {std::pair<int, int>{32, 24}, {128, 96}}) {
      std::string custom = std::to_string(ow) + "x" + std::to_string(oh);
      SCOPED_TRACE(py);
      auto [filtered, direct] =
          run_teed("tensor_filter framework=python3 model=" + script(py) + " custom=" + custom, w,
                   h, frames);
      ASSERT_EQ(direct.size(), static_cast<size_t>(frames * w * h * 3));
      ASSERT_EQ(filtered.size(), static_cast<size_t>(frames * ow * oh * 3)) << custom;
      for (int f = 0; f < frames; f++)
        for (int y = 0; y < oh; y++)
          for (int x = 0; x < ow; x++)
            for (int c = 0; c < 3; c++) {
              int sx = x * w / ow, sy = y * h / oh;
              ASSERT_EQ(filtered[((f * oh + y) * ow + x) * 3 + c],
                        direct[((f * h + sy) * w + sx) * 3 + c])
                  << custom << " frame " << f << " at " << x << "," << y;
            }
    }
}

TEST(FilterPython3Pipeline, TwoOutputTensors) {
  REQUIRE_PYTHON3_FILTER();
  // output_cases.py: one uint8 tensor of 8 in (fakesrc's pattern 0..7), two of 4 out.
  for (auto [mode, want] :
       {std::pair<const char *, std::vector<uint8_t>>{"copy", {0, 1, 2, 3, 4, 5, 6, 7}},
        {"alias", {0, 1, 2, 3, 4, 5, 6, 7}},
        {"strided", {0, 2, 4, 6, 7, 5, 3, 1}}}) {
    std::string dir = nns::test::make_temp_dir();
    auto r = run_pipeline(
        "fakesrc num-buffers=2 sizetype=fixed sizemax=8 filltype=pattern ! "
        "other/tensors,format=static,num_tensors=1,types=(string)uint8,dimensions=(string)8,"
        "framerate=0/1 ! tensor_filter framework=python3 model=" +
        script("output_cases.py") + " custom=" + mode + " ! filesink location=" + dir + "/out");
    ASSERT_TRUE(r.eos) << mode << ": " << r.error_text;
    std::vector<uint8_t> twice = want;
    twice.insert(twice.end(), want.begin(), want.end());
    EXPECT_EQ(nns::test::read_file(dir + "/out"), twice) << mode;
  }
}

TEST(FilterPython3Pipeline, InvokeDynamicGivesFlexibleTensors) {
  REQUIRE_PYTHON3_FILTER();
  // dynamic.py: 8 uint8 (0..7) in; out: the input doubled, and its numpy shape as int32.
  std::string dir = nns::test::make_temp_dir();
  auto r = run_pipeline(
      "fakesrc num-buffers=1 sizetype=fixed sizemax=8 filltype=pattern ! "
      "other/tensors,format=static,num_tensors=1,types=(string)uint8,dimensions=(string)8,"
      "framerate=0/1 ! tensor_filter framework=python3 invoke-dynamic=true model=" +
      script("dynamic.py") + " ! other/tensors,format=flexible ! filesink location=" + dir +
      "/out");
  ASSERT_TRUE(r.eos) << r.error_text;
  // Each flexible tensor: a 128-byte header, then the data.
  auto out = nns::test::read_file(dir + "/out");
  ASSERT_EQ(out.size(), 128u + 8 + 128 + 4);
  EXPECT_EQ(std::vector<uint8_t>(out.begin() + 128, out.begin() + 136),
            (std::vector<uint8_t>{0, 2, 4, 6, 8, 10, 12, 14}));
  int32_t n = 0;
  std::memcpy(&n, out.data() + 128 + 8 + 128, 4);
  EXPECT_EQ(n, 8);
}

TEST(FilterPython3Pipeline, SyntaxErrorIsABusError_n) {
  REQUIRE_PYTHON3_FILTER();
  auto r = run_pipeline(
      "videotestsrc num-buffers=1 ! video/x-raw,format=RGB,width=8,height=8 ! "
      "tensor_converter ! tensor_filter framework=python3 model=" +
      script("bad_syntax.py") + " ! fakesink");
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("bad_syntax.py"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("SyntaxError"), std::string::npos) << r.error_text;
}

TEST(FilterPython3Pipeline, ExceptionInInvokeIsABusError_n) {
  REQUIRE_PYTHON3_FILTER();
  auto r = run_pipeline(
      "fakesrc num-buffers=1 sizetype=fixed sizemax=16 filltype=zero ! "
      "other/tensors,format=static,num_tensors=1,types=(string)float32,dimensions=(string)4,"
      "framerate=0/1 ! tensor_filter framework=python3 model=" +
      script("raise_invoke.py") + " ! fakesink");
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("raise_invoke.py"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("ValueError: input rejected by raise_invoke.py: 4 elements"),
            std::string::npos)
      << r.error_text;
}

TEST(FilterPython3Pipeline, ScriptRefusingTheInput_n) {
  REQUIRE_PYTHON3_FILTER();
  // scaler.py's setInputDim returns None for two input tensors.
  auto r = run_pipeline(
      "fakesrc num-buffers=1 sizetype=fixed sizemax=24 filltype=zero ! "
      "other/tensors,format=static,num_tensors=2,types=(string)\"uint8,uint8\","
      "dimensions=(string)\"3:2:2:1,3:2:2:1\",framerate=0/1 ! tensor_filter framework=python3 "
      "model=" +
      script("scaler.py") + " ! fakesink");
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("setInputDim() returned None"), std::string::npos) << r.error_text;
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter framework=armnn in pipelines on the tiny add.tflite, the tflite names and auto
// (which reach our tflite back end first when it is built), and the bus errors. (The real MobileNet
// run is tests/slow/armnn_mobilenet_test.cc.)
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/harness.h"

namespace {

bool have_armnn() {
  GstElementFactory *f = gst_element_factory_find("tensor_filter");
  if (f) gst_object_unref(f);
  return f && std::filesystem::exists(std::string(NNS_BUILD_DIR) +
                                      "/subplugins/filters/libnnstreamer_filter_armnn.so");
}

#define REQUIRE_ARMNN_PIPELINE()                                                        \
  do {                                                                                  \
    if (!have_armnn()) GTEST_SKIP() << "tensor_filter or the armnn back end is absent"; \
    NNS_REQUIRE_SHARED_MODELS();                                                        \
  } while (0)

std::string add_model() {
  return nns::test::shared_models_dir() + "/models/add.tflite";
}

class ArmnnPipeline : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = nns::test::make_temp_dir();
    input_ = dir_ + "/x.raw";
    float x[3] = {1.5f, -4.f, 10.f};
    std::ofstream(input_, std::ios::binary).write(reinterpret_cast<const char *>(x), sizeof x);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  // Three float32 frames of one element each.
  std::string src() const {
    return "filesrc location=" + input_ +
           " blocksize=4 ! application/octet-stream ! tensor_converter input-dim=1 "
           "input-type=float32 ! ";
  }

  std::vector<float> run_floats(const std::string &filter, nns::test::RunResult *res) {
    std::vector<float> out;
    GError *err = nullptr;
    GstElement *p = gst_parse_launch((src() + filter + " ! tensor_sink name=sink").c_str(), &err);
    if (!p || err) {
      res->error = true;
      res->error_text = err ? err->message : "parse failed";
      if (err) g_error_free(err);
      if (p) gst_object_unref(p);
      return out;
    }
    GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
    g_signal_connect(sink, "new-data", G_CALLBACK(+[](GstElement *, GstBuffer *b, gpointer d) {
                       float v = 0;
                       if (gst_buffer_get_size(b) == 4) gst_buffer_extract(b, 0, &v, 4);
                       static_cast<std::vector<float> *>(d)->push_back(v);
                     }),
                     &out);
    gst_object_unref(sink);
    *res = nns::test::run_pipeline(p, 30.0);
    gst_object_unref(p);
    return out;
  }

  std::string dir_, input_;
};

TEST_F(ArmnnPipeline, AddModel) {
  REQUIRE_ARMNN_PIPELINE();
  nns::test::RunResult r;
  auto out = run_floats("tensor_filter framework=armnn model=" + add_model(), &r);
  ASSERT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(out, (std::vector<float>{3.5f, -2.f, 12.f}));
}

// The tflite names and framework=auto reach a .tflite back end (our tensorflow2-lite first, armnn
// when it is not built): same results either way.
TEST_F(ArmnnPipeline, ReachedThroughTfliteNamesAndAuto) {
  REQUIRE_ARMNN_PIPELINE();
  for (const char *fw : {"tensorflow-lite", "tensorflow2-lite", "auto"}) {
    nns::test::RunResult r;
    auto out = run_floats(std::string("tensor_filter framework=") + fw + " model=" + add_model() +
                              " input=1 inputtype=float32 output=1 outputtype=float32",
                          &r);
    ASSERT_TRUE(r.eos) << fw << ": " << r.error_text;
    EXPECT_EQ(out, (std::vector<float>{3.5f, -2.f, 12.f})) << fw;
  }
}

TEST_F(ArmnnPipeline, PropertiesDisagreeWithModel) {
  REQUIRE_ARMNN_PIPELINE();
  nns::test::RunResult r;
  run_floats("tensor_filter framework=armnn model=" + add_model() + " output=1 outputtype=uint8",
             &r);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("output tensor #0 is float32 1, but output=/outputtype= say uint8"),
            std::string::npos)
      << r.error_text;
}

TEST_F(ArmnnPipeline, UnsupportedOperatorAndCustomKey) {
  REQUIRE_ARMNN_PIPELINE();
  nns::test::RunResult r;
  run_floats("tensor_filter framework=armnn model=" + nns::test::shared_models_dir() +
                 "/models/sample_4x4x4x4x4_two_input_one_output.tflite",
             &r);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("Operator not supported"), std::string::npos) << r.error_text;
  nns::test::RunResult r2;
  run_floats("tensor_filter framework=armnn model=" + add_model() + " custom=Backend:CpuRef,Foo:1",
             &r2);
  ASSERT_TRUE(r2.error);
  EXPECT_NE(r2.error_text.find("unknown custom option 'Foo'"), std::string::npos) << r2.error_text;
}

}  // namespace

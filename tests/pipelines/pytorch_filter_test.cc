// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter framework=pytorch in real pipelines: LeNet on 9.raw (static and invoke-dynamic,
// with and without output=, framework=auto) and the bus errors a user sees.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/harness.h"

namespace {

bool have_pytorch() {
  GstElementFactory *f = gst_element_factory_find("tensor_filter");
  if (f) gst_object_unref(f);
  return f && std::filesystem::exists(std::string(NNS_BUILD_DIR) +
                                      "/subplugins/filters/libnnstreamer_filter_pytorch.so");
}

#define REQUIRE_PYTORCH_PIPELINE()                                                          \
  do {                                                                                      \
    if (!have_pytorch()) GTEST_SKIP() << "tensor_filter or the pytorch back end is absent"; \
    NNS_REQUIRE_SHARED_MODELS();                                                            \
  } while (0)

std::string models() {
  return nns::test::shared_models_dir() + "/models/";
}
std::string digit() {
  return nns::test::shared_models_dir() + "/data/9.raw";
}

// Runs `desc` (which ends in `tensor_sink name=sink`) and returns every buffer's bytes.
struct Captured {
  nns::test::RunResult run;
  std::vector<std::vector<uint8_t>> buffers;
};

void on_new_data(GstElement *, GstBuffer *buf, gpointer data) {
  auto *c = static_cast<Captured *>(data);
  std::vector<uint8_t> bytes(gst_buffer_get_size(buf));
  gst_buffer_extract(buf, 0, bytes.data(), bytes.size());
  c->buffers.push_back(std::move(bytes));
}

Captured run_capture(const std::string &desc) {
  Captured c;
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    c.run.error = true;
    c.run.error_text = err ? err->message : "parse failed";
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return c;
  }
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  if (sink) {
    g_signal_connect(sink, "new-data", G_CALLBACK(on_new_data), &c);
    gst_object_unref(sink);
  }
  c.run = nns::test::run_pipeline(p, 30.0);
  gst_object_unref(p);
  return c;
}

std::string lenet_src() {
  return "filesrc location=" + digit() +
         " ! application/octet-stream ! tensor_converter input-dim=1:28:28:1 input-type=uint8 ! ";
}

void expect_nine(const std::vector<uint8_t> &scores) {
  ASSERT_EQ(scores.size(), 10u);
  EXPECT_EQ(std::max_element(scores.begin(), scores.end()) - scores.begin(), 9);
  EXPECT_EQ(scores[9], 254);
}

TEST(PytorchPipeline, LenetClassifiesNine) {
  REQUIRE_PYTORCH_PIPELINE();
  Captured c = run_capture(lenet_src() + "tensor_filter framework=pytorch model=" + models() +
                           "pytorch_lenet5.pt input=1:28:28:1 inputtype=uint8 output=10:1 "
                           "outputtype=uint8 ! tensor_sink name=sink");
  ASSERT_TRUE(c.run.eos) << c.run.error_text;
  ASSERT_EQ(c.buffers.size(), 1u);
  expect_nine(c.buffers[0]);
}

// No output=: the back end finds the output by running the model once. framework=auto picks
// pytorch from the .pt extension.
TEST(PytorchPipeline, OutputFromModelAndAutoFramework) {
  REQUIRE_PYTORCH_PIPELINE();
  for (const char *fw : {"pytorch", "auto"}) {
    Captured c = run_capture(lenet_src() + "tensor_filter framework=" + fw + " model=" + models() +
                             "pytorch_lenet5.pt input=1:28:28:1 inputtype=uint8 ! "
                             "tensor_sink name=sink");
    ASSERT_TRUE(c.run.eos) << fw << ": " << c.run.error_text;
    ASSERT_EQ(c.buffers.size(), 1u) << fw;
    expect_nine(c.buffers[0]);
  }
}

// invoke-dynamic: flexible output whose 128-byte header carries the result's shape.
TEST(PytorchPipeline, InvokeDynamicFlexibleOutput) {
  REQUIRE_PYTORCH_PIPELINE();
  Captured c = run_capture(lenet_src() + "tensor_filter framework=pytorch model=" + models() +
                           "pytorch_lenet5.pt invoke-dynamic=true ! tensor_sink name=sink");
  ASSERT_TRUE(c.run.eos) << c.run.error_text;
  ASSERT_EQ(c.buffers.size(), 1u);
  ASSERT_EQ(c.buffers[0].size(), 128u + 10u);
  const uint8_t *h = c.buffers[0].data();
  uint32_t type, d0, d1;
  std::memcpy(&type, h + 8, 4);
  std::memcpy(&d0, h + 12, 4);
  std::memcpy(&d1, h + 16, 4);
  EXPECT_EQ(type, static_cast<uint32_t>(5));  // uint8
  EXPECT_EQ(d0, 10u);
  EXPECT_EQ(d1, 1u);
  expect_nine(std::vector<uint8_t>(h + 128, h + 138));
}

// ---- bus errors ----

// Every open prints the accelerator line of NNStreamer's pytorch sub-plugin (g_message
// "gpu = N, accl = X"; scripts, NNStreamer's own runTest.sh among them, grep for it), whatever
// `silent` says and also when the open then fails (a GPU asked for on a machine without CUDA,
// output= not matching the model).
std::vector<std::string> *g_messages = nullptr;
void collect_message(const gchar *, GLogLevelFlags, const gchar *message, gpointer) {
  if (g_messages) g_messages->push_back(message);
}

TEST(PytorchPipeline, EveryOpenPrintsTheAccelerator) {
  REQUIRE_PYTORCH_PIPELINE();
  std::vector<std::string> got;
  g_messages = &got;
  const guint id = g_log_set_handler(nullptr, G_LOG_LEVEL_MESSAGE, collect_message, nullptr);
  struct Case {
    const char *props, *want;
    bool ok;
  };
  const Case cases[] = {
      {"", "gpu = 0, accl = cpu", true},  // unset: NNStreamer's default, the first supported
      {"silent=false", "gpu = 0, accl = cpu", true},
      {"accelerator=true:cpu", "gpu = 0, accl = cpu", true},
      {"accelerator=true:npu", "gpu = 0, accl = cpu", true},  // none supported named: auto
      {"accelerator=false", "gpu = 0, accl = none", true},
      {"accelerator=true:gpu,cpu", "gpu = 0, accl = cpu", true},     // no CUDA here: falls back
      {"accelerator=true:gpu", "gpu = 1, accl = gpu", false},        // no CUDA here: fails
      {"output=1:7 outputtype=int8", "gpu = 0, accl = cpu", false},  // output= mismatch
  };
  for (const Case &k : cases) {
    SCOPED_TRACE(k.props);
    got.clear();
    Captured c = run_capture(lenet_src() + "tensor_filter framework=pytorch model=" + models() +
                             "pytorch_lenet5.pt " + k.props + " ! tensor_sink name=sink");
    EXPECT_EQ(c.run.eos, k.ok) << c.run.error_text;
    const auto n = std::count_if(got.begin(), got.end(),
                                 [](const std::string &m) { return m.rfind("gpu = ", 0) == 0; });
    EXPECT_GE(n, 1) << ::testing::PrintToString(got);
    EXPECT_NE(std::find(got.begin(), got.end(), k.want), got.end())
        << ::testing::PrintToString(got);
  }
  g_log_remove_handler(nullptr, id);
  g_messages = nullptr;
}

TEST(PytorchPipelineErrors, MissingModel) {
  REQUIRE_PYTORCH_PIPELINE();
  auto r = nns::test::run_pipeline(lenet_src() +
                                   "tensor_filter framework=pytorch model=/nonexistent/lenet.pt "
                                   "input=1:28:28:1 inputtype=uint8 ! tensor_sink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("/nonexistent/lenet.pt"), std::string::npos) << r.error_text;
}

TEST(PytorchPipelineErrors, CorruptModel) {
  REQUIRE_PYTORCH_PIPELINE();
  std::string dir = nns::test::make_temp_dir();
  std::string path = dir + "/corrupt.pt";
  std::ofstream(path) << "plain text renamed to .pt\n";
  auto r = nns::test::run_pipeline(lenet_src() + "tensor_filter framework=pytorch model=" + path +
                                   " input=1:28:28:1 inputtype=uint8 ! tensor_sink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("tensorfilter"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find(path), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("PytorchStreamReader"), std::string::npos) << r.error_text;
  std::filesystem::remove_all(dir);
}

// A 28x56 image reaches LeNet's fully connected layer with the wrong size: torch's message.
TEST(PytorchPipelineErrors, WrongInputShapeGivesTorchMessage) {
  REQUIRE_PYTORCH_PIPELINE();
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=1 ! video/x-raw,format=GRAY8,width=28,height=56 ! "
      "tensor_converter ! tensor_filter framework=pytorch model=" +
      models() +
      "pytorch_lenet5.pt input=1:28:56:1 inputtype=uint8 output=10:1 outputtype=uint8 ! "
      "tensor_sink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("pytorch_lenet5.pt"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("shapes cannot be multiplied"), std::string::npos) << r.error_text;
}

TEST(PytorchPipelineErrors, UnknownCustomKey) {
  REQUIRE_PYTORCH_PIPELINE();
  auto r =
      nns::test::run_pipeline(lenet_src() + "tensor_filter framework=pytorch model=" + models() +
                              "pytorch_lenet5.pt input=1:28:28:1 inputtype=uint8 "
                              "custom=NumThreads:1,Bogus:2 ! tensor_sink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("unknown custom option 'Bogus'"), std::string::npos) << r.error_text;
}

TEST(PytorchPipelineErrors, OutputDisagreesWithModel) {
  REQUIRE_PYTORCH_PIPELINE();
  auto r =
      nns::test::run_pipeline(lenet_src() + "tensor_filter framework=pytorch model=" + models() +
                              "pytorch_lenet5.pt input=1:28:28:1 inputtype=uint8 "
                              "output=10:1 outputtype=float32 ! tensor_sink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("float32 10:1"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("uint8"), std::string::npos) << r.error_text;
}

}  // namespace

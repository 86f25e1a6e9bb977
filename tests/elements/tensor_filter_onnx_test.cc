// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter with ONNX Runtime on the generated models (tests/data/generate_models.py):
// inputname=/outputname= picking tensors by name, framework=auto and framework_priority_onnx on
// a real .onnx, and is-updatable reloads of real models. Skipped when the onnxruntime back end
// or the generated models are missing.
#include <filesystem>

#include "backends/backend_loader.h"
#include "elements/filter_test_util.h"

using namespace nns::test;

namespace {

std::vector<float> floats(const std::vector<uint8_t> &b) {
  std::vector<float> f(b.size() / sizeof(float));
  std::memcpy(f.data(), b.data(), f.size() * sizeof(float));
  return f;
}

// sub_scale: inputs x, y float32 [1,2,3] (3:2:1); outputs diff = x - y, wsum = x + 2y,
// prod = x * y.
class OnnxFilter : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!std::filesystem::exists(backend_path("onnxruntime")))
      GTEST_SKIP() << backend_path("onnxruntime") << " is not built (no ONNX Runtime)";
    auto m = load_ref("sub_scale");
    if (!m) GTEST_SKIP() << "generated models missing in " << models_dir();
    m_ = *m;
    x_ = floats(m_.inputs[0].bytes);
    y_ = floats(m_.inputs[1].bytes);
  }

  std::string model() const { return m_.file("onnx"); }
  static std::string caps() { return tensors_caps("float32,float32", "3:2:1,3:2:1", 2); }

  // One frame (x, y) through `tensor_filter <props>`: the output tensors.
  std::vector<std::vector<uint8_t>> run(const std::string &props) {
    FilterHarness fh("tensor_filter " + props, caps());
    return push_pull(fh);
  }
  std::vector<std::vector<uint8_t>> push_pull(FilterHarness &fh) {
    std::vector<std::vector<uint8_t>> out;
    GstFlowReturn ret =
        gst_harness_push(fh.h.get(), tensor_buffer({m_.inputs[0].bytes, m_.inputs[1].bytes}));
    EXPECT_EQ(ret, GST_FLOW_OK) << fh.error_text();
    if (ret != GST_FLOW_OK) return out;
    GstBuffer *b = gst_harness_pull(fh.h.get());
    if (!b) return out;
    for (guint i = 0; i < gst_buffer_n_memory(b); ++i) out.push_back(memory_bytes(b, i));
    gst_buffer_unref(b);
    return out;
  }
  // `got` equals reference output `o` of the model.
  void expect_ref(const std::vector<uint8_t> &got, std::size_t o) const {
    EXPECT_EQ(compare(m_.outputs[o], got.data(), got.size(), m_.abs_tol, m_.rel_tol), "")
        << "reference output " << o << " ('" << m_.outputs[o].desc.name << "')";
  }
  // `got` equals f(x[i], y[i]) element-wise.
  template <typename F>
  void expect_each(const std::vector<uint8_t> &got, F f) const {
    std::vector<float> g = floats(got);
    ASSERT_EQ(g.size(), x_.size());
    for (std::size_t i = 0; i < g.size(); ++i)
      EXPECT_NEAR(g[i], f(x_[i], y_[i]), 1e-5) << "element " << i;
  }
  // Starts `tensor_filter <props>` in a pipeline and returns the bus error.
  std::string start_error(const std::string &props) {
    auto r = run_pipeline(fake_source(48, caps()) + "tensor_filter " + props + " ! fakesink");
    EXPECT_TRUE(r.error) << props;
    return r.error_text;
  }

  RefModel m_;
  std::vector<float> x_, y_;
};

}  // namespace

// --- inputname / outputname -----------------------------------------------------------------

TEST_F(OnnxFilter, AllOutputsWithoutNames) {
  auto out = run("framework=onnxruntime model=" + model());
  ASSERT_EQ(out.size(), 3u);
  for (std::size_t o = 0; o < 3; ++o) expect_ref(out[o], o);
}

TEST_F(OnnxFilter, OutputNameAlonePicksThatOutput) {
  auto out = run("framework=onnxruntime model=" + model() + " outputname=prod");
  ASSERT_EQ(out.size(), 1u);
  expect_ref(out[0], 2);
}

TEST_F(OnnxFilter, OutputNamesPickOutputsInTheOrderGiven) {
  auto out = run("framework=onnxruntime model=" + model() + " outputname=wsum,diff");
  ASSERT_EQ(out.size(), 2u);
  expect_ref(out[0], 1);
  expect_ref(out[1], 0);
}

// inputname=y,x: the frame's first tensor goes to model input y.
TEST_F(OnnxFilter, InputNamesAloneFeedTensorsByName) {
  auto out = run("framework=onnxruntime model=" + model() + " inputname=y,x");
  ASSERT_EQ(out.size(), 3u);
  expect_each(out[0], [](float x, float y) { return y - x; });
  expect_each(out[1], [](float x, float y) { return y + 2.0f * x; });
  expect_each(out[2], [](float x, float y) { return x * y; });
  out = run("framework=onnxruntime model=" + model() + " inputname=x,y");
  ASSERT_EQ(out.size(), 3u);
  expect_ref(out[0], 0);
}

TEST_F(OnnxFilter, NamesWithShapesAndTypes) {
  auto out = run("framework=onnxruntime model=" + model() +
                 " input=3:2:1,3:2:1 inputtype=float32,float32 inputname=y,x"
                 " output=3:2:1 outputtype=float32 outputname=diff");
  ASSERT_EQ(out.size(), 1u);
  expect_each(out[0], [](float x, float y) { return y - x; });
}

TEST_F(OnnxFilter, UnknownOutputNameIsABusErrorListingTheOutputs) {
  std::string e = start_error("framework=onnxruntime model=" + model() + " outputname=quotient");
  EXPECT_NE(e.find("outputname 'quotient' is not an output of the model (outputs: 'diff', "
                   "'wsum', 'prod')"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(model()), std::string::npos) << e;
}

TEST_F(OnnxFilter, UnknownInputNameIsABusErrorListingTheInputs) {
  std::string e = start_error("framework=onnxruntime model=" + model() + " inputname=z,x");
  EXPECT_NE(e.find("inputname 'z' is not an input of the model (inputs: 'x', 'y')"),
            std::string::npos)
      << e;
  EXPECT_NE(e.find(model()), std::string::npos) << e;
  e = start_error("framework=onnxruntime model=" + model() + " inputname=x");
  EXPECT_NE(e.find("got 1 inputname= tensors, the model has 2"), std::string::npos) << e;
}

// --- framework=auto -------------------------------------------------------------------------

TEST_F(OnnxFilter, AutoRunsOnnxThroughOnnxruntime) {
  for (const char *fw : {"", "framework=auto "}) {
    SCOPED_TRACE(fw);
    auto out = run(std::string(fw) + "model=" + model());
    ASSERT_EQ(out.size(), 3u);
    for (std::size_t o = 0; o < 3; ++o) expect_ref(out[o], o);
  }
  // Which back end it picked: its name is in the message of a shape conflict.
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter model=" + model() + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("framework 'onnxruntime', model '" + model() + "'"),
            std::string::npos)
      << r.error_text;
}

TEST_F(OnnxFilter, AutoFollowsFrameworkPriorityOnnx) {
  if (!std::filesystem::exists(backend_path("opencv")))
    GTEST_SKIP() << backend_path("opencv") << " is not built";
  std::string ini = write_temp("nnstreamer.ini",
                               "[common]\nenable_envvar=False\n[filter]\nfilters=" + filters_dir() +
                                   "\nframework_priority_onnx=opencv\n");
  ScopedEnv conf("NNSTREAMER_CONF", ini);
  auto out = run("model=" + model());
  ASSERT_EQ(out.size(), 3u);
  for (std::size_t o = 0; o < 3; ++o) expect_ref(out[o], o);
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter model=" + model() + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("framework 'opencv', model '" + model() + "'"), std::string::npos)
      << r.error_text;
}

// --- is-updatable with real models ----------------------------------------------------------

TEST_F(OnnxFilter, ReloadSwapsToAnotherModelOfTheSameTensors) {
  std::string dir = make_temp_dir(), copy = dir + "/copy.onnx";
  std::filesystem::copy_file(model(), copy);
  FilterHarness fh(
      "tensor_filter framework=onnxruntime is-updatable=true outputname=diff model=" + model(),
      caps());
  auto out = push_pull(fh);
  ASSERT_EQ(out.size(), 1u);
  expect_ref(out[0], 0);
  g_object_set(fh.element(), "model", copy.c_str(), nullptr);
  EXPECT_EQ(fh.warning_text(), "");
  out = push_pull(fh);
  ASSERT_EQ(out.size(), 1u);
  expect_ref(out[0], 0);  // outputname= still applies to the new model
  gchar *m = nullptr;
  g_object_get(fh.element(), "model", &m, nullptr);
  EXPECT_EQ(std::string(m), copy);
  g_free(m);
  EXPECT_EQ(fh.error_text(), "");
  std::filesystem::remove_all(dir);
}

// add_mul takes 4:3:1 tensors: refused, and sub_scale goes on answering.
TEST_F(OnnxFilter, ReloadToContradictingModelKeepsTheOldOne) {
  auto other = load_ref("add_mul");
  ASSERT_TRUE(other);
  FilterHarness fh("tensor_filter framework=onnxruntime is-updatable=true model=" + model(),
                   caps());
  auto out = push_pull(fh);
  ASSERT_EQ(out.size(), 3u);
  g_object_set(fh.element(), "model", other->file("onnx").c_str(), nullptr);
  std::string w = fh.warning_text();
  EXPECT_NE(w.find("reload refused, still running model '" + model() + "'"), std::string::npos)
      << w;
  EXPECT_NE(w.find("model '" + other->file("onnx") + "' cannot replace"), std::string::npos) << w;
  EXPECT_NE(w.find("float32 4:3:1"), std::string::npos) << w;
  EXPECT_NE(w.find("float32 3:2:1"), std::string::npos) << w;
  out = push_pull(fh);
  ASSERT_EQ(out.size(), 3u);
  for (std::size_t o = 0; o < 3; ++o) expect_ref(out[o], o);
  EXPECT_EQ(fh.error_text(), "");
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter ! tensor_filter with real models: the first filter negotiates its output with
// a second filter whose model input is known only once that model is open (ONNX Runtime reads
// it from the opened session) or only from the caps (a TorchScript model without input=).
// Models: the generated add_mul / sub_scale twins (tests/data/generate_models.py) and
// ../shared/models; each test skips, saying why, when a back end or a model is missing.
#include <gst/app/gstappsink.h>

#include <cmath>
#include <filesystem>

#include "backends/backend_loader.h"
#include "elements/filter_test_util.h"
#include "elements/stream_util.h"
#include "gst/tensor_caps.h"

using namespace nns::test;

namespace {

#define REQUIRE_BACKEND(name)                                                         \
  do {                                                                                \
    if (!std::filesystem::exists(backend_path(name)))                                 \
      GTEST_SKIP() << backend_path(name) << " is not built (its runtime is missing)"; \
  } while (0)

std::vector<float> floats(const std::vector<uint8_t> &b) {
  std::vector<float> f(b.size() / sizeof(float));
  std::memcpy(f.data(), b.data(), f.size() * sizeof(float));
  return f;
}

const char *kTwoInputs =
    "other/tensors,format=static,num_tensors=2,types=(string)\\\"float32,float32\\\","
    "dimensions=(string)\\\"4:3:1,4:3:1\\\",framerate=0/1";

// add_mul: (a, b) float32 4:3:1 -> (a + b, a * b).
class FilterChain : public ::testing::Test {
 protected:
  void SetUp() override {
    auto m = load_ref("add_mul");
    if (!m) GTEST_SKIP() << "generated models missing in " << models_dir();
    m_ = *m;
  }
  // Path of add_mul for back end `fw` ("onnxruntime" or "pytorch").
  std::string model(const std::string &fw) const {
    return m_.file(fw == "onnxruntime" ? "onnx" : "pytorch");
  }
  // appsrc (a, b) ! tensor_filter fw1 ! tensor_filter fw2 ! appsink; returns the output tensors
  // of the one frame and checks them against ((a+b) + a*b, (a+b) * a*b).
  void run_chain(const std::string &fw1, const std::string &fw2) {
    SCOPED_TRACE(fw1 + " ! " + fw2);
    Pipe p(appsrc("src", kTwoInputs) + "! tensor_filter name=first framework=" + fw1 +
           " model=" + model(fw1) + " ! tensor_filter name=second framework=" + fw2 +
           " model=" + model(fw2) + " ! appsink name=out sync=false");
    p.collect("out");
    p.push("src", make_buffer({m_.inputs[0].bytes, m_.inputs[1].bytes}, 0));
    p.eos("src");
    RunResult r = p.run(60);
    ASSERT_TRUE(r.eos) << r.error_text;
    ASSERT_EQ(p.out().size(), 1u);
    GstBuffer *b = p.out()[0];
    ASSERT_EQ(gst_buffer_n_memory(b), 2u);
    std::vector<float> a = floats(m_.inputs[0].bytes), bb = floats(m_.inputs[1].bytes);
    std::vector<float> sum2 = floats(tensor_bytes(b, 0)), prod2 = floats(tensor_bytes(b, 1));
    ASSERT_EQ(sum2.size(), 12u);
    ASSERT_EQ(prod2.size(), 12u);
    for (std::size_t i = 0; i < 12; ++i) {
      float s = a[i] + bb[i], q = a[i] * bb[i];
      EXPECT_NEAR(sum2[i], s + q, 1e-5 + 1e-5 * std::fabs(s + q)) << "element " << i;
      EXPECT_NEAR(prod2[i], s * q, 1e-5 + 1e-5 * std::fabs(s * q)) << "element " << i;
    }
  }

  RefModel m_;
};

// The caps of a pad's peer, as a string ("" when none).
std::string peer_caps(GstElement *e, const char *pad) {
  GstPad *p = gst_element_get_static_pad(e, pad);
  GstCaps *c = gst_pad_peer_query_caps(p, nullptr);
  gst_object_unref(p);
  gchar *s = gst_caps_to_string(c);
  std::string out = s;
  g_free(s);
  gst_caps_unref(c);
  return out;
}

std::string string_prop(GstElement *e, const char *name) {
  gchar *v = nullptr;
  g_object_get(e, name, &v, nullptr);
  std::string out = v ? v : "";
  g_free(v);
  return out;
}

}  // namespace

// ONNX Runtime then a TorchScript model that tells no shapes: the second filter answers the
// first one's caps query with its template (legacy other/tensor first); the first filter must
// still fixate to its model's two output tensors, which the second one then takes.
TEST_F(FilterChain, OnnxThenPytorchWithoutShapes) {
  REQUIRE_BACKEND("onnxruntime");
  REQUIRE_BACKEND("pytorch");
  run_chain("onnxruntime", "pytorch");
}

TEST_F(FilterChain, PytorchThenOnnx) {
  REQUIRE_BACKEND("onnxruntime");
  REQUIRE_BACKEND("pytorch");
  run_chain("pytorch", "onnxruntime");
}

TEST_F(FilterChain, OnnxThenOnnx) {
  REQUIRE_BACKEND("onnxruntime");
  run_chain("onnxruntime", "onnxruntime");
}

TEST_F(FilterChain, PytorchThenPytorch) {
  REQUIRE_BACKEND("pytorch");
  run_chain("pytorch", "pytorch");
}

// Before start (NULL state), a caps query is answered with the model's input: the model is
// opened for it, as NNStreamer does, and start() keeps that instance.
TEST_F(FilterChain, CapsQueryBeforeStartOpensTheModel) {
  REQUIRE_BACKEND("onnxruntime");
  auto sub = load_ref("sub_scale");
  if (!sub) GTEST_SKIP() << "generated models missing in " << models_dir();
  Pipe p("tensor_filter name=first framework=onnxruntime model=" + model("onnxruntime") +
         " ! tensor_filter name=second framework=onnxruntime model=" + sub->file("onnx") +
         " ! fakesink");
  GstElement *first = p.get("first"), *second = p.get("second");
  // What the second filter takes, asked from the first one's src pad.
  std::string caps = peer_caps(first, "src");
  EXPECT_EQ(caps.rfind("other/tensors, format=(string)static, num_tensors=(int)2", 0), 0u) << caps;
  EXPECT_NE(caps.find("\"3:2:1\\,3:2:1\""), std::string::npos) << caps;
  EXPECT_EQ(string_prop(second, "input"), "3:2:1,3:2:1");
  EXPECT_EQ(string_prop(second, "inputname"), "x,y");
  // The first filter's sink pad, asked from upstream: add_mul's input.
  GstPad *sink = gst_element_get_static_pad(first, "sink");
  GstCaps *c = gst_pad_query_caps(sink, nullptr);
  gst_object_unref(sink);
  gchar *s = gst_caps_to_string(c);
  caps = s;
  g_free(s);
  gst_caps_unref(c);
  EXPECT_NE(caps.find("\"4:3:1\\,4:3:1\""), std::string::npos) << caps;
  EXPECT_EQ(string_prop(first, "output"), "4:3:1,4:3:1");
  // READY -> NULL releases the models opened for the queries (LeakSanitizer checks the rest).
  EXPECT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_READY), GST_STATE_CHANGE_SUCCESS);
  EXPECT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS);
}

// The same on ../shared's MobileNet: its float32 224:224:3:1 input is known before start.
TEST(FilterChainShared, MobilenetInputBeforeStart) {
  NNS_REQUIRE_SHARED_MODELS();
  REQUIRE_BACKEND("onnxruntime");
  Pipe p("tensor_filter name=f framework=onnxruntime model=" + shared_models_dir() +
         "/models/mobilenet_v2_quant.onnx ! fakesink");
  GstElement *f = p.get("f");
  GstPad *sink = gst_element_get_static_pad(f, "sink");
  GstCaps *c = gst_pad_query_caps(sink, nullptr);
  gst_object_unref(sink);
  GstCaps *want = gst_caps_from_string(
      "other/tensors,format=static,num_tensors=1,types=float32,dimensions=224:224:3:1,"
      "framerate=30/1");
  EXPECT_TRUE(gst_caps_can_intersect(c, want));
  GstCaps *other = gst_caps_from_string(
      "other/tensors,format=static,num_tensors=1,types=float32,dimensions=3:224:224:1,"
      "framerate=30/1");
  // The template is still appended (a wrong shape links and set_caps names both shapes), but
  // the model's shape comes first.
  GstCaps *first = gst_caps_copy_nth(c, 0);
  EXPECT_TRUE(gst_caps_can_intersect(first, want));
  EXPECT_FALSE(gst_caps_can_intersect(first, other));
  gst_caps_unref(first);
  gst_caps_unref(want);
  gst_caps_unref(other);
  gst_caps_unref(c);
  EXPECT_EQ(string_prop(f, "input"), "224:224:3:1");
  EXPECT_EQ(string_prop(f, "inputtype"), "float32");
}

// add_mul's two 4:3:1 outputs into sub_scale, which takes two 3:2:1 tensors: the second filter
// posts the error, naming itself, its model, the first filter and its model, and both shapes.
TEST_F(FilterChain, ShapesThatDoNotFitNameBothFilters) {
  REQUIRE_BACKEND("onnxruntime");
  auto sub = load_ref("sub_scale");
  if (!sub) GTEST_SKIP() << "generated models missing in " << models_dir();
  Pipe p(appsrc("src", kTwoInputs) +
         "! tensor_filter name=first framework=onnxruntime model=" + model("onnxruntime") +
         " ! tensor_filter name=second framework=onnxruntime model=" + sub->file("onnx") +
         " ! fakesink");
  p.push("src", make_buffer({m_.inputs[0].bytes, m_.inputs[1].bytes}, 0));
  p.eos("src");
  RunResult r = p.run(60);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(r.error_source, "second") << r.error_text;
  const std::string &t = r.error_text;
  EXPECT_NE(t.find("model '" + sub->file("onnx") + "'"), std::string::npos) << t;
  EXPECT_NE(t.find("the input stream has 2 tensor(s): [0] float32 4:3:1, [1] float32 4:3:1, "),
            std::string::npos)
      << t;
  EXPECT_NE(t.find("but the model's input is 2 tensor(s): [0] float32 3:2:1 'x', "
                   "[1] float32 3:2:1 'y'"),
            std::string::npos)
      << t;
  EXPECT_NE(t.find("the stream comes from first (tensor_filter framework 'onnxruntime', model '" +
                   model("onnxruntime") + "')"),
            std::string::npos)
      << t;
}

// ../shared: MobileNet's float32 1000:1 scores into LeNet-5 (uint8 1:28:28:1).
TEST(FilterChainShared, MobilenetIntoLenetNamesBothFilters) {
  NNS_REQUIRE_SHARED_MODELS();
  REQUIRE_BACKEND("onnxruntime");
  REQUIRE_BACKEND("pytorch");
  std::string m = shared_models_dir() + "/models/";
  auto r = run_pipeline(fake_source(224 * 224 * 3 * 4, tensors_caps("float32", "224:224:3:1"), 1) +
                            "tensor_filter name=mobilenet framework=onnxruntime model=" + m +
                            "mobilenet_v2_quant.onnx ! tensor_filter name=lenet framework=pytorch "
                            "model=" +
                            m + "pytorch_lenet5.pt input=1:28:28:1 inputtype=uint8 ! fakesink",
                        60);
  ASSERT_TRUE(r.error);
  EXPECT_EQ(r.error_source, "lenet") << r.error_text;
  const std::string &t = r.error_text;
  EXPECT_NE(t.find("model '" + m + "pytorch_lenet5.pt'"), std::string::npos) << t;
  EXPECT_NE(t.find("the input stream has 1 tensor(s): [0] float32 1000:1, but input=/inputtype= "
                   "give 1 tensor(s): [0] uint8 1:28:28:1"),
            std::string::npos)
      << t;
  EXPECT_NE(t.find("the stream comes from mobilenet (tensor_filter framework 'onnxruntime', "
                   "model '" +
                   m + "mobilenet_v2_quant.onnx')"),
            std::string::npos)
      << t;
}

// A model opened for a caps query before start keeps its open warnings for the start: here the
// element has no bus yet when it is asked (not in a pipeline), and the pipeline's bus still gets
// the warning, once, when the element starts.
TEST(FilterQueryOpen, OpenWarningsArePostedAtStart) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  GstElement *f = gst_element_factory_make("tensor_filter", "f");
  g_object_set(f, "framework", "custom", "model", so.c_str(), "inputname", "pixels", nullptr);
  GstPad *sink = gst_element_get_static_pad(f, "sink");
  GstCaps *c = gst_pad_query_caps(sink, nullptr);  // opens the model (NULL state, no bus)
  EXPECT_NE(nns::gst::caps_to_string(c).find("10:1:1:1"), std::string::npos);
  gst_caps_unref(c);
  gst_object_unref(sink);
  EXPECT_EQ(string_prop(f, "input"), "10:1:1:1");
  GstElement *p = gst_parse_launch(
      (fake_source(40, tensors_caps("float32", "10:1:1:1"), 1) + "identity name=i").c_str(),
      nullptr);
  ASSERT_NE(p, nullptr);
  GstElement *out = gst_element_factory_make("fakesink", nullptr);
  gst_bin_add_many(GST_BIN(p), f, out, nullptr);
  GstElement *i = gst_bin_get_by_name(GST_BIN(p), "i");
  ASSERT_TRUE(gst_element_link_many(i, f, out, nullptr));
  gst_object_unref(i);
  RunResult r = run_pipeline(p);
  gst_object_unref(p);
  EXPECT_TRUE(r.eos) << r.error_text;
  // "f: <text> | <debug>": the message part starts with the element name.
  const std::string w =
      "f: inputname='pixels' is ignored: framework 'custom' does not pick tensors by name";
  auto first = r.warning_text.find(w);
  EXPECT_NE(first, std::string::npos) << r.warning_text;
  EXPECT_EQ(r.warning_text.find(w, first + 1), std::string::npos) << "posted twice";
}

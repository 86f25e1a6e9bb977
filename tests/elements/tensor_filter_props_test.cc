// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter properties: framework detection and aliases, combinations, shared models,
// reload, invoke-dynamic, statistics and latency reporting, suspend, config-file, cpp filters.
#include <atomic>
#include <chrono>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <thread>

#include "core/filter_instance.h"
#include "core/filter_registry.h"
#include "core/meta_header.h"
#include "elements/filter_test_util.h"
#include "nns_filter_backend.hh"
#include "tensor_filter_cpp.hh"

using namespace nns::test;

namespace {

// In-process test back end "nnstest". Model file: "<add> [<type> <dims>]": invoke adds <add>
// to every byte; with a type/dims the model reports its shapes, otherwise the output mirrors
// the input. custom= accepts only "event:1" (suspend with events) and "fail:1".
std::atomic<int> g_opens{0}, g_closes{0}, g_suspends{0}, g_resumes{0}, g_invokes{0};
std::string g_last_accel;

class TestBackend : public nns::FilterBackend {
 public:
  explicit TestBackend(const nns_filter_props &p) {
    g_opens++;
    g_last_accel = p.accelerator ? p.accelerator : "";
    for (auto &kv : nns::split(p.custom ? p.custom : "", ",")) {
      auto parts = nns::split(kv, ":");
      if (parts.size() != 2 || (parts[0] != "event" && parts[0] != "fail"))
        throw nns::FilterError("unknown custom option '" + kv + "' (known: event, fail)");
      if (parts[0] == "event") events_ = parts[1] == "1";
      if (parts[0] == "fail") fail_ = parts[1] == "1";
    }
    load(p.model_files[0]);
  }
  ~TestBackend() override { g_closes++; }
  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    if (!shaped_) return false;
    in = nns_tensors_desc{};
    in.num_tensors = 1;
    in.tensors[0].type = static_cast<uint32_t>(type_);
    for (std::size_t i = 0; i < nns::kRankLimit; ++i) in.tensors[0].dims[i] = dims_[i];
    out = in;
    return true;
  }
  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    out = in;
    return true;
  }
  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    g_invokes++;
    if (fail_) throw nns::FilterError("simulated inference failure in nnstest");
    for (uint32_t t = 0; t < num_in && t < num_out; ++t)
      for (std::size_t i = 0; i < out[t].size && i < in[t].size; ++i)
        static_cast<uint8_t *>(out[t].data)[i] =
            static_cast<uint8_t>(static_cast<const uint8_t *>(in[t].data)[i] + add_);
  }
  void reload(const nns_filter_props &p) override { load(p.model_files[0]); }
  bool handle_event(nns_filter_event ev) override {
    if (!events_) return false;
    if (ev == NNS_FILTER_EVENT_SUSPEND) g_suspends++;
    if (ev == NNS_FILTER_EVENT_RESUME) g_resumes++;
    return true;
  }

 private:
  void load(const char *path) {
    std::ifstream f(path);
    std::string type, dims;
    if (!(f >> add_)) throw nns::FilterError(std::string("cannot parse model ") + path);
    if (f >> type >> dims) {
      shaped_ = true;
      type_ = nns::parse_type(type);
      dims_ = nns::parse_dims(dims);
    }
  }
  int add_ = 0;
  bool shaped_ = false, events_ = false, fail_ = false;
  nns::TensorType type_ = nns::TensorType::kUInt8;
  nns::Dims dims_{};
};

const nns_filter_backend_i *test_table() {
  static const nns_filter_backend_i t =
      nns::FilterBackendAdapter<TestBackend>::make("nnstest", 0, nullptr);
  return &t;
}

struct RegisterTestBackend {
  RegisterTestBackend() { nns::FilterRegistry::get().add_builtin(test_table()); }
} g_register;

std::vector<uint8_t> push_pull(FilterHarness &fh, std::vector<std::vector<uint8_t>> in,
                               guint mem = 0) {
  EXPECT_EQ(gst_harness_push(fh.h.get(), tensor_buffer(in)), GST_FLOW_OK) << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  if (!out) return {};
  auto v = memory_bytes(out, mem);
  gst_buffer_unref(out);
  return v;
}

}  // namespace

// --- framework resolution -----------------------------------------------------------------

TEST(TensorFilterFramework, AutoUsesIniPriorityForExtension) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini("framework_priority_echo=nosuch,testecho\n"));
  std::string model = write_temp("m.echo", "x");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter model=" + model + " ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(TensorFilterFramework, AutoOnnxListsCandidatesWhenMissing) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  std::string model = write_temp("m.onnx", "x");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=auto model=" + model + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("needs one of onnxruntime, opencv"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("libnnstreamer_filter_onnxruntime.so"), std::string::npos);
}

TEST(TensorFilterFramework, AutoUnknownExtensionAsksForFramework) {
  std::string model = write_temp("m.weird", "x");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter model=" + model + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("cannot tell which framework reads model"), std::string::npos)
      << r.error_text;
}

TEST(TensorFilterFramework, TfliteAliasResolvesThroughSubpluginPriority) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini("[tensorflow2-lite]\nsubplugin_priority=testecho\n"));
  std::string model = write_temp("m.tflite", "x");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=tensorflow2-lite model=" + model + " ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(TensorFilterFramework, TfliteAutoUsesFrameworkPriorityTflite) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini("framework_priority_tflite=testecho\n"));
  std::string model = write_temp("m.tflite", "x");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter model=" + model + " ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

// The tflite names try our back end (tensorflow2-lite) first, then armnn.
TEST(TensorFilterFramework, TfliteAliasDefaultsToArmnn) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  std::string model = write_temp("m.tflite", "x");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=tensorflow-lite model=" + model + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("framework 'tensorflow-lite' is not available: none of "
                              "libnnstreamer_filter_tensorflow-lite.so, "
                              "libnnstreamer_filter_tensorflow2-lite.so, "
                              "libnnstreamer_filter_armnn.so in " +
                              filter_dir()),
            std::string::npos)
      << r.error_text;
}

TEST(TensorFilterFramework, FilterAliasesSection) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini("[filter-aliases]\nmyecho=testecho\n"));
  std::string model = write_temp("m.bin", "x");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=myecho model=" + model + " ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(TensorFilterFramework, SubPluginsListsLoadableBackends) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  GstElement *f = gst_element_factory_make("tensor_filter", nullptr);
  gchar *s = nullptr;
  g_object_get(f, "sub-plugins", &s, nullptr);
  std::string list = s;
  g_free(s);
  gst_object_unref(f);
  EXPECT_EQ(list.rfind("custom,custom-easy,cpp", 0), 0u) << list;
  EXPECT_NE(list.find("testecho"), std::string::npos) << list;
  EXPECT_NE(list.find("nnstest"), std::string::npos) << list;
}

// --- custom options, accelerator, back-end errors ---------------------------------------

TEST(TensorFilterProps, WrongCustomKeyNamesKeyAndModel) {
  std::string model = write_temp("m.t", "1");
  auto r =
      run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                   "tensor_filter framework=nnstest custom=Bogus:3 model=" + model + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("unknown custom option 'Bogus:3'"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find(model), std::string::npos) << r.error_text;
}

TEST(TensorFilterProps, InferenceErrorCarriesBackendText) {
  std::string model = write_temp("m.t", "1");
  auto r =
      run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                   "tensor_filter framework=nnstest custom=fail:1 model=" + model + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("simulated inference failure in nnstest"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("framework 'nnstest', model '" + model + "'"), std::string::npos)
      << r.error_text;
}

TEST(TensorFilterProps, AcceleratorAndLayoutsReachBackendAndReadBack) {
  std::string model = write_temp("m.t", "0 uint8 4");
  FilterHarness fh(
      "tensor_filter framework=nnstest accelerator=true:gpu,!cpu inputlayout=NHWC "
      "outputlayout=nchw model=" +
          model,
      tensors_caps("uint8", "4"));
  EXPECT_EQ(g_last_accel, "true:gpu,!cpu");
  gchar *il = nullptr, *ol = nullptr, *ir = nullptr, *orr = nullptr;
  g_object_get(fh.element(), "inputlayout", &il, "outputlayout", &ol, "inputranks", &ir,
               "outputranks", &orr, nullptr);
  EXPECT_STREQ(il, "NHWC");
  EXPECT_STREQ(ol, "NCHW");
  EXPECT_STREQ(ir, "1");
  EXPECT_STREQ(orr, "1");
  g_free(il);
  g_free(ol);
  g_free(ir);
  g_free(orr);
}

TEST(TensorFilterProps, BadPropertyValuesAreNamed) {
  std::string model = write_temp("m.t", "1");
  struct Case {
    std::string props, expect;
  } cases[] = {
      {"inputtype=uint8", "inputtype='uint8' is set but input="},
      {"input=4 inputtype=foo", "unknown tensor type 'foo'"},
      {"input=4,4 inputtype=uint8", "input= gives 2 tensor(s) but inputtype= gives 1"},
      {"input-combination=a", "input-combination: 'a' is not a tensor index"},
      {"output-combination=x1", "output-combination: 'x1' is neither i<N>"},
  };
  for (const auto &c : cases) {
    auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                          "tensor_filter framework=nnstest model=" + model + " " + c.props +
                          " ! fakesink");
    ASSERT_TRUE(r.error) << c.props;
    EXPECT_NE(r.error_text.find(c.expect), std::string::npos) << c.props << ": " << r.error_text;
  }
}

TEST(TensorFilterProps, PropertyOverridesAreCheckedAgainstModelOutput) {
  std::string model = write_temp("m.t", "0 uint8 4");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=nnstest output=8 outputtype=uint8 model=" + model +
                        " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("uint8 8"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("the model's output is 1 tensor(s): [0] uint8 4"), std::string::npos)
      << r.error_text;
}

TEST(TensorFilterProps, PropertiesDefineShapesForShapelessModel) {
  std::string model = write_temp("m.t", "2");
  FilterHarness fh(
      "tensor_filter framework=nnstest input=2:2 inputtype=uint8 output=2:2 "
      "outputtype=uint8 model=" +
          model,
      tensors_caps("uint8", "2:2"));
  EXPECT_EQ(push_pull(fh, {{1, 2, 3, 4}}), (std::vector<uint8_t>{3, 4, 5, 6}));
}

// --- combinations ---------------------------------------------------------------------------

TEST(TensorFilterProps, InputAndOutputCombination) {
  std::string model = write_temp("m.t", "10");
  FilterHarness fh(
      "tensor_filter framework=nnstest input-combination=1 "
      "output-combination=i0,o0 model=" +
          model,
      tensors_caps("uint8,uint8", "2,3", 2));
  ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{1, 2}, {3, 4, 5}})), GST_FLOW_OK)
      << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(gst_buffer_n_memory(out), 2u);
  EXPECT_EQ(memory_bytes(out, 0), (std::vector<uint8_t>{1, 2}));
  EXPECT_EQ(memory_bytes(out, 1), (std::vector<uint8_t>{13, 14, 15}));
  gst_buffer_unref(out);
  GstCaps *caps = gst_pad_get_current_caps(fh.h->sinkpad);
  gchar *s = gst_caps_to_string(caps);
  EXPECT_NE(std::string(s).find("dimensions=(string)\"2\\,3\""), std::string::npos) << s;
  g_free(s);
  gst_caps_unref(caps);
}

TEST(TensorFilterProps, InputCombinationOutOfRangeIsAnError) {
  std::string model = write_temp("m.t", "1");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=nnstest input-combination=3 model=" + model +
                        " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("input-combination index 3 is out of range"), std::string::npos)
      << r.error_text;
}

// --- shared models, reload, suspend ------------------------------------------------------

TEST(TensorFilterProps, SharedKeySharesOneInstance) {
  std::string model = write_temp("m.t", "1 uint8 4");
  int before = g_opens;
  auto r = run_pipeline(
      fake_source(4, tensors_caps("uint8", "4")) +
      "tee name=t ! queue ! tensor_filter framework=nnstest shared-tensor-filter-key=k1 model=" +
      model +
      " ! fakesink t. ! queue ! tensor_filter framework=nnstest "
      "shared-tensor-filter-key=k1 model=" +
      model + " ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(g_opens - before, 1);
  before = g_opens;
  r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                   "tee name=t ! queue ! tensor_filter framework=nnstest "
                   "shared-tensor-filter-key=k2 model=" +
                   model + " ! fakesink t. ! queue ! tensor_filter framework=nnstest model=" +
                   model + " ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(g_opens - before, 2);
  EXPECT_EQ(nns::FilterInstance::shared_use_count("k1"), 0u);
}

TEST(TensorFilterProps, ReloadWhilePlayingWhenUpdatable) {
  std::string m1 = write_temp("m1.t", "1 uint8 4"), m2 = write_temp("m2.t", "5 uint8 4");
  FilterHarness fh("tensor_filter framework=nnstest is-updatable=true model=" + m1,
                   tensors_caps("uint8", "4"));
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  g_object_set(fh.element(), "model", m2.c_str(), nullptr);
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{6, 6, 6, 6}));
  // The custom event of NNStreamer does the same.
  GstStructure *st =
      gst_structure_new("evt_update_model", "model_files", G_TYPE_STRING, m1.c_str(), nullptr);
  EXPECT_TRUE(
      gst_harness_push_event(fh.h.get(), gst_event_new_custom(GST_EVENT_CUSTOM_DOWNSTREAM, st)));
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  EXPECT_EQ(fh.error_text(), "");
}

// A refused reload leaves the old model loaded and running: a WARNING (the stream goes on, as
// in NNStreamer, which only logs it) names both models and the cause, `model` reads the old path.
TEST(TensorFilterProps, ReloadToContradictingModelKeepsTheOldOne) {
  std::string m1 = write_temp("m1.t", "1 uint8 4"), m2 = write_temp("m2.t", "5 uint8 8");
  FilterHarness fh("tensor_filter framework=nnstest is-updatable=true model=" + m1,
                   tensors_caps("uint8", "4"));
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  int opens = g_opens, closes = g_closes;
  g_object_set(fh.element(), "model", m2.c_str(), nullptr);
  std::string w = fh.warning_text();
  EXPECT_NE(w.find("reload refused, still running model '" + m1 + "'"), std::string::npos) << w;
  EXPECT_NE(w.find("model '" + m2 + "' cannot replace model '" + m1 + "'"), std::string::npos) << w;
  EXPECT_NE(w.find("the reloaded model's input 1 tensor(s): [0] uint8 8 differs from the "
                   "negotiated input 1 tensor(s): [0] uint8 4"),
            std::string::npos)
      << w;
  EXPECT_EQ(g_opens - opens, 1);    // the new model was opened beside the old one ...
  EXPECT_EQ(g_closes - closes, 1);  // ... and closed again
  gchar *model = nullptr;
  g_object_get(fh.element(), "model", &model, nullptr);
  EXPECT_EQ(std::string(model), m1);
  g_free(model);
  EXPECT_EQ(push_pull(fh, {{1, 2, 3, 4}}), (std::vector<uint8_t>{2, 3, 4, 5}));
  EXPECT_EQ(fh.error_text(), "");
  // A model that does not load at all is refused the same way.
  std::string bad = write_temp("bad.t", "not a number");
  g_object_set(fh.element(), "model", bad.c_str(), nullptr);
  w = fh.warning_text();
  EXPECT_NE(w.find("could not open model '" + bad + "': cannot parse model " + bad),
            std::string::npos)
      << w;
  EXPECT_EQ(push_pull(fh, {{1, 2, 3, 4}}), (std::vector<uint8_t>{2, 3, 4, 5}));
  // And a good model still loads afterwards.
  std::string m3 = write_temp("m3.t", "3 uint8 4");
  g_object_set(fh.element(), "model", m3.c_str(), nullptr);
  EXPECT_EQ(fh.warning_text(), "");
  EXPECT_EQ(push_pull(fh, {{1, 2, 3, 4}}), (std::vector<uint8_t>{4, 5, 6, 7}));
  EXPECT_EQ(fh.error_text(), "");
}

// Filters sharing one instance (shared-tensor-filter-key) keep the old model too.
TEST(TensorFilterProps, RefusedReloadKeepsTheSharedModel) {
  std::string m1 = write_temp("m1.t", "1 uint8 4"), m2 = write_temp("m2.t", "5 uint8 8");
  std::string desc =
      "tensor_filter framework=nnstest is-updatable=true shared-tensor-filter-key=reload_k "
      "model=" +
      m1;
  FilterHarness a(desc, tensors_caps("uint8", "4")), b(desc, tensors_caps("uint8", "4"));
  EXPECT_EQ(nns::FilterInstance::shared_use_count("reload_k"), 2u);
  EXPECT_EQ(push_pull(a, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  EXPECT_EQ(push_pull(b, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  g_object_set(a.element(), "model", m2.c_str(), nullptr);
  EXPECT_NE(a.warning_text().find("differs from the negotiated input"), std::string::npos);
  EXPECT_EQ(push_pull(a, {{3, 3, 3, 3}}), (std::vector<uint8_t>{4, 4, 4, 4}));
  EXPECT_EQ(push_pull(b, {{3, 3, 3, 3}}), (std::vector<uint8_t>{4, 4, 4, 4}));
  // A good reload through one filter changes the model of both.
  std::string m3 = write_temp("m3.t", "7 uint8 4");
  g_object_set(a.element(), "model", m3.c_str(), nullptr);
  EXPECT_EQ(push_pull(b, {{1, 1, 1, 1}}), (std::vector<uint8_t>{8, 8, 8, 8}));
  EXPECT_EQ(a.error_text() + b.error_text(), "");
}

TEST(TensorFilterProps, ModelChangeIgnoredWithoutIsUpdatable) {
  std::string m1 = write_temp("m1.t", "1 uint8 4"), m2 = write_temp("m2.t", "5 uint8 4");
  FilterHarness fh("tensor_filter framework=nnstest model=" + m1, tensors_caps("uint8", "4"));
  g_object_set(fh.element(), "model", m2.c_str(), nullptr);
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
}

TEST(TensorFilterProps, SuspendWithEventAndResumeOnData) {
  std::string model = write_temp("m.t", "1 uint8 4");
  int s0 = g_suspends, r0 = g_resumes;
  FilterHarness fh("tensor_filter framework=nnstest custom=event:1 suspend=40 model=" + model,
                   tensors_caps("uint8", "4"));
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  for (int i = 0; i < 500 && g_suspends == s0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(g_suspends - s0, 1);
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  EXPECT_EQ(g_resumes - r0, 1);
}

TEST(TensorFilterProps, SuspendClosesAndReopensWithoutEvents) {
  std::string model = write_temp("m.t", "3 uint8 4");
  int o0 = g_opens, c0 = g_closes;
  FilterHarness fh("tensor_filter framework=nnstest suspend=30 model=" + model,
                   tensors_caps("uint8", "4"));
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{4, 4, 4, 4}));
  for (int i = 0; i < 500 && g_closes == c0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  EXPECT_EQ(g_closes - c0, 1);
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{4, 4, 4, 4}));
  EXPECT_EQ(g_opens - o0, 2);
}

// --- statistics -------------------------------------------------------------------------------

namespace {
int easy_slow(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
              GstTensorMemory *out) {
  std::this_thread::sleep_for(std::chrono::microseconds(300));
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
}
int easy_drop(void *, const GstTensorFilterProperties *, const GstTensorMemory *,
              GstTensorMemory *) {
  return 1;
}
}  // namespace

TEST(TensorFilterProps, LatencyAndThroughputAreMeasured) {
  GstTensorsInfo i = gst_info(_NNS_UINT8, {4});
  ASSERT_EQ(NNS_custom_easy_register("tf_slow", easy_slow, nullptr, &i, &i), 0);
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=tf_slow latency=1 throughput=1",
                     tensors_caps("uint8", "4"));
    for (int k = 0; k < 5; ++k) push_pull(fh, {{1, 2, 3, 4}});
    gint latency = 0, throughput = 0;
    g_object_get(fh.element(), "latency", &latency, "throughput", &throughput, nullptr);
    EXPECT_GE(latency, 250);
    EXPECT_LT(latency, 100000);
    EXPECT_GT(throughput, 0);
    EXPECT_LE(throughput, 4000 * 1000);  // at most ~3333 invokes/s at 300 us each
  }
  EXPECT_EQ(NNS_custom_easy_unregister("tf_slow"), 0);
}

TEST(TensorFilterProps, LatencyReportAnswersQueryAndPostsMessage) {
  GstTensorsInfo i = gst_info(_NNS_UINT8, {4});
  ASSERT_EQ(NNS_custom_easy_register("tf_slow2", easy_slow, nullptr, &i, &i), 0);
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=tf_slow2 latency-report=true",
                     tensors_caps("uint8", "4"));
    GstQuery *q = gst_query_new_latency();
    ASSERT_TRUE(gst_pad_peer_query(fh.h->sinkpad, q));
    GstClockTime min0 = 0, max0 = 0;
    gboolean live = FALSE;
    gst_query_parse_latency(q, &live, &min0, &max0);
    gst_query_unref(q);
    for (int k = 0; k < 5; ++k) push_pull(fh, {{1, 2, 3, 4}});
    GstMessage *m = gst_bus_pop_filtered(fh.bus, GST_MESSAGE_LATENCY);
    EXPECT_NE(m, nullptr) << "no latency message";
    if (m) gst_message_unref(m);
    q = gst_query_new_latency();
    ASSERT_TRUE(gst_pad_peer_query(fh.h->sinkpad, q));
    GstClockTime min1 = 0, max1 = 0;
    gst_query_parse_latency(q, &live, &min1, &max1);
    gst_query_unref(q);
    EXPECT_GE(min1, min0 + 250 * GST_USECOND);
    EXPECT_LT(min1, min0 + 100 * GST_MSECOND);
  }
  EXPECT_EQ(NNS_custom_easy_unregister("tf_slow2"), 0);
}

TEST(TensorFilterProps, PositiveInvokeResultDropsTheFrame) {
  GstTensorsInfo i = gst_info(_NNS_UINT8, {4});
  ASSERT_EQ(NNS_custom_easy_register("tf_drop", easy_drop, nullptr, &i, &i), 0);
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=tf_drop",
                     tensors_caps("uint8", "4"));
    EXPECT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{1, 2, 3, 4}})), GST_FLOW_OK);
    EXPECT_EQ(gst_harness_buffers_received(fh.h.get()), 0u);
  }
  EXPECT_EQ(NNS_custom_easy_unregister("tf_drop"), 0);
}

// --- invoke-dynamic and flexible tensors ------------------------------------------------

namespace {
// Output: the input bytes repeated twice (so the size changes with the input).
int easy_double(void *, const GstTensorsInfo *in_info, GstTensorsInfo *out_info,
                const GstTensorMemory *in, GstTensorMemory *out) {
  out_info->num_tensors = 1;
  out_info->info[0] = in_info->info[0];
  out_info->info[0].name = nullptr;
  out_info->info[0].dimension[0] *= 2;
  out[0].size = in[0].size * 2;
  out[0].data = malloc(out[0].size);
  std::memcpy(out[0].data, in[0].data, in[0].size);
  std::memcpy(static_cast<uint8_t *>(out[0].data) + in[0].size, in[0].data, in[0].size);
  return 0;
}

GstBuffer *flex_buffer(const std::vector<uint8_t> &payload, uint32_t dim0) {
  nns::MetaHeader h;
  h.type = nns::TensorType::kUInt8;
  h.dims = nns::make_dims({dim0});
  h.format = nns::TensorFormat::kFlexible;
  std::vector<uint8_t> bytes(nns::kMetaHeaderSize + payload.size());
  nns::write_meta_header(h, bytes.data());
  std::memcpy(bytes.data() + nns::kMetaHeaderSize, payload.data(), payload.size());
  return tensor_buffer({bytes});
}
}  // namespace

TEST(TensorFilterProps, InvokeDynamicWithFlexibleTensors) {
  GstTensorsInfo i = gst_info(_NNS_UINT8, {2});
  ASSERT_EQ(NNS_custom_easy_dynamic_register("tf_dyn", easy_double, nullptr, &i), 0);
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=tf_dyn invoke-dynamic=true",
                     "other/tensors,format=flexible,framerate=0/1");
    for (uint32_t n : {2u, 3u}) {
      std::vector<uint8_t> payload(n);
      for (uint32_t k = 0; k < n; ++k) payload[k] = static_cast<uint8_t>(k + 1);
      ASSERT_EQ(gst_harness_push(fh.h.get(), flex_buffer(payload, n)), GST_FLOW_OK)
          << fh.error_text();
      GstBuffer *out = gst_harness_pull(fh.h.get());
      ASSERT_NE(out, nullptr);
      auto bytes = memory_bytes(out, 0);
      ASSERT_EQ(bytes.size(), nns::kMetaHeaderSize + 2 * n);
      nns::MetaHeader h = nns::parse_meta_header(bytes.data(), bytes.size());
      EXPECT_EQ(h.dims[0], 2 * n);
      EXPECT_EQ(bytes[nns::kMetaHeaderSize + n], 1);
      gst_buffer_unref(out);
    }
    GstCaps *caps = gst_pad_get_current_caps(fh.h->sinkpad);
    gchar *s = gst_caps_to_string(caps);
    EXPECT_NE(std::string(s).find("flexible"), std::string::npos) << s;
    g_free(s);
    gst_caps_unref(caps);
  }
  EXPECT_EQ(NNS_custom_easy_unregister("tf_dyn"), 0);
}

TEST(TensorFilterProps, FlexibleInputWithStaticModel) {
  std::string model = write_temp("m.t", "1 uint8 3");
  FilterHarness fh("tensor_filter framework=nnstest model=" + model,
                   "other/tensors,format=flexible,framerate=0/1");
  ASSERT_EQ(gst_harness_push(fh.h.get(), flex_buffer({1, 2, 3}, 3)), GST_FLOW_OK)
      << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  auto bytes = memory_bytes(out, 0);
  // Downstream (harness) accepts anything: the filter prefers static output.
  EXPECT_EQ(bytes, (std::vector<uint8_t>{2, 3, 4}));
  gst_buffer_unref(out);
  // A flexible frame of the wrong size is an error that names both sizes.
  EXPECT_EQ(gst_harness_push(fh.h.get(), flex_buffer({1, 2}, 2)), GST_FLOW_ERROR);
  EXPECT_NE(fh.error_text().find("has 2 bytes, but the model input 0 needs 3"), std::string::npos);
}

TEST(TensorFilterProps, InvokeDynamicNeedsSupportingFramework) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  auto r = run_pipeline(fake_source(40, tensors_caps("float32", "10")) +
                        "tensor_filter framework=custom invoke-dynamic=true model=" + so +
                        " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("does not support dynamic invoke"), std::string::npos)
      << r.error_text;
}

// --- config-file ----------------------------------------------------------------------------

TEST(TensorFilterProps, ConfigFileSetsProperties) {
  std::string model = write_temp("m.t", "7 uint8 4");
  std::string cfg =
      write_temp("filter.conf", "# comment\nframework = nnstest\nmodel=" + model + "\nlatency=1\n");
  FilterHarness fh("tensor_filter config-file=" + cfg, tensors_caps("uint8", "4"));
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{8, 8, 8, 8}));
  gint latency = -5;
  g_object_get(fh.element(), "latency", &latency, nullptr);
  EXPECT_GE(latency, 0);
}

TEST(TensorFilterProps, ConfigFileProblemsAreReported) {
  std::string cfg = write_temp("bad.conf", "framework=nnstest\nnot-a-prop=1\nlatency=zz\n");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter config-file=" + cfg + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("line 2: unknown property 'not-a-prop'"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("line 3: 'zz' is not a valid value for property 'latency'"),
            std::string::npos)
      << r.error_text;
  r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                   "tensor_filter config-file=/nonexistent.conf ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("config-file '/nonexistent.conf' cannot be read"), std::string::npos)
      << r.error_text;
}

// --- cpp ----------------------------------------------------------------------------------

namespace {
class Doubler : public tensor_filter_cpp {
 public:
  Doubler() : tensor_filter_cpp("tf_cpp_doubler") {}
  int getInputDim(GstTensorsInfo *) override { return -EINVAL; }  // use setInputDim
  int getOutputDim(GstTensorsInfo *) override { return -EINVAL; }
  int setInputDim(const GstTensorsInfo *in, GstTensorsInfo *out) override {
    *out = *in;
    out->info[0].name = nullptr;
    return 0;
  }
  int invoke(const GstTensorMemory *in, GstTensorMemory *out) override {
    calls++;
    if (!prop || prop->input_meta.num_tensors != 1) return -1;
    for (size_t k = 0; k < in[0].size; ++k)
      static_cast<uint8_t *>(out[0].data)[k] =
          static_cast<uint8_t>(2 * static_cast<const uint8_t *>(in[0].data)[k]);
    return 0;
  }
  bool isAllocatedBeforeInvoke() override { return true; }
  int calls = 0;
};
}  // namespace

TEST(TensorFilterCpp, RegisteredClassRuns) {
  Doubler d;
  ASSERT_EQ(d._register(), 0);
  EXPECT_EQ(d._register(), -EEXIST);
  {
    FilterHarness fh("tensor_filter framework=cpp model=tf_cpp_doubler",
                     tensors_caps("uint8", "3"));
    EXPECT_EQ(push_pull(fh, {{1, 2, 3}}), (std::vector<uint8_t>{2, 4, 6}));
    EXPECT_EQ(d.calls, 1);
    EXPECT_EQ(d._unregister(), -EBUSY);
  }
  EXPECT_EQ(d._unregister(), 0);
  auto r = run_pipeline(fake_source(3, tensors_caps("uint8", "3")) +
                        "tensor_filter framework=cpp model=tf_cpp_doubler ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("cpp filter 'tf_cpp_doubler' is not registered"), std::string::npos)
      << r.error_text;
}

// --- leaks -----------------------------------------------------------------------------------

namespace {
std::size_t count_in_maps(const std::string &needle) {
  std::ifstream f("/proc/self/maps");
  std::string line;
  std::size_t n = 0;
  while (std::getline(f, line))
    if (line.find(needle) != std::string::npos) ++n;
  return n;
}
std::size_t open_fds() {
  std::size_t n = 0;
  std::error_code ec;
  for (auto it = std::filesystem::directory_iterator("/proc/self/fd", ec);
       !ec && it != std::filesystem::directory_iterator(); it.increment(ec))
    ++n;
  return n;
}
}  // namespace

TEST(TensorFilterProps, CustomFilterIsUnloadedAfterClose) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  auto r = run_pipeline(fake_source(40, tensors_caps("float32", "10")) +
                        "tensor_filter framework=custom model=" + so + " ! fakesink");
  ASSERT_TRUE(r.eos) << r.error_text;
  std::size_t fds = open_fds();
  for (int k = 0; k < 10; ++k) {
    r = run_pipeline(fake_source(40, tensors_caps("float32", "10")) +
                     "tensor_filter framework=custom model=" + so + " ! fakesink");
    ASSERT_TRUE(r.eos) << r.error_text;
  }
  EXPECT_EQ(count_in_maps("libcustom_passthrough.so"), 0u);
  EXPECT_LE(open_fds(), fds + 2);
}

TEST(TensorFilterCpp, ClassFromLibraryLoadedByModelList) {
  std::string lib = filter_dir() + "/libcpp_filter_lib.so";
  FilterHarness fh("tensor_filter framework=cpp model=tf_cpp_lib," + lib,
                   tensors_caps("uint8", "2"));
  EXPECT_EQ(push_pull(fh, {{1, 2}}), (std::vector<uint8_t>{4, 5}));
}

TEST(TensorFilterProps, InvokeAsyncIsAcceptedAndReadable) {
  std::string model = write_temp("m.t", "1 uint8 4");
  FilterHarness fh("tensor_filter framework=nnstest invoke-async=true silent=false model=" + model,
                   tensors_caps("uint8", "4"));
  EXPECT_EQ(push_pull(fh, {{1, 1, 1, 1}}), (std::vector<uint8_t>{2, 2, 2, 2}));
  gboolean async = FALSE, silent = TRUE;
  g_object_get(fh.element(), "invoke-async", &async, "silent", &silent, nullptr);
  EXPECT_TRUE(async);
  EXPECT_FALSE(silent);
}

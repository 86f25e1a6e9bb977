// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer 2.x sub-plugins (tests/data/subplugins2x, C against the 2.x ABI) found through
// the folders beside ours, run in pipelines with exact outputs, and their failures.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/compat2x/filter2x.h"
#include "core/filter_registry.h"
#include "elements/cycle_check.h"
#include "elements/filter_test_util.h"
#include "elements/flow_harness.h"
#include "nnstreamer_plugin_api_converter.h"
#include "nnstreamer_plugin_api_decoder.h"
#include "nnstreamer_plugin_api_filter.h"

namespace nns::test {
namespace {

const std::string kDir = NNS_COMPAT2X_DIR;

// The build's folders plus the 2.x test folders (our "clash" and twox_* share filters/).
struct Folders {
  ScopedEnv filters{"NNSTREAMER_FILTERS", std::string(NNS_BUILD_DIR) + "/subplugins/filters:" +
                                              kDir + "/filters:" + kDir + "/clash_2x"};
  ScopedEnv decoders{"NNSTREAMER_DECODERS",
                     std::string(NNS_BUILD_DIR) + "/subplugins/decoders:" + kDir + "/decoders"};
  ScopedEnv converters{
      "NNSTREAMER_CONVERTERS",
      std::string(NNS_BUILD_DIR) + "/subplugins/converters:" + kDir + "/converters"};
};

// A counter export of a loaded test sub-plugin (RTLD_NOLOAD: it must already be loaded).
// Buffers (and the model state their memory keeps alive) may be released by another thread
// shortly after a pipeline is gone: balanced() waits up to 5 s for the pairs to match.
template <int N>
std::vector<int> counters(const std::string &file, const char *symbol) {
  void *h = dlopen((kDir + "/filters/" + file).c_str(), RTLD_NOW | RTLD_NOLOAD);
  if (!h) return {};
  auto fn = reinterpret_cast<void (*)(int *)>(dlsym(h, symbol));
  std::vector<int> c(N, -1);
  if (fn) fn(c.data());
  dlclose(h);
  return c;
}

template <int N>
std::vector<int> balanced(const std::string &file, const char *symbol) {
  std::vector<int> c;
  for (int i = 0; i < 500; ++i) {
    c = counters<N>(file, symbol);
    bool ok = c.size() == N;
    for (int k = 0; ok && k + 1 < N; k += 2) ok = c[k] == c[k + 1];
    if (ok) break;
    g_usleep(10000);
  }
  return c;
}

std::vector<float> run_float_filter(const std::string &framework, const std::string &extra,
                                    const std::vector<uint8_t> &in) {
  AppPipeline p("appsrc name=src ! tensor_filter framework=" + framework + " " + extra +
                " ! appsink name=out");
  p.set_caps("src", tensors_caps("uint8", "4:1"));
  p.push("src", Frame({in}));
  p.eos("src");
  auto r = p.run();
  EXPECT_TRUE(r.eos) << r.error_text;
  auto f = p.frames("out");
  if (f.size() != 1 || f[0].mems.size() != 1) {
    ADD_FAILURE() << "expected one output frame, got " << f.size();
    return {};
  }
  return values_of<float>(f[0].mems[0]);
}

TEST(Subplugins2x, V0FilterAllocatesInInvokeAndFreesEveryBlock) {
  Folders folders;
  {
    AppPipeline p("appsrc name=src ! tensor_filter framework=twox_v0 ! appsink name=out");
    p.set_caps("src", tensors_caps("uint8", "3:2"));
    p.push("src", Frame({Bytes{0, 1, 2, 100, 200, 255}}));
    p.push("src", Frame({Bytes{10, 20, 30, 40, 50, 60}}));
    p.eos("src");
    auto r = p.run();
    ASSERT_TRUE(r.eos) << r.error_text;
    auto f = p.frames("out");
    ASSERT_EQ(f.size(), 2u);
    EXPECT_EQ(f[0].mems[0], (Bytes{255, 254, 253, 155, 55, 0}));
    EXPECT_EQ(f[1].mems[0], (Bytes{245, 235, 225, 215, 205, 195}));
    EXPECT_NE(f[0].caps.find("3:2"), std::string::npos) << f[0].caps;
  }
  auto c = balanced<4>("libnnstreamer_filter_twox_v0.so", "nns2x_v0_counters");
  ASSERT_EQ(c.size(), 4u);
  EXPECT_EQ(c[0], c[1]) << "open/close";
  EXPECT_GE(c[2], 2);
  EXPECT_EQ(c[2], c[3]) << "allocated in invoke / released by destroyNotify";
}

TEST(Subplugins2x, V1FilterModelInfoCustomAndAccelerator) {
  Folders folders;
  EXPECT_EQ(run_float_filter("twox_v1", "", {2, 4, 6, 255}),
            (std::vector<float>{2.f, 3.f, 4.f, 128.5f}));
  EXPECT_EQ(run_float_filter("twox_v1", "custom=add:-1 accelerator=true:npu,cpu", {0, 2, 8, 10}),
            (std::vector<float>{-1.f, 0.f, 3.f, 4.f}));
  auto c = balanced<2>("libnnstreamer_filter_twox_v1.so", "nns2x_v1_counters");
  ASSERT_EQ(c.size(), 2u);
  EXPECT_GE(c[0], 2);
  EXPECT_EQ(c[0], c[1]);
}

// The accelerator list a version-1 sub-plugin gets in open(), as NNStreamer 2.7 fills
// prop->hw_list / num_hw: nothing when the property is unset; otherwise the "true:..." names
// the framework supports, in order (none of them named: auto), auto and default resolved to the
// framework's choice; anything not starting with "true": ACCL_NONE.
TEST(Subplugins2x, V1FilterAcceleratorListAsNNStreamer) {
  Folders folders;
  const int cpu = ACCL_CPU, none = ACCL_NONE;
  struct Case {
    std::string prop;
    std::vector<int> want;  // num_hw, hw_list[0..3] (-1 past the end)
  };
  const Case cases[] = {
      {"", {0, -1, -1, -1, -1}},
      {"accelerator=true:cpu", {1, cpu, -1, -1, -1}},
      {"accelerator=true:auto", {1, cpu, -1, -1, -1}},
      {"accelerator=true:default", {1, cpu, -1, -1, -1}},
      {"accelerator=true:npu", {1, cpu, -1, -1, -1}},
      {"accelerator=true", {1, cpu, -1, -1, -1}},
      {"accelerator=true:cpu,default,!auto", {2, cpu, cpu, -1, -1}},
      {"accelerator=false", {1, none, -1, -1, -1}},
  };
  for (const Case &c : cases) {
    SCOPED_TRACE(c.prop);
    run_pipeline(fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                 "tensor_filter framework=twox_v1 " + c.prop + " ! fakesink");
    EXPECT_EQ(counters<5>("libnnstreamer_filter_twox_v1.so", "nns2x_v1_last_accelerators"), c.want);
  }
}

TEST(Subplugins2x, V1FilterInvokeDynamicFlexibleOutput) {
  Folders folders;
  AppPipeline p(
      "appsrc name=src ! tensor_filter framework=twox_v1 invoke-dynamic=true ! appsink name=out");
  p.set_caps("src", tensors_caps("uint8", "4:1"));
  p.push("src", Frame({Bytes{2, 4, 6, 8}}));
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto f = p.frames("out");
  ASSERT_EQ(f.size(), 1u);
  ASSERT_EQ(f[0].mems.size(), 1u);
  ASSERT_EQ(f[0].mems[0].size(), 128u + 16u) << "flexible header + 4 float32";
  // NNStreamer marks invoke-dynamic output headers flexible: format word (offset 76) = 1.
  EXPECT_EQ(f[0].mems[0][76], 1u);
  EXPECT_EQ(f[0].mems[0][80], 4u) << "media type tensor";
  EXPECT_EQ(values_of<float>(Bytes(f[0].mems[0].begin() + 128, f[0].mems[0].end())),
            (std::vector<float>{2.f, 3.f, 4.f, 5.f}));
  EXPECT_NE(f[0].caps.find("flexible"), std::string::npos) << f[0].caps;
}

TEST(Subplugins2x, V1FilterWithoutSupportedAcceleratorFailsInvoke) {
  Folders folders;
  // accelerator=false gives the sub-plugin ACCL_NONE, which this one refuses in invoke.
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                        "tensor_filter framework=twox_v1 accelerator=false ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("NNStreamer 2.x sub-plugin 'twox_v1'"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("invoke returned -19"), std::string::npos) << r.error_text;
}

// 100 PLAYING/NULL cycles of each filter: every buffer and event freed, every open closed,
// every block allocated in invoke released.
void hundred_cycles(const std::string &framework, const std::string &file, const char *symbol,
                    int ncount) {
  AppPipeline p("appsrc name=src ! tensor_filter framework=" + framework + " ! fakesink name=out");
  p.set_caps("src", tensors_caps("uint8", "4:1"));
  state_cycles(p.pipeline(), 100, [&](int i, LiveObjects &live) {
    std::size_t n = live.delivered("out");
    p.push("src", Frame({Bytes{1, 2, 3, 4}}));
    p.push("src", Frame({Bytes{5, 6, 7, 8}}));
    EXPECT_TRUE(live.wait_delivered("out", n + 2)) << "cycle " << i;
  });
  auto c = ncount == 4 ? balanced<4>(file, symbol) : balanced<2>(file, symbol);
  ASSERT_EQ(c.size(), static_cast<std::size_t>(ncount));
  EXPECT_GE(c[0], 100) << "one open per cycle";
  EXPECT_EQ(c[0], c[1]) << "every open closed";
  if (ncount == 4) {
    EXPECT_GE(c[2], 200);
    EXPECT_EQ(c[2], c[3]) << "every block allocated in invoke released";
  }
}

TEST(Subplugins2x, HundredPlayingNullCyclesLeakNothing) {
  Folders folders;
  hundred_cycles("twox_v0", "libnnstreamer_filter_twox_v0.so", "nns2x_v0_counters", 4);
  hundred_cycles("twox_v1", "libnnstreamer_filter_twox_v1.so", "nns2x_v1_counters", 2);
}

TEST(Subplugins2x, FailedProbeNamesFileAndReason) {
  Folders folders;
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                        "tensor_filter framework=twox_bad ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find(kDir + "/filters/libnnstreamer_filter_twox_bad.so"),
            std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("failed its probe"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("getModelInfo"), std::string::npos) << r.error_text;

  r = run_pipeline(fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                   "tensor_filter framework=twox_badver ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("libnnstreamer_filter_twox_badver.so"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("version word 0x0000000200000000 is not NNStreamer's filter "
                              "sub-plugin ABI"),
            std::string::npos)
      << r.error_text;
}

TEST(Subplugins2x, NameClashOursFirstUnlessConfigured) {
  Folders folders;
  // filters/ has our "clash" (x + 100), clash_2x/ NNStreamer 2.x's (x * 0.5 + 200).
  EXPECT_EQ(run_float_filter("clash", "", {0, 2, 4, 6}),
            (std::vector<float>{100.f, 102.f, 104.f, 106.f}));
  {
    ScopedEnv prio("NNSTREAMER_filter_subplugin_abi_priority", "nnstreamer-2");
    EXPECT_EQ(run_float_filter("clash", "", {0, 2, 4, 6}),
              (std::vector<float>{200.f, 201.f, 202.f, 203.f}));
  }
  // Both loaded now: the default order again picks ours.
  EXPECT_EQ(run_float_filter("clash", "", {0, 2, 4, 6}),
            (std::vector<float>{100.f, 102.f, 104.f, 106.f}));
}

TEST(Subplugins2x, SubpluginsPropertyListsBoth) {
  Folders folders;
  ASSERT_NE(nnstreamer_filter_find("twox_v1"), nullptr);  // loads and registers it
  GstElement *f = gst_element_factory_make("tensor_filter", nullptr);
  ASSERT_NE(f, nullptr);
  gchar *list = nullptr;
  g_object_get(f, "sub-plugins", &list, nullptr);
  std::string s = list ? list : "";
  g_free(list);
  gst_object_unref(f);
  for (const char *n : {"custom", "custom-easy", "twox_v0", "twox_v1", "clash"})
    EXPECT_NE(("," + s + ",").find(std::string(",") + n + ","), std::string::npos)
        << n << " in " << s;
}

// Runs a gst tool on the built plugin (not the test program's static registration), with our
// back ends and the 2.x folders configured; returns its output, *rc its exit status.
#ifdef NNS_TEST_SANITIZED
#define SKIP_IF_SANITIZED() GTEST_SKIP() << "the gst tools cannot load the sanitizer-built plugin"
#else
#define SKIP_IF_SANITIZED() \
  do {                      \
  } while (0)
#endif

std::string run_tool(const std::string &args, int *rc) {
  std::string b = NNS_BUILD_DIR;
  std::string cmd = "env GST_REGISTRY=" + make_temp_dir() + "/registry.bin GST_PLUGIN_PATH=" + b +
                    "/plugin NNSTREAMER_CONF=" + b + "/nnstreamer.ini NNSTREAMER_FILTERS=" + b +
                    "/subplugins/filters:" + kDir + "/filters:" + kDir + "/clash_2x " + args +
                    " 2>&1";
  FILE *f = popen(cmd.c_str(), "r");
  std::string out;
  if (!f) return out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, f)) out.append(buf, n);
  *rc = pclose(f);
  return out;
}

// In the real plugin the sub-plugin resolves nnstreamer_filter_probe() and the shared-model
// functions it references in libnnstreamer.so.
TEST(Subplugins2x, GstLaunchLoadsIntoThePlugin) {
  SKIP_IF_SANITIZED();
  for (const char *fw : {"twox_v0", "twox_v1"}) {
    int rc = -1;
    std::string out = run_tool(
        "gst-launch-1.0 -q fakesrc num-buffers=2 sizetype=fixed sizemax=4 filltype=zero ! "
        "'other/tensors,format=static,num_tensors=1,types=(string)uint8,dimensions=(string)4:1,"
        "framerate=0/1' ! tensor_filter framework=" +
            std::string(fw) + " ! fakesink",
        &rc);
    EXPECT_EQ(rc, 0) << fw << ": " << out;
  }
}

TEST(Subplugins2x, GstInspectListsOursAndTheirs) {
  SKIP_IF_SANITIZED();
  int rc = -1;
  std::string out = run_tool("gst-inspect-1.0 tensor_filter", &rc);
  ASSERT_EQ(rc, 0) << out;
  auto line = out.find("sub-plugins");
  ASSERT_NE(line, std::string::npos) << out;
  std::string rest = out.substr(line, out.find('\n', out.find("Default:", line)) - line);
  for (const char *n : {"custom-easy", "clash", "twox_v0", "twox_v1"})
    EXPECT_NE(rest.find(n), std::string::npos) << n << " in " << rest;
}

TEST(Subplugins2x, FindExitAndCustomPropertyDesc) {
  Folders folders;
  const GstTensorFilterFramework *fw = nnstreamer_filter_find("twox_v1");
  ASSERT_NE(fw, nullptr);
  EXPECT_TRUE(checkGstTensorFilterFrameworkVersion(fw->version, 1));
  EXPECT_EQ(nnstreamer_filter_find("no_such_2x"), nullptr);
  nnstreamer_filter_set_custom_property_desc("twox_v1", "add", "value added to x/2", nullptr);
  auto d = compat2x::Filter2xRegistry::get().custom_desc("twox_v1");
  ASSERT_EQ(d.size(), 1u);
  EXPECT_EQ(d[0].first, "add");
  EXPECT_EQ(d[0].second, "value added to x/2");
  // Probing the same table again is refused while registered; after exit it comes back.
  auto *mut = const_cast<GstTensorFilterFramework *>(fw);
  EXPECT_EQ(nnstreamer_filter_probe(mut), 0);
  nnstreamer_filter_exit("twox_v1");
  EXPECT_EQ(compat2x::Filter2xRegistry::get().find("twox_v1"), nullptr);
  EXPECT_EQ(nnstreamer_filter_probe(mut), 1);
  EXPECT_EQ(run_float_filter("twox_v1", "", {2, 2, 2, 2}),
            (std::vector<float>{2.f, 2.f, 2.f, 2.f}));
}

TEST(Subplugins2x, ReservedNamesRefused) {
  GstTensorFilterFramework fw;
  std::memset(&fw, 0, sizeof fw);
  fw.version = GST_TENSOR_FILTER_FRAMEWORK_V0;
  fw.name = const_cast<char *>("Auto");
  fw.invoke_NN = [](const GstTensorFilterProperties *, void **, const GstTensorMemory *,
                    GstTensorMemory *) { return 0; };
  fw.setInputDimension = [](const GstTensorFilterProperties *, void **, const GstTensorsInfo *,
                            GstTensorsInfo *) { return 0; };
  EXPECT_EQ(nnstreamer_filter_probe(&fw), 0);
  fw.name = const_cast<char *>("inproc_v0");
  fw.setInputDimension = nullptr;
  EXPECT_EQ(nnstreamer_filter_probe(&fw), 0) << "no way to learn the tensors";
}

// ---- decoder and converter -----------------------------------------------------------------

TEST(Subplugins2x, DecoderWithOnlyMandatoryCallbacks) {
  Folders folders;
  std::string out = make_temp_dir() + "/dec.txt";
  AppPipeline p(
      "appsrc name=src ! tensor_decoder mode=twox_dec option1=ignored ! "
      "filesink location=" +
      out);
  p.set_caps("src", tensors_caps("uint8", "4:1"));
  p.push("src", Frame({Bytes{1, 2, 3, 4}}));
  p.push("src", Frame({Bytes{100, 100, 100, 255}}));
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto b = read_file(out);
  EXPECT_EQ(std::string(b.begin(), b.end()), "sum=10\nsum=555\n");
}

TEST(Subplugins2x, DecoderFailingItsProbeNamesFileAndReason) {
  Folders folders;
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                        "tensor_decoder mode=twox_baddec ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find(kDir + "/decoders/libnnstreamer_decoder_twox_baddec.so: the "
                                     "decoder sub-plugin failed its probe: 'twox_baddec' "
                                     "rejected: init, getOutCaps and decode are mandatory"),
            std::string::npos)
      << r.error_text;
}

TEST(Subplugins2x, ConverterCopiedAndAnyRefused) {
  Folders folders;
  EXPECT_EQ(nnstreamer_converter_find("any"), nullptr);
  const NNStreamerExternalConverter *ex = nnstreamer_converter_find("twox_conv");
  ASSERT_NE(ex, nullptr);
  EXPECT_STREQ(ex->name, "twox_conv") << "the registered struct was the caller's stack copy";
  AppPipeline p("appsrc name=src ! tensor_converter ! appsink name=out");
  p.set_caps("src", "application/x-twox,n=3");
  p.push("src", Frame({Bytes{1, 2, 250}}));
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto f = p.frames("out");
  ASSERT_EQ(f.size(), 1u);
  EXPECT_EQ(f[0].mems[0], (Bytes{2, 3, 251}));

  NNStreamerExternalConverter any = *ex;
  any.name = "ANY";
  EXPECT_FALSE(registerExternalConverter(&any));
}

// ---- shared model table and custom-easy registration ---------------------------------------

int g_freed = 0;
std::vector<std::pair<void *, void *>> g_replaced;

TEST(Subplugins2x, SharedModelTable) {
  int a = 0, b = 0, model = 1, model2 = 2;
  char key[] = "shared-key-1";
  auto on_free = [](void *m) { g_freed += *static_cast<int *>(m); };
  auto on_replace = [](void *user, void *m) { g_replaced.emplace_back(user, m); };
  g_freed = 0;
  g_replaced.clear();
  EXPECT_EQ(nnstreamer_filter_shared_model_get(&a, key), nullptr);
  EXPECT_EQ(nnstreamer_filter_shared_model_insert_and_get(&a, key, &model), &model);
  EXPECT_EQ(nnstreamer_filter_shared_model_insert_and_get(&b, key, &model2), nullptr)
      << "key taken";
  EXPECT_EQ(nnstreamer_filter_shared_model_insert_and_get(&b, nullptr, &model2), nullptr);
  EXPECT_EQ(nnstreamer_filter_shared_model_get(&b, key), &model);
  nnstreamer_filter_shared_model_replace(&a, key, &model2, on_replace, on_free);
  ASSERT_EQ(g_replaced.size(), 2u);
  EXPECT_EQ(g_replaced[0], (std::pair<void *, void *>{&a, &model2}));
  EXPECT_EQ(g_replaced[1], (std::pair<void *, void *>{&b, &model2}));
  EXPECT_EQ(g_freed, 1) << "old representation freed";
  EXPECT_TRUE(nnstreamer_filter_shared_model_remove(&a, key, on_free));
  EXPECT_EQ(g_freed, 1) << "b still uses it";
  EXPECT_TRUE(nnstreamer_filter_shared_model_remove(&b, key, on_free));
  EXPECT_EQ(g_freed, 3) << "last user out frees model2";
  EXPECT_FALSE(nnstreamer_filter_shared_model_remove(&b, key, on_free));
  EXPECT_EQ(nnstreamer_filter_shared_model_get(&a, key), nullptr);
}

TEST(Subplugins2x, CustomEasyAcceptsFlexibleInfo) {
  auto fn = [](void *, const GstTensorFilterProperties *, const GstTensorMemory *,
               GstTensorMemory *) { return 0; };
  auto dyn = [](void *, const GstTensorsInfo *, GstTensorsInfo *, const GstTensorMemory *,
                GstTensorMemory *) { return 0; };
  GstTensorsInfo flex, stat;
  std::memset(&flex, 0, sizeof flex);
  std::memset(&stat, 0, sizeof stat);
  flex.format = _NNS_TENSOR_FORMAT_FLEXIBLE;  // no tensors described: they come per buffer
  stat.format = _NNS_TENSOR_FORMAT_STATIC;    // a static one with no tensor is invalid
  EXPECT_EQ(NNS_custom_easy_register("flex2x", fn, nullptr, &flex, &flex), 0);
  EXPECT_EQ(NNS_custom_easy_dynamic_register("flexdyn2x", dyn, nullptr, &flex), 0);
  EXPECT_EQ(NNS_custom_easy_register("stat2x", fn, nullptr, &stat, &flex), -EINVAL);
  const int seven = 7;  // not a tensor_format (written as int: UBSan checks enum loads)
  std::memcpy(&flex.format, &seven, sizeof seven);
  EXPECT_EQ(NNS_custom_easy_register("bad2x", fn, nullptr, &flex, &flex), -EINVAL);
  EXPECT_EQ(NNS_custom_easy_unregister("flex2x"), 0);
  EXPECT_EQ(NNS_custom_easy_unregister("flexdyn2x"), 0);
}

}  // namespace
}  // namespace nns::test

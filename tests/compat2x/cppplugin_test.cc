// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer 2.x C++ filter sub-plugins (nnstreamer::tensor_filter_subplugin, built from
// tests/data/subplugins2x/cpp_filters.cc against nnstreamer_cppplugin_api_filter.hh) loaded
// from a filters= folder: exact outputs in pipelines, a failing open, 100 PLAYING/NULL cycles
// each, and the class's ABI (layout, vtable order, exported names) as NNStreamer 2.x has it.
#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "elements/cycle_check.h"
#include "elements/filter_test_util.h"
#include "elements/flow_harness.h"
#include "nnstreamer_cppplugin_api_filter.hh"
#include "nnstreamer_plugin_api_filter.h"

namespace nns::test {
namespace {

const std::string kDir = NNS_COMPAT2X_DIR;

struct Folders {
  ScopedEnv filters{"NNSTREAMER_FILTERS",
                    std::string(NNS_BUILD_DIR) + "/subplugins/filters:" + kDir + "/filters"};
};

// cppx_counters() of a loaded sub-plugin: objects made / deleted, blocks allocated / freed.
// Waits up to 5 s for the pairs to match (buffers may be released by another thread).
std::vector<int> counters(const std::string &name) {
  std::vector<int> c;
  for (int i = 0; i < 500; ++i) {
    void *h = dlopen((kDir + "/filters/libnnstreamer_filter_" + name + ".so").c_str(),
                     RTLD_NOW | RTLD_NOLOAD);
    if (!h) return {};
    auto fn = reinterpret_cast<void (*)(int *)>(dlsym(h, "cppx_counters"));
    c.assign(4, -1);
    if (fn) fn(c.data());
    dlclose(h);
    if (c[0] == c[1] && c[2] == c[3]) break;
    g_usleep(10000);
  }
  return c;
}

TEST(CppSubplugin, PassThroughOfAnyTensors) {
  Folders folders;
  AppPipeline p("appsrc name=src ! tensor_filter framework=cppx_pass ! appsink name=out");
  p.set_caps("src", tensors_caps("uint8,int16", "3:1,2:1", 2));
  p.push("src", Frame({Bytes{1, 2, 3}, bytes_of(std::vector<int16_t>{-7, 300})}));
  p.push("src", Frame({Bytes{9, 8, 7}, bytes_of(std::vector<int16_t>{5, -5})}));
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto f = p.frames("out");
  ASSERT_EQ(f.size(), 2u);
  ASSERT_EQ(f[0].mems.size(), 2u);
  EXPECT_EQ(f[0].mems[0], (Bytes{1, 2, 3}));
  EXPECT_EQ(values_of<int16_t>(f[0].mems[1]), (std::vector<int16_t>{-7, 300}));
  EXPECT_EQ(f[1].mems[0], (Bytes{9, 8, 7}));
  EXPECT_EQ(values_of<int16_t>(f[1].mems[1]), (std::vector<int16_t>{5, -5}));
  EXPECT_NE(f[0].caps.find("int16"), std::string::npos) << f[0].caps;
  auto c = counters("cppx_pass");
  ASSERT_EQ(c.size(), 4u);
  EXPECT_GE(c[0], 1);
  EXPECT_EQ(c[0], c[1]) << "every object made in open deleted in close";
}

TEST(CppSubplugin, SeveralTensorsInAndOut) {
  Folders folders;
  AppPipeline p("appsrc name=src ! tensor_filter framework=cppx_multi ! appsink name=out");
  p.set_caps("src", tensors_caps("float32,uint8", "4:1,2:1", 2));
  p.push("src", Frame({bytes_of(std::vector<float>{0.f, 1.5f, -2.f, 10.f}), Bytes{200, 100}}));
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto f = p.frames("out");
  ASSERT_EQ(f.size(), 1u);
  ASSERT_EQ(f[0].mems.size(), 3u);
  EXPECT_EQ(values_of<float>(f[0].mems[0]), (std::vector<float>{1.f, 4.f, -3.f, 21.f}));
  EXPECT_EQ(f[0].mems[1], (Bytes{100, 200}));
  EXPECT_EQ(values_of<int32_t>(f[0].mems[2]), (std::vector<int32_t>{300}));
  EXPECT_NE(f[0].caps.find("num_tensors=(int)3"), std::string::npos) << f[0].caps;
}

TEST(CppSubplugin, InvokeDynamicGivesFlexibleOutputsAndFreesThem) {
  Folders folders;
  {
    AppPipeline p(
        "appsrc name=src ! tensor_filter framework=cppx_dyn invoke-dynamic=true ! appsink "
        "name=out");
    p.set_caps("src", tensors_caps("uint8", "3:1"));
    p.push("src", Frame({Bytes{2, 5, 255}}));
    p.eos("src");
    auto r = p.run();
    ASSERT_TRUE(r.eos) << r.error_text;
    auto f = p.frames("out");
    ASSERT_EQ(f.size(), 1u);
    ASSERT_EQ(f[0].mems.size(), 2u);
    ASSERT_EQ(f[0].mems[0].size(), 128u + 12u) << "flexible header + 3 float32";
    EXPECT_EQ(values_of<float>(Bytes(f[0].mems[0].begin() + 128, f[0].mems[0].end())),
              (std::vector<float>{1.f, 2.5f, 127.5f}));
    ASSERT_EQ(f[0].mems[1].size(), 128u + 4u);
    EXPECT_EQ(values_of<int32_t>(Bytes(f[0].mems[1].begin() + 128, f[0].mems[1].end())),
              (std::vector<int32_t>{3}));
    EXPECT_NE(f[0].caps.find("flexible"), std::string::npos) << f[0].caps;
  }
  auto c = counters("cppx_dyn");
  ASSERT_EQ(c.size(), 4u);
  EXPECT_GE(c[2], 2);
  EXPECT_EQ(c[2], c[3]) << "every output allocated in invoke released by DESTROY_NOTIFY";
}

TEST(CppSubplugin, InvokeWithoutDynamicSupportFails) {
  Folders folders;
  // cppx_pass does not override invoke_dynamic: the base class refuses it (invoke -EINVAL).
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                        "tensor_filter framework=cppx_pass invoke-dynamic=true ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("'cppx_pass'"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("returned -22"), std::string::npos) << r.error_text;
}

TEST(CppSubplugin, FailingOpenPostsErrorAndLeaksNothing) {
  Folders folders;
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                        "tensor_filter framework=cppx_fail model=m.bin ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("NNStreamer 2.x sub-plugin 'cppx_fail'"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("open() returned -22"), std::string::npos) << r.error_text;
  // 100 more failing starts: each object made by open is deleted again.
  GstElement *pipe = gst_parse_launch((fake_source(4, tensors_caps("uint8", "4:1"), 1) +
                                       "tensor_filter framework=cppx_fail model=m.bin ! fakesink")
                                          .c_str(),
                                      nullptr);
  ASSERT_NE(pipe, nullptr);
  for (int i = 0; i < 100; ++i) {
    gst_element_set_state(pipe, GST_STATE_PLAYING);
    gst_element_get_state(pipe, nullptr, nullptr, 5 * GST_SECOND);
    ASSERT_EQ(gst_element_set_state(pipe, GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS) << i;
  }
  gst_object_unref(pipe);
  auto c = counters("cppx_fail");
  ASSERT_EQ(c.size(), 4u);
  EXPECT_GE(c[0], 101);
  EXPECT_EQ(c[0], c[1]);
}

void hundred_cycles(const std::string &framework, const std::string &extra, const std::string &caps,
                    const Frame &frame) {
  SCOPED_TRACE(framework);
  AppPipeline p("appsrc name=src ! tensor_filter framework=" + framework + " " + extra +
                " ! fakesink name=out");
  p.set_caps("src", caps);
  state_cycles(p.pipeline(), 100, [&](int i, LiveObjects &live) {
    std::size_t n = live.delivered("out");
    p.push("src", frame);
    p.push("src", frame);
    EXPECT_TRUE(live.wait_delivered("out", n + 2)) << "cycle " << i;
  });
  auto c = counters(framework);
  ASSERT_EQ(c.size(), 4u);
  EXPECT_GE(c[0], 100) << "one object per open";
  EXPECT_EQ(c[0], c[1]) << "every object deleted at close";
  EXPECT_EQ(c[2], c[3]) << "every block allocated in invoke released";
}

TEST(CppSubplugin, HundredPlayingNullCyclesLeakNothing) {
  Folders folders;
  hundred_cycles("cppx_pass", "", tensors_caps("uint8", "4:1"), Frame({Bytes{1, 2, 3, 4}}));
  hundred_cycles("cppx_multi", "", tensors_caps("float32,uint8", "4:1,2:1", 2),
                 Frame({bytes_of(std::vector<float>{1, 2, 3, 4}), Bytes{1, 2}}));
  hundred_cycles("cppx_dyn", "invoke-dynamic=true", tensors_caps("uint8", "4:1"),
                 Frame({Bytes{1, 2, 3, 4}}));
}

// The table the sub-plugin registered is its representative's, a version-1 one made from the
// base class's template; its getFrameworkInfo answers before any open.
TEST(CppSubplugin, FindReturnsTheRepresentativeTable) {
  Folders folders;
  const GstTensorFilterFramework *fw = nnstreamer_filter_find("cppx_multi");
  ASSERT_NE(fw, nullptr);
  EXPECT_EQ(fw->version, GST_TENSOR_FILTER_FRAMEWORK_V1);
  ASSERT_NE(fw->subplugin_data, nullptr);
  GstTensorFilterFrameworkInfo info;
  std::memset(&info, 0, sizeof info);
  ASSERT_EQ(fw->getFrameworkInfo(fw, nullptr, nullptr, &info), 0);
  EXPECT_STREQ(info.name, "cppx_multi");
  // An object that is not an opened instance is refused, not dereferenced.
  GstTensorsInfo in, out;
  std::memset(&in, 0, sizeof in);
  std::memset(&out, 0, sizeof out);
  EXPECT_EQ(fw->getModelInfo(fw, nullptr, fw->subplugin_data, GET_IN_OUT_INFO, &in, &out), -EINVAL);
  int junk[64] = {};
  EXPECT_EQ(fw->invoke(fw, nullptr, junk, nullptr, nullptr), -EINVAL);
}

// In gst-launch the sub-plugin resolves the class (vtable, typeinfo, constructor, destructor,
// fwdesc_template) in the plugin itself, libnnstreamer.so.
TEST(CppSubplugin, GstLaunchLoadsIntoThePlugin) {
#ifdef NNS_TEST_SANITIZED
  GTEST_SKIP() << "gst-launch cannot load the sanitizer-built plugin";
#endif
  std::string b = NNS_BUILD_DIR;
  std::string cmd = "env GST_REGISTRY=" + make_temp_dir() + "/registry.bin GST_PLUGIN_PATH=" + b +
                    "/plugin NNSTREAMER_CONF=" + b + "/nnstreamer.ini NNSTREAMER_FILTERS=" + kDir +
                    "/filters timeout 60 gst-launch-1.0 -q fakesrc num-buffers=2 sizetype=fixed "
                    "sizemax=4 filltype=zero ! 'other/tensors,format=static,num_tensors=1,"
                    "types=(string)uint8,dimensions=(string)4:1,framerate=0/1' ! "
                    "tensor_filter framework=cppx_pass ! fakesink 2>&1";
  FILE *f = popen(cmd.c_str(), "r");
  ASSERT_NE(f, nullptr);
  std::string out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, f)) out.append(buf, n);
  EXPECT_EQ(pclose(f), 0) << out;
}

// NNStreamer 2.x's object layout: vtable pointer, the 64-bit sanity word, then the table.
TEST(CppSubplugin, LayoutAndExportedNames) {
  EXPECT_EQ(sizeof(nnstreamer::tensor_filter_subplugin),
            sizeof(void *) + sizeof(uint64_t) + sizeof(GstTensorFilterFramework));
  // The names a sub-plugin compiled against NNStreamer's header needs from libnnstreamer.so.
  FILE *nm = popen(("nm -D --defined-only " + std::string(NNS_BUILD_DIR) +
                    "/plugin/libnnstreamer.so 2>/dev/null")
                       .c_str(),
                   "r");
  ASSERT_NE(nm, nullptr);
  std::string out;
  char buf[4096];
  while (std::size_t n = std::fread(buf, 1, sizeof buf, nm)) out.append(buf, n);
  pclose(nm);
  if (out.empty()) GTEST_SKIP() << "nm or the plugin is not available";
  for (const char *s : {"_ZN10nnstreamer23tensor_filter_subplugin15fwdesc_templateE",
                        "_ZN10nnstreamer23tensor_filter_subpluginC2Ev",
                        "_ZN10nnstreamer23tensor_filter_subpluginD2Ev",
                        "_ZN10nnstreamer23tensor_filter_subpluginD1Ev",
                        "_ZN10nnstreamer23tensor_filter_subpluginD0Ev",
                        "_ZTIN10nnstreamer23tensor_filter_subpluginE",
                        "_ZTVN10nnstreamer23tensor_filter_subpluginE",
                        "_ZN10nnstreamer23tensor_filter_subplugin12eventHandlerE9event_opsR34_"
                        "GstTensorFilterFrameworkEventData"})
    EXPECT_NE(out.find(std::string(" ") + s + "\n"), std::string::npos) << s;
}

}  // namespace
}  // namespace nns::test

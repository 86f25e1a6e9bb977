// SPDX-License-Identifier: LGPL-2.1-only
// Symbol binding: a library defining NNStreamer's names (tests/compat/bind/fake_nnstreamer.c:
// element *_get_type, gst_tensor_info_init, NNS_custom_easy_register, ...) is loaded with
// RTLD_GLOBAL before GStreamer loads our real plugin file. The plugin must still register its
// own elements and compute with its own code: none of the fake functions may be called. The
// control library (bind/control.c, linked without -Bsymbolic-functions) shows that the same
// set-up does divert an unprotected library's calls.
// This program links neither nns_gst nor the test harness: the plugin comes from its .so only.
#include <dlfcn.h>
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "nnstreamer_plugin_api.h"
#include "tensor_filter_custom_easy.h"

namespace {

using CountFn = int (*)();
using NameFn = const char *(*)();

struct Fake {
  void *dl = nullptr;
  CountFn calls = nullptr;
  NameFn last = nullptr;
};

Fake &fake() {
  static Fake f;
  return f;
}

int doubler(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
            GstTensorMemory *out) {
  const float *a = static_cast<const float *>(in[0].data);
  float *b = static_cast<float *>(out[0].data);
  for (std::size_t i = 0; i < in[0].size / sizeof(float); ++i) b[i] = 2 * a[i];
  return 0;
}

class BindEnv : public ::testing::Environment {
 public:
  void SetUp() override {
    Fake &f = fake();
    f.dl = dlopen(NNS_BIND_FAKE_LIB, RTLD_NOW | RTLD_GLOBAL);
    ASSERT_NE(f.dl, nullptr) << dlerror();
    f.calls = reinterpret_cast<CountFn>(dlsym(f.dl, "fake_nnstreamer_calls"));
    f.last = reinterpret_cast<NameFn>(dlsym(f.dl, "fake_nnstreamer_last"));
    ASSERT_NE(f.calls, nullptr);
    // Only the plugin file: no other nnstreamer plugin, no registry cache.
    g_setenv("GST_PLUGIN_PATH", "", TRUE);
    gst_init(nullptr, nullptr);
  }
  // gst_deinit() ends GStreamer's threads; GLib's idle pool threads are then told to exit and
  // waited for (up to 3 s). Threads alive at exit keep GLib's per-thread memory, which
  // LeakSanitizer reports in the sanitizer pass (use_tls=0: thread-local storage is no root).
  void TearDown() override {
    if (!gst_is_initialized()) return;
    gst_deinit();
    g_thread_pool_set_max_unused_threads(0);
    for (int i = 0; i < 300 && thread_count() > 1; ++i) {
      g_thread_pool_stop_unused_threads();
      g_usleep(10000);
    }
  }

 private:
  static int thread_count() {
    std::ifstream f("/proc/self/status");
    for (std::string line; std::getline(f, line);)
      if (line.rfind("Threads:", 0) == 0) return std::atoi(line.c_str() + 8);
    return -1;
  }
};

const auto *const env = ::testing::AddGlobalTestEnvironment(new BindEnv);

template <typename T>
T plugin_symbol(const char *name) {
  void *h = dlopen(NNS_BIND_PLUGIN, RTLD_NOW | RTLD_NOLOAD);
  if (!h) return nullptr;
  void *s = dlsym(h, name);
  dlclose(h);
  return reinterpret_cast<T>(s);
}

TEST(CompatBind, PluginKeepsItsOwnDefinitions) {
  GError *err = nullptr;
  GstPlugin *plugin = gst_plugin_load_file(NNS_BIND_PLUGIN, &err);
  ASSERT_NE(plugin, nullptr) << (err ? err->message : "");
  gst_object_unref(plugin);

  // Our registration function, taken from the plugin itself (the process-wide name is the
  // fake's, as in a process that linked NNStreamer first).
  auto reg = plugin_symbol<decltype(&NNS_custom_easy_register)>("NNS_custom_easy_register");
  auto unreg = plugin_symbol<decltype(&NNS_custom_easy_unregister)>("NNS_custom_easy_unregister");
  auto caps_from =
      plugin_symbol<decltype(&gst_tensors_caps_from_config)>("gst_tensors_caps_from_config");
  ASSERT_TRUE(reg && unreg && caps_from);
  GstTensorsInfo info{};
  info.num_tensors = 1;
  info.info[0].type = _NNS_FLOAT32;
  info.info[0].dimension[0] = 4;
  info.info[0].dimension[1] = 1;
  ASSERT_EQ(reg("bind_double", doubler, nullptr, &info, &info), 0);

  GstElement *pipe = gst_parse_launch(
      "appsrc name=in caps=other/tensors,format=static,num_tensors=1,dimensions=(string)4:1,"
      "types=(string)uint8,"
      "framerate=0/1 ! tensor_transform mode=typecast option=float32 ! "
      "tensor_filter framework=custom-easy model=bind_double ! appsink name=out sync=false",
      &err);
  ASSERT_NE(pipe, nullptr) << (err ? err->message : "");
  GstElement *src = gst_bin_get_by_name(GST_BIN(pipe), "in");
  GstElement *sink = gst_bin_get_by_name(GST_BIN(pipe), "out");
  ASSERT_EQ(gst_element_set_state(pipe, GST_STATE_PLAYING), GST_STATE_CHANGE_ASYNC);
  const guint8 bytes[4] = {1, 2, 3, 4};
  gst_app_src_push_buffer(GST_APP_SRC(src), gst_buffer_new_memdup(bytes, 4));
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  GstSample *sample = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 10 * GST_SECOND);
  ASSERT_NE(sample, nullptr) << "no output (elements not working?)";
  GstMapInfo map;
  GstBuffer *buf = gst_sample_get_buffer(sample);
  ASSERT_TRUE(gst_buffer_map(buf, &map, GST_MAP_READ));
  std::vector<float> got(map.size / sizeof(float));
  std::memcpy(got.data(), map.data, got.size() * sizeof(float));
  gst_buffer_unmap(buf, &map);
  gst_sample_unref(sample);
  EXPECT_EQ(got, (std::vector<float>{2, 4, 6, 8}));
  gst_element_set_state(pipe, GST_STATE_NULL);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(pipe);
  EXPECT_EQ(unreg("bind_double"), 0);

  // The plugin's API functions call the plugin's own helpers, not the fake's.
  GstTensorsConfig cfg{};
  cfg.info = info;
  cfg.rate_n = 0;
  cfg.rate_d = 1;
  GstCaps *caps = caps_from(&cfg);
  gchar *text = gst_caps_to_string(caps);
  EXPECT_STREQ(text,
               "other/tensors, format=(string)static, num_tensors=(int)1, "
               "framerate=(fraction)0/1, dimensions=(string)4:1, types=(string)float32");
  g_free(text);
  gst_caps_unref(caps);

  EXPECT_EQ(fake().calls(), 0) << "our plugin called the fake " << fake().last();
}

TEST(CompatBind, ControlLibraryWithoutBindingIsDiverted) {
  void *dl = dlopen(NNS_BIND_CONTROL_LIB, RTLD_NOW | RTLD_LOCAL);
  ASSERT_NE(dl, nullptr) << dlerror();
  auto own = reinterpret_cast<int (*)()>(dlsym(dl, "control_own_definition_used"));
  ASSERT_NE(own, nullptr);
  int before = fake().calls();
  EXPECT_EQ(own(), 0) << "the control's own definition ran: the fake did not interpose";
  EXPECT_EQ(fake().calls(), before + 1);
  EXPECT_STREQ(fake().last(), "gst_tensor_info_init");
  dlclose(dl);
}

}  // namespace

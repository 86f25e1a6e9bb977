// SPDX-License-Identifier: LGPL-2.1-only
// gtest main of the Pipeline API tests. Like an application, the tests link only
// libcapi-nnstreamer, which initialises GStreamer itself. The nnstreamer plugin comes from this
// build tree (GST_PLUGIN_PATH) and the few system plugins the tests use from a folder of links
// (GST_PLUGIN_SYSTEM_PATH), with a registry file of their own and the scan done in-process
// (GST_REGISTRY_FORK=no): the uninstrumented gst-plugin-scanner cannot load the plugin of the
// sanitizer tree, and no other build tree's or installed nnstreamer plugin is ever picked up.
// At exit it calls gst_deinit(), as an application may.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

namespace {

int thread_count() {
  std::ifstream f("/proc/self/status");
  for (std::string line; std::getline(f, line);)
    if (line.rfind("Threads:", 0) == 0) return std::atoi(line.c_str() + 8);
  return -1;
}

// The library initialised GStreamer; an application may end it. gst_deinit() stops the streaming
// thread pool; GLib's idle pool threads (GstBin's state-change pool) are then told to exit and
// waited for (up to 3 s). Threads alive at exit keep GLib's per-thread memory, which
// LeakSanitizer reports in the sanitizer pass (use_tls=0: thread-local storage is no root).
void end_gstreamer() {
  if (!gst_is_initialized()) return;
  gst_deinit();
  g_thread_pool_set_max_unused_threads(0);
  for (int i = 0; i < 300 && thread_count() > 1; ++i) {
    g_thread_pool_stop_unused_threads();
    g_usleep(10000);
  }
}

}  // namespace

int main(int argc, char **argv) {
  namespace fs = std::filesystem;
  const std::string b = NNS_BUILD_DIR;
  fs::path sys = fs::path(b) / "tests" / "capi-gst-plugins";
  fs::create_directories(sys);
  for (const char *p : {"libgstcoreelements.so", "libgstapp.so", "libgstvideotestsrc.so",
                        "libgstaudiotestsrc.so", "libgstvideoconvertscale.so"}) {
    fs::path src = fs::path(NNS_GST_PLUGINS_DIR) / p, dst = sys / p;
    std::error_code ec;
    if (fs::exists(src) && !fs::exists(fs::symlink_status(dst))) fs::create_symlink(src, dst, ec);
  }
  setenv("GST_PLUGIN_SYSTEM_PATH", sys.c_str(), 1);
  setenv("GST_PLUGIN_PATH", (b + "/plugin").c_str(), 1);
  setenv("GST_REGISTRY", (b + "/tests/capi-registry.bin").c_str(), 1);
  setenv("GST_REGISTRY_FORK", "no", 1);
  setenv("NNSTREAMER_CONF", (b + "/nnstreamer.ini").c_str(), 0);
  setenv("NNSTREAMER_FILTERS", (b + "/subplugins/filters").c_str(), 0);
  setenv("NNSTREAMER_DECODERS", (b + "/subplugins/decoders").c_str(), 0);
  setenv("NNSTREAMER_CONVERTERS", (b + "/subplugins/converters").c_str(), 0);
  ::testing::InitGoogleTest(&argc, argv);
  int rc = RUN_ALL_TESTS();
  end_gstreamer();
  return rc;
}

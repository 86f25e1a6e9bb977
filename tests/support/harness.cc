// SPDX-License-Identifier: LGPL-2.1-only
#include "support/harness.h"

#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <mutex>
#include <vector>

namespace nns::test {

RunResult run_pipeline(GstElement *pipeline, double timeout_s) {
  RunResult r;
  GstBus *bus = gst_element_get_bus(pipeline);
  GstStateChangeReturn sret = gst_element_set_state(pipeline, GST_STATE_PLAYING);
  (void)sret;  // failures arrive as bus errors
  const gint64 end = g_get_monotonic_time() + static_cast<gint64>(timeout_s * G_USEC_PER_SEC);
  GstMessage *msg = nullptr;
  for (;;) {
    const gint64 left = std::max<gint64>(0, end - g_get_monotonic_time());
    msg = gst_bus_timed_pop_filtered(
        bus, static_cast<GstClockTime>(left) * GST_USECOND,
        static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR | GST_MESSAGE_WARNING));
    if (!msg || GST_MESSAGE_TYPE(msg) != GST_MESSAGE_WARNING) break;
    GError *err = nullptr;
    gchar *dbg = nullptr;
    gst_message_parse_warning(msg, &err, &dbg);
    r.warning_text += std::string(err->message) + " | " + (dbg ? dbg : "") + "\n";
    g_error_free(err);
    g_free(dbg);
    gst_message_unref(msg);
  }
  if (!msg) {
    r.timed_out = true;
  } else if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_EOS) {
    r.eos = true;
  } else {
    GError *err = nullptr;
    gchar *dbg = nullptr;
    gst_message_parse_error(msg, &err, &dbg);
    r.error = true;
    r.error_domain = err->domain;
    r.error_code = err->code;
    r.error_text = std::string(err->message) + " | " + (dbg ? dbg : "");
    r.error_source = GST_MESSAGE_SRC_NAME(msg) ? GST_MESSAGE_SRC_NAME(msg) : "";
    g_error_free(err);
    g_free(dbg);
  }
  if (msg) gst_message_unref(msg);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(bus);
  return r;
}

RunResult run_pipeline(const std::string &description, double timeout_s) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(description.c_str(), &err);
  if (!p || err) {
    RunResult r;
    r.error = true;
    r.error_text = std::string("parse error: ") + (err ? err->message : "unknown");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return r;
  }
  RunResult r = run_pipeline(p, timeout_s);
  gst_object_unref(p);
  return r;
}

std::vector<uint8_t> read_file(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>((std::istreambuf_iterator<char>(f)),
                              std::istreambuf_iterator<char>());
}

std::string shared_models_dir() {
  namespace fs = std::filesystem;
  if (const char *env = std::getenv("NNS_SHARED_DIR")) {
    fs::path p = fs::path(env) / "models" / "upstream";
    return fs::exists(p) ? fs::absolute(p).string() : std::string();
  }
  fs::path p = fs::path(NNS_SOURCE_DIR) / ".." / "shared" / "models" / "upstream";
  return fs::exists(p) ? fs::canonical(p).string() : std::string();
}

std::string imagenet_labels_1000() {
  std::filesystem::path p =
      std::filesystem::path(NNS_BUILD_DIR) / "data" / "imagenet_labels_1000.txt";
  return std::filesystem::exists(p) ? p.string() : std::string();
}

namespace {

// The folders make_temp_dir() made in this process, removed when it exits. A forked child
// inherits the list but not the ownership: only the process that made them removes them.
struct TempDirs {
  std::mutex lock;
  std::vector<std::string> dirs;
  pid_t owner = getpid();
};

TempDirs &temp_dirs() {
  static TempDirs *t = [] {
    auto *p = new TempDirs;  // never destroyed: the exit handler below still needs it
    std::atexit([] {
      TempDirs &td = temp_dirs();
      if (getpid() != td.owner || std::getenv("NNS_KEEP_TEST_TMP")) return;
      std::lock_guard<std::mutex> g(td.lock);
      for (const auto &d : td.dirs) {
        std::error_code ec;
        std::filesystem::remove_all(d, ec);
      }
    });
    return p;
  }();
  return *t;
}

}  // namespace

std::string make_temp_dir() {
  char tmpl[] = "/tmp/nns-test-XXXXXX";
  char *d = mkdtemp(tmpl);
  if (!d) return std::string("/tmp");
  TempDirs &td = temp_dirs();
  std::lock_guard<std::mutex> g(td.lock);
  td.dirs.emplace_back(d);
  return std::string(d);
}

}  // namespace nns::test

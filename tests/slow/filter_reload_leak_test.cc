// SPDX-License-Identifier: LGPL-2.1-only
// Unloading and reloading a model leaks nothing: for each real back end (ONNX Runtime, PyTorch,
// python3, OpenCV), many PLAYING<->NULL cycles (the model opened and closed each time) and many
// is-updatable reloads, with the process's resident memory, open file descriptors and mapped
// shared objects measured before and after (after a warm-up). The model has 4 MiB of weights
// (tests/data/generate_models.py wide_linear; tests/data/python/wide_linear.py), so one model
// kept per cycle would add 4 MiB x kCycles, far above the allowance for allocator noise.
// Label "slow" (tests/slow/): about a second per back end and kind of cycle.
// Measured with mallinfo2() (memory in use through malloc), /proc/self/statm (resident),
// /proc/self/fd and /proc/self/maps.
#include <dirent.h>
#include <malloc.h>
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace nns::test {
namespace {

constexpr int kWarmup = 5;   // first loads fill caches, thread pools, Python imports
constexpr int kCycles = 60;  // measured
// Allowances over kCycles. A model kept per cycle adds >= 4 MiB x 60 = 240 MiB (measured
// with the back ends' close() disabled: 245-505 MiB malloc'd), a file descriptor or mapped
// library per cycle 60. Measured without leaks: malloc'd memory +0.02..1 MiB, resident memory
// +0..9 MiB (allocator caches, freed pages kept by glibc), no descriptor or library.
// malloc'd memory is the precise measure (freed memory reused without RSS growth hides a leak
// from RSS alone); RSS also covers memory from mmap (model files, Python's object arenas).
constexpr long kHeapSlackKib = 16 * 1024;
constexpr long kRssSlackKib = 64 * 1024;
constexpr int kFdSlack = 2;

struct Usage {
  long rss_kib = 0;
  long heap_kib = 0;  // in use through malloc (mallinfo2: arenas + mmapped blocks)
  int fds = 0;
  std::set<std::string> libs;  // mapped shared objects
};

Usage usage() {
  Usage u;
  long pages = 0, resident = 0;
  std::ifstream("/proc/self/statm") >> pages >> resident;
  u.rss_kib = resident * (sysconf(_SC_PAGESIZE) / 1024);
  struct mallinfo2 mi = mallinfo2();
  u.heap_kib = static_cast<long>((mi.uordblks + mi.hblkhd) / 1024);
  if (DIR *d = opendir("/proc/self/fd")) {
    while (dirent *e = readdir(d))
      if (e->d_name[0] != '.') ++u.fds;
    closedir(d);
  }
  std::ifstream maps("/proc/self/maps");
  std::string line;
  while (std::getline(maps, line)) {
    auto slash = line.find('/');
    if (slash == std::string::npos) continue;
    std::string path = line.substr(slash);
    if (path.find(".so") != std::string::npos) u.libs.insert(path);
  }
  return u;
}

struct Case {
  const char *framework;
  std::string model;  // file name in build/tests/models, or a path
  std::string extra;  // more tensor_filter properties
};

void PrintTo(const Case &c, std::ostream *os) {
  *os << c.framework;
}

std::string case_name(const ::testing::TestParamInfo<Case> &i) {
  return i.param.framework;
}

std::string model_path(const Case &c) {
  return c.model.find('/') != std::string::npos ? c.model : models_dir() + "/" + c.model;
}

const std::string kCaps =
    "other/tensors,format=static,num_tensors=1,types=(string)float32,"
    "dimensions=(string)1024:1,framerate=0/1";
constexpr std::size_t kBytes = 4096;

class FilterLeak : public ::testing::TestWithParam<Case> {
 protected:
  void SetUp() override {
    const Case &c = GetParam();
    if (!std::filesystem::exists(backend_path(c.framework)))
      GTEST_SKIP() << backend_path(c.framework) << " is not built";
    if (!std::filesystem::exists(model_path(c)))
      GTEST_SKIP() << model_path(c) << " is missing (generated models not built?)";
  }
  std::string filter(const std::string &model) const {
    const Case &c = GetParam();
    return std::string("tensor_filter framework=") + c.framework + " model=" + model + " " +
           c.extra;
  }
  // Reports and checks the growth from `before` to now.
  static void expect_bounded(const Usage &before, const char *what) {
    Usage after = usage();
    std::vector<std::string> new_libs;
    for (const auto &l : after.libs)
      if (!before.libs.count(l)) new_libs.push_back(l);
    long rss = after.rss_kib - before.rss_kib, heap = after.heap_kib - before.heap_kib;
    std::printf(
        "[ leak     ] %s: %d cycles: RSS %+ld KiB, malloc'd %+ld KiB, fds %+d, shared objects "
        "%+d\n",
        what, kCycles, rss, heap, after.fds - before.fds,
        static_cast<int>(after.libs.size()) - static_cast<int>(before.libs.size()));
    EXPECT_LT(heap, kHeapSlackKib) << what << ": memory in use grew by " << heap << " KiB";
    EXPECT_LT(rss, kRssSlackKib) << what << ": resident memory grew by " << rss << " KiB";
    EXPECT_LE(after.fds - before.fds, kFdSlack) << what << ": file descriptors leak";
    EXPECT_TRUE(new_libs.empty()) << what << ": new shared object mapped: " << new_libs[0];
    EXPECT_LE(after.libs.size(), before.libs.size()) << what;
  }
};

bool run_once(GstElement *pipeline, GstBus *bus, std::string *err) {
  if (gst_element_set_state(pipeline, GST_STATE_PLAYING) == GST_STATE_CHANGE_FAILURE) {
    *err = "cannot set PLAYING";
  } else if (GstMessage *m = gst_bus_timed_pop_filtered(
                 bus, 60 * GST_SECOND,
                 static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR))) {
    if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      *err = e->message;
      g_error_free(e);
    }
    gst_message_unref(m);
  } else {
    *err = "no EOS within 60 s";
  }
  gst_element_set_state(pipeline, GST_STATE_NULL);
  return err->empty();
}

// The model is opened at every start and closed at every stop.
TEST_P(FilterLeak, PlayingNullCycles) {
  std::string desc = "fakesrc num-buffers=2 sizetype=fixed sizemax=" + std::to_string(kBytes) +
                     " filltype=zero ! " + kCaps + " ! " + filter(model_path(GetParam())) +
                     " ! fakesink";
  GError *gerr = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &gerr);
  ASSERT_NE(p, nullptr) << (gerr ? gerr->message : "");
  GstBus *bus = gst_element_get_bus(p);
  std::string err;
  Usage before;
  for (int i = 0; i < kWarmup + kCycles && err.empty(); ++i) {
    if (i == kWarmup) before = usage();
    run_once(p, bus, &err);
  }
  EXPECT_EQ(err, "") << desc;
  if (err.empty()) expect_bounded(before, "PLAYING<->NULL");
  gst_object_unref(bus);
  gst_object_unref(p);
}

// is-updatable: each new model is opened beside the old one, which then closes.
TEST_P(FilterLeak, ReloadCycles) {
  std::string dir = make_temp_dir();
  std::string src = model_path(GetParam());
  std::string ext = std::filesystem::path(src).extension().string();
  std::string models[2] = {dir + "/a" + ext, dir + "/b" + ext};
  for (const auto &m : models) std::filesystem::copy_file(src, m);

  std::string desc = filter(models[0]) + " is-updatable=true";
  GstElement *e = gst_parse_launch(desc.c_str(), nullptr);
  ASSERT_NE(e, nullptr);
  GstBus *bus = gst_bus_new();
  gst_element_set_bus(e, bus);
  GstHarness *h = gst_harness_new_with_element(e, "sink", "src");
  gst_object_unref(e);
  gst_harness_set_src_caps_str(h, kCaps.c_str());
  Usage before;
  for (int i = 0; i < kWarmup + kCycles; ++i) {
    if (i == kWarmup) before = usage();
    g_object_set(h->element, "model", models[(i + 1) % 2].c_str(), nullptr);
    ASSERT_EQ(gst_harness_push(h, gst_buffer_new_allocate(nullptr, kBytes, nullptr)), GST_FLOW_OK)
        << "cycle " << i;
    GstBuffer *out = gst_harness_pull(h);
    ASSERT_NE(out, nullptr) << "cycle " << i;
    EXPECT_EQ(gst_buffer_get_size(out), kBytes);
    gst_buffer_unref(out);
  }
  GstMessage *m = gst_bus_pop_filtered(
      bus, static_cast<GstMessageType>(GST_MESSAGE_ERROR | GST_MESSAGE_WARNING));
  EXPECT_EQ(m, nullptr) << "the reloads posted a message";
  if (m) gst_message_unref(m);
  gchar *model = nullptr;
  g_object_get(h->element, "model", &model, nullptr);
  EXPECT_EQ(std::string(model), models[(kWarmup + kCycles) % 2]);
  g_free(model);
  expect_bounded(before, "reload");
  gst_bus_set_flushing(bus, TRUE);
  gst_harness_teardown(h);
  gst_object_unref(bus);
  std::filesystem::remove_all(dir);
}

const char kTorchShapes[] = "input=1024:1 inputtype=float32 output=1024:1 outputtype=float32";

INSTANTIATE_TEST_SUITE_P(
    Backends, FilterLeak,
    ::testing::Values(Case{"onnxruntime", "wide_linear.onnx", "custom=NumThreads:1"},
                      Case{"opencv", "wide_linear.onnx", ""},
                      Case{"pytorch", "wide_linear.pt", kTorchShapes},
                      Case{"python3",
                           std::string(NNS_SOURCE_DIR) + "/tests/data/python/wide_linear.py", ""}),
    case_name);

}  // namespace
}  // namespace nns::test

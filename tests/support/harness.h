// SPDX-License-Identifier: LGPL-2.1-only
// Test helpers: RAII GstHarness, pipeline runner that collects the bus error, and paths to
// ../shared test data.
#pragma once

#include <gst/check/gstharness.h>
#include <gst/gst.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

namespace nns::test {

struct HarnessDeleter {
  void operator()(GstHarness *h) const {
    if (h) gst_harness_teardown(h);
  }
};
using HarnessPtr = std::unique_ptr<GstHarness, HarnessDeleter>;

// Result of running a pipeline to EOS or ERROR.
struct RunResult {
  bool eos = false;
  bool error = false;
  bool timed_out = false;
  std::string error_text;    // "<message> | <debug>"
  std::string error_source;  // element name that posted the error
  std::string warning_text;  // every WARNING message before the end: "<message> | <debug>\n"...
  GQuark error_domain = 0;
  int error_code = 0;
};

// Parses and runs `description` until EOS, ERROR or `timeout_s`. The pipeline is set to NULL
// before returning.
RunResult run_pipeline(const std::string &description, double timeout_s = 20.0);
// Same, for an already built pipeline (not unreffed).
RunResult run_pipeline(GstElement *pipeline, double timeout_s = 20.0);

// Reads a whole file into bytes.
std::vector<uint8_t> read_file(const std::string &path);

// ../shared/models/upstream (absolute), or "" if absent. NNS_SHARED_DIR overrides.
std::string shared_models_dir();
// GTEST_SKIP()s when the shared models are missing.
#define NNS_REQUIRE_SHARED_MODELS()                                                      \
  do {                                                                                   \
    if (::nns::test::shared_models_dir().empty())                                        \
      GTEST_SKIP() << "../shared/models is not beside the project; skipping model test"; \
  } while (0)

// True when CI=true (.ci/run): what scripts/setup.sh installs or the build generates must be
// there, so a test that would skip for want of it fails instead.
inline bool in_ci() {
  const char *ci = std::getenv("CI");
  return ci && std::string(ci) == "true";
}
// GTEST_SKIP()s with the streamed message, or FAILs with it under CI=true. Only for test data and
// dependencies CI always provides (not for back ends a tree leaves out by design).
#define NNS_SKIP_UNLESS_CI(message)                             \
  do {                                                          \
    if (::nns::test::in_ci()) FAIL() << "CI=true: " << message; \
    GTEST_SKIP() << message;                                    \
  } while (0)

// build/data/imagenet_labels_1000.txt (absolute): the 1000 ImageNet labels in the 1000-class
// order, derived at build time from ../shared's 1001-line labels.txt without "background"
// (cmake/imagenet_labels.cmake); "" if it was not generated.
std::string imagenet_labels_1000();

// A fresh temporary folder under /tmp, removed with its contents when the test process exits
// (kept when NNS_KEEP_TEST_TMP is set, to look at after a failure).
std::string make_temp_dir();

}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// gtest main for GStreamer tests: initialises GStreamer and registers the nnstreamer plugin
// statically, so tests never depend on GST_PLUGIN_PATH or an installed plugin.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

#include "gst/plugin_init.h"

// ctest passes only part of a list-valued ENVIRONMENT through gtest_discover_tests, and test
// binaries are also run by hand: point NNStreamer's configuration at the build tree here,
// unless the caller already did.
static void use_build_tree_config() {
  const std::string b = NNS_BUILD_DIR;
  setenv("NNSTREAMER_CONF", (b + "/nnstreamer.ini").c_str(), 0);
  setenv("NNSTREAMER_FILTERS", (b + "/subplugins/filters").c_str(), 0);
  setenv("NNSTREAMER_DECODERS", (b + "/subplugins/decoders").c_str(), 0);
  setenv("NNSTREAMER_CONVERTERS", (b + "/subplugins/converters").c_str(), 0);
  setenv("NNSTREAMER_TRAINERS", (b + "/subplugins/trainers").c_str(), 0);
  setenv("PYTHONPATH", (b + "/python").c_str(), 0);
}

int main(int argc, char **argv) {
  use_build_tree_config();
  ::testing::InitGoogleTest(&argc, argv);
  gst_init(&argc, &argv);
  if (!nns_register_static()) {
    fprintf(stderr, "failed to register the nnstreamer plugin statically\n");
    return 1;
  }
  int rc = RUN_ALL_TESTS();
  gst_deinit();
  return rc;
}

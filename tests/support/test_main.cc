// SPDX-License-Identifier: LGPL-2.1-only
// gtest main for GStreamer tests: initialises GStreamer and registers the nnstreamer plugin
// statically, so tests never depend on GST_PLUGIN_PATH or an installed plugin.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include "gst/plugin_init.h"

int main(int argc, char **argv) {
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

// SPDX-License-Identifier: LGPL-2.1-only
// gtest main of the Pipeline API tests. Like an application, the tests link only
// libcapi-nnstreamer, which initialises GStreamer itself; the nnstreamer plugin is found
// through GST_PLUGIN_PATH, set here to this build tree's plugin folder (with a registry file of
// its own, so other build trees' plugins are never picked up).
#include <gtest/gtest.h>

#include <cstdlib>
#include <string>

int main(int argc, char **argv) {
  const std::string b = NNS_BUILD_DIR;
  setenv("GST_PLUGIN_PATH", (b + "/plugin").c_str(), 1);
  setenv("GST_REGISTRY", (b + "/tests/capi-registry.bin").c_str(), 1);
  setenv("NNSTREAMER_CONF", (b + "/nnstreamer.ini").c_str(), 0);
  setenv("NNSTREAMER_FILTERS", (b + "/subplugins/filters").c_str(), 0);
  setenv("NNSTREAMER_DECODERS", (b + "/subplugins/decoders").c_str(), 0);
  setenv("NNSTREAMER_CONVERTERS", (b + "/subplugins/converters").c_str(), 0);
  ::testing::InitGoogleTest(&argc, argv);
  return RUN_ALL_TESTS();
}

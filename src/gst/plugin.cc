// SPDX-License-Identifier: LGPL-2.1-only
// The GStreamer plugin "nnstreamer": `gst-inspect-1.0 nnstreamer` lists its elements.
#include "gst/plugin_init.h"

#define PACKAGE "nnstreamer-cpp"
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, nnstreamer,
                  "nnstreamer-cpp: neural network filters for GStreamer", nns_plugin_init,
                  NNS_VERSION, "LGPL", "nnstreamer-cpp", "https://github.com/nnstreamer")

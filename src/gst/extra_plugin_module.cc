// SPDX-License-Identifier: LGPL-2.1-only
// The module entry point of one plugin of gst/extra_plugins.h, picked by NNS_EXTRA_PLUGIN_MQTT or
// NNS_EXTRA_PLUGIN_GRPC (src/CMakeLists.txt). Only the modules have it: programs that link the
// object libraries register the plugins statically instead.
#include "gst/extra_plugins.h"

#define PACKAGE "nnstreamer-cpp"
#if defined(NNS_EXTRA_PLUGIN_MQTT)
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, mqtt, NNS_MQTT_PLUGIN_DESCRIPTION,
                  nns_mqtt_plugin_init, NNS_VERSION, "LGPL", "nnstreamer-cpp",
                  "https://github.com/nnstreamer")
#elif defined(NNS_EXTRA_PLUGIN_GRPC)
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, nnstreamer_grpc,
                  NNS_GRPC_PLUGIN_DESCRIPTION, nns_grpc_plugin_init, NNS_VERSION, "LGPL",
                  "nnstreamer-cpp", "https://github.com/nnstreamer")
#else
#error "define NNS_EXTRA_PLUGIN_MQTT or NNS_EXTRA_PLUGIN_GRPC"
#endif

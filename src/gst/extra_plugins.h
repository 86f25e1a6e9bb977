// SPDX-License-Identifier: LGPL-2.1-only
// The plugins built apart from "nnstreamer" (src/CMakeLists.txt), as upstream packages them:
// "mqtt" (libgstmqtt.so: mqttsink, mqttsrc) and "nnstreamer_grpc" (libnnstreamer-grpc.so:
// tensor_src_grpc, tensor_sink_grpc). gst-inspect-1.0 and gst-launch-1.0 find them in the plugin
// folder; a program linking their object library (nns_gst_mqtt / nns_gst_grpc) registers them
// in its own process with these, after gst_init() (as nns_register_static() does for the rest).
#pragma once

#include <gst/gst.h>

#define NNS_MQTT_PLUGIN_DESCRIPTION "nnstreamer-cpp: MQTT publish/subscribe of any stream"
#define NNS_GRPC_PLUGIN_DESCRIPTION "nnstreamer-cpp: tensor streams over gRPC"

gboolean nns_mqtt_register_static(void);
gboolean nns_grpc_register_static(void);
// The plugins' init functions (their elements), for the modules' GST_PLUGIN_DEFINE.
gboolean nns_mqtt_plugin_init(GstPlugin *plugin);
gboolean nns_grpc_plugin_init(GstPlugin *plugin);

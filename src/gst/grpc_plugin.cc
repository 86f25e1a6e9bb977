// SPDX-License-Identifier: LGPL-2.1-only
// The "nnstreamer_grpc" plugin (libnnstreamer-grpc.so, as upstream's gRPC registerer):
// tensor_src_grpc and tensor_sink_grpc, apart from the nnstreamer plugin so that only pipelines
// using them load gRPC++ and protobuf. Its module entry point is in extra_plugin_module.cc.
#include "gst/extra_plugins.h"

GST_ELEMENT_REGISTER_DECLARE(tensor_sink_grpc);
GST_ELEMENT_REGISTER_DECLARE(tensor_src_grpc);

gboolean nns_grpc_plugin_init(GstPlugin *plugin) {
  gboolean ok = GST_ELEMENT_REGISTER(tensor_src_grpc, plugin);
  ok = GST_ELEMENT_REGISTER(tensor_sink_grpc, plugin) && ok;
  return ok;
}

gboolean nns_grpc_register_static(void) {
  return gst_plugin_register_static(GST_VERSION_MAJOR, GST_VERSION_MINOR, "nnstreamer_grpc",
                                    NNS_GRPC_PLUGIN_DESCRIPTION, nns_grpc_plugin_init, NNS_VERSION,
                                    "LGPL", "nnstreamer-cpp", "nnstreamer-cpp",
                                    "https://github.com/nnstreamer");
}

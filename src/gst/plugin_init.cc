// SPDX-License-Identifier: LGPL-2.1-only
// Registers every element of the plugin. Shared by the plugin module (plugin.cc) and by the
// tests, which register the plugin statically.
#include "gst/plugin_init.h"

#include "nns_elements_decl.inc"
#include "profile/tracer.h"

gboolean nns_plugin_init(GstPlugin *plugin) {
  gboolean ok = TRUE;
#include "nns_elements_reg.inc"
  ok = nns_profile_tracer_register(plugin) && ok;
  return ok;
}

gboolean nns_register_static(void) {
  gboolean ok = gst_plugin_register_static(GST_VERSION_MAJOR, GST_VERSION_MINOR, "nnstreamer",
                                           "nnstreamer-cpp: neural network filters for GStreamer",
                                           nns_plugin_init, NNS_VERSION, "LGPL", "nnstreamer-cpp",
                                           "nnstreamer-cpp", "https://github.com/nnstreamer");
  // GST_TRACERS was read by gst_init(), before this registration: start nnsprofile now.
  if (ok) nns::profile::activate_from_env();
  return ok;
}

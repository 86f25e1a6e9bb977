// SPDX-License-Identifier: LGPL-2.1-only
// The "mqtt" plugin (libgstmqtt.so, as upstream's gst/mqtt): mqttsink and mqttsrc, apart from
// the nnstreamer plugin. Its module entry point is in extra_plugin_module.cc.
#include "gst/extra_plugins.h"

GST_ELEMENT_REGISTER_DECLARE(mqttsink);
GST_ELEMENT_REGISTER_DECLARE(mqttsrc);

gboolean nns_mqtt_plugin_init(GstPlugin *plugin) {
  gboolean ok = GST_ELEMENT_REGISTER(mqttsink, plugin);
  ok = GST_ELEMENT_REGISTER(mqttsrc, plugin) && ok;
  return ok;
}

gboolean nns_mqtt_register_static(void) {
  return gst_plugin_register_static(GST_VERSION_MAJOR, GST_VERSION_MINOR, "mqtt",
                                    NNS_MQTT_PLUGIN_DESCRIPTION, nns_mqtt_plugin_init, NNS_VERSION,
                                    "LGPL", "nnstreamer-cpp", "nnstreamer-cpp",
                                    "https://github.com/nnstreamer");
}

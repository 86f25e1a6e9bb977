// SPDX-License-Identifier: LGPL-2.1-only
#pragma once

#include <gst/gst.h>

gboolean nns_plugin_init(GstPlugin *plugin);
// Registers the plugin in this process without loading the module (used by tests/tools).
gboolean nns_register_static(void);

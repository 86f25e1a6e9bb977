// SPDX-License-Identifier: LGPL-2.1-only
// The nnsprofile GStreamer tracer (GST_TRACERS="nnsprofile(file=/tmp/p.json)"): element times,
// rates, latencies, queue levels, thread CPU and tensor_filter invoke times (docs/profiler.md).
#pragma once

#include <gst/gst.h>

#include <string>

// Registers the tracer factory "nnsprofile" in `plugin`.
gboolean nns_profile_tracer_register(GstPlugin *plugin);

namespace nns::profile {

// Creates an nnsprofile tracer with `params` (the text between the parentheses of GST_TRACERS)
// unless one is active in this process. True when one is active afterwards. For programs that
// register the plugin statically after gst_init(), where GST_TRACERS was read before the
// tracer existed.
bool activate(const char *params);
// activate() with the parameters of "nnsprofile" in GST_TRACERS, when it is listed there.
void activate_from_env();
// The active tracer's figures as JSON ("" when none is active), and a rewrite of its file.
std::string snapshot();
bool write_snapshot(const char *reason);

}  // namespace nns::profile

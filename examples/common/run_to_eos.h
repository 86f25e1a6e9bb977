// SPDX-License-Identifier: LGPL-2.1-only
// Shared by the example applications (header only, GStreamer API only): plays a pipeline until
// EOS or the first bus error, then sets it to NULL.
#pragma once

#include <gst/gst.h>

#include <string>

namespace nns_example {

// Returns "" at EOS, "<element>: <message> | <debug>" on an error, `timeout_text` when neither
// came within `timeout_s` seconds.
inline std::string run_to_eos(GstElement *pipeline, int timeout_s, const char *timeout_text) {
  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  GstBus *bus = gst_element_get_bus(pipeline);
  GstMessage *msg =
      gst_bus_timed_pop_filtered(bus, static_cast<GstClockTime>(timeout_s) * GST_SECOND,
                                 static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  std::string err;
  if (!msg) {
    err = timeout_text;
  } else if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ERROR) {
    GError *e = nullptr;
    gchar *dbg = nullptr;
    gst_message_parse_error(msg, &e, &dbg);
    err = std::string(GST_OBJECT_NAME(msg->src)) + ": " + e->message + (dbg ? " | " : "") +
          (dbg ? dbg : "");
    g_error_free(e);
    g_free(dbg);
  }
  if (msg) gst_message_unref(msg);
  gst_object_unref(bus);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  return err;
}

}  // namespace nns_example

// SPDX-License-Identifier: LGPL-2.1-only
// The nnstreamer_ros plugin module (libnnstreamer_ros.so): tensor_ros_sink and tensor_ros_src,
// built apart from the nnstreamer plugin (as nnstreamer-ros is) so that only this module links
// the ROS libraries.
#include "ros/ros_elements.h"

static gboolean plugin_init(GstPlugin *plugin) {
  gboolean ok = GST_ELEMENT_REGISTER(tensor_ros_sink, plugin);
  ok = GST_ELEMENT_REGISTER(tensor_ros_src, plugin) && ok;
  return ok;
}

#define PACKAGE "nnstreamer-cpp"
GST_PLUGIN_DEFINE(GST_VERSION_MAJOR, GST_VERSION_MINOR, nnstreamer_ros,
                  "NNStreamer tensor streams over ROS topics", plugin_init, NNS_VERSION, "LGPL",
                  "nnstreamer-cpp", "https://github.com/nnstreamer/nnstreamer-ros")

// SPDX-License-Identifier: LGPL-2.1-only
// The elements of the nnstreamer_ros plugin (src/ros/plugin.cc registers them).
#pragma once

#include <gst/gst.h>

G_BEGIN_DECLS
GST_ELEMENT_REGISTER_DECLARE(tensor_ros_sink);
GST_ELEMENT_REGISTER_DECLARE(tensor_ros_src);
G_END_DECLS

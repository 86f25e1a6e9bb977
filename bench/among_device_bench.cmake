# SPDX-License-Identifier: LGPL-2.1-only
# mqttsink/mqttsrc and tensor_src_grpc/tensor_sink_grpc are their own plugins: linked and
# registered statically here (gst/extra_plugins.h).
target_link_libraries(${name} PRIVATE nns_gst_mqtt nns_gst_grpc)

# SPDX-License-Identifier: LGPL-2.1-only
# tensor_src_grpc/tensor_sink_grpc are their own plugin (libnnstreamer-grpc.so): the gRPC test
# links its objects and registers it statically (nns_grpc_register_static in the test's
# environment).
if(TARGET tensor_grpc_test)
  target_link_libraries(tensor_grpc_test PRIVATE nns_gst_grpc)
endif()
# TensorGrpc.OnlyTheGrpcPluginLinksGrpc reads both plugin modules.
if(TARGET tensor_grpc_test)
  add_dependencies(tensor_grpc_test nnstreamer nnstreamer_grpc)
endif()

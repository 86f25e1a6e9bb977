# SPDX-License-Identifier: LGPL-2.1-only
# connect-type CUSTOM test libraries (tests/edge/custom_conn_lib.c), linked to our
# libnnstreamer-edge as an upstream-built custom library is linked to nnstreamer-edge's; the
# second one lacks nns_edge_custom_start. edge_custom_test gets their paths.
if(TARGET edge_custom_test)
  foreach(v ok nostart)
    add_library(nns_test_edge_custom_${v} MODULE ${CMAKE_CURRENT_SOURCE_DIR}/edge/custom_conn_lib.c)
    target_include_directories(nns_test_edge_custom_${v} PRIVATE ${CMAKE_SOURCE_DIR}/src)
    target_link_libraries(nns_test_edge_custom_${v} PRIVATE nns_edge_capi Threads::Threads)
    add_dependencies(edge_custom_test nns_test_edge_custom_${v})
  endforeach()
  target_compile_definitions(nns_test_edge_custom_nostart PRIVATE NNS_TEST_NO_START)
  target_compile_definitions(edge_custom_test PRIVATE
    NNS_TEST_CUSTOM_LIB="$<TARGET_FILE:nns_test_edge_custom_ok>"
    NNS_TEST_CUSTOM_LIB_NOSTART="$<TARGET_FILE:nns_test_edge_custom_nostart>"
    NNS_TEST_EDGE_CAPI="$<TARGET_FILE:nns_edge_capi>")
endif()

# Query server batching runs generated ONNX models through the onnxruntime back end.
if(TARGET query_batch_test AND TARGET nns_filter_onnxruntime)
  add_dependencies(query_batch_test nns_filter_onnxruntime)
endif()
if(TARGET query_batch_test AND TARGET nns_filter_pytorch)
  add_dependencies(query_batch_test nns_filter_pytorch)
endif()
if(TARGET query_batch_test AND TARGET nns_filter_tflite)
  add_dependencies(query_batch_test nns_filter_tflite)
endif()

# SPDX-License-Identifier: LGPL-2.1-only
# image_segment / pose_estimation decoders: upstream's golden and the classification and
# segmentation examples as tests. Exit 77 (../shared, a back end or a GStreamer element
# missing) counts as skipped. The deeplab runs take ~9 s of CPU on ArmNN CpuRef: label "slow".
set(_nns_shared "${CMAKE_SOURCE_DIR}/../shared")
if(DEFINED ENV{NNS_SHARED_DIR})
  set(_nns_shared "$ENV{NNS_SHARED_DIR}")
endif()

add_test(NAME decoder.image_segment_golden
         COMMAND bash ${CMAKE_CURRENT_SOURCE_DIR}/decoders/image_segment_golden.sh
                 ${CMAKE_BINARY_DIR} ${_nns_shared})
set_tests_properties(decoder.image_segment_golden PROPERTIES
  SKIP_RETURN_CODE 77 LABELS "decoders;slow" TIMEOUT 180)

add_test(NAME example.classification
         COMMAND bash ${CMAKE_SOURCE_DIR}/examples/classification/run.sh)
set_tests_properties(example.classification PROPERTIES
  ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SHARED_DIR=${_nns_shared};NNS_SKIP_MISSING=1"
  PASS_REGULAR_EXPRESSION "^orange\n$" SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 60)

add_test(NAME example.segmentation
         COMMAND bash -c "\"$0\" && /usr/bin/python3 \"$1\" \"$2\""
                 ${CMAKE_SOURCE_DIR}/examples/segmentation/run.sh
                 ${CMAKE_SOURCE_DIR}/examples/segmentation/check_mask.py
                 ${CMAKE_BINARY_DIR}/demo/segmentation-test-mask.rgba)
set_tests_properties(example.segmentation PROPERTIES
  ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SHARED_DIR=${_nns_shared};NNS_SKIP_MISSING=1;NNS_SEG_OUTPUT=${CMAKE_BINARY_DIR}/demo/segmentation-test.png;NNS_SEG_MASK=${CMAKE_BINARY_DIR}/demo/segmentation-test-mask.rgba"
  SKIP_RETURN_CODE 77 LABELS "demo;slow" TIMEOUT 180)

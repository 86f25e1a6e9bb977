# SPDX-License-Identifier: LGPL-2.1-only
# examples/face_demo/boxes.sh as a test: BlazeFace through tensor_decoder mode=bounding_boxes
# must find the astronaut's face at x=179 y=81 w=93 h=93 (+-3 px) of the 512x512 photo.
# Exit 77 (model, photo or ONNX Runtime back end missing) counts as skipped.
add_test(NAME demo.face_boxes COMMAND bash ${CMAKE_SOURCE_DIR}/examples/face_demo/boxes.sh)
set_tests_properties(demo.face_boxes PROPERTIES
  ENVIRONMENT "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_FACE_SKIP_MISSING=1;NNS_FACE_BOXES_OUTPUT=${CMAKE_BINARY_DIR}/demo/faces_boxes-test.png"
  PASS_REGULAR_EXPRESSION "Detect 1 boxes in 128 x 128 input image\n[^\n]*-> output x:(17[6-9]|18[0-2]) y:(7[89]|8[0-4]) w:(9[0-6]) h:(9[0-6])\n"
  SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)

# SPDX-License-Identifier: LGPL-2.1-only
# The TensorFlow Lite demos (examples/tflite_classification, object_detection, tflite_face,
# pose) as tests. They use tensor_filter framework=tensorflow-lite, which is our TFLite back end
# (libnnstreamer_filter_tensorflow2-lite.so, docs/backends/tflite.md) when it is built, Arm NN
# otherwise (Arm NN cannot parse BlazeFace's fp16 weights nor MoveNet's CAST). Exit 77 (../shared,
# a photo, or a back end that opens the model missing) counts as skipped, except in CI
# (CI=true), where the scripts fail.
set(_nns_shared "${CMAKE_SOURCE_DIR}/../shared")
if(DEFINED ENV{NNS_SHARED_DIR})
  set(_nns_shared "$ENV{NNS_SHARED_DIR}")
endif()
set(_nns_tflite_env "NNS_BUILD_DIR=${CMAKE_BINARY_DIR};NNS_SHARED_DIR=${_nns_shared};NNS_SKIP_MISSING=1")

add_test(NAME example.tflite_classification
         COMMAND bash ${CMAKE_SOURCE_DIR}/examples/tflite_classification/run.sh)
set_tests_properties(example.tflite_classification PROPERTIES
  ENVIRONMENT "${_nns_tflite_env};NNS_TFLITE_CLS_OUTPUT=${CMAKE_BINARY_DIR}/demo/tflite_classification-test.png"
  PASS_REGULAR_EXPRESSION "(^|\n)orange\n" SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)

# orange.png: the orange (COCO class 54) at Arm NN CpuRef's box 58,61 212x212 (300x300 pixels,
# score 0.75) +-3 px; astronaut.png: a person about the photo's height. Label "slow": on Arm NN
# (no TFLite back end) it takes ~7 s of CPU per photo.
add_test(NAME example.object_detection
         COMMAND bash ${CMAKE_SOURCE_DIR}/examples/object_detection/run.sh)
set_tests_properties(example.object_detection PROPERTIES
  ENVIRONMENT "${_nns_tflite_env};NNS_DETECT_OUTPUT_DIR=${CMAKE_BINARY_DIR}/demo/object_detection-test"
  PASS_REGULAR_EXPRESSION "Detect 1 boxes in 300 x 300 input image\n\\[orange\\] x:(5[5-9]|6[01]) y:(5[89]|6[0-4]) w:(209|21[0-5]) h:(209|21[0-5]) prob:0\\.[78][0-9]*[^\n]*\n.*\\[person\\] x:[0-9] y:[0-9] w:2[0-4][0-9] h:2[89][0-9]"
  SKIP_RETURN_CODE 77 LABELS "demo;slow" TIMEOUT 240)

# The face within 3 px of examples/face_demo's ONNX box (x 179 y 81 w 93 h 93 of 512x512).
add_test(NAME example.tflite_face COMMAND bash ${CMAKE_SOURCE_DIR}/examples/tflite_face/run.sh)
set_tests_properties(example.tflite_face PROPERTIES
  ENVIRONMENT "${_nns_tflite_env};NNS_TFLITE_FACE_OUTPUT=${CMAKE_BINARY_DIR}/demo/tflite_face-test.png"
  PASS_REGULAR_EXPRESSION "Detect 1 boxes in 128 x 128 input image\n[^\n]*-> output x:(17[6-9]|18[0-2]) y:(7[89]|8[0-4]) w:(9[0-6]) h:(9[0-6])\n"
  SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)

add_test(NAME example.pose
         COMMAND bash -c "\"$0\" && /usr/bin/python3 \"$1\" \"$2\""
                 ${CMAKE_SOURCE_DIR}/examples/pose/run.sh
                 ${CMAKE_SOURCE_DIR}/examples/pose/check_pose.py
                 ${CMAKE_BINARY_DIR}/demo/pose-test-layer.rgba)
set_tests_properties(example.pose PROPERTIES
  ENVIRONMENT "${_nns_tflite_env};NNS_POSE_OUTPUT=${CMAKE_BINARY_DIR}/demo/pose-test.png;NNS_POSE_LAYER=${CMAKE_BINARY_DIR}/demo/pose-test-layer.rgba"
  SKIP_RETURN_CODE 77 LABELS demo TIMEOUT 120)


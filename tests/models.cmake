# SPDX-License-Identifier: LGPL-2.1-only
# Generated test models (tests/data/generate_models.py) into build/tests/models/: tiny torch
# modules exported to ONNX and TorchScript, python3 filter twins, TensorFlow Lite twins
# (tests/data/tflite_writer.py), a tiny Darknet model and reference outputs.
# Needs Debian's python3-torch, python3-onnx and python3-numpy under /usr/bin/python3; the .tflite
# twins also need python3-flatbuffers (without it their sidecars say "not_written").
set(NNS_TEST_MODELS_DIR ${CMAKE_BINARY_DIR}/tests/models)
set(NNS_MODELS_PYTHON /usr/bin/python3 CACHE FILEPATH "Python with torch+onnx+numpy for test models")
execute_process(COMMAND ${NNS_MODELS_PYTHON} -c "import torch, onnx, numpy"
                RESULT_VARIABLE _nns_torch_rc OUTPUT_QUIET ERROR_QUIET)
if(_nns_torch_rc EQUAL 0)
  set(_gen ${CMAKE_SOURCE_DIR}/tests/data/generate_models.py)
  set(_stamp ${NNS_TEST_MODELS_DIR}/models.json)
  add_custom_command(OUTPUT ${_stamp}
    COMMAND ${NNS_MODELS_PYTHON} ${_gen} ${NNS_TEST_MODELS_DIR}
    DEPENDS ${_gen} ${CMAKE_SOURCE_DIR}/tests/data/tflite_writer.py
    COMMENT "Generating test models in ${NNS_TEST_MODELS_DIR}"
    VERBATIM)
  add_custom_target(nns_test_models ALL DEPENDS ${_stamp})
else()
  message(STATUS "tests: ${NNS_MODELS_PYTHON} lacks torch/onnx/numpy; generated-model tests will skip")
  add_custom_target(nns_test_models)
endif()

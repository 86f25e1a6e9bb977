# SPDX-License-Identifier: LGPL-2.1-only
# build/data/imagenet_labels_1000.txt: the 1000 ImageNet class names in the usual 1000-class
# order (torchvision, ONNX model zoo), derived at build time from the shared
# ../shared/models/upstream/labels/labels.txt, which is upstream's 1001-line file for TFLite
# MobileNet (line 1 = "background"). It is labels.txt without its first line; the shared file is
# never copied into the source tree. mobilenet_v2_quant.onnx (a PyTorch export) needs this file;
# mobilenet_v2_1.0_224_quant.tflite keeps labels.txt.
#
# Two uses of this file:
#  - include()d from the top CMakeLists: when labels.txt is there, adds the build step (target
#    nns_imagenet_labels, built by default) and sets NNS_IMAGENET_LABELS to the output path.
#  - cmake -DIN=labels.txt -DOUT=imagenet_labels_1000.txt -P imagenet_labels.cmake: the step.
if(CMAKE_SCRIPT_MODE_FILE)
  file(READ "${IN}" _text)
  string(FIND "${_text}" "\n" _nl)
  if(_nl LESS 0)
    message(FATAL_ERROR "${IN}: no line break; expected background + 1000 ImageNet labels")
  endif()
  string(SUBSTRING "${_text}" 0 ${_nl} _first)
  if(NOT _first STREQUAL "background")
    message(FATAL_ERROR "${IN}: first line is '${_first}', expected 'background'")
  endif()
  math(EXPR _start "${_nl} + 1")
  string(SUBSTRING "${_text}" ${_start} -1 _rest)
  string(REGEX MATCHALL "\n" _lines "${_rest}")
  list(LENGTH _lines _count)
  if(NOT _count EQUAL 1000)
    message(FATAL_ERROR "${IN}: ${_count} lines after 'background', expected 1000")
  endif()
  file(WRITE "${OUT}" "${_rest}")
  return()
endif()

set(NNS_SHARED_DIR "${CMAKE_SOURCE_DIR}/../shared" CACHE PATH
    "The shared folder with models/upstream (test models and data, never copied)")
if(DEFINED ENV{NNS_SHARED_DIR})
  set(NNS_SHARED_DIR "$ENV{NNS_SHARED_DIR}" CACHE PATH "" FORCE)
endif()
set(_nns_labels_1001 "${NNS_SHARED_DIR}/models/upstream/labels/labels.txt")
set(NNS_IMAGENET_LABELS "${CMAKE_BINARY_DIR}/data/imagenet_labels_1000.txt")
if(EXISTS "${_nns_labels_1001}")
  add_custom_command(OUTPUT "${NNS_IMAGENET_LABELS}"
    COMMAND ${CMAKE_COMMAND} -DIN=${_nns_labels_1001} -DOUT=${NNS_IMAGENET_LABELS}
            -P ${CMAKE_CURRENT_LIST_DIR}/imagenet_labels.cmake
    DEPENDS "${_nns_labels_1001}" ${CMAKE_CURRENT_LIST_DIR}/imagenet_labels.cmake
    COMMENT "Deriving ${NNS_IMAGENET_LABELS} (1000 ImageNet labels) from ${_nns_labels_1001}"
    VERBATIM)
  add_custom_target(nns_imagenet_labels ALL DEPENDS "${NNS_IMAGENET_LABELS}")
else()
  message(STATUS "imagenet labels: ${_nns_labels_1001} not found; "
                 "build/data/imagenet_labels_1000.txt not generated")
  add_custom_target(nns_imagenet_labels)
endif()

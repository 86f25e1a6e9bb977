# SPDX-License-Identifier: LGPL-2.1-only
# The engine-free reader + translator of the tflite back end, relative to this folder. One list
# for the two builds that compile it: nns_tflite_model (CMakeLists.txt here) and the fuzz tree's
# fuzz_tflite (fuzz/CMakeLists.txt, a separate clang project). The translation also calls
# src/core/detection_postprocess.cc, which the main build takes from nns_core.
set(NNS_TFLITE_MODEL_SOURCES tflite_model.cc tflite_to_onnx.cc tflite_layers.cc tflite_ops.cc
                             tflite_quant_add.cc)

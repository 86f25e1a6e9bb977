// SPDX-License-Identifier: LGPL-2.1-only
// Translation of a verified TFLite graph (tflite_model.h) into an ONNX graph held in memory,
// run by ONNX Runtime. Quantized tensors stay quantized at the graph's edges and between ops:
// every quantized op becomes DequantizeLinear -> float op -> QuantizeLinear, a pattern ORT
// fuses into its integer kernels (QLinearConv, QLinearAdd, ...). Layout-sensitive ops (conv,
// pooling, resize...) read NHWC tensors through Transpose pairs that ORT's transpose optimizer
// cancels between layers; constant weights are transposed here once. See
// docs/backends/tflite.md.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/detection_postprocess.h"
#include "tflite_model.h"

namespace nns::tfl {

// The custom op TFLite_Detection_PostProcess runs on the CPU after ORT: ORT gives its float
// inputs (box encodings, class scores), the anchors are decoded here.
struct DetectionPost {
  DetectionPostProcessOptions opts;  // the op's custom options, TFLite's defaults
  std::string boxes, scores;         // ONNX outputs feeding it
  std::vector<float> anchors;        // [num_anchors][4]
  int num_anchors = 0;
  std::vector<int> outputs;  // its 4 TFLite output tensors
  int op_index = -1;
  // Output rows (detection_postprocess_slots): max_detections x max_classes_per_detection (fast
  // NMS, TFLite's output shape), max_detections (regular NMS); translate() refuses options that
  // give 0 (invalid).
  int slots() const { return detection_postprocess_slots(opts); }
};

struct Translation {
  std::string onnx;                    // ModelProto bytes
  std::vector<std::string> in_names;   // ONNX names of the TFLite inputs, in order
  std::vector<std::string> out_names;  // ONNX outputs to fetch (model outputs first, in order,
                                       // then the post-process inputs)
  std::optional<DetectionPost> post;   // set when the model ends in TFLite_Detection_PostProcess
};

// `input_shapes` (one per model input, TFLite order) replaces the declared input shapes.
// Throws ModelError naming the model, the operator index and name when an op is not supported.
Translation translate(const Model &m, const std::vector<std::vector<int64_t>> &input_shapes);

// ONNX element type of a TFLite tensor type (0 if none).
int onnx_type(int tflite_type);

}  // namespace nns::tfl

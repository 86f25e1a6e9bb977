// SPDX-License-Identifier: LGPL-2.1-only
// Reads the declared inputs and outputs (names, element types, shapes) of an ONNX model file
// with a minimal protobuf wire-format reader, for back ends whose runtime does not expose them
// (OpenCV DNN 4.6). Initializers listed among the graph inputs (old exporters) are skipped.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "../common/onnx_types.h"

namespace nns::onnx {

struct ValueInfo {
  std::string name;
  int32_t elem_type = kUndefined;
  std::vector<int64_t> shape;  // -1 for a free (symbolic or missing) dimension
  bool is_tensor = false;
};

struct GraphInfo {
  std::vector<ValueInfo> inputs, outputs;
};

// Parses the model file; throws std::runtime_error naming the file on a read or format error.
GraphInfo read_graph_info(const std::string &path);
// Same, from bytes already in memory (for tests).
GraphInfo parse_graph_info(const uint8_t *data, std::size_t size);

}  // namespace nns::onnx

// SPDX-License-Identifier: LGPL-2.1-only
// libFuzzer target: the tflite back end's model loader (backends/filter/tflite/tflite_model.cc:
// flatbuffer verification and every cross-reference check) and, on what it accepts, the
// translation into an ONNX graph (tflite_to_onnx.cc), which reads constants, options and
// custom options. Properties: no crash/UB/leak; every rejection is a ModelError; an accepted
// model has in-range tensor indices and constant sizes that match shape x type.
#include <cstdlib>
#include <vector>

#include "tflite_model.h"
#include "tflite_to_onnx.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t *data, size_t size) {
  nns::tfl::Model m;
  try {
    m = nns::tfl::parse_model(std::vector<uint8_t>(data, data + size), "fuzz.tflite");
  } catch (const nns::tfl::ModelError &) {
    return 0;
  }
  const std::size_t n = m.tensors.size();
  for (const auto &t : m.tensors)
    if (t.data && t.bytes != static_cast<std::size_t>(t.elements()) * nns::tfl::type_size(t.type))
      std::abort();
  for (const auto &op : m.ops) {
    for (int i : op.inputs)
      if (i < -1 || i >= static_cast<int>(n)) std::abort();
    for (int i : op.outputs)
      if (i < 0 || i >= static_cast<int>(n)) std::abort();
  }
  std::vector<std::vector<int64_t>> shapes;
  for (int i : m.inputs) shapes.emplace_back(m.tensors[i].shape.begin(), m.tensors[i].shape.end());
  try {
    nns::tfl::translate(m, shapes);
  } catch (const nns::tfl::ModelError &) {
  } catch (const std::exception &) {  // std::out_of_range etc. from .at() on odd graphs
  }
  return 0;
}

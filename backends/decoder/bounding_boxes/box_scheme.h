// SPDX-License-Identifier: LGPL-2.1-only
// Box schemes of tensor_decoder mode=bounding_boxes, GStreamer-free. A scheme turns one frame
// of detector output tensors into boxes in model-input pixels (option5 W:H); the sub-plugin
// (bounding_boxes.cc) scales them to the output frame (option4), tracks, draws and attaches
// metadata. Each file schemes/<file>.cc defines
//     void nns_bbox_register_<file>(nns::bbox::SchemeTable &table);
// and the build generates the call list from the file names, so adding a scheme touches no
// central list.
#pragma once

#include <cstddef>
#include <functional>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include "core/error.h"
#include "core/tensor_info.h"

namespace nns::bbox {

struct Box {
  float x = 0, y = 0, w = 0, h = 0;  // top-left corner and size, model-input pixels
  float angle = 0;                   // radians, clockwise about the centre (oriented boxes)
  int class_id = -1;                 // index into the option2 labels; -1 = no class
  float score = 0;
  int track_id = 0;                                // 0 = not tracked
  std::vector<std::pair<float, float>> keypoints;  // (x, y), model-input pixels
};

// What the element knows when a scheme decodes.
struct Context {
  unsigned in_w = 300, in_h = 300;  // option5: model input size
  std::size_t num_labels = 0;       // lines of the option2 label file; 0 when none is given
};

// One input tensor of the current frame (data as negotiated; static format).
struct TensorView {
  const void *data = nullptr;
  std::size_t size = 0;  // bytes
  const TensorInfo *info = nullptr;
};

class Scheme {
 public:
  virtual ~Scheme() = default;
  // option3 for this scheme ("" keeps every default). Throws nns::Error(kSettings) naming
  // option3, the field at fault, what was expected and what was given.
  virtual void set_option3(const std::string &text) = 0;
  // Called at caps negotiation (and when option3/option5 change). Throws nns::Error
  // (kNegotiation) "scheme <name> expects ..., got ..." when the tensors do not fit.
  virtual void check_input(const TensorsInfo &in, const Context &ctx) = 0;
  // Boxes of one frame after thresholds and NMS, best score first. `out` is cleared first.
  // Must not allocate per frame beyond growing reused vectors. Throws nns::Error(kStream)
  // for data that cannot be decoded.
  virtual void decode(std::span<const TensorView> in, const Context &ctx,
                      std::vector<Box> &out) = 0;
};

using Factory = std::function<std::unique_ptr<Scheme>()>;

class SchemeTable {
 public:
  // `canonical` is the scheme's own name (aliases map to it). Later adds of a name replace it.
  void add(const std::string &name, Factory f, const std::string &canonical = {});
  // nullptr if unknown.
  std::unique_ptr<Scheme> make(const std::string &name) const;
  // Canonical name for a name or alias ("" if unknown).
  std::string canonical(const std::string &name) const;
  std::vector<std::string> names() const;  // sorted, aliases included

 private:
  struct Entry {
    Factory make;
    std::string canonical;
  };
  std::vector<std::pair<std::string, Entry>> entries_;
};

// Every built-in scheme, filled once (thread-safe).
const SchemeTable &schemes();

// Intersection over union of two axis-aligned boxes (angle ignored).
float iou(const Box &a, const Box &b);
// Greedy NMS: sorts by score (best first) and drops every box whose IoU with a kept box is
// above `threshold`; `per_class` limits suppression to boxes of the same class.
void nms(std::vector<Box> &boxes, float threshold, bool per_class);

}  // namespace nns::bbox

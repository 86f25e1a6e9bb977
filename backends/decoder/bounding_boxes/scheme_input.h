// SPDX-License-Identifier: LGPL-2.1-only
// The decoder input (C tensor descriptions of tensor_typedef.h) a scheme was checked against,
// kept between frames, and the per-frame decode over it. Shared by the bounding_boxes and
// tensor_region decoders (GStreamer-free).
#pragma once

#include <string>
#include <vector>

#include "box_scheme.h"
#include "tensor_typedef.h"

namespace nns::bbox {

class SchemeInput {
 public:
  // Forget the checked input (an option changed): the next bind() checks again.
  void reset() { checked_ = false; }

  // Checks `c` against `scheme` (unless it equals the input checked last). False when the input
  // is not fixed yet or has an unknown type (`why` empty) or the scheme rejects it (`why` is
  // the scheme's reason).
  bool bind(Scheme &scheme, const Context &ctx, const GstTensorsInfo &c, std::string &why);

  // Decodes one frame of the bound input into `boxes`. False with the scheme's reason in `why`.
  bool decode(Scheme &scheme, const Context &ctx, const GstTensorMemory *input,
              std::vector<Box> &boxes, std::string &why);

 private:
  GstTensorsInfo checked_c_{};
  bool checked_ = false;
  TensorsInfo in_info_;
  std::vector<TensorView> views_;
};

}  // namespace nns::bbox

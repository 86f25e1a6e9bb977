// SPDX-License-Identifier: LGPL-2.1-only
// Helpers shared by the SSD-family schemes (GStreamer-free): reading any numeric tensor as
// float into a reused buffer, option3 field parsing with errors that name the field, and
// dims checks that say what a scheme expected.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

#include "box_scheme.h"

namespace nns::bbox {

// The tensor as floats: the data itself when it is float32, otherwise converted into
// `scratch` (grown once, reused). Throws nns::Error(kStream) when the data is short.
const float *as_float(const TensorView &t, std::size_t count, std::vector<float> &scratch);

// Parses a float field of option3 ("" keeps `def`). Throws kSettings naming scheme/field.
float opt_float(const std::string &scheme, const std::string &field_name, const std::string &text,
                float def);
int opt_int(const std::string &scheme, const std::string &field_name, const std::string &text,
            int def);

// True when every dim from `from` on is 0 or 1.
bool ones_from(const Dims &d, std::size_t from);

// Throws kNegotiation "scheme <name> expects <what>, got <in>".
[[noreturn]] void reject_input(const std::string &scheme, const std::string &what,
                               const TensorsInfo &in);

// Pixel-inclusive IoU on integer boxes as NNStreamer's bounding_boxes computes it, and the
// greedy NMS over it (sort by score, drop later boxes overlapping more than `threshold`).
float iou_pixels(const Box &a, const Box &b);
void nms_pixels(std::vector<Box> &boxes, float threshold);

}  // namespace nns::bbox

// SPDX-License-Identifier: LGPL-2.1-only
// Helpers for filter back ends working on nns_tensors_desc (nns_filter_backend.h): converting
// between NNStreamer dims (innermost first) and framework shapes (outermost first), matching
// what the user said (input=/output=) against what the model says, and error text.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "core/tensor_info.h"
#include "nns_filter_backend.h"

namespace nns {

// Framework shape of `d` at rank `rank` (outermost first): dims 3:224:224:1 at rank 4 give
// [1,224,224,3]. Dims past the desc's rank count as 1. Throws nns::Error(kSettings) when the
// desc has a non-1 dim beyond `rank`.
std::vector<int64_t> shape_of(const nns_tensor_desc &d, std::size_t rank);
// NNStreamer dims from a framework shape; negative (free) entries become `free_as`.
void set_dims(nns_tensor_desc &d, const std::vector<int64_t> &shape, uint32_t free_as = 1);
// Bytes of one tensor (0 if the type is unknown or the rank is 0).
std::size_t desc_bytes(const nns_tensor_desc &d);
std::size_t desc_rank(const nns_tensor_desc &d);
// Names only (inputname= alone; NNS_FILTER_FLAG_TENSOR_NAMES back ends): every tensor has no
// type and no dims. False for an empty set.
bool desc_names_only(const nns_tensors_desc &d);
// Whether the dims equal with trailing 1s ignored.
bool desc_dims_equal(const nns_tensor_desc &a, const nns_tensor_desc &b);
// "float32 4:3:1" / "'name' float32 4:3:1" when named and with_name.
std::string desc_string(const nns_tensor_desc &d, bool with_name = true);
// Dims alone: "4:3:1".
std::string desc_dims_string(const nns_tensor_desc &d);
// "[1,224,224,3]" with free dims printed as '?'.
std::string shape_string(const std::vector<int64_t> &shape);
void set_name(nns_tensor_desc &d, const std::string &name);
TensorType desc_type(const nns_tensor_desc &d);

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
// Conversions between the filter back-end ABI's nns_tensors_desc and nns::TensorsInfo.
// GStreamer-free; used by tensor_filter, the built-in custom back ends and the single-shot API.
// GstTensorsInfo <-> nns_tensors_desc: core/c_tensor_info.h.
#pragma once

#include <memory>
#include <string>

#include "core/tensor_info.h"
#include "nns_filter_backend.h"

namespace nns {

// nns_tensors_desc is large (~80 KiB): allocate it on the heap, zeroed.
std::unique_ptr<nns_tensors_desc> new_desc();
// Throws Error(kSettings) when `info` has more than 256 tensors or a name too long.
void desc_from_info(const TensorsInfo &info, nns_tensors_desc &out);
std::unique_ptr<nns_tensors_desc> make_desc(const TensorsInfo &info);
// Throws Error(kLibrary) when the back end filled an invalid type or count.
TensorsInfo info_from_desc(const nns_tensors_desc &desc);

}  // namespace nns

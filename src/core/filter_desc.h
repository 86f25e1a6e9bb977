// SPDX-License-Identifier: LGPL-2.1-only
// Conversions between the filter back-end ABI's nns_tensors_desc, NNStreamer's C
// GstTensorsInfo (tensor_typedef.h) and nns::TensorsInfo. GStreamer-free; used by
// tensor_filter, the built-in custom back ends and the single-shot API.
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

// GstTensorsInfo <-> nns_tensors_desc. gst_info_from_desc allocates names and the `extra`
// array; release them with gst_info_clear. Both zero-initialize what they fill.
void gst_info_from_desc(const nns_tensors_desc &desc, GstTensorsInfo *out);
void desc_from_gst_info(const GstTensorsInfo *info, nns_tensors_desc &out);
void gst_info_clear(GstTensorsInfo *info);
// A zeroed GstTensorsInfo (num_tensors 0, every type _NNS_END).
void gst_info_init(GstTensorsInfo *info);
// Entry `i` of a GstTensorsInfo (info[] for the first 16, extra[] after).
GstTensorInfo *gst_info_at(GstTensorsInfo *info, unsigned i);
const GstTensorInfo *gst_info_at(const GstTensorsInfo *info, unsigned i);

}  // namespace nns

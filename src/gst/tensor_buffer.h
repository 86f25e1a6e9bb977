// SPDX-License-Identifier: LGPL-2.1-only
// One frame of tensors = one GstBuffer with one GstMemory per tensor. When a frame has more
// than 16 tensors, tensors 15.. are packed into the 16th memory behind NNStreamer's "extra"
// header, so buffers stay within GStreamer's 16-memory limit.
#pragma once

#include <gst/gst.h>

#include <string>

#include "core/meta_header.h"
#include "core/tensor_info.h"

namespace nns::gst {

// Number of tensors a buffer carries (reads the extra header when there are 16 memories).
std::size_t buffer_tensor_count(GstBuffer *buf);
// New reference to the memory of tensor `index` (a shared sub-memory for packed tensors), or
// nullptr when the buffer has no such tensor.
GstMemory *buffer_get_tensor(GstBuffer *buf, std::size_t index);
// Appends `mem` (taking ownership) as the next tensor; `info` describes it (used for packing).
void buffer_append_tensor(GstBuffer *buf, GstMemory *mem, const TensorInfo &info);

// Checks a static buffer against the negotiated tensors: tensor count and each tensor's byte
// size. Throws nns::Error(kStream) naming the tensor, the expected and the actual size.
void check_static_buffer(GstBuffer *buf, const TensorsInfo &info);

// Flexible/sparse helpers: a memory whose first 128 bytes are the meta header.
GstMemory *memory_with_header(const MetaHeader &h, GstMemory *payload);  // copies payload
MetaHeader memory_header(GstMemory *mem);  // throws nns::Error(kStream) if invalid

}  // namespace nns::gst

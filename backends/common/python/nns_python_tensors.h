// SPDX-License-Identifier: LGPL-2.1-only
// Tensor descriptions and data between NNStreamer and Python scripts, shared by the python3
// sub-plugins: tensor_type <-> numpy dtype, nns_tensors_desc <-> lists of
// nnstreamer_python.TensorShape, and zero-copy numpy views of tensor memory. All functions need
// the GIL and nns::py::ensure_runtime() done; failures throw nns::py::PyError.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "nns_filter_backend.h"
#include "nns_python.h"

namespace nns::py {

// numpy type number for a tensor_type (NNStreamer numbering), or -1 when there is none.
int numpy_type(uint32_t tensor_type) noexcept;
// Bytes per element of a tensor_type, 0 for an unknown type.
size_t element_size(uint32_t tensor_type) noexcept;
// NNStreamer's name of a tensor_type ("uint8", "float32", ...), "unknown" otherwise.
const char *type_name_of(uint32_t tensor_type) noexcept;
// The tensor_type of a numpy dtype-like object (np.uint8, "float32", np.dtype(...)). Throws
// PyError naming `what` for non-dtypes and for dtypes NNStreamer has no type for.
uint32_t tensor_type_from_dtype(PyObject *dtype_like, const std::string &what);

// Rank (leading non-zero dims), byte size and "3:224:224:1" text of one tensor.
uint32_t rank_of(const nns_tensor_desc &t) noexcept;
size_t tensor_bytes(const nns_tensor_desc &t) noexcept;
std::string dims_text(const nns_tensor_desc &t);
// "3:224:224:1 uint8, 10 float32" for messages.
std::string desc_text(const nns_tensors_desc &d);

// A Python list with one nnstreamer_python.TensorShape per tensor of `desc`. Dims are innermost
// first, padded with 1 to rank 4 (the rank-4 view that NNStreamer scripts index, e.g. dims[3]).
Ref shapes_from_desc(const nns_tensors_desc &desc);

// Reads a list (or tuple) of TensorShape-like objects (anything with getDims() and getType())
// into `desc`. `what` names the source for messages, e.g. "getInputDim() of 'x.py'".
void desc_from_shapes(PyObject *shapes, const std::string &what, nns_tensors_desc &desc);

// A read-only numpy array of `type` over `data` (no copy; the memory must outlive every use the
// script makes of the array): 1-D with `bytes / element_size(type)` elements, or, with `shape`,
// shaped as the tensor's dims reversed (numpy order, outermost first).
Ref wrap_readonly(const void *data, size_t bytes, uint32_t type,
                  const nns_tensor_desc *shape = nullptr);

}  // namespace nns::py

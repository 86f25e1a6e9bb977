// SPDX-License-Identifier: LGPL-2.1-only
// Shared by the Python bindings (module nnstreamer._nnstreamer): ML API errors as
// nnstreamer.Error, tensor types <-> numpy dtypes, NNStreamer dimensions <-> numpy shapes.
#pragma once

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include <string>
#include <vector>

#include "ml-api-common.h"

namespace nns::py {

namespace pyb = pybind11;

// An ML API call failed: becomes nnstreamer.Error(message) with .code = the ml_error_e value.
struct MlError {
  int code;
  std::string message;
};

// str(o) as a C++ string.
inline std::string text(pyb::handle o) {
  return pyb::str(o).cast<std::string>();
}

// Throws MlError for rc != ML_ERROR_NONE: "<what>: <ml_error() text>".
void check(int rc, const char *what);
// Registers nnstreamer.Error and its translator on `m`.
void register_errors(pyb::module_ &m);

// One tensor of an info handle, as numpy sees it.
struct TensorSpec {
  std::string name;
  ml_tensor_type_e type = ML_TENSOR_TYPE_UNKNOWN;
  std::vector<pyb::ssize_t> shape;  // outermost first: NNStreamer's dimension reversed
  std::size_t bytes = 0;
  pyb::dtype dtype;
  int dtype_num = -1;
};

pyb::dtype dtype_of(ml_tensor_type_e t);
// The tensor type of a numpy dtype; throws TypeError when there is none.
ml_tensor_type_e type_of(const pyb::dtype &d);
std::vector<TensorSpec> specs_of(ml_tensors_info_h info);
// A new extended info handle (the caller destroys it) with these tensors.
ml_tensors_info_h info_from_specs(const std::vector<TensorSpec> &specs);
// A TensorSpec from the Python side: nnstreamer.TensorInfo, or (dtype, shape[, name]).
TensorSpec spec_from_py(const pyb::handle &o);
// nnstreamer.TensorInfo objects for `specs`.
pyb::list specs_to_py(const std::vector<TensorSpec> &specs);

// Numpy arrays over the tensors of `data` without a copy; the arrays keep `data` alive (one
// capsule owns it and destroys it when the last array goes). Shapes from `specs`.
pyb::list arrays_over(ml_tensors_data_h data, const std::vector<TensorSpec> &specs);

void bind_single(pyb::module_ &m);
void bind_pipeline(pyb::module_ &m);

}  // namespace nns::py

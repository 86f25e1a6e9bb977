// SPDX-License-Identifier: LGPL-2.1-only
// Includes numpy's C API with one shared API table per shared object. nns_python.cc defines the
// table (NNS_PY_NUMPY_DEFINE) and fills it in ensure_runtime(); every other file only includes
// this header, after nns::py::ensure_runtime() has run.
#pragma once

#include "nns_python.h"

#define PY_ARRAY_UNIQUE_SYMBOL nns_py_numpy_api
#ifndef NNS_PY_NUMPY_DEFINE
#define NO_IMPORT_ARRAY
#endif
#define NPY_NO_DEPRECATED_API NPY_1_7_API_VERSION
#include <numpy/arrayobject.h>

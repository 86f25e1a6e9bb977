// SPDX-License-Identifier: LGPL-2.1-only
// Tensor descriptions and data between NNStreamer and Python; see nns_python_tensors.h.
#include "nns_python_tensors.h"

#include <cmath>
#include <cstring>
#include <memory>

#include "nns_numpy.h"

namespace nns::py {
namespace {

struct TypeRow {
  uint32_t nns;
  int npy;
  size_t size;
  const char *name;
};

// Indexed by tensor_type.
constexpr TypeRow kTypes[] = {
    {_NNS_INT32, NPY_INT32, 4, "int32"},       {_NNS_UINT32, NPY_UINT32, 4, "uint32"},
    {_NNS_INT16, NPY_INT16, 2, "int16"},       {_NNS_UINT16, NPY_UINT16, 2, "uint16"},
    {_NNS_INT8, NPY_INT8, 1, "int8"},          {_NNS_UINT8, NPY_UINT8, 1, "uint8"},
    {_NNS_FLOAT64, NPY_FLOAT64, 8, "float64"}, {_NNS_FLOAT32, NPY_FLOAT32, 4, "float32"},
    {_NNS_INT64, NPY_INT64, 8, "int64"},       {_NNS_UINT64, NPY_UINT64, 8, "uint64"},
    {_NNS_FLOAT16, NPY_FLOAT16, 2, "float16"},
};
static_assert(sizeof(kTypes) / sizeof(kTypes[0]) == _NNS_END);

// The dims list for one tensor: rank dims, padded with 1 to 4.
Ref dims_list(const nns_tensor_desc &t) {
  uint32_t rank = rank_of(t);
  Py_ssize_t n = rank < 4 ? 4 : rank;
  Ref list(PyList_New(n));
  if (!list) throw_pending("cannot build a dimension list");
  for (Py_ssize_t i = 0; i < n; i++) {
    PyObject *v = PyLong_FromUnsignedLong(i < rank ? t.dims[i] : 1u);
    if (!v) throw_pending("cannot build a dimension list");
    PyList_SET_ITEM(list.get(), i, v);
  }
  return list;
}

// One dimension value: a Python int (or numpy integer), or a float with an integral value.
uint32_t dim_value(PyObject *item, const std::string &where) {
  if (PyFloat_Check(item)) {
    double d = PyFloat_AsDouble(item);
    if (d >= 0 && d <= 4294967295.0 && std::floor(d) == d) return static_cast<uint32_t>(d);
    throw PyError(where + " is " + std::to_string(d) + "; dimensions are integers from 0 to " +
                  "4294967295");
  }
  Ref idx(PyNumber_Index(item));
  if (!idx) {
    PyErr_Clear();
    throw PyError(where + " is a " + type_name(item) + ", not an integer");
  }
  int overflow = 0;
  long long v = PyLong_AsLongLongAndOverflow(idx.get(), &overflow);
  if (overflow || v < 0 || v > 4294967295LL)
    throw PyError(where + " is " + str(idx.get()) +
                  "; dimensions are integers from 0 to 4294967295");
  return static_cast<uint32_t>(v);
}

}  // namespace

int numpy_type(uint32_t t) noexcept {
  return t < _NNS_END ? kTypes[t].npy : -1;
}
size_t element_size(uint32_t t) noexcept {
  return t < _NNS_END ? kTypes[t].size : 0;
}
const char *type_name_of(uint32_t t) noexcept {
  return t < _NNS_END ? kTypes[t].name : "unknown";
}

uint32_t tensor_type_from_dtype(PyObject *dtype_like, const std::string &what) {
  PyArray_Descr *descr = nullptr;
  if (!PyArray_DescrConverter2(dtype_like, &descr) || !descr) {
    PyErr_Clear();
    Py_XDECREF(descr);
    throw PyError(what + " is a " + type_name(dtype_like) + ", not a numpy element type");
  }
  Ref hold(reinterpret_cast<PyObject *>(descr));
  if (PyDataType_ISNOTSWAPPED(descr)) {
    for (const TypeRow &r : kTypes)
      if (PyArray_EquivTypenums(descr->type_num, r.npy)) return r.nns;
  }
  Ref s(PyObject_Str(hold.get()));
  const char *n = s ? PyUnicode_AsUTF8(s.get()) : nullptr;
  std::string name = n ? n : "?";
  PyErr_Clear();
  throw PyError(what + " is numpy type '" + name +
                "', which NNStreamer has no tensor type for (int8..int64, uint8..uint64, "
                "float16, float32, float64 in native byte order)");
}

uint32_t rank_of(const nns_tensor_desc &t) noexcept {
  uint32_t r = 0;
  while (r < NNS_TENSOR_RANK_LIMIT && t.dims[r] != 0) r++;
  return r;
}

size_t tensor_bytes(const nns_tensor_desc &t) noexcept {
  uint32_t r = rank_of(t);
  if (r == 0) return 0;
  size_t n = element_size(t.type);
  for (uint32_t i = 0; i < r; i++) n *= t.dims[i];
  return n;
}

std::string dims_text(const nns_tensor_desc &t) {
  std::string s;
  for (uint32_t i = 0, r = rank_of(t); i < r; i++) {
    if (i) s += ':';
    s += std::to_string(t.dims[i]);
  }
  return s.empty() ? "(none)" : s;
}

std::string desc_text(const nns_tensors_desc &d) {
  std::string s;
  for (uint32_t i = 0; i < d.num_tensors && i < NNS_TENSOR_SIZE_LIMIT; i++) {
    if (i) s += ", ";
    s += dims_text(d.tensors[i]) + " " + type_name_of(d.tensors[i].type);
  }
  return s.empty() ? "(no tensors)" : s;
}

Ref shapes_from_desc(const nns_tensors_desc &desc) {
  Ref mod(PyImport_ImportModule("nnstreamer_python"));
  if (!mod) throw_pending("cannot import the nnstreamer_python module");
  Ref cls(PyObject_GetAttrString(mod.get(), "TensorShape"));
  if (!cls) throw_pending("nnstreamer_python has no TensorShape");
  Ref list(PyList_New(desc.num_tensors));
  if (!list) throw_pending("cannot build the TensorShape list");
  for (uint32_t i = 0; i < desc.num_tensors; i++) {
    const nns_tensor_desc &t = desc.tensors[i];
    int npy = numpy_type(t.type);
    if (npy < 0) throw PyError("tensor " + std::to_string(i) + " has an unknown type");
    Ref dims = dims_list(t);
    Ref dtype(reinterpret_cast<PyObject *>(PyArray_DescrFromType(npy)));
    if (!dtype) throw_pending("cannot build a numpy dtype");
    PyObject *shape = PyObject_CallFunctionObjArgs(cls.get(), dims.get(), dtype.get(), nullptr);
    if (!shape) throw_pending("nnstreamer_python.TensorShape() failed");
    PyList_SET_ITEM(list.get(), i, shape);
  }
  return list;
}

void desc_from_shapes(PyObject *shapes, const std::string &what, nns_tensors_desc &desc) {
  if (!shapes || (!PyList_Check(shapes) && !PyTuple_Check(shapes)))
    throw PyError(what + " returned " + type_name(shapes) +
                  "; expected a list of nnstreamer_python.TensorShape");
  Py_ssize_t n = PySequence_Fast_GET_SIZE(shapes);
  if (n < 1 || n > NNS_TENSOR_SIZE_LIMIT)
    throw PyError(what + " returned " + std::to_string(n) + " tensors; expected 1 to " +
                  std::to_string(NNS_TENSOR_SIZE_LIMIT));
  auto heap = std::make_unique<nns_tensors_desc>();  // 83 KB: not on a streaming thread's stack
  nns_tensors_desc &out = *heap;
  out.num_tensors = static_cast<uint32_t>(n);
  out.format = _NNS_TENSOR_FORMAT_STATIC;
  for (Py_ssize_t i = 0; i < n; i++) {
    PyObject *shape = PySequence_Fast_GET_ITEM(shapes, i);  // borrowed
    std::string where = what + ", tensor " + std::to_string(i);
    Ref dims(PyObject_CallMethod(shape, "getDims", nullptr));
    if (!dims) {
      if (PyErr_ExceptionMatches(PyExc_AttributeError)) {
        PyErr_Clear();
        throw PyError(where + " is a " + type_name(shape) +
                      ", not a nnstreamer_python.TensorShape");
      }
      throw_pending(where + ": getDims() failed");
    }
    Ref type(PyObject_CallMethod(shape, "getType", nullptr));
    if (!type) throw_pending(where + ": getType() failed");
    nns_tensor_desc &t = out.tensors[i];
    t.type = tensor_type_from_dtype(type.get(), where + " type");
    Ref seq(PySequence_Fast(dims.get(), "dims"));
    if (!seq) {
      PyErr_Clear();
      throw PyError(where + " dims are a " + type_name(dims.get()) + ", not a list of integers");
    }
    Py_ssize_t rank = PySequence_Fast_GET_SIZE(seq.get());
    if (rank > NNS_TENSOR_RANK_LIMIT)
      throw PyError(where + " has rank " + std::to_string(rank) + "; the limit is " +
                    std::to_string(NNS_TENSOR_RANK_LIMIT));
    bool ended = false;  // a 0 ends the rank (NNStreamer pads unused dims with 0)
    for (Py_ssize_t j = 0; j < rank; j++) {
      std::string dw = where + " dimension " + std::to_string(j);
      uint32_t v = dim_value(PySequence_Fast_GET_ITEM(seq.get(), j), dw);
      if (v == 0) {
        ended = true;
      } else if (ended) {
        throw PyError(dw + " is " + std::to_string(v) + " after a 0 dimension");
      } else {
        t.dims[j] = v;
      }
    }
    if (t.dims[0] == 0) throw PyError(where + " has no dimensions (empty or 0)");
  }
  desc = out;
}

Ref wrap_readonly(const void *data, size_t bytes, uint32_t type, const nns_tensor_desc *shape) {
  int npy = numpy_type(type);
  size_t es = element_size(type);
  if (npy < 0 || es == 0) throw PyError("unknown tensor type " + std::to_string(type));
  npy_intp dims[NNS_TENSOR_RANK_LIMIT];
  int nd = 1;
  dims[0] = static_cast<npy_intp>(bytes / es);
  if (shape && rank_of(*shape) > 0) {
    nd = static_cast<int>(rank_of(*shape));
    for (int j = 0; j < nd; j++) dims[j] = shape->dims[nd - 1 - j];
  }
  PyObject *arr = PyArray_New(&PyArray_Type, nd, dims, npy, nullptr, const_cast<void *>(data), 0,
                              NPY_ARRAY_CARRAY_RO, nullptr);
  if (!arr) throw_pending("cannot wrap a tensor as a numpy array");
  return Ref(arr);
}

}  // namespace nns::py

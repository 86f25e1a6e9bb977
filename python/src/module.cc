// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer._nnstreamer: the extension module under the `nnstreamer` package. Errors,
// TensorInfo, dtype/shape conversion, zero-copy output arrays; the classes are bound in
// single.cc and pipeline.cc.
#include <cstring>

#include "nns_py.h"
#include "nnstreamer-tizen-internal.h"

namespace nns::py {

namespace {

PyObject *g_error = nullptr;        // nnstreamer.Error (a RuntimeError)
PyObject *g_tensor_info = nullptr;  // nnstreamer.TensorInfo (a namedtuple)

struct TypeRow {
  ml_tensor_type_e type;
  const char *numpy;
};
constexpr TypeRow kTypes[] = {
    {ML_TENSOR_TYPE_INT32, "int32"},     {ML_TENSOR_TYPE_UINT32, "uint32"},
    {ML_TENSOR_TYPE_INT16, "int16"},     {ML_TENSOR_TYPE_UINT16, "uint16"},
    {ML_TENSOR_TYPE_INT8, "int8"},       {ML_TENSOR_TYPE_UINT8, "uint8"},
    {ML_TENSOR_TYPE_FLOAT64, "float64"}, {ML_TENSOR_TYPE_FLOAT32, "float32"},
    {ML_TENSOR_TYPE_INT64, "int64"},     {ML_TENSOR_TYPE_UINT64, "uint64"},
    {ML_TENSOR_TYPE_FLOAT16, "float16"},
};

}  // namespace

void check(int rc, const char *what) {
  if (rc == ML_ERROR_NONE) return;
  const char *detail = ml_error();
  const char *text = ml_strerror(rc);
  // The library's messages already start with the function's name.
  std::string msg;
  if (detail && *detail)
    msg = detail;
  else
    msg = std::string(what) + ": " + (text ? text : "error " + std::to_string(rc));
  throw MlError{rc, msg};
}

void register_errors(pyb::module_ &m) {
  g_error = PyErr_NewExceptionWithDoc(
      "nnstreamer.Error",
      "An ML API call failed. str(e) is the library's message (ml_error()); e.code is the "
      "ml_error_e value (nnstreamer.ERROR_*).",
      PyExc_RuntimeError, nullptr);
  m.add_object("Error", pyb::handle(g_error));
  pyb::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const MlError &e) {
      pyb::object exc = pyb::reinterpret_borrow<pyb::object>(g_error)(e.message);
      exc.attr("code") = e.code;
      PyErr_SetObject(g_error, exc.ptr());
    }
  });
}

pyb::dtype dtype_of(ml_tensor_type_e t) {
  for (const auto &r : kTypes)
    if (r.type == t) return pyb::dtype(r.numpy);
  throw MlError{ML_ERROR_INVALID_PARAMETER, "tensor type " + std::to_string(t) + " has no dtype"};
}

ml_tensor_type_e type_of(const pyb::dtype &d) {
  for (const auto &r : kTypes)
    if (d.is(pyb::dtype(r.numpy)) || d.equal(pyb::dtype(r.numpy))) return r.type;
  throw pyb::type_error("dtype " + text(d) +
                        " is not a tensor type (int8..int64, uint8..uint64, float16/32/64)");
}

std::vector<TensorSpec> specs_of(ml_tensors_info_h info) {
  unsigned n = 0;
  check(ml_tensors_info_get_count(info, &n), "ml_tensors_info_get_count");
  std::vector<TensorSpec> out(n);
  for (unsigned i = 0; i < n; ++i) {
    TensorSpec &s = out[i];
    check(ml_tensors_info_get_tensor_type(info, i, &s.type), "ml_tensors_info_get_tensor_type");
    ml_tensor_dimension d;
    check(ml_tensors_info_get_tensor_dimension(info, i, d), "ml_tensors_info_get_tensor_dimension");
    std::size_t rank = 0;
    while (rank < ML_TENSOR_RANK_LIMIT && d[rank]) ++rank;
    for (std::size_t k = rank; k-- > 0;) s.shape.push_back(d[k]);
    check(ml_tensors_info_get_tensor_size(info, static_cast<int>(i), &s.bytes),
          "ml_tensors_info_get_tensor_size");
    char *name = nullptr;
    check(ml_tensors_info_get_tensor_name(info, i, &name), "ml_tensors_info_get_tensor_name");
    if (name) s.name = name;
    std::free(name);
    if (s.type != ML_TENSOR_TYPE_UNKNOWN) {
      s.dtype = dtype_of(s.type);
      s.dtype_num = s.dtype.num();
    }
  }
  return out;
}

ml_tensors_info_h info_from_specs(const std::vector<TensorSpec> &specs) {
  ml_tensors_info_h h = nullptr;
  check(ml_tensors_info_create_extended(&h), "ml_tensors_info_create_extended");
  try {
    if (specs.empty() || specs.size() > ML_TENSOR_SIZE_LIMIT)
      throw MlError{ML_ERROR_INVALID_PARAMETER, "tensors info: " + std::to_string(specs.size()) +
                                                    " tensors (1.." +
                                                    std::to_string(ML_TENSOR_SIZE_LIMIT) + ")"};
    check(ml_tensors_info_set_count(h, static_cast<unsigned>(specs.size())),
          "ml_tensors_info_set_count");
    for (unsigned i = 0; i < specs.size(); ++i) {
      const TensorSpec &s = specs[i];
      if (s.shape.empty() || s.shape.size() > ML_TENSOR_RANK_LIMIT)
        throw MlError{ML_ERROR_INVALID_PARAMETER, "tensor " + std::to_string(i) + ": rank " +
                                                      std::to_string(s.shape.size()) + " (1.." +
                                                      std::to_string(ML_TENSOR_RANK_LIMIT) + ")"};
      ml_tensor_dimension d = {0};
      for (std::size_t k = 0; k < s.shape.size(); ++k) {
        pyb::ssize_t v = s.shape[s.shape.size() - 1 - k];
        if (v <= 0 || v > 0xffffffffLL)
          throw MlError{ML_ERROR_INVALID_PARAMETER, "tensor " + std::to_string(i) +
                                                        ": shape entry " + std::to_string(v) +
                                                        " (each must be >= 1)"};
        d[k] = static_cast<unsigned>(v);
      }
      check(ml_tensors_info_set_tensor_type(h, i, s.type), "ml_tensors_info_set_tensor_type");
      check(ml_tensors_info_set_tensor_dimension(h, i, d), "ml_tensors_info_set_tensor_dimension");
      if (!s.name.empty())
        check(ml_tensors_info_set_tensor_name(h, i, s.name.c_str()),
              "ml_tensors_info_set_tensor_name");
    }
  } catch (...) {
    ml_tensors_info_destroy(h);
    throw;
  }
  return h;
}

TensorSpec spec_from_py(const pyb::handle &o) {
  TensorSpec s;
  pyb::tuple t = pyb::reinterpret_borrow<pyb::object>(o).cast<pyb::tuple>();
  if (t.size() < 2 || t.size() > 3)
    throw pyb::type_error("a tensor is TensorInfo(dtype, shape, name=None) or (dtype, shape)");
  pyb::dtype dt = pyb::dtype::from_args(pyb::reinterpret_borrow<pyb::object>(t[0]));
  s.type = type_of(dt);
  s.dtype = dt;
  s.dtype_num = dt.num();
  for (auto v : pyb::reinterpret_borrow<pyb::iterable>(t[1]))
    s.shape.push_back(v.cast<pyb::ssize_t>());
  if (t.size() == 3 && !t[2].is_none()) s.name = t[2].cast<std::string>();
  std::size_t n = 1;
  for (auto v : s.shape) n *= static_cast<std::size_t>(v > 0 ? v : 0);
  s.bytes = n * static_cast<std::size_t>(dt.itemsize());
  return s;
}

pyb::list specs_to_py(const std::vector<TensorSpec> &specs) {
  pyb::list out;
  pyb::object cls = pyb::reinterpret_borrow<pyb::object>(g_tensor_info);
  for (const auto &s : specs) {
    pyb::tuple shape(s.shape.size());
    for (std::size_t k = 0; k < s.shape.size(); ++k) shape[k] = pyb::int_(s.shape[k]);
    out.append(cls(s.dtype, shape,
                   s.name.empty() ? pyb::object(pyb::none()) : pyb::object(pyb::str(s.name))));
  }
  return out;
}

pyb::list arrays_over(ml_tensors_data_h data, const std::vector<TensorSpec> &specs) {
  pyb::capsule owner(data, [](void *p) { ml_tensors_data_destroy(p); });
  pyb::list out(specs.size());
  for (std::size_t i = 0; i < specs.size(); ++i) {
    void *raw = nullptr;
    std::size_t size = 0;
    check(ml_tensors_data_get_tensor_data(data, static_cast<unsigned>(i), &raw, &size),
          "ml_tensors_data_get_tensor_data");
    if (size != specs[i].bytes)
      throw MlError{ML_ERROR_STREAMS_PIPE, "output tensor " + std::to_string(i) + " has " +
                                               std::to_string(size) + " bytes, its info says " +
                                               std::to_string(specs[i].bytes)};
    out[i] = pyb::array(specs[i].dtype, specs[i].shape, raw, owner);
  }
  return out;
}

}  // namespace nns::py

PYBIND11_MODULE(_nnstreamer, m) {
  namespace py = nns::py;
  pybind11::module_::import("numpy");
  m.doc() = "nnstreamer-cpp's ML API (libnnstreamer-single) for Python";
  py::register_errors(m);
  pybind11::object nt = pybind11::module_::import("collections").attr("namedtuple");
  pybind11::dict kw;
  kw["defaults"] = pybind11::make_tuple(pybind11::none());
  kw["module"] = "nnstreamer";
  pybind11::object ti = nt("TensorInfo", pybind11::make_tuple("dtype", "shape", "name"), **kw);
  ti.attr("__doc__") =
      "One tensor: numpy dtype, shape (outermost first: NNStreamer's dimension 3:224:224:1 is "
      "(1, 224, 224, 3)) and name (None when it has none).";
  nns::py::g_tensor_info = ti.inc_ref().ptr();
  m.add_object("TensorInfo", ti);
  for (auto [name, v] : std::initializer_list<std::pair<const char *, int>>{
           {"ERROR_NONE", ML_ERROR_NONE},
           {"ERROR_INVALID_PARAMETER", ML_ERROR_INVALID_PARAMETER},
           {"ERROR_STREAMS_PIPE", ML_ERROR_STREAMS_PIPE},
           {"ERROR_TRY_AGAIN", ML_ERROR_TRY_AGAIN},
           {"ERROR_UNKNOWN", static_cast<int>(ML_ERROR_UNKNOWN)},
           {"ERROR_TIMED_OUT", static_cast<int>(ML_ERROR_TIMED_OUT)},
           {"ERROR_NOT_SUPPORTED", static_cast<int>(ML_ERROR_NOT_SUPPORTED)},
           {"ERROR_PERMISSION_DENIED", ML_ERROR_PERMISSION_DENIED},
           {"ERROR_OUT_OF_MEMORY", ML_ERROR_OUT_OF_MEMORY},
           {"ERROR_IO_ERROR", ML_ERROR_IO_ERROR}})
    m.attr(name) = v;
  char *v = ml_api_get_version_string();
  m.attr("ml_api_version") = std::string(v ? v : "");
  std::free(v);
  py::bind_single(m);
  py::bind_pipeline(m);
}

// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer.Single: ml_single_* for numpy arrays. Inputs go to the back end as they are (the
// array's own memory wrapped in a data handle, no copy, when the array is C-contiguous and of
// the tensor's dtype); outputs are numpy arrays over the ML API's output buffers (no copy).
#include <pybind11/stl.h>

#include <atomic>
#include <chrono>
#include <climits>
#include <memory>
#include <mutex>
#include <optional>
#include <shared_mutex>

#include "api/ml_api_internal.h"
#include "nns_py.h"
#include "nnstreamer-single.h"

namespace nns::py {

namespace {

const char *nnfw_name_error =
    "framework: a tensor_filter framework name (\"onnxruntime\", \"custom-easy\", ...) or None";

struct InfoDeleter {
  void operator()(void *h) const { ml_tensors_info_destroy(h); }
};
using InfoPtr = std::unique_ptr<void, InfoDeleter>;
struct DataDeleter {
  void operator()(void *h) const { ml_tensors_data_destroy(h); }
};
using DataPtr = std::unique_ptr<void, DataDeleter>;

std::string to_property_value(const pyb::handle &v) {
  if (pyb::isinstance<pyb::bool_>(v)) return v.cast<bool>() ? "true" : "false";
  if (pyb::isinstance<pyb::str>(v)) return v.cast<std::string>();
  return pyb::str(v).cast<std::string>();
}

class Single {
 public:
  Single(const pyb::object &model, const std::optional<std::string> &framework,
         const pyb::kwargs &options) {
    std::string models;
    if (pyb::isinstance<pyb::str>(model)) {
      models = model.cast<std::string>();
    } else {
      for (auto m : pyb::reinterpret_borrow<pyb::iterable>(model)) {
        if (!models.empty()) models += ",";
        models += pyb::str(m).cast<std::string>();
      }
    }
    std::string fw = framework.value_or("auto");
    if (fw.empty()) throw pyb::value_error(nnfw_name_error);
    std::string custom, hw;
    InfoPtr in, out;
    std::optional<unsigned> timeout;
    std::vector<std::pair<std::string, std::string>> props;
    for (auto [k, v] : options) {
      std::string key = k.cast<std::string>();
      if (key == "custom")
        custom = v.cast<std::string>();
      else if (key == "input_info")
        in.reset(info_from_py(v));
      else if (key == "output_info")
        out.reset(info_from_py(v));
      else if (key == "timeout")
        timeout = v.cast<unsigned>();
      else {
        // Any tensor_filter property ml_single_set_property takes (is_updatable=True ->
        // "is-updatable" "true", accelerator="true:cpu", inputlayout="NHWC", ...).
        for (char &c : key)
          if (c == '_') c = '-';
        props.emplace_back(key, to_property_value(v));
      }
    }
    // Properties are set after the open (layouts/accelerator reopen the model with them).
    ml_option_h opt = nullptr;
    check(ml_option_create(&opt), "ml_option_create");
    std::unique_ptr<void, int (*)(ml_option_h)> opt_guard(opt, ml_option_destroy);
    check(ml_option_set(opt, "models", models.data(), nullptr), "ml_option_set");
    check(ml_option_set(opt, "framework_name", fw.data(), nullptr), "ml_option_set");
    if (!custom.empty())
      check(ml_option_set(opt, "custom", custom.data(), nullptr), "ml_option_set");
    if (in) check(ml_option_set(opt, "input_info", in.get(), nullptr), "ml_option_set");
    if (out) check(ml_option_set(opt, "output_info", out.get(), nullptr), "ml_option_set");
    ml_single_h h = nullptr;
    int rc;
    {
      pyb::gil_scoped_release nogil;
      rc = ml_single_open_with_option(&h, opt);
    }
    check(rc, "ml_single_open");
    h_ = h;
    try {
      if (timeout) set_timeout(*timeout);
      for (auto &[k, v] : props) set_property(k, v);
      refresh();
    } catch (...) {
      close();
      throw;
    }
  }

  ~Single() { close(); }

  // Waits for calls of other threads that run without the GIL, then closes the handle.
  void close() {
    if (!h_.load()) return;
    {
      pyb::gil_scoped_release nogil;
      std::unique_lock lk(use_);
      if (ml_single_h h = h_.exchange(nullptr)) ml_single_close(h);
    }
    in_info_.reset();
  }

  pyb::list invoke(const pyb::args &args) {
    handle();
    const std::size_t n = args.size();
    if (n != in_.size())
      throw MlError{ML_ERROR_INVALID_PARAMETER, "invoke: " + std::to_string(n) +
                                                    " array(s) given, the model takes " +
                                                    std::to_string(in_.size())};
    // Keep converted arrays alive until the call returns; pointers into them go to the model.
    pyb::object keep[16];
    std::vector<pyb::object> keep_more;
    void *ptrs_small[16];
    std::vector<void *> ptrs_big;
    void **ptrs = n <= 16 ? ptrs_small : (ptrs_big.resize(n), ptrs_big.data());
    bool reshaped = false;
    for (std::size_t i = 0; i < n; ++i) {
      pyb::array a = as_input(args[i], i);
      if (static_cast<std::size_t>(a.nbytes()) != in_[i].bytes) reshaped = true;
      ptrs[i] = const_cast<void *>(a.data());
      if (i < 16)
        keep[i] = std::move(a);
      else
        keep_more.push_back(std::move(a));
    }
    if (reshaped) return invoke_reshaped(args);
    ml_tensors_data_h in = nullptr;
    check(nns_ml_tensors_data_wrap(in_info_.get(), ptrs, static_cast<unsigned>(n), &in), "invoke");
    DataPtr in_guard(in);
    ml_tensors_data_h out = nullptr;
    check(without_gil([&](ml_single_h h) { return ml_single_invoke(h, in, &out); }),
          "ml_single_invoke");
    DataPtr out_guard(out);
    if (out_dynamic_) {  // the output is decided per call: its info comes with the data
      ml_tensors_info_h oi = nullptr;
      check(ml_tensors_data_get_info(out, &oi), "ml_tensors_data_get_info");
      InfoPtr g(oi);
      auto specs = specs_of(oi);
      return arrays_over(out_guard.release(), specs);
    }
    return arrays_over(out_guard.release(), out_);
  }

  pyb::list input_info() const { return specs_to_py(in_); }
  pyb::list output_info() const { return specs_to_py(out_); }

  void set_input_info(const pyb::object &info) {
    InfoPtr p(info_from_py(info));
    check(without_gil([&](ml_single_h h) { return ml_single_set_input_info(h, p.get()); }),
          "ml_single_set_input_info");
    refresh();
  }

  void set_timeout(unsigned ms) {
    check(with_gil([&](ml_single_h h) { return ml_single_set_timeout(h, ms); }),
          "ml_single_set_timeout");
  }

  void set_property(const std::string &name, const std::string &value) {
    check(without_gil([&](ml_single_h h) {
            return ml_single_set_property(h, name.c_str(), value.c_str());
          }),
          "ml_single_set_property");
    refresh();
  }

  std::string get_property(const std::string &name) {
    char *v = nullptr;
    check(with_gil([&](ml_single_h h) { return ml_single_get_property(h, name.c_str(), &v); }),
          "ml_single_get_property");
    std::string s = v ? v : "";
    std::free(v);
    return s;
  }

  // Benchmark helper: the same invoke from C (data created once, output destroyed each time),
  // `count` times; returns seconds per call.
  double c_invoke_seconds(const pyb::list &args, unsigned count) {
    handle();
    ml_tensors_data_h in = nullptr;
    check(ml_tensors_data_create(in_info_.get(), &in), "ml_tensors_data_create");
    DataPtr g(in);
    for (std::size_t i = 0; i < args.size() && i < in_.size(); ++i) {
      pyb::array a = as_input(args[i], i);
      check(ml_tensors_data_set_tensor_data(in, static_cast<unsigned>(i), a.data(),
                                            static_cast<std::size_t>(a.nbytes())),
            "ml_tensors_data_set_tensor_data");
    }
    double seconds = 0;
    check(without_gil([&](ml_single_h h) {
            auto t0 = std::chrono::steady_clock::now();
            for (unsigned k = 0; k < count; ++k) {
              ml_tensors_data_h out = nullptr;
              if (int rc = ml_single_invoke(h, in, &out)) return rc;
              ml_tensors_data_destroy(out);
            }
            seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
            return static_cast<int>(ML_ERROR_NONE);
          }),
          "ml_single_invoke");
    return seconds / (count ? count : 1);
  }

 private:
  static constexpr int kClosed = INT_MIN;  // not an ml_error_e

  void handle() const {
    if (!h_.load()) throw MlError{ML_ERROR_INVALID_PARAMETER, "the Single is closed"};
  }

  // Runs fn(handle) with the handle kept open (close() on another thread waits): without the
  // GIL for calls that may take long, with it for quick ones. "Closed" becomes an MlError.
  template <typename F>
  int without_gil(F &&fn) {
    int rc;
    {
      pyb::gil_scoped_release nogil;
      std::shared_lock lk(use_);
      ml_single_h h = h_.load();
      rc = h ? fn(h) : kClosed;
    }
    if (rc == kClosed) handle();
    return rc;
  }
  template <typename F>
  int with_gil(F &&fn) {
    std::shared_lock lk(use_);
    ml_single_h h = h_.load();
    if (!h) handle();
    return fn(h);
  }

  // `o` as an array of input i's dtype, C-contiguous: the object itself when it is one,
  // otherwise a converted copy (lists, other layouts). A numpy array of another dtype is an
  // error, not a silent conversion.
  pyb::array as_input(const pyb::handle &o, std::size_t i) const {
    const TensorSpec &s = in_[i];
    if (pyb::isinstance<pyb::array>(o)) {
      auto a = pyb::reinterpret_borrow<pyb::array>(o);
      if (a.dtype().num() != s.dtype_num)
        throw pyb::type_error("invoke: input " + std::to_string(i) + " is " + text(a.dtype()) +
                              ", the model takes " + text(s.dtype));
      if (a.flags() & pyb::array::c_style) return a;
      return pyb::array::ensure(a, pyb::array::c_style | pyb::array::forcecast);
    }
    return pyb::array(pyb::module_::import("numpy").attr("ascontiguousarray")(o, s.dtype));
  }

  // Arrays whose sizes differ from the input info: ml_single_invoke_dynamic with their
  // shapes (the handle's input info then follows, as NNStreamer's invoke_dynamic).
  pyb::list invoke_reshaped(const pyb::args &args) {
    std::vector<TensorSpec> specs(args.size());
    std::vector<pyb::array> arrays;
    for (std::size_t i = 0; i < args.size(); ++i) {
      pyb::array a = as_input(args[i], i);
      TensorSpec &s = specs[i];
      s.type = in_[i].type;
      s.dtype = in_[i].dtype;
      s.dtype_num = in_[i].dtype_num;
      for (pyb::ssize_t k = 0; k < a.ndim(); ++k) s.shape.push_back(a.shape(k));
      if (s.shape.empty()) s.shape.push_back(1);
      s.bytes = static_cast<std::size_t>(a.nbytes());
      arrays.push_back(std::move(a));
    }
    InfoPtr info(info_from_specs(specs));
    std::vector<void *> ptrs;
    for (auto &a : arrays) ptrs.push_back(const_cast<void *>(a.data()));
    ml_tensors_data_h in = nullptr;
    check(
        nns_ml_tensors_data_wrap(info.get(), ptrs.data(), static_cast<unsigned>(ptrs.size()), &in),
        "invoke");
    DataPtr in_guard(in);
    ml_tensors_data_h out = nullptr;
    ml_tensors_info_h out_info = nullptr;
    check(without_gil([&](ml_single_h h) {
            return ml_single_invoke_dynamic(h, in, info.get(), &out, &out_info);
          }),
          "ml_single_invoke_dynamic");
    DataPtr out_guard(out);
    InfoPtr oi(out_info);
    auto out_specs = specs_of(out_info);
    refresh();
    return arrays_over(out_guard.release(), out_specs);
  }

  static ml_tensors_info_h info_from_py(const pyb::handle &o) {
    std::vector<TensorSpec> specs;
    for (auto t : pyb::reinterpret_borrow<pyb::iterable>(o)) specs.push_back(spec_from_py(t));
    return info_from_specs(specs);
  }

  // The handle's input/output info, cached for invoke.
  void refresh() {
    ml_tensors_info_h in = nullptr, out = nullptr;
    check(with_gil([&](ml_single_h h) { return ml_single_get_input_info(h, &in); }),
          "ml_single_get_input_info");
    in_info_.reset(in);
    in_ = specs_of(in);
    check(with_gil([&](ml_single_h h) { return ml_single_get_output_info(h, &out); }),
          "ml_single_get_output_info");
    InfoPtr g(out);
    out_ = specs_of(out);
    out_dynamic_ = out_.empty();
  }

  std::atomic<ml_single_h> h_{nullptr};
  std::shared_mutex use_;  // shared: a call on the handle; exclusive: close()
  InfoPtr in_info_;
  std::vector<TensorSpec> in_, out_;
  bool out_dynamic_ = false;
};

}  // namespace

void bind_single(pyb::module_ &m) {
  pyb::class_<Single>(m, "Single",
                      R"doc(A model opened with the single-shot ML API (ml_single_open).

Single(model, framework=None, **options)
  model: a path (or a list of paths; a registered name for custom-easy)
  framework: a tensor_filter framework name ("onnxruntime", "pytorch", "armnn",
    "tensorflow-lite", "python3", "custom", "custom-easy", ...); None: from the extension
  options: custom="..." (the back end's custom string), input_info=/output_info=
    [TensorInfo or (dtype, shape)], timeout=<ms>, and any property ml_single_set_property
    takes, with '_' for '-' (is_updatable=True, accelerator="true:cpu", inputlayout="NHWC").)doc")
      .def(
          pyb::init<const pyb::object &, const std::optional<std::string> &, const pyb::kwargs &>(),
          pyb::arg("model"), pyb::arg("framework") = pyb::none())
      .def("invoke", &Single::invoke,
           "invoke(*arrays) -> list of numpy arrays. Inputs of the model's dtype and size go to "
           "the model without a copy; arrays of another size run ml_single_invoke_dynamic with "
           "their shapes. The outputs are views of the ML API's output buffers.")
      .def_property_readonly("input_info", &Single::input_info, "list of TensorInfo")
      .def_property_readonly("output_info", &Single::output_info,
                             "list of TensorInfo (empty for a model that decides it per call)")
      .def("set_input_info", &Single::set_input_info, pyb::arg("info"),
           "Changes the input shapes (ml_single_set_input_info); the output info follows.")
      .def("set_timeout", &Single::set_timeout, pyb::arg("ms"))
      .def("set_property", &Single::set_property, pyb::arg("name"), pyb::arg("value"))
      .def("get_property", &Single::get_property, pyb::arg("name"))
      .def("close", &Single::close, "ml_single_close; later calls raise nnstreamer.Error.")
      .def("__enter__", [](pyb::object self) { return self; })
      .def("__exit__",
           [](Single &s, const pyb::args &) {
             s.close();
             return false;
           })
      .def("_c_invoke_seconds", &Single::c_invoke_seconds, pyb::arg("arrays"), pyb::arg("count"));
}

}  // namespace nns::py

// SPDX-License-Identifier: LGPL-2.1-only
// Header-only C++ RAII wrapper over nnstreamer-single.h. Errors throw nns::ml::Error carrying
// the ml_error_e code and the library's message.
//
//   nns::ml::Single model("mobilenet.onnx", nns::ml::Framework::kOnnxRuntime);
//   nns::ml::TensorsData in(model.input_info());
//   std::memcpy(in.data(0), image, in.size(0));
//   nns::ml::TensorsData out = model.invoke(in);
//
//   auto r = model.invoke_dynamic(in, in_info);   // r.data, r.info: this call's output
//   model.set_property("is-updatable", "true");
//   model.set_property("model", "other.onnx");    // reload
#pragma once

#include <cstdlib>
#include <initializer_list>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "nnstreamer-single.h"

namespace nns::ml {

class Error : public std::runtime_error {
 public:
  Error(int code, const std::string &msg) : std::runtime_error(msg), code_(code) {}
  int code() const noexcept { return code_; }

 private:
  int code_;
};

inline void check(int rc, const char *what) {
  if (rc != ML_ERROR_NONE) {
    const char *detail = ml_error();
    const char *text = ml_strerror(rc);
    throw Error(rc, std::string(what) + ": " +
                        (detail && *detail ? detail
                         : text            ? text
                                           : "error " + std::to_string(rc)));
  }
}

// Owns a C handle; move-only.
template <typename H, int (*Destroy)(H)>
class Handle {
 public:
  Handle() = default;
  explicit Handle(H h) : h_(h) {}
  ~Handle() { reset(); }
  Handle(Handle &&o) noexcept : h_(std::exchange(o.h_, nullptr)) {}
  Handle &operator=(Handle &&o) noexcept {
    if (this != &o) {
      reset();
      h_ = std::exchange(o.h_, nullptr);
    }
    return *this;
  }
  Handle(const Handle &) = delete;
  Handle &operator=(const Handle &) = delete;
  H get() const { return h_; }
  void reset() {
    if (h_) Destroy(h_);
    h_ = nullptr;
  }

 protected:
  H h_ = nullptr;
};

class TensorsInfo : public Handle<ml_tensors_info_h, ml_tensors_info_destroy> {
 public:
  // Extended (rank limit 16); TensorsInfo(ml_tensors_info_h) adopts a handle of either kind.
  TensorsInfo() { check(ml_tensors_info_create_extended(&h_), "ml_tensors_info_create_extended"); }
  explicit TensorsInfo(ml_tensors_info_h adopt) : Handle(adopt) {}
  unsigned count() const {
    unsigned n = 0;
    check(ml_tensors_info_get_count(h_, &n), "ml_tensors_info_get_count");
    return n;
  }
  TensorsInfo &set_count(unsigned n) {
    check(ml_tensors_info_set_count(h_, n), "ml_tensors_info_set_count");
    return *this;
  }
  TensorsInfo &set(unsigned i, ml_tensor_type_e type, std::initializer_list<unsigned> dims) {
    ml_tensor_dimension d = {0};
    unsigned k = 0;
    for (unsigned v : dims)
      if (k < ML_TENSOR_RANK_LIMIT) d[k++] = v;
    check(ml_tensors_info_set_tensor_type(h_, i, type), "ml_tensors_info_set_tensor_type");
    check(ml_tensors_info_set_tensor_dimension(h_, i, d), "ml_tensors_info_set_tensor_dimension");
    return *this;
  }
  TensorsInfo &set_name(unsigned i, const std::string &name) {
    check(ml_tensors_info_set_tensor_name(h_, i, name.c_str()), "ml_tensors_info_set_tensor_name");
    return *this;
  }
  ml_tensor_type_e type(unsigned i) const {
    ml_tensor_type_e t;
    check(ml_tensors_info_get_tensor_type(h_, i, &t), "ml_tensors_info_get_tensor_type");
    return t;
  }
  // Dimension of tensor i up to its rank, innermost first ({3, 224, 224, 1}).
  std::vector<unsigned> dims(unsigned i) const {
    ml_tensor_dimension d = {0};
    check(ml_tensors_info_get_tensor_dimension(h_, i, d), "ml_tensors_info_get_tensor_dimension");
    std::vector<unsigned> v;
    for (unsigned k = 0; k < ML_TENSOR_RANK_LIMIT && d[k]; ++k) v.push_back(d[k]);
    return v;
  }
  std::string name(unsigned i) const {
    char *n = nullptr;
    check(ml_tensors_info_get_tensor_name(h_, i, &n), "ml_tensors_info_get_tensor_name");
    std::string s = n ? n : "";
    std::free(n);
    return s;
  }
  size_t size(int i = -1) const {
    size_t s = 0;
    check(ml_tensors_info_get_tensor_size(h_, i, &s), "ml_tensors_info_get_tensor_size");
    return s;
  }
};

class TensorsData : public Handle<ml_tensors_data_h, ml_tensors_data_destroy> {
 public:
  explicit TensorsData(const TensorsInfo &info) {
    check(ml_tensors_data_create(info.get(), &h_), "ml_tensors_data_create");
  }
  explicit TensorsData(ml_tensors_data_h adopt) : Handle(adopt) {}
  void *data(unsigned i) const {
    void *p = nullptr;
    size_t s = 0;
    check(ml_tensors_data_get_tensor_data(h_, i, &p, &s), "ml_tensors_data_get_tensor_data");
    return p;
  }
  size_t size(unsigned i) const {
    void *p = nullptr;
    size_t s = 0;
    check(ml_tensors_data_get_tensor_data(h_, i, &p, &s), "ml_tensors_data_get_tensor_data");
    return s;
  }
  template <typename T>
  T *as(unsigned i) const {
    return static_cast<T *>(data(i));
  }
};

class Single : public Handle<ml_single_h, ml_single_close> {
 public:
  // What invoke_dynamic() gives: this call's output and its shapes.
  struct Dynamic {
    TensorsData data;
    TensorsInfo info;
  };

  // Takes ownership of a handle opened with the C API.
  static Single adopt(ml_single_h h) {
    Single s;
    s.h_ = h;
    return s;
  }

  // ml_single_open_full: a framework type, hardware and custom option.
  Single(const std::string &models, ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw = ML_NNFW_HW_ANY,
         const TensorsInfo *in = nullptr, const TensorsInfo *out = nullptr,
         const std::string &custom = "") {
    check(ml_single_open_full(&h_, models.c_str(), in ? in->get() : nullptr,
                              out ? out->get() : nullptr, nnfw, hw,
                              custom.empty() ? nullptr : custom.c_str()),
          "ml_single_open_full");
  }
  // framework: any tensor_filter framework= value ("onnxruntime", "pytorch", "auto", ...).
  Single(const std::string &models, const std::string &framework = "auto",
         const TensorsInfo *in = nullptr, const TensorsInfo *out = nullptr,
         const std::string &custom = "") {
    ml_option_h opt = nullptr;
    check(ml_option_create(&opt), "ml_option_create");
    std::string m = models, f = framework, c = custom;
    ml_option_set(opt, "models", m.data(), nullptr);
    ml_option_set(opt, "framework_name", f.data(), nullptr);
    if (!c.empty()) ml_option_set(opt, "custom", c.data(), nullptr);
    if (in) ml_option_set(opt, "input_info", in->get(), nullptr);
    if (out) ml_option_set(opt, "output_info", out->get(), nullptr);
    int rc = ml_single_open_with_option(&h_, opt);
    ml_option_destroy(opt);
    check(rc, "ml_single_open");
  }
  TensorsInfo input_info() const {
    ml_tensors_info_h i = nullptr;
    check(ml_single_get_input_info(h_, &i), "ml_single_get_input_info");
    return TensorsInfo(i);
  }
  TensorsInfo output_info() const {
    ml_tensors_info_h i = nullptr;
    check(ml_single_get_output_info(h_, &i), "ml_single_get_output_info");
    return TensorsInfo(i);
  }
  TensorsData invoke(const TensorsData &in) const {
    ml_tensors_data_h out = nullptr;
    check(ml_single_invoke(h_, in.get(), &out), "ml_single_invoke");
    return TensorsData(out);
  }
  void invoke(const TensorsData &in, TensorsData &out) const {
    check(ml_single_invoke_fast(h_, in.get(), out.get()), "ml_single_invoke_fast");
  }
  // ml_single_invoke_dynamic: `in` shaped as `in_info`.
  Dynamic invoke_dynamic(const TensorsData &in, const TensorsInfo &in_info) const {
    ml_tensors_data_h out = nullptr;
    ml_tensors_info_h info = nullptr;
    check(ml_single_invoke_dynamic(h_, in.get(), in_info.get(), &out, &info),
          "ml_single_invoke_dynamic");
    return Dynamic{TensorsData(out), TensorsInfo(info)};
  }
  void set_input_info(const TensorsInfo &info) {
    check(ml_single_set_input_info(h_, info.get()), "ml_single_set_input_info");
  }
  void set_timeout(unsigned ms) { check(ml_single_set_timeout(h_, ms), "ml_single_set_timeout"); }
  // tensor_filter property names ("input", "custom", "is-updatable", "model", ...).
  void set_property(const std::string &name, const std::string &value) {
    check(ml_single_set_property(h_, name.c_str(), value.c_str()), "ml_single_set_property");
  }
  std::string property(const std::string &name) const {
    char *v = nullptr;
    check(ml_single_get_property(h_, name.c_str(), &v), "ml_single_get_property");
    std::string s = v ? v : "";
    std::free(v);
    return s;
  }
  // The full message of this handle's last error.
  std::string last_error() const { return ml_single_get_last_error(h_); }

 private:
  Single() = default;
};

}  // namespace nns::ml

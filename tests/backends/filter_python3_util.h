// SPDX-License-Identifier: LGPL-2.1-only
// Test helpers for the python3 filter back end through its C ABI (dlopen of the built .so).
#pragma once

#include <dlfcn.h>
#include <gtest/gtest.h>

#include <cerrno>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "nns_filter_backend.h"

namespace nns::test::python3 {

inline const std::string kSo =
    std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_python3.so";

inline std::string script(const std::string &name) {
  return std::string(NNS_SOURCE_DIR) + "/tests/data/python/" + name;
}

inline const nns_filter_backend_i *backend() {
  static const nns_filter_backend_i *table = [] {
    void *so = dlopen(kSo.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!so) return static_cast<const nns_filter_backend_i *>(nullptr);
    auto entry = reinterpret_cast<nns_filter_backend_entry_fn>(dlsym(so, NNS_FILTER_BACKEND_ENTRY));
    return entry ? entry() : nullptr;
  }();
  return table;
}

#define REQUIRE_BACKEND()                                                         \
  do {                                                                            \
    if (!backend()) GTEST_SKIP() << "python3 back end not built (" << kSo << ")"; \
  } while (0)

struct Tensor {
  std::vector<uint32_t> dims;
  uint32_t type;
};

inline std::unique_ptr<nns_tensors_desc> make_desc(const std::vector<Tensor> &ts) {
  auto d = std::make_unique<nns_tensors_desc>();
  std::memset(d.get(), 0, sizeof(*d));
  d->num_tensors = static_cast<uint32_t>(ts.size());
  for (size_t i = 0; i < ts.size(); i++) {
    d->tensors[i].type = ts[i].type;
    for (size_t j = 0; j < ts[i].dims.size(); j++) d->tensors[i].dims[j] = ts[i].dims[j];
  }
  return d;
}

inline std::vector<uint32_t> dims_of(const nns_tensor_desc &t) {
  std::vector<uint32_t> v;
  for (uint32_t d : t.dims) {
    if (!d) break;
    v.push_back(d);
  }
  return v;
}

// An opened script; closes on destruction.
struct Filter {
  void *priv = nullptr;
  int rc = 0;
  char err[8192] = {};
  std::unique_ptr<nns_tensors_desc> in = make_desc({}), out = make_desc({});

  explicit Filter(const std::string &path, const char *custom = nullptr,
                  const nns_tensors_desc *input = nullptr) {
    const char *models[] = {path.c_str()};
    nns_filter_props p{};
    p.framework = "python3";
    p.model_files = models;
    p.num_models = 1;
    p.custom = custom;
    auto none = make_desc({});
    p.input = input ? input : none.get();
    p.output = none.get();
    rc = backend()->open(&p, &priv, err, sizeof err);
  }
  ~Filter() {
    if (priv) backend()->close(priv);
  }
  int model_info() { return backend()->get_model_info(priv, in.get(), out.get(), err, sizeof err); }
  int set_input(const nns_tensors_desc &d) {
    return backend()->set_input_info(priv, &d, out.get(), err, sizeof err);
  }
  int invoke(const std::vector<GstTensorMemory> &ins, std::vector<GstTensorMemory> &outs) {
    return backend()->invoke(priv, ins.data(), static_cast<uint32_t>(ins.size()), outs.data(),
                             static_cast<uint32_t>(outs.size()), err, sizeof err);
  }
  void release(std::vector<GstTensorMemory> &outs) {
    for (auto &o : outs)
      if (o.data) backend()->free_output(priv, o.data);
    for (auto &o : outs) o = {nullptr, 0};
  }
  std::string error() const { return err; }
};

}  // namespace nns::test::python3

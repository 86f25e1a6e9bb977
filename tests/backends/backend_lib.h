// SPDX-License-Identifier: LGPL-2.1-only
// Test helper: loads a filter back-end .so from the build tree through its C ABI (dlopen +
// nns_filter_backend_entry), builds nns_filter_props, and wraps one opened instance.
#pragma once

#include <dlfcn.h>

#include <cstring>
#include <filesystem>
#include <initializer_list>
#include <string>
#include <vector>

#include "nnstreamer/nns_filter_backend.h"

namespace nns::test {

inline std::string filter_so_path(const std::string &name) {
  return std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_" + name + ".so";
}

// One dlopen'ed back end. ok() is false (and error() says why) when the .so is absent.
class BackendLib {
 public:
  explicit BackendLib(const std::string &name) {
    std::string path = filter_so_path(name);
    if (!std::filesystem::exists(path)) {
      error_ = path + " was not built (its runtime is missing)";
      return;
    }
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) {
      error_ = dlerror();
      return;
    }
    auto entry =
        reinterpret_cast<nns_filter_backend_entry_fn>(dlsym(handle_, NNS_FILTER_BACKEND_ENTRY));
    if (!entry) {
      error_ = "no " NNS_FILTER_BACKEND_ENTRY " in " + path;
      return;
    }
    api_ = entry();
  }
  // Deliberately never dlclose()d: runtimes such as libtorch do not unload cleanly.
  BackendLib(const BackendLib &) = delete;
  BackendLib &operator=(const BackendLib &) = delete;

  bool ok() const { return api_ != nullptr; }
  const std::string &error() const { return error_; }
  const nns_filter_backend_i *api() const { return api_; }
  void *sym(const char *name) const { return handle_ ? dlsym(handle_, name) : nullptr; }

 private:
  void *handle_ = nullptr;
  const nns_filter_backend_i *api_ = nullptr;
  std::string error_;
};

inline nns_tensor_desc tensor_desc(uint32_t type, std::initializer_list<uint32_t> dims,
                                   const char *name = "") {
  nns_tensor_desc t{};
  t.type = type;
  std::size_t i = 0;
  for (uint32_t d : dims) t.dims[i++] = d;
  std::strncpy(t.name, name, sizeof(t.name) - 1);
  return t;
}

inline nns_tensors_desc tensors_desc(std::initializer_list<nns_tensor_desc> ts) {
  nns_tensors_desc d{};
  for (const auto &t : ts) d.tensors[d.num_tensors++] = t;
  return d;
}

inline std::size_t desc_bytes(const nns_tensor_desc &t) {
  static const std::size_t sizes[] = {4, 4, 2, 2, 1, 1, 8, 4, 8, 8, 2};
  std::size_t n = 1;
  bool any = false;
  for (uint32_t d : t.dims) {
    if (!d) break;
    n *= d;
    any = true;
  }
  return any && t.type < 11 ? n * sizes[t.type] : 0;
}

// Everything open() needs; the pointers inside stay valid while this object lives.
struct Props {
  std::string framework;
  std::vector<std::string> models;
  nns_tensors_desc input{}, output{};
  std::string custom, accelerator;
  bool has_custom = false, has_accelerator = false;
  int invoke_dynamic = 0, num_threads = 0;

  std::vector<const char *> model_ptrs;
  tensor_layout layouts[NNS_TENSOR_SIZE_LIMIT]{};
  nns_filter_props p{};

  Props &set_custom(std::string c) {
    custom = std::move(c);
    has_custom = true;
    return *this;
  }
  Props &set_accelerator(std::string a) {
    accelerator = std::move(a);
    has_accelerator = true;
    return *this;
  }
  const nns_filter_props *get() {
    model_ptrs.clear();
    for (const auto &m : models) model_ptrs.push_back(m.c_str());
    p = nns_filter_props{};
    p.framework = framework.c_str();
    p.model_files = model_ptrs.data();
    p.num_models = static_cast<uint32_t>(models.size());
    p.input = &input;
    p.output = &output;
    p.custom = has_custom ? custom.c_str() : nullptr;
    p.accelerator = has_accelerator ? accelerator.c_str() : nullptr;
    p.input_layout = layouts;
    p.output_layout = layouts;
    p.invoke_dynamic = invoke_dynamic;
    p.num_threads = num_threads;
    return &p;
  }
};

// One opened back-end instance.
class Instance {
 public:
  Instance(const nns_filter_backend_i *api, Props &props) : api_(api) {
    err_[0] = '\0';
    rc_ = api_->open(props.get(), &priv_, err_, sizeof(err_));
    if (rc_ != 0) priv_ = nullptr;
  }
  ~Instance() {
    if (priv_) api_->close(priv_);
  }
  Instance(const Instance &) = delete;
  Instance &operator=(const Instance &) = delete;

  int rc() const { return rc_; }
  std::string error() const { return err_; }
  void *priv() const { return priv_; }

  int model_info(nns_tensors_desc &in, nns_tensors_desc &out) {
    in = nns_tensors_desc{};
    out = nns_tensors_desc{};
    return api_->get_model_info(priv_, &in, &out, err_, sizeof(err_));
  }
  int set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) {
    return api_->set_input_info(priv_, &in, &out, err_, sizeof(err_));
  }
  int invoke(const std::vector<GstTensorMemory> &in, std::vector<GstTensorMemory> &out) {
    return api_->invoke(priv_, in.data(), static_cast<uint32_t>(in.size()), out.data(),
                        static_cast<uint32_t>(out.size()), err_, sizeof(err_));
  }
  int invoke_dynamic(const nns_tensors_desc &in_info, const std::vector<GstTensorMemory> &in,
                     nns_tensors_desc &out_info, std::vector<GstTensorMemory> &out) {
    out.assign(NNS_TENSOR_SIZE_LIMIT, GstTensorMemory{});
    int rc =
        api_->invoke_dynamic(priv_, &in_info, in.data(), &out_info, out.data(), err_, sizeof(err_));
    if (rc == 0) out.resize(out_info.num_tensors);
    return rc;
  }
  void free_output(void *data) { api_->free_output(priv_, data); }
  int reload(Props &props) { return api_->reload(priv_, props.get(), err_, sizeof(err_)); }

 private:
  const nns_filter_backend_i *api_;
  void *priv_ = nullptr;
  int rc_ = 0;
  char err_[2048];
};

}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// Test helpers that load a filter back end .so directly (dlopen + nns_filter_backend_entry),
// build nns_filter_props, and read the generated models' JSON sidecars
// (tests/data/generate_models.py). Header-only; included by tests/backends/*_test.cc.
#pragma once

#include <dlfcn.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "core/backend_desc.h"
#include "core/tensor_info.h"
#include "nns_filter_backend.h"

namespace nns::test {

// Folder of the built filter back ends (NNSTREAMER_FILTERS as ctest sets it, else build tree).
inline std::string filters_dir() {
  const char *env = std::getenv("NNSTREAMER_FILTERS");
  if (env && *env) return env;
  return std::string(NNS_BUILD_DIR) + "/subplugins/filters";
}

// Folder of the generated models (build/tests/models).
inline std::string models_dir() {
  return std::string(NNS_BUILD_DIR) + "/tests/models";
}

inline std::string backend_path(const std::string &name) {
  return filters_dir() + "/libnnstreamer_filter_" + name + ".so";
}

// A dlopen'ed back end. Stays loaded for the process (back ends may register static state).
struct LoadedBackend {
  void *handle = nullptr;
  const nns_filter_backend_i *api = nullptr;
};

// Loads libnnstreamer_filter_<name>.so; on failure returns nullopt and sets *why.
inline std::optional<LoadedBackend> load_backend(const std::string &name, std::string *why) {
  std::string path = backend_path(name);
  if (!std::filesystem::exists(path)) {
    if (why) *why = path + " is not built";
    return std::nullopt;
  }
  void *h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    if (why) *why = std::string("dlopen failed: ") + dlerror();
    return std::nullopt;
  }
  auto entry = reinterpret_cast<nns_filter_backend_entry_fn>(dlsym(h, NNS_FILTER_BACKEND_ENTRY));
  if (!entry) {
    if (why) *why = path + " does not export " NNS_FILTER_BACKEND_ENTRY;
    return std::nullopt;
  }
  LoadedBackend b{h, entry()};
  if (!b.api || b.api->api_version != NNS_FILTER_BACKEND_API_VERSION) {
    if (why) *why = path + ": wrong API version";
    return std::nullopt;
  }
  return b;
}

inline nns_tensor_desc make_desc(const std::string &name, tensor_type type,
                                 const std::string &dims) {
  nns_tensor_desc d{};
  set_name(d, name);
  d.type = type;
  if (dims.empty()) return d;
  Dims dd = parse_dims(dims);
  for (std::size_t i = 0; i < NNS_TENSOR_RANK_LIMIT; ++i) d.dims[i] = dd[i];
  return d;
}

// What a tensor_filter would pass: model files, custom=, input=/output= descriptions.
struct Props {
  std::vector<std::string> models;
  std::string custom;
  nns_tensors_desc input{};
  nns_tensors_desc output{};
  bool invoke_dynamic = false;
  int num_threads = 0;

  // Keep these alive while `get()`'s result is used.
  std::vector<const char *> model_ptrs;
  std::vector<tensor_layout> layouts = std::vector<tensor_layout>(NNS_TENSOR_SIZE_LIMIT);
  nns_filter_props props{};

  const nns_filter_props *get(const char *framework) {
    model_ptrs.clear();
    for (auto &m : models) model_ptrs.push_back(m.c_str());
    props = nns_filter_props{};
    props.framework = framework;
    props.model_files = model_ptrs.data();
    props.num_models = static_cast<uint32_t>(model_ptrs.size());
    props.input = &input;
    props.output = &output;
    props.custom = custom.empty() ? nullptr : custom.c_str();
    props.input_layout = layouts.data();
    props.output_layout = layouts.data();
    props.invoke_dynamic = invoke_dynamic;
    props.num_threads = num_threads;
    return &props;
  }
};

// An open back-end instance.
class Instance {
 public:
  Instance(const nns_filter_backend_i *api, void *priv) : api_(api), priv_(priv) {}
  ~Instance() {
    if (priv_) api_->close(priv_);
  }
  Instance(const Instance &) = delete;
  Instance &operator=(const Instance &) = delete;

  // Opens; on failure returns nullptr and fills rc/err.
  static std::unique_ptr<Instance> open(const nns_filter_backend_i *api, Props &p,
                                        int *rc = nullptr, std::string *err = nullptr) {
    char buf[1024] = {0};
    void *priv = nullptr;
    int r = api->open(p.get(api->name), &priv, buf, sizeof(buf));
    if (rc) *rc = r;
    if (err) *err = buf;
    if (r != 0) return nullptr;
    return std::make_unique<Instance>(api, priv);
  }

  int info(nns_tensors_desc &in, nns_tensors_desc &out, std::string *err = nullptr) {
    char buf[1024] = {0};
    int r = api_->get_model_info(priv_, &in, &out, buf, sizeof(buf));
    if (err) *err = buf;
    return r;
  }

  int invoke(std::vector<GstTensorMemory> &in, std::vector<GstTensorMemory> &out,
             std::string *err = nullptr) {
    char buf[1024] = {0};
    int r = api_->invoke(priv_, in.data(), static_cast<uint32_t>(in.size()), out.data(),
                         static_cast<uint32_t>(out.size()), buf, sizeof(buf));
    if (err) *err = buf;
    return r;
  }

  void *priv() const { return priv_; }
  const nns_filter_backend_i *api() const { return api_; }

 private:
  const nns_filter_backend_i *api_;
  void *priv_;
};

// One tensor of a generated model's sidecar, with its reference bytes.
struct RefTensor {
  nns_tensor_desc desc{};
  std::vector<int64_t> shape;
  std::vector<uint8_t> bytes;
};

struct RefModel {
  std::string name;
  std::string dir;
  nlohmann::json files;
  std::vector<RefTensor> inputs, outputs;
  double abs_tol = 1e-5, rel_tol = 1e-4;

  // Path of the file for `kind` ("onnx", "pytorch", "python3", ...) or "" if none.
  std::string file(const std::string &kind) const {
    if (!files.contains(kind)) return "";
    return dir + "/" + files[kind].get<std::string>();
  }
};

inline std::vector<uint8_t> slurp(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

// Reads build/tests/models/<name>.json; nullopt if the models were not generated.
inline std::optional<RefModel> load_ref(const std::string &name) {
  std::string dir = models_dir();
  std::ifstream f(dir + "/" + name + ".json");
  if (!f) return std::nullopt;
  nlohmann::json j = nlohmann::json::parse(f);
  RefModel m;
  m.name = name;
  m.dir = dir;
  m.files = j["files"];
  m.abs_tol = j["tolerance"]["abs"].get<double>();
  m.rel_tol = j["tolerance"]["rel"].get<double>();
  for (const char *kind : {"inputs", "outputs"}) {
    for (const auto &t : j[kind]) {
      RefTensor r;
      auto type = type_from_name(t["type"].get<std::string>());
      r.desc = make_desc(t["name"].get<std::string>(),
                         static_cast<tensor_type>(type.value_or(TensorType::kEnd)),
                         t["dims"].get<std::string>());
      r.shape = t["shape"].get<std::vector<int64_t>>();
      r.bytes = slurp(dir + "/" + t["file"].get<std::string>());
      (std::string(kind) == "inputs" ? m.inputs : m.outputs).push_back(std::move(r));
    }
  }
  return m;
}

inline nns_tensors_desc descs_of(const std::vector<RefTensor> &v) {
  nns_tensors_desc d{};
  d.num_tensors = static_cast<uint32_t>(v.size());
  for (std::size_t i = 0; i < v.size(); ++i) d.tensors[i] = v[i].desc;
  return d;
}

// Compares `got` with reference tensor `ref` element-wise within the tolerances; returns ""
// when equal or a message naming the first differing element.
inline std::string compare(const RefTensor &ref, const uint8_t *got, std::size_t size,
                           double abs_tol, double rel_tol) {
  if (size != ref.bytes.size())
    return "size " + std::to_string(size) + " != " + std::to_string(ref.bytes.size());
  auto t = desc_type(ref.desc);
  std::size_t n = size / type_size(t);
  for (std::size_t i = 0; i < n; ++i) {
    double a = 0, b = 0;
    if (t == TensorType::kFloat32) {
      float x, y;
      std::memcpy(&x, got + 4 * i, 4);
      std::memcpy(&y, ref.bytes.data() + 4 * i, 4);
      a = x;
      b = y;
    } else if (t == TensorType::kUInt8) {
      a = got[i];
      b = ref.bytes[i];
    } else {
      if (std::memcmp(got, ref.bytes.data(), size) != 0) return "bytes differ";
      return "";
    }
    if (!(std::fabs(a - b) <= abs_tol + rel_tol * std::fabs(b)))
      return "element " + std::to_string(i) + ": got " + std::to_string(a) + ", expected " +
             std::to_string(b);
  }
  return "";
}

}  // namespace nns::test

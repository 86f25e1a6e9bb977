// SPDX-License-Identifier: LGPL-2.1-only
// Test helpers that load a filter back end .so directly through its C ABI (dlopen +
// nns_filter_backend_entry), build nns_filter_props, wrap one opened instance, and read the
// generated models' JSON sidecars (tests/data/generate_models.py). Header-only; included by
// tests/backends/*_test.cc, tests/pipelines, tests/slow and bench/pytorch_pipeline_bench.cc.
#pragma once

#include <dlfcn.h>

#include <nlohmann/json.hpp>

#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <map>
#include <memory>
#include <mutex>
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

// One dlopen'ed back end (libnnstreamer_filter_<name>.so). ok() is false and error() says why
// when the .so is absent, does not load, or has another ABI version.
class BackendLib {
 public:
  explicit BackendLib(const std::string &name) {
    std::string path = backend_path(name);
    if (!std::filesystem::exists(path)) {
      error_ = path + " was not built (its runtime is missing)";
      return;
    }
    handle_ = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!handle_) {
      error_ = std::string("dlopen failed: ") + dlerror();
      return;
    }
    auto entry =
        reinterpret_cast<nns_filter_backend_entry_fn>(dlsym(handle_, NNS_FILTER_BACKEND_ENTRY));
    if (!entry) {
      error_ = path + " does not export " NNS_FILTER_BACKEND_ENTRY;
      return;
    }
    const nns_filter_backend_i *api = entry();
    if (!api || api->api_version != NNS_FILTER_BACKEND_API_VERSION) {
      error_ = path + ": wrong API version";
      return;
    }
    api_ = api;
  }
  // Deliberately never dlclose()d: back ends register static state and runtimes such as
  // libtorch do not unload cleanly.
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

// The process-wide BackendLib for `name` (loaded on first use, kept for the process).
inline const BackendLib &backend_lib(const std::string &name) {
  static std::mutex mu;
  static std::map<std::string, std::unique_ptr<BackendLib>> libs;
  std::lock_guard lk(mu);
  auto &l = libs[name];
  if (!l) l = std::make_unique<BackendLib>(name);
  return *l;
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

// What a tensor_filter would pass to open(): model files, custom=, accelerator=, input=/output=
// descriptions. The pointers get() returns stay valid while this object lives and is unchanged.
struct Props {
  std::string framework;  // empty: Instance uses the back end's own name
  std::vector<std::string> models;
  nns_tensors_desc input{}, output{};
  std::optional<std::string> custom, accelerator;  // nullopt: property not set (NULL)
  int invoke_dynamic = 0, num_threads = 0;

  std::vector<const char *> model_ptrs;
  std::vector<tensor_layout> layouts = std::vector<tensor_layout>(NNS_TENSOR_SIZE_LIMIT);
  nns_filter_props p{};

  const nns_filter_props *get(const char *fw) {
    framework = fw;
    return get();
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
    p.custom = custom ? custom->c_str() : nullptr;
    p.accelerator = accelerator ? accelerator->c_str() : nullptr;
    p.input_layout = layouts.data();
    p.output_layout = layouts.data();
    p.invoke_dynamic = invoke_dynamic;
    p.num_threads = num_threads;
    return &p;
  }
};

// One opened back-end instance. Every call clears error() first; the `err` out-parameters
// receive the same text.
class Instance {
 public:
  Instance(const nns_filter_backend_i *api, Props &props) : api_(api) {
    if (props.framework.empty()) props.framework = api->name;
    rc_ = api_->open(props.get(), &priv_, reset_err(), sizeof(err_));
    if (rc_ != 0) priv_ = nullptr;
  }
  ~Instance() {
    if (priv_) api_->close(priv_);
  }
  Instance(const Instance &) = delete;
  Instance &operator=(const Instance &) = delete;

  // Opens; on failure returns nullptr. *rc / *err (when given) receive open()'s result.
  static std::unique_ptr<Instance> open(const nns_filter_backend_i *api, Props &p,
                                        int *rc = nullptr, std::string *err = nullptr) {
    auto inst = std::make_unique<Instance>(api, p);
    if (rc) *rc = inst->rc();
    if (err) *err = inst->error();
    if (inst->rc() != 0) return nullptr;
    return inst;
  }

  int rc() const { return rc_; }
  std::string error() const { return err_; }
  void *priv() const { return priv_; }
  const nns_filter_backend_i *api() const { return api_; }

  // get_model_info into zeroed `in` / `out`.
  int model_info(nns_tensors_desc &in, nns_tensors_desc &out, std::string *err = nullptr) {
    in = nns_tensors_desc{};
    out = nns_tensors_desc{};
    return done(api_->get_model_info(priv_, &in, &out, reset_err(), sizeof(err_)), err);
  }
  int set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) {
    return api_->set_input_info(priv_, &in, &out, reset_err(), sizeof(err_));
  }
  int invoke(const std::vector<GstTensorMemory> &in, std::vector<GstTensorMemory> &out,
             std::string *err = nullptr) {
    return done(api_->invoke(priv_, in.data(), static_cast<uint32_t>(in.size()), out.data(),
                             static_cast<uint32_t>(out.size()), reset_err(), sizeof(err_)),
                err);
  }
  // Sizes `out` to what the back end returned.
  int invoke_dynamic(const nns_tensors_desc &in_info, const std::vector<GstTensorMemory> &in,
                     nns_tensors_desc &out_info, std::vector<GstTensorMemory> &out) {
    out.assign(NNS_TENSOR_SIZE_LIMIT, GstTensorMemory{});
    int rc = api_->invoke_dynamic(priv_, &in_info, in.data(), &out_info, out.data(), reset_err(),
                                  sizeof(err_));
    if (rc == 0) out.resize(out_info.num_tensors);
    return rc;
  }
  void free_output(void *data) { api_->free_output(priv_, data); }
  int reload(Props &props) { return api_->reload(priv_, props.get(), reset_err(), sizeof(err_)); }

 private:
  char *reset_err() {
    err_[0] = '\0';
    return err_;
  }
  int done(int rc, std::string *err) const {
    if (err) *err = err_;
    return rc;
  }

  const nns_filter_backend_i *api_;
  void *priv_ = nullptr;
  int rc_ = 0;
  char err_[2048];
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
  nlohmann::json not_written;  // flavour -> why the generator could not write it
  std::vector<RefTensor> inputs, outputs;
  double abs_tol = 1e-5, rel_tol = 1e-4;

  // Path of the file for `kind` ("onnx", "pytorch", "python3", ...) or "" if none.
  std::string file(const std::string &kind) const {
    if (!files.contains(kind)) return "";
    return dir + "/" + files[kind].get<std::string>();
  }
  // Why the `kind` flavour was expected but not generated (e.g. python3-flatbuffers missing for
  // "tflite"), or "" when it was generated or this model never has one.
  std::string why_not_written(const std::string &kind) const {
    if (!not_written.is_object() || !not_written.contains(kind)) return "";
    return not_written[kind].get<std::string>();
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
  if (j.contains("not_written")) m.not_written = j["not_written"];
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

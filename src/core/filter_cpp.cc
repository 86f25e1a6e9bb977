// SPDX-License-Identifier: LGPL-2.1-only
// framework=cpp: C++ objects derived from tensor_filter_cpp (include/nnstreamer/
// tensor_filter_cpp.hh), registered by model name. `model=name,/path/lib.so` dlopens lib.so
// first when `name` is not registered yet.
#include <dlfcn.h>

#include <cstdlib>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/c_tensor_info.h"
#include "core/filter_builtin_util.h"
#include "core/filter_compat_props.h"
#include "core/filter_registry.h"
#include "tensor_filter_cpp.hh"

namespace {
constexpr uint32_t kValidity = 0x2e83a7cbu;

struct CppEntry {
  tensor_filter_cpp *obj;
  std::mutex call_mu;  // one object serves every filter naming it
};

std::mutex g_mu;
std::map<std::string, std::shared_ptr<CppEntry>> &registry() {
  static auto *m = new std::map<std::string, std::shared_ptr<CppEntry>>();
  return *m;
}
std::vector<void *> &handles() {  // libraries loaded through model=name,lib.so
  static auto *v = new std::vector<void *>();
  return *v;
}
}  // namespace

struct nns_cpp_filter_access {
  static const char *name(tensor_filter_cpp *f) { return f->name; }
  static std::atomic_uint &refs(tensor_filter_cpp *f) { return f->ref_count; }
  static void set_prop(tensor_filter_cpp *f, const GstTensorFilterProperties *p) { f->prop = p; }
};

tensor_filter_cpp::tensor_filter_cpp(const char *modelName)
    : validity(kValidity), name(modelName), ref_count(0), prop(nullptr) {}

tensor_filter_cpp::~tensor_filter_cpp() = default;

bool tensor_filter_cpp::isValid() {
  return validity == kValidity;
}

int tensor_filter_cpp::__register(tensor_filter_cpp *filter, unsigned int ref_count) {
  if (!filter || !filter->isValid() || !filter->name || !*filter->name) return -EINVAL;
  std::lock_guard lk(g_mu);
  if (registry().count(filter->name)) return -EEXIST;
  auto e = std::make_shared<CppEntry>();
  e->obj = filter;
  filter->ref_count = ref_count;
  registry()[filter->name] = e;
  return 0;
}

int tensor_filter_cpp::__unregister(const char *name) {
  if (!name) return -EINVAL;
  std::lock_guard lk(g_mu);
  auto it = registry().find(name);
  if (it == registry().end()) return -EINVAL;
  if (it->second->obj->ref_count > 0) return -EBUSY;
  registry().erase(it);
  return 0;
}

namespace nns {
namespace {

using builtin::set_err;
using A = nns_cpp_filter_access;

struct CppPriv {
  std::string name;
  std::shared_ptr<CppEntry> entry;
  std::unique_ptr<CompatProps> props;
  std::vector<GstTensorMemory> scratch;
};

std::shared_ptr<CppEntry> lookup(const std::string &name) {
  std::lock_guard lk(g_mu);
  auto it = registry().find(name);
  if (it == registry().end()) return nullptr;
  A::refs(it->second->obj)++;
  return it->second;
}

int cpp_open(const nns_filter_props *p, void **priv, char *err, size_t len) {
  if (p->num_models < 1 || !p->model_files || !p->model_files[0])
    return set_err(err, len, "framework=cpp needs model=<registered class name>[,<lib.so>]");
  std::string name = p->model_files[0];
  auto entry = lookup(name);
  if (!entry && p->num_models > 1) {
    std::string lib = p->model_files[1];
    dlerror();
    void *h = dlopen(lib.c_str(), RTLD_NOW | RTLD_LOCAL);
    if (!h) {
      const char *e = dlerror();
      return set_err(err, len,
                     "cannot load '" + lib + "' for cpp filter '" + name +
                         "': " + (e ? e : "unknown dlopen error"));
    }
    {
      std::lock_guard lk(g_mu);
      handles().push_back(h);
    }
    entry = lookup(name);
  }
  if (!entry) {
    std::string known;
    {
      std::lock_guard lk(g_mu);
      for (auto &[n, e] : registry()) known += (known.empty() ? "" : ", ") + n;
    }
    return set_err(err, len,
                   "cpp filter '" + name + "' is not registered (registered: " +
                       (known.empty() ? "none" : known) + "); call _register() on the object first",
                   -ENOENT);
  }
  auto c = std::make_unique<CppPriv>();
  c->name = name;
  c->entry = entry;
  c->props = std::make_unique<CompatProps>(*p);
  *priv = c.release();
  return 0;
}

void cpp_close(void *priv) {
  auto *c = static_cast<CppPriv *>(priv);
  {
    std::lock_guard lk(c->entry->call_mu);
    if (A::refs(c->entry->obj) > 0) A::refs(c->entry->obj)--;
    A::set_prop(c->entry->obj, nullptr);
  }
  delete c;
}

int cpp_model_info(void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *, size_t) {
  auto *c = static_cast<CppPriv *>(priv);
  std::lock_guard lk(c->entry->call_mu);
  tensor_filter_cpp *o = c->entry->obj;
  A::set_prop(o, c->props->get());
  int rc = c->props->query_model_info(in, out, [o](GstTensorsInfo *gi, GstTensorsInfo *go) {
    int r = o->getInputDim(gi);
    return r == 0 ? o->getOutputDim(go) : r;
  });
  return rc == 0 ? 0 : -ENOTSUP;  // non-zero: ask setInputDim
}

int cpp_set_input(void *priv, const nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                  size_t len) {
  auto *c = static_cast<CppPriv *>(priv);
  std::lock_guard lk(c->entry->call_mu);
  tensor_filter_cpp *o = c->entry->obj;
  A::set_prop(o, c->props->get());
  int rc = c->props->negotiate_input(
      *in, out, [o](GstTensorsInfo *gi, GstTensorsInfo *go) { return o->setInputDim(gi, go); });
  if (rc != 0)
    return set_err(err, len,
                   "cpp filter '" + c->name + "': setInputDim returned " + std::to_string(rc));
  return 0;
}

int cpp_invoke(void *priv, const GstTensorMemory *in, uint32_t, GstTensorMemory *out,
               uint32_t num_out, char *err, size_t len) {
  auto *c = static_cast<CppPriv *>(priv);
  std::lock_guard lk(c->entry->call_mu);
  tensor_filter_cpp *o = c->entry->obj;
  A::set_prop(o, c->props->get());
  int rc;
  if (o->isAllocatedBeforeInvoke()) {
    rc = o->invoke(in, out);
  } else {
    c->scratch.assign(num_out, GstTensorMemory{nullptr, 0});
    for (uint32_t i = 0; i < num_out; ++i) c->scratch[i].size = out[i].size;
    rc = o->invoke(in, c->scratch.data());
    for (uint32_t i = 0; i < num_out; ++i) {
      if (!c->scratch[i].data) continue;
      if (rc == 0)
        std::memcpy(out[i].data, c->scratch[i].data, std::min(out[i].size, c->scratch[i].size));
      std::free(c->scratch[i].data);
    }
  }
  if (rc < 0)
    return set_err(err, len, "cpp filter '" + c->name + "' invoke returned " + std::to_string(rc),
                   rc);
  return rc;
}

// invoke-async: the object sends its outputs with nnstreamer_filter_dispatch_output_async(prop)
// or a captured handle; what invoke writes into `out` is ignored.
int cpp_invoke_async(void *priv, const nns_tensors_desc *, const GstTensorMemory *in, uint32_t,
                     const nns_filter_async_ctx *ctx, char *err, size_t len) {
  auto *c = static_cast<CppPriv *>(priv);
  std::lock_guard lk(c->entry->call_mu);
  tensor_filter_cpp *o = c->entry->obj;
  A::set_prop(o, c->props->get());
  CompatAsync &a = c->props->async();
  ScratchOutputs out(c->props->get()->output_meta);
  bool preallocated = o->isAllocatedBeforeInvoke();
  GstTensorMemory *mem = out.get();
  if (!preallocated)
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) mem[i].data = nullptr;
  a.begin(*ctx);
  int rc = o->invoke(in, mem);
  bool pending = a.end();
  if (!preallocated)
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) std::free(mem[i].data);
  if (rc < 0)
    return set_err(err, len, "cpp filter '" + c->name + "' invoke returned " + std::to_string(rc),
                   rc);
  return pending ? NNS_FILTER_ASYNC_PENDING : 0;
}

}  // namespace

const nns_filter_backend_i *builtin_cpp_backend() {
  static const nns_filter_backend_i table = [] {
    nns_filter_backend_i t{};
    t.api_version = NNS_FILTER_BACKEND_API_VERSION;
    t.name = "cpp";
    t.flags = NNS_FILTER_FLAG_RUN_WITHOUT_MODEL;
    t.open = cpp_open;
    t.close = cpp_close;
    t.get_model_info = cpp_model_info;
    t.set_input_info = cpp_set_input;
    t.invoke = cpp_invoke;
    t.invoke_async = cpp_invoke_async;
    return t;
  }();
  return &table;
}

}  // namespace nns

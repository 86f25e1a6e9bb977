// SPDX-License-Identifier: LGPL-2.1-only
// framework=custom: model= is a shared object exporting NNStreamer_custom
// (include/nnstreamer/tensor_filter_custom.h). Opened with dlopen per filter instance and
// closed again when the filter closes, so unloading and reloading leaks nothing.
#include <dlfcn.h>

#include <cstdlib>
#include <memory>
#include <vector>

#include "core/c_tensor_info.h"
#include "core/filter_builtin_util.h"
#include "core/filter_compat_props.h"
#include "core/filter_registry.h"
#include "tensor_filter_custom.h"

namespace nns {
namespace {

using builtin::set_err;

struct CustomSo {
  void *dl = nullptr;
  NNStreamer_custom_class *cls = nullptr;
  void *data = nullptr;
  std::unique_ptr<CompatProps> props;
  std::string path;
  std::vector<GstTensorMemory> scratch;  // allocate_invoke results
};

// A block the filter allocated: its destroy_notify, else free().
void release_block(void *cls, void *data) {
  auto *k = static_cast<NNStreamer_custom_class *>(cls);
  if (k->destroy_notify)
    k->destroy_notify(data);
  else
    std::free(data);
}

int custom_open(const nns_filter_props *p, void **priv, char *err, size_t len) {
  if (p->num_models < 1 || !p->model_files || !p->model_files[0])
    return set_err(err, len, "framework=custom needs model=<path of the custom filter .so>");
  auto c = std::make_unique<CustomSo>();
  c->path = p->model_files[0];
  // dlopen() searches the library path for names without '/'; model= means a file here.
  if (c->path.find('/') == std::string::npos) c->path = "./" + c->path;
  promote_filter_api();  // the filter may call nnstreamer_filter_dispatch_output_async()
  dlerror();
  c->dl = dlopen(c->path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!c->dl) {
    const char *e = dlerror();
    return set_err(
        err, len,
        "cannot load custom filter '" + c->path + "': " + (e ? e : "unknown dlopen error"));
  }
  auto close_dl = [&](const std::string &msg) {
    dlclose(c->dl);
    c->dl = nullptr;
    return set_err(err, len, msg);
  };
  void *sym = dlsym(c->dl, "NNStreamer_custom");
  if (!sym)
    return close_dl("custom filter '" + c->path +
                    "' does not export the symbol NNStreamer_custom (see tensor_filter_custom.h)");
  c->cls = *static_cast<NNStreamer_custom_class **>(sym);
  if (!c->cls) return close_dl("custom filter '" + c->path + "': NNStreamer_custom is NULL");
  const NNStreamer_custom_class *k = c->cls;
  if (!k->initfunc || !k->exitfunc)
    return close_dl("custom filter '" + c->path + "' lacks initfunc or exitfunc");
  if (!((k->getInputDim && k->getOutputDim) || k->setInputDim))
    return close_dl("custom filter '" + c->path +
                    "' must define getInputDim and getOutputDim, or setInputDim");
  if ((k->invoke != nullptr) == (k->allocate_invoke != nullptr))
    return close_dl("custom filter '" + c->path +
                    "' must define exactly one of invoke and allocate_invoke");
  c->props = std::make_unique<CompatProps>(*p);
  c->props->async().set_release(release_block, c->cls);
  c->data = k->initfunc(c->props->get());
  *priv = c.release();
  return 0;
}

void custom_close(void *priv) {
  auto *c = static_cast<CustomSo *>(priv);
  if (!c) return;
  c->cls->exitfunc(c->data, c->props->get());
  c->props.reset();
  dlclose(c->dl);
  delete c;
}

int custom_model_info(void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                      size_t len) {
  auto *c = static_cast<CustomSo *>(priv);
  if (!c->cls->getInputDim || !c->cls->getOutputDim) return -ENOTSUP;
  int rc = c->props->query_model_info(in, out, [c](GstTensorsInfo *gi, GstTensorsInfo *go) {
    int r = c->cls->getInputDim(c->data, c->props->get(), gi);
    return r == 0 ? c->cls->getOutputDim(c->data, c->props->get(), go) : r;
  });
  if (rc != 0)
    return set_err(
        err, len,
        "custom filter '" + c->path + "': getInputDim/getOutputDim returned " + std::to_string(rc));
  return 0;
}

int custom_set_input(void *priv, const nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                     size_t len) {
  auto *c = static_cast<CustomSo *>(priv);
  if (!c->cls->setInputDim) return -ENOTSUP;
  int rc = c->props->negotiate_input(*in, out, [c](GstTensorsInfo *gi, GstTensorsInfo *go) {
    return c->cls->setInputDim(c->data, c->props->get(), gi, go);
  });
  if (rc != 0)
    return set_err(err, len,
                   "custom filter '" + c->path + "': setInputDim returned " + std::to_string(rc));
  return 0;
}

int custom_invoke(void *priv, const GstTensorMemory *in, uint32_t, GstTensorMemory *out,
                  uint32_t num_out, char *err, size_t len) {
  auto *c = static_cast<CustomSo *>(priv);
  int rc;
  if (c->cls->invoke) {
    rc = c->cls->invoke(c->data, c->props->get(), in, out);
  } else {
    // allocate_invoke: the filter allocates; copy into the element's buffers.
    c->scratch.assign(num_out, GstTensorMemory{nullptr, 0});
    for (uint32_t i = 0; i < num_out; ++i) c->scratch[i].size = out[i].size;
    rc = c->cls->allocate_invoke(c->data, c->props->get(), in, c->scratch.data());
    for (uint32_t i = 0; i < num_out; ++i) {
      void *d = c->scratch[i].data;
      if (!d) continue;
      if (rc == 0) std::memcpy(out[i].data, d, std::min(out[i].size, c->scratch[i].size));
      if (c->cls->destroy_notify)
        c->cls->destroy_notify(d);
      else
        std::free(d);
    }
  }
  if (rc < 0)
    return set_err(err, len,
                   "custom filter '" + c->path + "' invoke returned " + std::to_string(rc), rc);
  return rc;
}

// invoke-async: the filter sends its outputs with nnstreamer_filter_dispatch_output_async();
// what invoke (or allocate_invoke) produces is ignored.
int custom_invoke_async(void *priv, const nns_tensors_desc *, const GstTensorMemory *in, uint32_t,
                        const nns_filter_async_ctx *ctx, char *err, size_t len) {
  auto *c = static_cast<CustomSo *>(priv);
  CompatAsync &a = c->props->async();
  ScratchOutputs out(c->props->get()->output_meta);
  GstTensorMemory *mem = out.get();
  int rc;
  a.begin(*ctx);
  if (c->cls->invoke) {
    rc = c->cls->invoke(c->data, c->props->get(), in, mem);
  } else {
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) mem[i].data = nullptr;
    rc = c->cls->allocate_invoke(c->data, c->props->get(), in, mem);
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i)
      if (mem[i].data) release_block(c->cls, mem[i].data);
  }
  bool pending = a.end();
  if (rc < 0)
    return set_err(err, len,
                   "custom filter '" + c->path + "' invoke returned " + std::to_string(rc), rc);
  return pending ? NNS_FILTER_ASYNC_PENDING : 0;
}

const char *const kExtensions[] = {".so", nullptr};

}  // namespace

const nns_filter_backend_i *builtin_custom_backend() {
  static const nns_filter_backend_i table = [] {
    nns_filter_backend_i t{};
    t.api_version = NNS_FILTER_BACKEND_API_VERSION;
    t.name = "custom";
    t.flags = 0;
    t.extensions = kExtensions;
    t.open = custom_open;
    t.close = custom_close;
    t.get_model_info = custom_model_info;
    t.set_input_info = custom_set_input;
    t.invoke = custom_invoke;
    t.invoke_async = custom_invoke_async;
    return t;
  }();
  return &table;
}

}  // namespace nns

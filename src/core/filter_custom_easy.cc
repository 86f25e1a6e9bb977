// SPDX-License-Identifier: LGPL-2.1-only
// framework=custom-easy: functions registered in the running process with
// NNS_custom_easy_register() (include/nnstreamer/tensor_filter_custom_easy.h); model= is the
// registered name. The function gets the mapped input memories and the element's output
// buffers directly.
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>

#include "core/filter_builtin_util.h"
#include "core/filter_compat_props.h"
#include "core/c_tensor_info.h"
#include "core/filter_desc.h"
#include "core/filter_registry.h"
#include "tensor_filter_custom_easy.h"

namespace nns {
namespace {

using builtin::set_err;

struct EasyModel {
  NNS_custom_invoke func = nullptr;
  NNS_custom_invoke_dynamic dyn = nullptr;
  void *data = nullptr;
  std::unique_ptr<nns_tensors_desc> in, out;  // out empty for dynamic models
  int users = 0;                              // guarded by g_mu
};

std::mutex g_mu;
std::map<std::string, std::shared_ptr<EasyModel>> &models() {
  static auto *m = new std::map<std::string, std::shared_ptr<EasyModel>>();
  return *m;
}

struct EasyPriv {
  std::string name;
  std::shared_ptr<EasyModel> model;
  std::unique_ptr<CompatProps> props;
};

// As NNStreamer's gst_tensors_info_validate(): a flexible or sparse description is accepted
// as it is (its shapes travel with each buffer); a static one needs valid tensors.
bool valid_info(const GstTensorsInfo *i) {
  if (!i) return false;
  int format;  // read as int: the caller's value may be outside the enum
  static_assert(sizeof format == sizeof i->format);
  std::memcpy(&format, &i->format, sizeof format);
  if (format < 0 || format >= _NNS_TENSOR_FORMAT_END) return false;
  if (format != _NNS_TENSOR_FORMAT_STATIC) return i->num_tensors <= NNS_TENSOR_SIZE_LIMIT;
  if (i->num_tensors < 1 || i->num_tensors > NNS_TENSOR_SIZE_LIMIT) return false;
  for (unsigned k = 0; k < i->num_tensors; ++k) {
    const GstTensorInfo *t = gst_info_at(i, k);
    if (!t || t->type < 0 || t->type >= _NNS_END || t->dimension[0] == 0) return false;
  }
  return true;
}

int add_model(const char *name, std::shared_ptr<EasyModel> m) {
  std::lock_guard lk(g_mu);
  if (models().count(name)) return -EEXIST;
  models()[name] = std::move(m);
  return 0;
}

int easy_open(const nns_filter_props *p, void **priv, char *err, size_t len) {
  if (p->num_models < 1 || !p->model_files || !p->model_files[0])
    return set_err(err, len, "framework=custom-easy needs model=<registered name>");
  std::string name = p->model_files[0];
  std::shared_ptr<EasyModel> m;
  {
    std::lock_guard lk(g_mu);
    auto it = models().find(name);
    if (it == models().end()) {
      std::string known;
      for (auto &[n, v] : models()) known += (known.empty() ? "" : ", ") + n;
      return set_err(err, len,
                     "custom-easy model '" + name +
                         "' is not registered (registered: " + (known.empty() ? "none" : known) +
                         "); call NNS_custom_easy_register() first",
                     -ENOENT);
    }
    m = it->second;
    if (p->invoke_async && !m->func)
      return set_err(err, len,
                     "custom-easy model '" + name +
                         "' was registered with NNS_custom_easy_dynamic_register(), whose "
                         "function gets no GstTensorFilterProperties to dispatch with; "
                         "invoke-async=true needs NNS_custom_easy_register()",
                     -ENOTSUP);
    ++m->users;
  }
  auto e = std::make_unique<EasyPriv>();
  e->name = name;
  e->model = m;
  e->props = std::make_unique<CompatProps>(*p);
  e->props->set_input(*m->in);
  if (m->out) e->props->set_output(*m->out);
  *priv = e.release();
  return 0;
}

void easy_close(void *priv) {
  auto *e = static_cast<EasyPriv *>(priv);
  {
    std::lock_guard lk(g_mu);
    --e->model->users;
  }
  delete e;
}

int easy_model_info(void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *, size_t) {
  auto *e = static_cast<EasyPriv *>(priv);
  std::memcpy(in, e->model->in.get(), sizeof *in);
  if (e->model->out)
    std::memcpy(out, e->model->out.get(), sizeof *out);
  else
    out->num_tensors = 0;  // dynamic: decided per call
  return 0;
}

int easy_invoke(void *priv, const GstTensorMemory *in, uint32_t, GstTensorMemory *out, uint32_t,
                char *err, size_t len) {
  auto *e = static_cast<EasyPriv *>(priv);
  if (!e->model->func)
    return set_err(err, len,
                   "custom-easy model '" + e->name +
                       "' was registered with NNS_custom_easy_dynamic_register(); "
                       "use invoke-dynamic=true");
  int rc = e->model->func(e->model->data, e->props->get(), in, out);
  if (rc < 0)
    return set_err(err, len,
                   "custom-easy function '" + e->name + "' returned " + std::to_string(rc), rc);
  return rc;
}

int easy_invoke_dynamic(void *priv, const nns_tensors_desc *in_info, const GstTensorMemory *in,
                        nns_tensors_desc *out_info, GstTensorMemory *out, char *err, size_t len) {
  auto *e = static_cast<EasyPriv *>(priv);
  if (!e->model->dyn)
    return set_err(err, len,
                   "custom-easy model '" + e->name +
                       "' was registered with NNS_custom_easy_register(), which has "
                       "fixed outputs; use NNS_custom_easy_dynamic_register() for "
                       "invoke-dynamic=true");
  GstTensorsInfo gi, go;
  gst_info_from_desc(*in_info, &gi);
  gst_info_init(&go);
  int rc = e->model->dyn(e->model->data, &gi, &go, in, out);
  if (rc == 0) desc_from_gst_info(&go, *out_info);
  gst_info_clear(&gi);
  gst_info_clear(&go);
  if (rc != 0)
    return set_err(err, len,
                   "custom-easy function '" + e->name + "' returned " + std::to_string(rc),
                   rc < 0 ? rc : -EINVAL);
  return 0;
}

void easy_free_output(void *, void *data) {
  std::free(data);
}

// invoke-async: the function sends its outputs with nnstreamer_filter_dispatch_output_async()
// or a captured handle; what it writes into `output` is ignored.
int easy_invoke_async(void *priv, const nns_tensors_desc *, const GstTensorMemory *in, uint32_t,
                      const nns_filter_async_ctx *ctx, char *err, size_t len) {
  auto *e = static_cast<EasyPriv *>(priv);
  if (!e->model->func)
    return set_err(err, len,
                   "custom-easy model '" + e->name +
                       "' was registered with NNS_custom_easy_dynamic_register(), whose "
                       "function gets no GstTensorFilterProperties to dispatch with; "
                       "invoke-async=true needs NNS_custom_easy_register()",
                   -ENOTSUP);
  CompatAsync &a = e->props->async();
  ScratchOutputs out(e->props->get()->output_meta);
  a.begin(*ctx);
  int rc = e->model->func(e->model->data, e->props->get(), in, out.get());
  bool pending = a.end();
  if (rc < 0)
    return set_err(err, len,
                   "custom-easy function '" + e->name + "' returned " + std::to_string(rc), rc);
  return pending ? NNS_FILTER_ASYNC_PENDING : 0;
}

}  // namespace

const nns_filter_backend_i *builtin_custom_easy_backend() {
  static const nns_filter_backend_i table = [] {
    nns_filter_backend_i t{};
    t.api_version = NNS_FILTER_BACKEND_API_VERSION;
    t.name = "custom-easy";
    t.flags = NNS_FILTER_FLAG_RUN_WITHOUT_MODEL | NNS_FILTER_FLAG_DYNAMIC;
    t.open = easy_open;
    t.close = easy_close;
    t.get_model_info = easy_model_info;
    t.invoke = easy_invoke;
    t.invoke_dynamic = easy_invoke_dynamic;
    t.free_output = easy_free_output;
    t.invoke_async = easy_invoke_async;
    return t;
  }();
  return &table;
}

}  // namespace nns

extern "C" {

__attribute__((visibility("default"))) int NNS_custom_easy_register(
    const char *modelname, NNS_custom_invoke func, void *data, const GstTensorsInfo *in_info,
    const GstTensorsInfo *out_info) {
  if (!modelname || !*modelname || !func || !nns::valid_info(in_info) || !nns::valid_info(out_info))
    return -EINVAL;
  auto m = std::make_shared<nns::EasyModel>();
  m->func = func;
  m->data = data;
  m->in = nns::new_desc();
  m->out = nns::new_desc();
  nns::desc_from_gst_info(in_info, *m->in);
  nns::desc_from_gst_info(out_info, *m->out);
  return nns::add_model(modelname, std::move(m));
}

__attribute__((visibility("default"))) int NNS_custom_easy_dynamic_register(
    const char *modelname, NNS_custom_invoke_dynamic func, void *data,
    const GstTensorsInfo *in_info) {
  if (!modelname || !*modelname || !func || !nns::valid_info(in_info)) return -EINVAL;
  auto m = std::make_shared<nns::EasyModel>();
  m->dyn = func;
  m->data = data;
  m->in = nns::new_desc();
  nns::desc_from_gst_info(in_info, *m->in);
  return nns::add_model(modelname, std::move(m));
}

__attribute__((visibility("default"))) int NNS_custom_easy_unregister(const char *modelname) {
  if (!modelname) return -EINVAL;
  std::lock_guard lk(nns::g_mu);
  auto it = nns::models().find(modelname);
  if (it == nns::models().end()) return -EINVAL;
  if (it->second->users > 0) return -EBUSY;
  nns::models().erase(it);
  return 0;
}

}  // extern "C"

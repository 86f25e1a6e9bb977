// SPDX-License-Identifier: LGPL-2.1-only
// GTensorFilterSingle (tensor_filter_single.h): NNStreamer 2.x's single-shot GObject, on
// nnstreamer-cpp's filter core (FilterSettings -> FilterOpenSpec -> FilterInstance), the same
// path our ml_single_* functions take. Properties are tensor_filter's; after start, input* /
// output* read back the model's tensors (NNStreamer's ML API reads them that way).
// invoke-async is emulated: the outputs of each invoke are handed to the callback before
// invoke returns.
#include "tensor_filter_single.h"

#include <cerrno>
#include <algorithm>
#include <cstring>
#include <new>
#include <map>
#include <memory>
#include <mutex>
#include <string>

#include "compat/compat_export.h"
#include "core/c_tensor_info.h"
#include "core/error.h"
#include "core/filter_desc.h"
#include "core/filter_instance.h"
#include "core/filter_registry.h"
#include "gst/filter_properties.h"

namespace {

using nns::gst::FilterProp;

struct Priv {
  std::mutex mu;
  nns::gst::FilterSettings s;
  std::shared_ptr<nns::FilterInstance> inst;
  nns::TensorsInfo in, out;
  bool alloc = false;
  // Output blocks the back end allocated, and the session that releases each.
  std::map<void *, std::shared_ptr<nns::FilterSession>> owned;
  GstTensorDataCallback async_cb = nullptr;
  void *async_data = nullptr;
};

Priv *priv_of(GTensorFilterSingle *self) {
  return static_cast<Priv *>(self->priv);
}

gpointer parent_class = nullptr;

bool start_locked(Priv *p) {
  if (p->inst) return true;
  try {
    auto conf = nns::current_filter_conf();
    auto models = nns::gst::split_models(p->s.model);
    nns::BackendRef be = nns::FilterRegistry::get().resolve(p->s.framework, models, *conf);
    nns::FilterOpenSpec spec = nns::gst::make_open_spec(p->s);
    auto inst = nns::FilterInstance::open(be, spec);
    nns::TensorsInfo in = spec.input, out = spec.output, mi, mo;
    if (inst->model_info(mi, mo)) {
      if (in.size() == 0) in = mi;
      if (out.size() == 0) out = mo;
    }
    if (in.size() > 0 && out.size() == 0) {
      nns::TensorsInfo o;
      if (inst->set_input_info(in, o)) out = o;
    }
    p->in = in;
    p->out = out;
    p->alloc = (inst->flags() & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE) != 0;
    if (p->s.framework.empty() || p->s.framework == "auto") p->s.framework = inst->name();
    p->inst = std::move(inst);
    return true;
  } catch (const std::exception &e) {
    g_critical("tensor_filter_single: %s", e.what());
    return false;
  }
}

void release_locked(Priv *p, void *data) {
  auto it = p->owned.find(data);
  if (it != p->owned.end()) {
    it->second->free_output(data);
    p->owned.erase(it);
  } else {
    g_free(data);
  }
}

gboolean single_start(GTensorFilterSingle *self) {
  Priv *p = priv_of(self);
  std::lock_guard lk(p->mu);
  return start_locked(p) ? TRUE : FALSE;
}

gboolean single_stop(GTensorFilterSingle *self) {
  Priv *p = priv_of(self);
  std::lock_guard lk(p->mu);
  p->inst.reset();  // blocks still owned keep their sessions alive until released
  return TRUE;
}

gboolean single_input_configured(GTensorFilterSingle *self) {
  Priv *p = priv_of(self);
  std::lock_guard lk(p->mu);
  return p->inst && p->in.size() > 0 ? TRUE : FALSE;
}

gboolean single_output_configured(GTensorFilterSingle *self) {
  Priv *p = priv_of(self);
  std::lock_guard lk(p->mu);
  return p->inst && p->out.size() > 0 ? TRUE : FALSE;
}

gboolean single_allocate_in_invoke(GTensorFilterSingle *self) {
  Priv *p = priv_of(self);
  std::lock_guard lk(p->mu);
  return p->alloc ? TRUE : FALSE;
}

gint single_set_input_info(GTensorFilterSingle *self, const GstTensorsInfo *in_info,
                           GstTensorsInfo *out_info) {
  Priv *p = priv_of(self);
  if (!in_info || !out_info) return -EINVAL;
  std::lock_guard lk(p->mu);
  if (!p->inst) return -EINVAL;
  try {
    nns::TensorsInfo in = nns::from_c(in_info), out;
    nns::gst_info_init(out_info);
    if (!p->inst->set_input_info(in, out)) return -ENOENT;
    nns::to_c(out, out_info);
    p->in = in;
    p->out = out;
    return 0;
  } catch (const std::exception &e) {
    g_critical("tensor_filter_single: %s", e.what());
    return -EINVAL;
  }
}

void single_destroy_notify(GTensorFilterSingle *self, GstTensorMemory *mem) {
  Priv *p = priv_of(self);
  if (!mem) return;
  std::lock_guard lk(p->mu);
  for (std::size_t i = 0; i < p->out.size(); ++i) {
    if (mem[i].data) release_locked(p, mem[i].data);
    mem[i].data = nullptr;
  }
}

gboolean single_set_async(GTensorFilterSingle *self, GstTensorDataCallback cb, void *data) {
  if (!cb) return FALSE;
  Priv *p = priv_of(self);
  std::lock_guard lk(p->mu);
  p->async_cb = cb;
  p->async_data = data;
  return TRUE;
}

gboolean single_invoke(GTensorFilterSingle *self, const GstTensorMemory *input,
                       GstTensorMemory *output, gboolean allocate) {
  Priv *p = priv_of(self);
  if (!input || !output) return FALSE;
  std::unique_lock lk(p->mu);
  if (!start_locked(p)) return FALSE;
  const auto n_in = static_cast<uint32_t>(p->in.size());
  auto n_out = static_cast<uint32_t>(p->out.size());
  try {
    std::shared_ptr<nns::FilterSession> used;
    if (p->s.invoke_dynamic) {
      auto in_desc = nns::make_desc(p->in);
      auto out_desc = nns::new_desc();
      GstTensorMemory out[NNS_TENSOR_SIZE_LIMIT] = {};
      p->inst->invoke_dynamic(*in_desc, input, *out_desc, out, &used);
      p->out = nns::info_from_desc(*out_desc);
      n_out = static_cast<uint32_t>(p->out.size());
      for (uint32_t i = 0; i < n_out; ++i) {
        output[i] = out[i];
        p->owned[out[i].data] = used;
      }
    } else if (p->alloc) {
      GstTensorMemory out[NNS_TENSOR_SIZE_LIMIT] = {};
      for (uint32_t i = 0; i < n_out; ++i) out[i].size = output[i].size;
      int rc = p->inst->invoke(input, n_in, out, n_out, &used);
      if (rc != 0) return FALSE;
      for (uint32_t i = 0; i < n_out; ++i) {
        if (allocate) {
          output[i] = out[i];
          p->owned[out[i].data] = used;
        } else {  // the caller gave memory: copy, then release the back end's block
          std::memcpy(output[i].data, out[i].data, std::min(output[i].size, out[i].size));
          used->free_output(out[i].data);
        }
      }
    } else {
      if (allocate)
        for (uint32_t i = 0; i < n_out; ++i) {
          output[i].size = p->out[i].byte_size();
          output[i].data = g_try_malloc(output[i].size ? output[i].size : 1);
          if (!output[i].data) throw std::bad_alloc();
        }
      int rc = p->inst->invoke(input, n_in, output, n_out, &used);
      if (rc != 0) {
        if (allocate)
          for (uint32_t i = 0; i < n_out; ++i) {
            g_free(output[i].data);
            output[i].data = nullptr;
          }
        return FALSE;
      }
    }
    if (p->s.invoke_async && p->async_cb) {
      GstTensorsInfo info;
      nns::gst_info_init(&info);
      nns::to_c(p->out, &info);
      GstTensorDataCallback cb = p->async_cb;
      void *data = p->async_data;
      lk.unlock();
      cb(output, &info, data);
      nns::gst_info_clear(&info);
    }
    return TRUE;
  } catch (const std::exception &e) {
    g_critical("tensor_filter_single: %s", e.what());
    return FALSE;
  }
}

// ---- properties ----------------------------------------------------------------------------

void set_property(GObject *object, guint id, const GValue *value, GParamSpec *pspec) {
  Priv *p = priv_of(G_TENSOR_FILTER_SINGLE(object));
  std::lock_guard lk(p->mu);
  nns::gst::FilterSettings &s = p->s;
  if (std::string *str = nns::gst::string_setting(s, g_param_spec_get_name(pspec))) {
    const gchar *v = g_value_get_string(value);
    *str = v ? v : "";
  } else if (!nns::gst::set_filter_value(s, id, value)) {
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

// After start, the tensor properties read back the model's tensors; before, what was set.
void get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  Priv *p = priv_of(G_TENSOR_FILTER_SINGLE(object));
  std::lock_guard lk(p->mu);
  nns::gst::FilterSettings &s = p->s;
  const bool in_known = p->inst && p->in.size() > 0, out_known = p->inst && p->out.size() > 0;
  try {
    switch (static_cast<FilterProp>(id)) {
      case FilterProp::kInput:
        if (in_known) return g_value_set_string(value, p->in.dims_string().c_str());
        break;
      case FilterProp::kInputType:
        if (in_known) return g_value_set_string(value, p->in.types_string().c_str());
        break;
      case FilterProp::kInputName:
        if (in_known) return g_value_set_string(value, p->in.names_string().c_str());
        break;
      case FilterProp::kOutput:
        if (out_known) return g_value_set_string(value, p->out.dims_string().c_str());
        break;
      case FilterProp::kOutputType:
        if (out_known) return g_value_set_string(value, p->out.types_string().c_str());
        break;
      case FilterProp::kOutputName:
        if (out_known) return g_value_set_string(value, p->out.names_string().c_str());
        break;
      case FilterProp::kInputRanks:
        return g_value_set_string(value, in_known ? nns::gst::ranks_string(p->in).c_str() : "");
      case FilterProp::kOutputRanks:
        return g_value_set_string(value, out_known ? nns::gst::ranks_string(p->out).c_str() : "");
      case FilterProp::kSubPlugins:
        return g_value_set_string(value, nns::gst::available_filters().c_str());
      default:
        break;
    }
  } catch (...) {
  }
  if (std::string *str = nns::gst::string_setting(s, g_param_spec_get_name(pspec)))
    g_value_set_string(value, str->c_str());
  else if (!nns::gst::get_filter_value(s, id, value))
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

void finalize(GObject *object) {
  auto *self = G_TENSOR_FILTER_SINGLE(object);
  Priv *p = priv_of(self);
  {
    std::lock_guard lk(p->mu);
    for (auto &[data, session] : p->owned) session->free_output(data);
    p->owned.clear();
    p->inst.reset();
  }
  delete p;
  self->priv = nullptr;
  G_OBJECT_CLASS(parent_class)->finalize(object);
}

void class_init(gpointer klass, gpointer) {
  parent_class = g_type_class_peek_parent(klass);
  auto *k = G_OBJECT_CLASS(klass);
  k->set_property = set_property;
  k->get_property = get_property;
  k->finalize = finalize;
  // tensor_filter's properties, as upstream's GTensorFilterSingle installs them; no states, so
  // nothing is marked mutable in PLAYING.
  nns::gst::install_filter_properties(k, static_cast<GParamFlags>(0));
  auto *sk = static_cast<GTensorFilterSingleClass *>(klass);
  sk->invoke = single_invoke;
  sk->start = single_start;
  sk->stop = single_stop;
  sk->input_configured = single_input_configured;
  sk->output_configured = single_output_configured;
  sk->set_input_info = single_set_input_info;
  sk->allocate_in_invoke = single_allocate_in_invoke;
  sk->destroy_notify = single_destroy_notify;
  sk->set_invoke_async_callback = single_set_async;
}

void instance_init(GTypeInstance *instance, gpointer) {
  G_TENSOR_FILTER_SINGLE_CAST(instance)->priv = new Priv;
}

}  // namespace

NNS_COMPAT_API GType g_tensor_filter_single_get_type(void) {
  static gsize type = 0;
  if (g_once_init_enter(&type)) {
    GType t = g_type_register_static_simple(
        G_TYPE_OBJECT, g_intern_static_string("GTensorFilterSingle"),
        sizeof(GTensorFilterSingleClass), class_init, sizeof(GTensorFilterSingle), instance_init,
        static_cast<GTypeFlags>(0));
    g_once_init_leave(&type, t);
  }
  return type;
}

// SPDX-License-Identifier: LGPL-2.1-only
// The reverse bridge: each of our back ends (nns_filter_backend_i) seen as an NNStreamer 2.x
// version-1 GstTensorFilterFramework, for nnstreamer_filter_find() callers (NNStreamer's ML API
// library, tools and tests that open, invoke and close a framework directly). One table per
// back end, made on first use and never freed (valid for the life of the process).
//
// How the 2.x calls map onto ours:
//   open(prop)                   open() with nns_filter_props made from prop (model_files,
//                                input/output_meta, custom_properties, accl_str or hw_list,
//                                layouts, invoke_dynamic)
//   getModelInfo(GET_IN_OUT)     get_model_info (-ENOTSUP -> -ENOENT)
//   getModelInfo(SET_INPUT)      set_input_info (-ENOTSUP or none -> -ENOENT)
//   invoke                       invoke, or invoke_dynamic when prop->invoke_dynamic (outputs
//                                described in prop->output_meta), statistics updated
//   eventHandler(DESTROY_NOTIFY) free_output (else free()); SUSPEND/RESUME: handle_event;
//                                CHECK_HW_AVAILABILITY: check_accelerator; others -ENOENT
//   getFrameworkInfo             name, flags, accelerators (check_accelerator over NNStreamer's
//                                names; none: cpu), this instance's statistics
#include <strings.h>

#include <cerrno>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/c_tensor_info.h"
#include "core/compat2x/filter2x.h"
#include "core/filter_accl.h"

namespace nns::compat2x {
namespace {

struct Exported {
  GstTensorFilterFramework fw;
  const nns_filter_backend_i *b = nullptr;
  std::string name;
  std::vector<accl_hw> hw;
};

struct Inst {
  const Exported *e = nullptr;
  void *priv = nullptr;
  uint32_t num_in = 0, num_out = 0;  // from the last model info (0: use prop's)
  GstTensorFilterFrameworkStatistics stats{};
  std::unique_ptr<nns_tensors_desc> in_desc = std::make_unique<nns_tensors_desc>();
  std::unique_ptr<nns_tensors_desc> out_desc = std::make_unique<nns_tensors_desc>();
};

// Never destroyed: tables handed out stay valid until the process ends, also during exit.
struct Tables {
  std::mutex mu;
  std::map<const nns_filter_backend_i *, std::unique_ptr<Exported>> by_backend;
  std::map<std::string, const Exported *> by_name;
};
Tables &tables() {
  static Tables *t = new Tables;
  return *t;
}

void report(const std::string &msg) {
  std::fprintf(stderr, "nnstreamer_filter_find: %s\n", msg.c_str());
}

const Exported *exported_of(const GstTensorFilterFramework *fw);

const Exported *exported_for_prop(const GstTensorFilterProperties *prop) {
  if (!prop || !prop->fwname) return nullptr;
  {
    Tables &t = tables();
    std::lock_guard lk(t.mu);
    auto it = t.by_name.find(prop->fwname);
    if (it != t.by_name.end()) return it->second;
  }
  return exported_of(nnstreamer_filter_find(prop->fwname));
}

Inst *inst_of(void *priv) {
  return static_cast<Inst *>(priv);
}

std::string accelerators_of(const GstTensorFilterProperties *prop) {
  if (prop->accl_str) return prop->accl_str;
  if (!prop->hw_list || prop->num_hw <= 0) return {};
  std::string s = "true:";
  for (int i = 0; i < prop->num_hw; ++i)
    s += std::string(i ? "," : "") + nns::accl::name_of(prop->hw_list[i]);
  return s;
}

int x_open(const GstTensorFilterProperties *prop, void **private_data) {
  if (!prop || !private_data) return -EINVAL;
  const Exported *e = exported_for_prop(prop);
  if (!e) return -EINVAL;
  try {
    auto c = std::make_unique<Inst>();
    c->e = e;
    nns_filter_props p{};
    p.framework = e->name.c_str();
    p.model_files = prop->model_files;
    p.num_models = prop->num_models > 0 ? static_cast<uint32_t>(prop->num_models) : 0;
    auto in = std::make_unique<nns_tensors_desc>();
    auto out = std::make_unique<nns_tensors_desc>();
    std::memset(in.get(), 0, sizeof *in);
    std::memset(out.get(), 0, sizeof *out);
    if (prop->input_meta.num_tensors > 0) desc_from_gst_info(&prop->input_meta, *in);
    if (prop->output_meta.num_tensors > 0) desc_from_gst_info(&prop->output_meta, *out);
    p.input = in.get();
    p.output = out.get();
    p.custom = prop->custom_properties;
    std::string accl = accelerators_of(prop);
    p.accelerator = accl.empty() ? nullptr : accl.c_str();
    p.input_layout = prop->input_layout;
    p.output_layout = prop->output_layout;
    p.invoke_dynamic = prop->invoke_dynamic;
    char err[1024] = "";
    int rc = e->b->open(&p, &c->priv, err, sizeof err);
    if (rc != 0) {
      report(e->name + ": open failed: " + err);
      return rc < 0 ? rc : -EINVAL;
    }
    c->num_in = in->num_tensors;
    c->num_out = out->num_tensors;
    *private_data = c.release();
    return 0;
  } catch (...) {
    return -ENOMEM;
  }
}

void x_close(const GstTensorFilterProperties *, void **private_data) {
  if (!private_data || !*private_data) return;
  Inst *c = inst_of(*private_data);
  c->e->b->close(c->priv);
  delete c;
  *private_data = nullptr;
}

int x_invoke(const GstTensorFilterFramework *, GstTensorFilterProperties *prop, void *priv,
             const GstTensorMemory *input, GstTensorMemory *output) {
  Inst *c = inst_of(priv);
  if (!c || !input || !output) return -EINVAL;
  const nns_filter_backend_i *b = c->e->b;
  char err[1024] = "";
  auto t0 = std::chrono::steady_clock::now();
  int rc;
  if (prop && prop->invoke_dynamic) {
    if (!b->invoke_dynamic) return -ENOTSUP;
    desc_from_gst_info(&prop->input_meta, *c->in_desc);
    std::memset(c->out_desc.get(), 0, sizeof *c->out_desc);
    rc = b->invoke_dynamic(c->priv, c->in_desc.get(), input, c->out_desc.get(), output, err,
                           sizeof err);
    if (rc == 0) {
      gst_info_clear(&prop->output_meta);
      gst_info_from_desc(*c->out_desc, &prop->output_meta);
    }
  } else {
    uint32_t ni = prop && prop->input_meta.num_tensors ? prop->input_meta.num_tensors : c->num_in;
    uint32_t no =
        prop && prop->output_meta.num_tensors ? prop->output_meta.num_tensors : c->num_out;
    rc = b->invoke(c->priv, input, ni, output, no, err, sizeof err);
  }
  auto us =
      std::chrono::duration_cast<std::chrono::microseconds>(std::chrono::steady_clock::now() - t0)
          .count();
  c->stats.total_invoke_num += 1;
  c->stats.total_invoke_latency += us;
  if (rc < 0) report(c->e->name + ": invoke failed: " + err);
  return rc;
}

void fill_info(const Exported &e, const Inst *c, GstTensorFilterFrameworkInfo *info) {
  std::memset(info, 0, sizeof *info);
  info->name = e.name.c_str();
  info->allow_in_place = 0;
  info->allocate_in_invoke = (e.b->flags & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE) != 0;
  info->run_without_model = (e.b->flags & NNS_FILTER_FLAG_RUN_WITHOUT_MODEL) != 0;
  info->verify_model_path = !info->run_without_model;
  info->hw_list = e.hw.data();
  info->num_hw = static_cast<int>(e.hw.size());
  info->accl_auto = e.hw.front();
  info->accl_default = e.hw.front();
  info->statistics = c ? &c->stats : nullptr;
}

int x_framework_info(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                     void *priv, GstTensorFilterFrameworkInfo *info) {
  if (!info) return -EINVAL;
  const Exported *e = priv ? inst_of(priv)->e : exported_of(self);
  if (!e) e = exported_for_prop(prop);
  if (!e) return -EINVAL;
  fill_info(*e, priv ? inst_of(priv) : nullptr, info);
  return 0;
}

int x_model_info(const GstTensorFilterFramework *, const GstTensorFilterProperties *, void *priv,
                 model_info_ops ops, GstTensorsInfo *in_info, GstTensorsInfo *out_info) {
  Inst *c = inst_of(priv);
  if (!c || !in_info || !out_info) return -EINVAL;
  const nns_filter_backend_i *b = c->e->b;
  char err[1024] = "";
  int rc;
  if (ops == GET_IN_OUT_INFO) {
    std::memset(c->in_desc.get(), 0, sizeof *c->in_desc);
    std::memset(c->out_desc.get(), 0, sizeof *c->out_desc);
    rc = b->get_model_info(c->priv, c->in_desc.get(), c->out_desc.get(), err, sizeof err);
    if (rc == 0) gst_info_from_desc(*c->in_desc, in_info);
  } else if (ops == SET_INPUT_INFO) {
    if (!b->set_input_info) return -ENOENT;
    desc_from_gst_info(in_info, *c->in_desc);
    std::memset(c->out_desc.get(), 0, sizeof *c->out_desc);
    rc = b->set_input_info(c->priv, c->in_desc.get(), c->out_desc.get(), err, sizeof err);
  } else {
    return -EINVAL;
  }
  if (rc == -ENOTSUP) return -ENOENT;
  if (rc != 0) {
    report(c->e->name + ": model info: " + err);
    return rc < 0 ? rc : -EINVAL;
  }
  gst_info_from_desc(*c->out_desc, out_info);
  c->num_in = c->in_desc->num_tensors;
  c->num_out = c->out_desc->num_tensors;
  return 0;
}

int x_event(const GstTensorFilterFramework *self, const GstTensorFilterProperties *, void *priv,
            event_ops ops, GstTensorFilterFrameworkEventData *data) {
  Inst *c = inst_of(priv);
  const Exported *e = c ? c->e : exported_of(self);
  if (!e) return -EINVAL;
  char err[1024] = "";
  switch (ops) {
    case DESTROY_NOTIFY:
      if (!c || !data) return -EINVAL;
      if (e->b->free_output)
        e->b->free_output(c->priv, data->data);
      else
        std::free(data->data);
      return 0;
    case CHECK_HW_AVAILABILITY:
      if (!data) return -EINVAL;
      for (accl_hw h : e->hw)
        if (h == data->hw) return 0;
      return data->hw == ACCL_AUTO || data->hw == ACCL_DEFAULT ? 0 : -ENOENT;
    case SUSPEND:
    case RESUME: {
      if (!c || !e->b->handle_event) return -ENOENT;
      int rc = e->b->handle_event(
          c->priv, ops == SUSPEND ? NNS_FILTER_EVENT_SUSPEND : NNS_FILTER_EVENT_RESUME, err,
          sizeof err);
      return rc == -ENOTSUP ? -ENOENT : rc;
    }
    default:
      return -ENOENT;
  }
}

const Exported *exported_of(const GstTensorFilterFramework *fw) {
  if (!fw || fw->open != x_open) return nullptr;
  return static_cast<const Exported *>(fw->subplugin_data);
}

std::vector<accl_hw> accelerators(const nns_filter_backend_i *b) {
  std::vector<accl_hw> out;
  if (b->check_accelerator) {
    for (accl_hw h :
         {ACCL_CPU, ACCL_CPU_SIMD, ACCL_GPU, ACCL_NPU, ACCL_NPU_MOVIDIUS, ACCL_NPU_EDGE_TPU,
          ACCL_NPU_VIVANTE, ACCL_NPU_SRCN, ACCL_NPU_SLSI, ACCL_NPU_SR}) {
      const char *n = nns::accl::name_of(h);
      if (n && b->check_accelerator(n) == 0) out.push_back(h);
    }
  }
  if (out.empty()) out.push_back(ACCL_CPU);
  return out;
}

}  // namespace

const GstTensorFilterFramework *framework_of_backend(const nns_filter_backend_i *b,
                                                     const std::string &asked) {
  if (!b || !b->name) return nullptr;
  Tables &t = tables();
  std::lock_guard lk(t.mu);
  auto &slot = t.by_backend[b];
  if (!slot) {
    auto e = std::make_unique<Exported>();
    std::memset(&e->fw, 0, sizeof e->fw);
    e->b = b;
    e->name = b->name;
    e->hw = accelerators(b);
    e->fw.version = GST_TENSOR_FILTER_FRAMEWORK_V1;
    e->fw.open = x_open;
    e->fw.close = x_close;
    e->fw.invoke = x_invoke;
    e->fw.getFrameworkInfo = x_framework_info;
    e->fw.getModelInfo = x_model_info;
    e->fw.eventHandler = x_event;
    e->fw.subplugin_data = e.get();
    slot = std::move(e);
    t.by_name.emplace(slot->name, slot.get());
  }
  t.by_name.emplace(asked, slot.get());  // an alias asked for opens the same back end
  return &slot->fw;
}

}  // namespace nns::compat2x

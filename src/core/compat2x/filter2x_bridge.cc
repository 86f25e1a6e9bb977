// SPDX-License-Identifier: LGPL-2.1-only
// The bridge: an nns_filter_backend_i per registered NNStreamer 2.x filter sub-plugin, whose
// functions call the sub-plugin's GstTensorFilterFramework (layout 0 or 1) the way NNStreamer's
// tensor_filter does: open/close around everything, input/output tensors from
// getInput/OutputDimension or setInputDimension (v0) or getModelInfo (v1), invoke_NN / invoke,
// allocate_in_invoke memory released through destroyNotify / DESTROY_NOTIFY (else free()),
// SUSPEND/RESUME events, accelerators from checkAvailability / the framework's hw_list.
//
// Our table's open() and check_accelerator() get no context, so each bridge is bound to one of
// kBridgeSlots slots whose functions know their slot number.
#include <strings.h>

#include <array>
#include <atomic>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <unordered_set>
#include <utility>
#include <vector>

#include "core/c_tensor_info.h"
#include "core/compat2x/filter2x.h"
#include "core/filter_accl.h"
#include "core/filter_builtin_util.h"
#include "core/filter_compat_props.h"

namespace nns::compat2x {
namespace {

using builtin::set_err;

struct Inst {
  const Filter2x *f = nullptr;
  std::unique_ptr<CompatProps> props;
  void *priv = nullptr;
  bool alloc = false;  // this instance's invoke allocates its outputs
  std::vector<accl_hw> hw;
  std::mutex own_mu;
  std::unordered_set<void *> own;  // blocks the bridge allocated (see invoke)
  std::vector<GstTensorMemory> scratch;
  std::string where;
};

std::string where_of(const Filter2x &f) {
  return "NNStreamer 2.x sub-plugin '" + f.name + "' (" + f.origin + ")";
}

const std::pair<const char *, accl_hw> kAccl[] = {
    {"none", ACCL_NONE},
    {"auto", ACCL_AUTO},
    {"default", ACCL_DEFAULT},
    {"cpu.simd", ACCL_CPU_SIMD},
    {"cpu.neon", ACCL_CPU_NEON},
    {"cpu", ACCL_CPU},
    {"gpu", ACCL_GPU},
    {"npu.movidius", ACCL_NPU_MOVIDIUS},
    {"npu.edgetpu", ACCL_NPU_EDGE_TPU},
    {"npu.vivante", ACCL_NPU_VIVANTE},
    {"npu.srcn", ACCL_NPU_SRCN},
    {"npu.slsi", ACCL_NPU_SLSI},
    {"npu.sr", ACCL_NPU_SR},
    {"npu", ACCL_NPU},
};

bool accl_of(std::string s, accl_hw &out) {
  while (!s.empty() && s.front() == ' ') s.erase(s.begin());
  while (!s.empty() && s.back() == ' ') s.pop_back();
  for (auto &[n, v] : kAccl)
    if (strcasecmp(n, s.c_str()) == 0) {
      out = v;
      return true;
    }
  return false;
}

// NNStreamer's reading of accelerator= for version 1 tables (nns::accl::match_all over the
// framework's accelerators plus auto and default): unset -> no list at all (num_hw 0: NNStreamer
// only parses the property when it was given, and a sub-plugin then picks its own default);
// "true[:a,b]" -> the listed accelerators the framework supports, in the given order (none of
// them: auto); anything else -> none. auto/default map to the framework's choice.
std::vector<accl_hw> parse_accelerators(const Filter2x &f, const char *accl) {
  std::vector<accl_hw> out;
  if (!accl || f.hw.empty()) return out;
  auto resolve = [&](accl_hw h) {
    if (h == ACCL_AUTO) return f.info.accl_auto < ACCL_NONE ? f.hw[0] : f.info.accl_auto;
    if (h == ACCL_DEFAULT) return f.info.accl_default < ACCL_NONE ? f.hw[0] : f.info.accl_default;
    return h;
  };
  std::vector<std::string> supported;
  for (accl_hw h : f.hw) supported.emplace_back(nns::accl::name_of(h));
  supported.emplace_back(ACCL_AUTO_STR);
  supported.emplace_back(ACCL_DEFAULT_STR);
  for (accl_hw h : nns::accl::match_all(accl, supported)) out.push_back(resolve(h));
  return out;
}

// Frees a block the sub-plugin allocated in invoke.
void destroy_block(Inst *c, void *data) {
  const GstTensorFilterFramework *fw = c->f->fw;
  if (c->f->version == 0) {
    if (fw->destroyNotify)
      fw->destroyNotify(&c->priv, data);
    else
      std::free(data);
    return;
  }
  GstTensorFilterFrameworkEventData ev;
  std::memset(&ev, 0, sizeof ev);
  ev.data = data;
  if (fw->eventHandler(fw, c->props->get(), c->priv, DESTROY_NOTIFY, &ev) == -ENOENT)
    std::free(data);
}

int call_invoke(Inst *c, const GstTensorMemory *in, GstTensorMemory *out) {
  const GstTensorFilterFramework *fw = c->f->fw;
  if (c->f->version == 0) return fw->invoke_NN(c->props->get(), &c->priv, in, out);
  return fw->invoke(fw, c->props->get(), c->priv, in, out);
}

int bridge_open(const Filter2x &f, const nns_filter_props *p, void **priv, char *err, size_t len) {
  auto c = std::make_unique<Inst>();
  c->f = &f;
  c->where = where_of(f);
  c->props = std::make_unique<CompatProps>(*p);
  GstTensorFilterProperties *prop = c->props->get();
  prop->fw_opened = 0;
  // As NNStreamer: the name the sub-plugin registered (framework= may be an alias or auto).
  // C++ sub-plugins find their table again through nnstreamer_filter_find(prop->fwname).
  prop->fwname = f.name.c_str();
  if (f.version == 1) {
    c->hw = parse_accelerators(f, p->accelerator);
    prop->hw_list = c->hw.empty() ? nullptr : c->hw.data();
    prop->num_hw = static_cast<int>(c->hw.size());
  }
  promote_filter_api();  // it may call nnstreamer_filter_dispatch_output_async()
  const GstTensorFilterFramework *fw = f.fw;
  if (fw->open) {
    int rc = fw->open(prop, &c->priv);
    if (rc < 0) return set_err(err, len, c->where + ": open() returned " + std::to_string(rc), rc);
  }
  prop->fw_opened = 1;
  if (f.version == 0) {
    c->alloc =
        fw->allocate_in_invoke && (!fw->allocateInInvoke || fw->allocateInInvoke(&c->priv) == 0);
  } else {
    GstTensorFilterFrameworkInfo info;
    std::memset(&info, 0, sizeof info);
    int rc = fw->getFrameworkInfo(fw, prop, c->priv, &info);
    if (rc != 0) {
      if (fw->close) fw->close(prop, &c->priv);
      return set_err(err, len,
                     c->where + ": getFrameworkInfo() after open returned " + std::to_string(rc),
                     rc < 0 ? rc : -EINVAL);
    }
    c->alloc = info.allocate_in_invoke != 0;
  }
  c->props->async().set_release(
      [](void *ctx, void *data) { destroy_block(static_cast<Inst *>(ctx), data); }, c.get());
  *priv = c.release();
  return 0;
}

void bridge_close(void *priv) {
  auto *c = static_cast<Inst *>(priv);
  if (!c) return;
  if (c->f->fw->close) c->f->fw->close(c->props->get(), &c->priv);
  {
    std::lock_guard lk(c->own_mu);
    for (void *b : c->own) std::free(b);
  }
  delete c;
}

int bridge_model_info(void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                      size_t len) {
  auto *c = static_cast<Inst *>(priv);
  const GstTensorFilterFramework *fw = c->f->fw;
  if (c->f->version == 0 && (!fw->getInputDimension || !fw->getOutputDimension)) return -ENOTSUP;
  int rc = c->props->query_model_info(in, out, [c, fw](GstTensorsInfo *gi, GstTensorsInfo *go) {
    if (c->f->version != 0)
      return fw->getModelInfo(fw, c->props->get(), c->priv, GET_IN_OUT_INFO, gi, go);
    int r = fw->getInputDimension(c->props->get(), &c->priv, gi);
    return r == 0 ? fw->getOutputDimension(c->props->get(), &c->priv, go) : r;
  });
  if (c->f->version != 0 && rc == -ENOENT) return -ENOTSUP;
  if (rc != 0)
    return set_err(err, len,
                   c->where +
                       (c->f->version == 0 ? ": getInputDimension/getOutputDimension"
                                           : ": getModelInfo(GET_IN_OUT_INFO)") +
                       " returned " + std::to_string(rc));
  return 0;
}

int bridge_set_input(void *priv, const nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                     size_t len) {
  auto *c = static_cast<Inst *>(priv);
  const GstTensorFilterFramework *fw = c->f->fw;
  if (c->f->version == 0 && !fw->setInputDimension) return -ENOTSUP;
  int rc = c->props->negotiate_input(*in, out, [c, fw](GstTensorsInfo *gi, GstTensorsInfo *go) {
    return c->f->version == 0
               ? fw->setInputDimension(c->props->get(), &c->priv, gi, go)
               : fw->getModelInfo(fw, c->props->get(), c->priv, SET_INPUT_INFO, gi, go);
  });
  if (c->f->version == 1 && rc == -ENOENT) return -ENOTSUP;
  if (rc != 0)
    return set_err(
        err, len,
        c->where + (c->f->version == 0 ? ": setInputDimension" : ": getModelInfo(SET_INPUT_INFO)") +
            " returned " + std::to_string(rc));
  return 0;
}

// The table says NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE when the framework's static information
// does; an opened model may still differ (allocateInInvoke(), getFrameworkInfo after open).
int bridge_invoke(void *priv, const GstTensorMemory *in, uint32_t, GstTensorMemory *out,
                  uint32_t num_out, char *err, size_t len) {
  auto *c = static_cast<Inst *>(priv);
  bool table_alloc = (c->f->iface.flags & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE) != 0;
  int rc;
  if (table_alloc == c->alloc) {
    rc = call_invoke(c, in, out);
  } else if (table_alloc) {
    // The host expects us to allocate, the model writes into given memory.
    for (uint32_t i = 0; i < num_out; ++i) {
      out[i].data = std::malloc(out[i].size ? out[i].size : 1);
      if (!out[i].data) return set_err(err, len, c->where + ": out of memory", -ENOMEM);
      std::lock_guard lk(c->own_mu);
      c->own.insert(out[i].data);
    }
    rc = call_invoke(c, in, out);
  } else {
    // The model allocates, the host gave memory: copy and release.
    c->scratch.assign(NNS_TENSOR_SIZE_LIMIT, GstTensorMemory{nullptr, 0});
    for (uint32_t i = 0; i < num_out; ++i) c->scratch[i].size = out[i].size;
    rc = call_invoke(c, in, c->scratch.data());
    for (uint32_t i = 0; i < num_out; ++i) {
      void *d = c->scratch[i].data;
      if (!d) continue;
      if (rc == 0) std::memcpy(out[i].data, d, std::min(out[i].size, c->scratch[i].size));
      destroy_block(c, d);
    }
  }
  if (rc < 0) return set_err(err, len, c->where + ": invoke returned " + std::to_string(rc), rc);
  return rc;
}

// invoke-dynamic=true: as NNStreamer, the sub-plugin allocates every output in invoke and
// describes them in prop->output_meta; the blocks come back through free_output.
int bridge_invoke_dynamic(void *priv, const nns_tensors_desc *in_info, const GstTensorMemory *in,
                          nns_tensors_desc *out_info, GstTensorMemory *out, char *err, size_t len) {
  auto *c = static_cast<Inst *>(priv);
  c->props->set_input(*in_info);
  for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) out[i] = GstTensorMemory{nullptr, 0};
  int rc = call_invoke(c, in, out);
  desc_from_gst_info(&c->props->get()->output_meta, *out_info);
  if (rc != 0) {
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i)
      if (out[i].data) destroy_block(c, out[i].data);
    out_info->num_tensors = 0;
    return set_err(err, len, c->where + ": invoke (dynamic) returned " + std::to_string(rc),
                   rc < 0 ? rc : -EINVAL);
  }
  for (uint32_t i = 0; i < out_info->num_tensors; ++i)
    if (!out[i].data)
      return set_err(err, len,
                     c->where + ": invoke (dynamic) gave no data for output " + std::to_string(i));
  return 0;
}

void bridge_free_output(void *priv, void *data) {
  auto *c = static_cast<Inst *>(priv);
  {
    std::lock_guard lk(c->own_mu);
    if (c->own.erase(data)) {
      std::free(data);
      return;
    }
  }
  destroy_block(c, data);
}

int bridge_event(void *priv, nns_filter_event event, char *err, size_t len) {
  auto *c = static_cast<Inst *>(priv);
  const GstTensorFilterFramework *fw = c->f->fw;
  event_ops op = event == NNS_FILTER_EVENT_SUSPEND ? SUSPEND : RESUME;
  int rc = -ENOENT;
  if (c->f->version == 0) {
    if (fw->handleEvent) rc = fw->handleEvent(op, nullptr);
  } else {
    rc = fw->eventHandler(fw, c->props->get(), c->priv, op, nullptr);
  }
  if (rc == -ENOENT) return -ENOTSUP;
  if (rc != 0)
    return set_err(
        err, len,
        c->where + (op == SUSPEND ? ": SUSPEND" : ": RESUME") + " returned " + std::to_string(rc),
        rc < 0 ? rc : -EINVAL);
  return 0;
}

// invoke-async: outputs come through nnstreamer_filter_dispatch_output_async().
int bridge_invoke_async(void *priv, const nns_tensors_desc *, const GstTensorMemory *in, uint32_t,
                        const nns_filter_async_ctx *ctx, char *err, size_t len) {
  auto *c = static_cast<Inst *>(priv);
  CompatAsync &a = c->props->async();
  ScratchOutputs out(c->props->get()->output_meta);
  GstTensorMemory *mem = out.get();
  if (c->alloc)
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) mem[i].data = nullptr;
  a.begin(*ctx);
  int rc = call_invoke(c, in, mem);
  if (c->alloc)
    for (unsigned i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i)
      if (mem[i].data) destroy_block(c, mem[i].data);
  bool pending = a.end();
  if (rc < 0) return set_err(err, len, c->where + ": invoke returned " + std::to_string(rc), rc);
  return pending ? NNS_FILTER_ASYNC_PENDING : 0;
}

int bridge_check_accl(const Filter2x &f, const char *accl) {
  accl_hw h;
  if (!accl || !accl_of(accl, h)) return -EINVAL;
  if (h == ACCL_AUTO || h == ACCL_DEFAULT) return 0;
  if (f.version == 0)
    return f.fw->checkAvailability && f.fw->checkAvailability(h) == 0 ? 0 : -ENOTSUP;
  for (accl_hw s : f.hw)
    if (s == h) return 0;
  return -ENOTSUP;
}

// ---- slots -----------------------------------------------------------------------------------

std::array<std::atomic<const Filter2x *>, kBridgeSlots> g_slots{};

template <int I>
int slot_open(const nns_filter_props *p, void **priv, char *err, size_t len) {
  const Filter2x *f = g_slots[I].load();
  return builtin::guarded(err, len, [&] { return bridge_open(*f, p, priv, err, len); });
}
template <int I>
int slot_check_accl(const char *accl) {
  return bridge_check_accl(*g_slots[I].load(), accl);
}

using OpenFn = int (*)(const nns_filter_props *, void **, char *, size_t);
using AcclFn = int (*)(const char *);

template <int... I>
constexpr std::array<std::pair<OpenFn, AcclFn>, sizeof...(I)> make_slots(
    std::integer_sequence<int, I...>) {
  return {{{&slot_open<I>, &slot_check_accl<I>}...}};
}
constexpr auto kSlotFns = make_slots(std::make_integer_sequence<int, kBridgeSlots>{});

int next_slot = 0;  // guarded by Filter2xRegistry's mutex (bind_bridge is called under it)

}  // namespace

bool bind_bridge(Filter2x &e) {
  if (next_slot >= kBridgeSlots) return false;
  e.slot = next_slot++;
  g_slots[e.slot].store(&e);
  nns_filter_backend_i &t = e.iface;
  std::memset(&t, 0, sizeof t);
  t.api_version = NNS_FILTER_BACKEND_API_VERSION;
  t.name = e.name.c_str();
  t.flags = 0;
  if (e.info.allocate_in_invoke) t.flags |= NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE;
  t.flags |= NNS_FILTER_FLAG_DYNAMIC;  // prop->invoke_dynamic tells the sub-plugin
  // NNStreamer checks the model files only when the sub-plugin asks for it.
  if (e.info.run_without_model || !e.info.verify_model_path)
    t.flags |= NNS_FILTER_FLAG_RUN_WITHOUT_MODEL;
  t.open = kSlotFns[e.slot].first;
  t.close = bridge_close;
  t.get_model_info = [](void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                        size_t len) {
    return builtin::guarded(err, len, [&] { return bridge_model_info(priv, in, out, err, len); });
  };
  t.set_input_info = [](void *priv, const nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                        size_t len) {
    return builtin::guarded(err, len, [&] { return bridge_set_input(priv, in, out, err, len); });
  };
  t.invoke = [](void *priv, const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
                uint32_t num_out, char *err, size_t len) {
    return builtin::guarded(
        err, len, [&] { return bridge_invoke(priv, in, num_in, out, num_out, err, len); });
  };
  t.free_output = bridge_free_output;
  t.invoke_dynamic = [](void *priv, const nns_tensors_desc *in_info, const GstTensorMemory *in,
                        nns_tensors_desc *out_info, GstTensorMemory *out, char *err, size_t len) {
    return builtin::guarded(err, len, [&] {
      return bridge_invoke_dynamic(priv, in_info, in, out_info, out, err, len);
    });
  };
  t.handle_event = [](void *priv, nns_filter_event ev, char *err, size_t len) {
    return builtin::guarded(err, len, [&] { return bridge_event(priv, ev, err, len); });
  };
  t.check_accelerator = kSlotFns[e.slot].second;
  t.invoke_async = [](void *priv, const nns_tensors_desc *info, const GstTensorMemory *in,
                      uint32_t num_in, const nns_filter_async_ctx *ctx, char *err, size_t len) {
    return builtin::guarded(
        err, len, [&] { return bridge_invoke_async(priv, info, in, num_in, ctx, err, len); });
  };
  return true;
}

}  // namespace nns::compat2x

// SPDX-License-Identifier: LGPL-2.1-only
// ml_single_*: single-shot inference on the same back ends and registry as tensor_filter,
// without GStreamer. Each handle owns one FilterInstance. With a timeout set, invokes run on a
// per-handle worker thread and the caller waits at most that long. Properties:
// ml_single_props.cc; the handle's internals: ml_single_handle.cc.
#include <cstring>
#include <filesystem>

#include "api/ml_model_check.h"
#include "api/ml_nnfw_names.h"
#include "api/ml_single_handle.h"
#include "core/filter_desc.h"
#include "nnstreamer-single.h"

using namespace nns;
using namespace nns::api;

namespace {

// framework= of `nnfw` ("auto" for ANY), accelerator= of `hw` ("" for ANY); nullptr if invalid.
const char *framework_name(ml_nnfw_type_e nnfw) {
  const char *n = nns::ml::nnfw_name(nnfw);
  return n && !*n ? "auto" : n;
}

std::string accelerator_value(const char *hw) {
  return hw && *hw ? std::string("true:") + hw : std::string();
}

// `nnfw`: the framework as an ml_nnfw_type_e (ML_NNFW_TYPE_ANY when given by name or not at all).
int open_common(ml_single_h *single, const char *models, const char *framework, ml_nnfw_type_e nnfw,
                TensorsInfoHandle *in, TensorsInfoHandle *out, const char *custom,
                const char *accel) {
  const std::string fn = "ml_single_open";
  if (!single) return report(ML_ERROR_INVALID_PARAMETER, fn + ": single is NULL");
  *single = nullptr;
  if (!models || !*models) return report(ML_ERROR_INVALID_PARAMETER, fn + ": no model path given");
  if (in && !in->info.valid())
    return report(ML_ERROR_INVALID_PARAMETER, fn + ": input_info is incomplete (" +
                                                  in->info.to_string() +
                                                  "); every tensor needs a type and a dimension");
  if (out && !out->info.valid())
    return report(ML_ERROR_INVALID_PARAMETER, fn + ": output_info is incomplete (" +
                                                  out->info.to_string() +
                                                  "); every tensor needs a type and a dimension");
  auto h = std::make_unique<SingleHandle>();
  h->spec.framework = framework && *framework ? framework : "auto";
  h->spec.models = split(models, ",");
  if (in) h->spec.input = in->info;
  if (out) h->spec.output = out->info;
  h->spec.custom = custom ? custom : "";
  h->spec.accelerator = accel ? accel : "";
  // As NNStreamer: every model path must name a file (or a folder); custom-easy and cpp
  // models are registered names instead.
  if (h->spec.framework != "custom-easy" && h->spec.framework != "cpp")
    for (std::size_t i = 0; i < h->spec.models.size(); ++i) {
      std::error_code ec;
      const std::string &m = h->spec.models[i];
      if (m.empty() || (!std::filesystem::is_regular_file(m, ec) &&
                        !(i == 0 && std::filesystem::is_directory(m, ec))))
        return report(ML_ERROR_INVALID_PARAMETER, fn + ": model path [" + std::to_string(i) +
                                                      "] '" + m +
                                                      "' is not a file that can be read");
    }
  // As NNStreamer, a framework that cannot open these files is refused before it is looked for.
  std::string why;
  if (int rc = nns::ml::check_models_for_nnfw(nnfw, h->spec.models, &why))
    return report(rc, fn + ": " + why);
  try {
    auto conf = current_filter_conf();
    try {
      h->be = FilterRegistry::get().resolve(h->spec.framework, h->spec.models, *conf);
    } catch (const Error &e) {
      // No back end for the framework: NNStreamer's "not supported" (no sub-plugin).
      if (e.kind() == ErrorKind::kNotFound)
        return report(ML_ERROR_NOT_SUPPORTED, fn + ": " + e.what());
      throw;
    }
    h->inst = FilterInstance::open(h->be, h->spec);
    h->apply(settle(*h->inst, in ? &in->info : nullptr, out ? &out->info : nullptr, false));
  } catch (const Error &e) {
    return report(error_code(e), fn + ": " + e.what());
  } catch (const std::exception &e) {
    return report(ML_ERROR_STREAMS_PIPE, fn + ": " + e.what());
  }
  *single = h.release();
  clear_error();
  return ML_ERROR_NONE;
}

std::vector<GstTensorMemory> mems(const TensorsDataHandle &d) {
  std::vector<GstTensorMemory> m;
  for (std::size_t i = 0; i < d.buffers.size(); ++i) m.push_back({d.buffers[i].get(), d.sizes[i]});
  return m;
}

using Bytes = std::vector<std::vector<uint8_t>>;

Bytes copy_of(const TensorsDataHandle &d) {
  Bytes b;
  for (std::size_t i = 0; i < d.buffers.size(); ++i)
    b.emplace_back(d.buffers[i].get(), d.buffers[i].get() + d.sizes[i]);
  return b;
}

std::vector<GstTensorMemory> mems(Bytes &b) {
  std::vector<GstTensorMemory> m;
  for (auto &v : b) m.push_back({v.data(), v.size()});
  return m;
}

// Input data against `info`: tensor count and byte sizes.
int check_input(SingleHandle &h, const std::string &fn, const TensorsDataHandle &in,
                const TensorsInfo &info) {
  if (in.buffers.size() != info.size())
    return h.fail(ML_ERROR_INVALID_PARAMETER,
                  fn + ": input has " + std::to_string(in.buffers.size()) +
                      " tensors, the model takes " + std::to_string(info.size()) + " (" +
                      info.to_string() + ")");
  for (std::size_t i = 0; i < in.sizes.size(); ++i)
    if (in.sizes[i] != info[i].byte_size())
      return h.fail(ML_ERROR_INVALID_PARAMETER,
                    fn + ": input tensor " + std::to_string(i) + " has " +
                        std::to_string(in.sizes[i]) + " bytes, the model takes " +
                        std::to_string(info[i].byte_size()) + " (" + info[i].to_string() + ")");
  return ML_ERROR_NONE;
}

// Fixed-shape invoke into `out` (sized from the output info). mu held.
int invoke_static(SingleHandle &h, std::unique_lock<std::mutex> &lk, const std::string &fn,
                  const TensorsDataHandle &in, TensorsDataHandle &out) {
  std::shared_ptr<FilterInstance> inst = h.inst;
  if (h.timeout_ms == 0) {
    auto inm = mems(in), outm = mems(out);
    return h.run_task(lk, fn, [&] { run_static(*inst, inm, outm); });
  }
  struct Io {
    Bytes in, out;
  };
  auto io = std::make_shared<Io>();
  io->in = copy_of(in);
  for (std::size_t s : out.sizes) io->out.emplace_back(s);
  int rc = h.run_task(lk, fn, [inst, io] {
    auto inm = mems(io->in), outm = mems(io->out);
    run_static(*inst, inm, outm);
  });
  if (rc != ML_ERROR_NONE) return rc;
  for (std::size_t i = 0; i < out.buffers.size(); ++i)
    std::memcpy(out.buffers[i].get(), io->out[i].data(), out.sizes[i]);
  return ML_ERROR_NONE;
}

// The back end's dynamic invoke with the shapes `in_info`; `result` gets the outputs. mu held.
int invoke_dyn(SingleHandle &h, std::unique_lock<std::mutex> &lk, const std::string &fn,
               const TensorsDataHandle &in, const TensorsInfo &in_info,
               std::unique_ptr<TensorsDataHandle> &result) {
  std::shared_ptr<FilterInstance> inst = h.inst;
  if (h.timeout_ms == 0) {
    auto inm = mems(in);
    return h.run_task(lk, fn, [&] { result = run_dynamic(*inst, in_info, inm); });
  }
  struct Io {
    Bytes in;
    TensorsInfo info;
    std::unique_ptr<TensorsDataHandle> out;
  };
  auto io = std::make_shared<Io>();
  io->in = copy_of(in);
  io->info = in_info;
  int rc = h.run_task(lk, fn, [inst, io] { io->out = run_dynamic(*inst, io->info, mems(io->in)); });
  if (rc == ML_ERROR_NONE) result = std::move(io->out);
  return rc;
}

}  // namespace

namespace nns::api {

int apply_input_info(SingleHandle &h, const TensorsInfo &info, const std::string &fn) {
  if (info.same_as(h.in)) {
    for (std::size_t i = 0; i < info.size(); ++i)
      if (!info[i].name.empty()) h.in[i].name = info[i].name;
    return ML_ERROR_NONE;
  }
  TensorsInfo out;
  try {
    if (!h.inst->set_input_info(info, out)) {
      if (h.dynamic) {  // output decided per call: nothing to ask the back end
        h.in = info;
        return ML_ERROR_NONE;
      }
      return h.fail(ML_ERROR_NOT_SUPPORTED, fn + ": " + h.inst->describe() +
                                                " cannot change its input from " +
                                                h.in.to_string() + " to " + info.to_string() +
                                                ": the back end runs this model with fixed input "
                                                "shapes only");
    }
  } catch (const Error &e) {
    return h.fail(ML_ERROR_INVALID_PARAMETER, fn + ": " + e.what());
  }
  h.in = info;
  h.out = out;
  h.out_from_user = false;
  h.dynamic = out.size() == 0 && supports_dynamic(*h.inst);
  return ML_ERROR_NONE;
}

}  // namespace nns::api

NNS_API int ml_single_open_full(ml_single_h *single, const char *model,
                                const ml_tensors_info_h input_info,
                                const ml_tensors_info_h output_info, ml_nnfw_type_e nnfw,
                                ml_nnfw_hw_e hw, const char *custom_option) {
  const char *fw = framework_name(nnfw);
  if (!fw)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_single_open: nnfw " + std::to_string(nnfw) + " is not a framework type");
  const char *accel = nns::ml::hw_name(hw);
  if (!accel)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_single_open: hw " + std::to_string(hw) + " is not a hardware type");
  TensorsInfoHandle *in = input_info ? as_info(input_info) : nullptr;
  TensorsInfoHandle *out = output_info ? as_info(output_info) : nullptr;
  if ((input_info && !in) || (output_info && !out))
    return report(ML_ERROR_INVALID_PARAMETER, "ml_single_open: invalid tensors-info handle");
  return open_common(single, model, fw, nnfw, in, out, custom_option,
                     accelerator_value(accel).c_str());
}

NNS_API int ml_single_open(ml_single_h *single, const char *model,
                           const ml_tensors_info_h input_info, const ml_tensors_info_h output_info,
                           ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw) {
  return ml_single_open_full(single, model, input_info, output_info, nnfw, hw, nullptr);
}

NNS_API int ml_single_open_with_option(ml_single_h *single, const ml_option_h option) {
  const std::string fn = "ml_single_open_with_option";
  if (!option) return report(ML_ERROR_INVALID_PARAMETER, fn + ": option is NULL");
  auto get = [&](const char *key) -> void * {
    void *v = nullptr;
    return ml_option_get(option, key, &v) == ML_ERROR_NONE ? v : nullptr;
  };
  if (!as_option(option))
    return report(ML_ERROR_INVALID_PARAMETER, fn + ": option is not an ml_option_h");
  const char *models = static_cast<const char *>(get("models"));
  const char *fw = static_cast<const char *>(get("framework_name"));
  if (!fw) fw = static_cast<const char *>(get("framework"));
  ml_nnfw_type_e by_type = ML_NNFW_TYPE_ANY;
  if (!fw) {
    auto *nnfw = static_cast<ml_nnfw_type_e *>(get("nnfw"));
    if (nnfw) by_type = *nnfw;
    fw = framework_name(by_type);
    if (!fw)
      return report(ML_ERROR_INVALID_PARAMETER,
                    fn + ": \"nnfw\" " + std::to_string(*nnfw) + " is not a framework type");
  }
  auto *hw = static_cast<ml_nnfw_hw_e *>(get("hw"));
  const char *accel = nns::ml::hw_name(hw ? *hw : ML_NNFW_HW_ANY);
  if (!accel)
    return report(ML_ERROR_INVALID_PARAMETER,
                  fn + ": \"hw\" " + std::to_string(*hw) + " is not a hardware type");
  void *in_v = get("input_info"), *out_v = get("output_info");
  TensorsInfoHandle *in = as_info(in_v), *out = as_info(out_v);
  if ((in_v && !in) || (out_v && !out))
    return report(ML_ERROR_INVALID_PARAMETER, fn + ": \"" +
                                                  (in_v && !in ? "input_info" : "output_info") +
                                                  "\" is not an ml_tensors_info_h");
  return open_common(single, models, fw, by_type, in, out, static_cast<const char *>(get("custom")),
                     accelerator_value(accel).c_str());
}

NNS_API int ml_single_close(ml_single_h single) {
  REQUIRE_SINGLE(h, single);
  h->magic = 0;
  delete h;  // waits for a timed-out invoke still running
  return ML_ERROR_NONE;
}

NNS_API int ml_single_invoke(ml_single_h single, const ml_tensors_data_h input,
                             ml_tensors_data_h *output) {
  const std::string fn = "ml_single_invoke";
  REQUIRE_SINGLE(h, single);
  TensorsDataHandle *in = as_data(input);
  if (!in || !output) return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": invalid input or output");
  std::unique_lock<std::mutex> lk(h->mu);
  REQUIRE_IDLE(h, fn);
  if (int rc = check_input(*h, fn, *in, h->in)) return rc;
  std::unique_ptr<TensorsDataHandle> out;
  int rc;
  try {
    if (h->dynamic) {
      rc = invoke_dyn(*h, lk, fn, *in, h->in, out);
      if (rc == ML_ERROR_NONE) h->out = out->info;
    } else {
      out.reset(new_data(h->out));
      rc = invoke_static(*h, lk, fn, *in, *out);
    }
  } catch (const std::bad_alloc &) {
    return h->fail(ML_ERROR_OUT_OF_MEMORY, fn + ": out of memory");
  }
  if (rc == ML_ERROR_NONE) *output = out.release();
  return rc;
}

NNS_API int ml_single_invoke_fast(ml_single_h single, const ml_tensors_data_h input,
                                  ml_tensors_data_h output) {
  const std::string fn = "ml_single_invoke_fast";
  REQUIRE_SINGLE(h, single);
  TensorsDataHandle *in = as_data(input);
  TensorsDataHandle *out = as_data(output);
  if (!in || !out) return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": invalid input or output");
  std::unique_lock<std::mutex> lk(h->mu);
  REQUIRE_IDLE(h, fn);
  if (int rc = check_input(*h, fn, *in, h->in)) return rc;
  auto check_output = [&](const TensorsInfo &info) {
    if (out->sizes.size() != info.size())
      return h->fail(ML_ERROR_INVALID_PARAMETER,
                     fn + ": output has " + std::to_string(out->sizes.size()) +
                         " tensors, the model gives " + std::to_string(info.size()) + " (" +
                         info.to_string() + ")");
    for (std::size_t i = 0; i < out->sizes.size(); ++i)
      if (out->sizes[i] != info[i].byte_size())
        return h->fail(ML_ERROR_INVALID_PARAMETER,
                       fn + ": output tensor " + std::to_string(i) + " has " +
                           std::to_string(out->sizes[i]) + " bytes, the model gives " +
                           std::to_string(info[i].byte_size()) + " (" + info[i].to_string() + ")");
    return static_cast<int>(ML_ERROR_NONE);
  };
  if (!h->dynamic) {
    if (int rc = check_output(h->out)) return rc;
    return invoke_static(*h, lk, fn, *in, *out);
  }
  if (h->out.size() > 0)
    if (int rc = check_output(h->out)) return rc;
  std::unique_ptr<TensorsDataHandle> res;
  if (int rc = invoke_dyn(*h, lk, fn, *in, h->in, res)) return rc;
  h->out = res->info;
  if (int rc = check_output(res->info)) return rc;
  for (std::size_t i = 0; i < out->buffers.size(); ++i)
    std::memcpy(out->buffers[i].get(), res->buffers[i].get(), out->sizes[i]);
  return ML_ERROR_NONE;
}

NNS_API int ml_single_invoke_dynamic(ml_single_h single, const ml_tensors_data_h input,
                                     const ml_tensors_info_h in_info, ml_tensors_data_h *output,
                                     ml_tensors_info_h *out_info) {
  const std::string fn = "ml_single_invoke_dynamic";
  REQUIRE_SINGLE(h, single);
  TensorsDataHandle *in = as_data(input);
  TensorsInfoHandle *ii = as_info(in_info);
  if (!in || !ii || !output || !out_info)
    return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": " +
                                                   (!in       ? "input"
                                                    : !ii     ? "in_info"
                                                    : !output ? "output"
                                                              : "out_info") +
                                                   " is NULL or invalid");
  *output = nullptr;
  *out_info = nullptr;
  if (!ii->info.valid())
    return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": in_info is incomplete (" +
                                                   ii->info.to_string() +
                                                   "); every tensor needs a type and a dimension");
  std::unique_lock<std::mutex> lk(h->mu);
  REQUIRE_IDLE(h, fn);
  if (int rc = check_input(*h, fn, *in, ii->info)) return rc;
  std::unique_ptr<TensorsDataHandle> out;
  int rc;
  try {
    bool same = ii->info.same_as(h->in);
    if (supports_dynamic(*h->inst) && (h->dynamic || !h->declared || !same)) {
      // The back end takes this call's shapes and reports the output's.
      rc = invoke_dyn(*h, lk, fn, *in, ii->info, out);
      if (rc != ML_ERROR_NONE) return rc;
      if (!ii->info.same_as(h->in) || !out->info.same_as(h->out)) {
        h->in = ii->info;
        h->out = out->info;
        h->out_from_user = false;
        h->dynamic = true;  // later invokes follow these shapes through the dynamic invoke
      }
    } else {
      // As NNStreamer: set the input info (same shapes: nothing to do), invoke; the previous
      // info is restored on failure.
      TensorsInfo prev = h->in;
      if ((rc = apply_input_info(*h, ii->info, fn))) return rc;
      out.reset(new_data(h->out));
      rc = invoke_static(*h, lk, fn, *in, *out);
      if (rc != ML_ERROR_NONE) {
        if (rc != ML_ERROR_TIMED_OUT) {
          std::string err = h->last_error;
          apply_input_info(*h, prev, fn);
          h->fail(rc, err);
        }
        return rc;
      }
    }
    if ((rc = new_info_handle(out->info, out_info))) return rc;
  } catch (const std::bad_alloc &) {
    return h->fail(ML_ERROR_OUT_OF_MEMORY, fn + ": out of memory");
  }
  *output = out.release();
  return ML_ERROR_NONE;
}

static int get_info(ml_single_h single, ml_tensors_info_h *info, bool input) {
  const std::string fn = input ? "ml_single_get_input_info" : "ml_single_get_output_info";
  REQUIRE_SINGLE(h, single);
  if (!info) return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": info is NULL");
  std::lock_guard<std::mutex> g(h->mu);
  return new_info_handle(input ? h->in : h->out, info);
}

NNS_API int ml_single_get_input_info(ml_single_h single, ml_tensors_info_h *info) {
  return get_info(single, info, true);
}

NNS_API int ml_single_get_output_info(ml_single_h single, ml_tensors_info_h *info) {
  return get_info(single, info, false);
}

NNS_API int ml_single_set_input_info(ml_single_h single, const ml_tensors_info_h info) {
  const std::string fn = "ml_single_set_input_info";
  REQUIRE_SINGLE(h, single);
  TensorsInfoHandle *p = as_info(info);
  if (!p) return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": info is NULL or invalid");
  if (!p->info.valid())
    return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": info is incomplete (" + p->info.to_string() +
                                                   "); every tensor needs a type and a dimension");
  std::unique_lock<std::mutex> lk(h->mu);
  REQUIRE_IDLE(h, fn);
  return apply_input_info(*h, p->info, fn);
}

NNS_API int ml_single_set_timeout(ml_single_h single, unsigned int timeout) {
  REQUIRE_SINGLE(h, single);
  std::lock_guard<std::mutex> g(h->mu);
  h->timeout_ms = timeout;
  return ML_ERROR_NONE;
}

NNS_API const char *ml_single_get_last_error(ml_single_h single) {
  SingleHandle *h = as_single(single);
  return h ? h->last_error.c_str() : "invalid handle";
}

// SPDX-License-Identifier: LGPL-2.1-only
// ml_single_*: single-shot inference on the same back ends and registry as tensor_filter,
// without GStreamer. Each handle owns one FilterInstance. With a timeout set, invokes run on a
// per-handle worker thread and the caller waits at most that long.
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <mutex>
#include <thread>

#include "api/ml_handles.h"
#include "core/error.h"
#include "core/filter_instance.h"
#include "core/filter_registry.h"
#include "nnstreamer-single.h"

using namespace nns;
using namespace nns::api;

#define NNS_API extern "C" __attribute__((visibility("default")))

namespace {

const char *framework_name(ml_nnfw_type_e nnfw) {
  switch (nnfw) {
    case ML_NNFW_TYPE_ANY: return "auto";
    case ML_NNFW_TYPE_CUSTOM_FILTER: return "custom";
    case ML_NNFW_TYPE_TENSORFLOW_LITE: return "tensorflow-lite";
    case ML_NNFW_TYPE_TENSORFLOW: return "tensorflow";
    case ML_NNFW_TYPE_NNFW: return "nnfw";
    case ML_NNFW_TYPE_MVNC: return "movidius-ncsdk2";
    case ML_NNFW_TYPE_OPENVINO: return "openvino";
    case ML_NNFW_TYPE_VIVANTE: return "vivante";
    case ML_NNFW_TYPE_EDGE_TPU: return "edgetpu";
    case ML_NNFW_TYPE_ARMNN: return "armnn";
    case ML_NNFW_TYPE_SNPE: return "snpe";
    case ML_NNFW_TYPE_PYTORCH: return "pytorch";
    case ML_NNFW_TYPE_NNTR_INF: return "nntrainer";
    case ML_NNFW_TYPE_VD_AIFW: return "vd_aifw";
    case ML_NNFW_TYPE_TRIX_ENGINE: return "trix-engine";
    case ML_NNFW_TYPE_MXNET: return "mxnet";
    case ML_NNFW_TYPE_TVM: return "tvm";
    case ML_NNFW_TYPE_ONNX_RUNTIME: return "onnxruntime";
    case ML_NNFW_TYPE_NCNN: return "ncnn";
    case ML_NNFW_TYPE_TENSORRT: return "tensorrt";
    case ML_NNFW_TYPE_QNN: return "qnn";
    case ML_NNFW_TYPE_LLAMACPP: return "llamacpp";
    case ML_NNFW_TYPE_TIZEN_HAL: return "tizen-hal";
    case ML_NNFW_TYPE_SNAP: return "snap";
  }
  return nullptr;
}

const char *accelerator_for(ml_nnfw_hw_e hw) {
  switch (hw) {
    case ML_NNFW_HW_ANY: return "";
    case ML_NNFW_HW_AUTO: return "true:auto";
    case ML_NNFW_HW_CPU: return "true:cpu";
    case ML_NNFW_HW_CPU_SIMD: return "true:cpu.simd";
    case ML_NNFW_HW_GPU: return "true:gpu";
    case ML_NNFW_HW_NPU: return "true:npu";
    case ML_NNFW_HW_NPU_MOVIDIUS: return "true:npu.movidius";
    case ML_NNFW_HW_NPU_EDGE_TPU: return "true:npu.edgetpu";
    case ML_NNFW_HW_NPU_VIVANTE: return "true:npu.vivante";
    case ML_NNFW_HW_NPU_SLSI: return "true:npu.slsi";
    case ML_NNFW_HW_NPU_SR: return "true:npu.sr";
  }
  return nullptr;
}

// One pending invoke for the timeout worker.
struct Job {
  std::vector<std::vector<uint8_t>> in, out;  // copies: the caller may leave on timeout
  int rc = 0;
  std::string error;
  bool done = false;
};

struct SingleHandle {
  uint32_t magic = kSingleMagic;
  std::shared_ptr<FilterInstance> inst;
  FilterOpenSpec spec;
  TensorsInfo in, out;
  std::mutex mu;  // one invoke at a time; guards everything below
  unsigned timeout_ms = 0;
  std::string last_error;

  // Timeout worker
  std::thread worker;
  std::condition_variable cv;
  std::shared_ptr<Job> job;  // set while the worker has work
  bool quit = false;

  ~SingleHandle() {
    {
      std::lock_guard<std::mutex> g(mu);
      quit = true;
    }
    cv.notify_all();
    if (worker.joinable()) worker.join();
  }

  int fail(int code, const std::string &msg) {
    last_error = msg;
    return report(code, msg);
  }

  // Runs the model on raw pointers; throws nns::Error.
  void run(const std::vector<GstTensorMemory> &inm, std::vector<GstTensorMemory> &outm) {
    bool allocates = inst->flags() & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE;
    std::vector<GstTensorMemory> tmp = outm;
    std::shared_ptr<FilterSession> used;
    int rc = inst->invoke(inm.data(), static_cast<uint32_t>(inm.size()), tmp.data(),
                          static_cast<uint32_t>(tmp.size()), allocates ? &used : nullptr);
    if (rc > 0) nns::fail(ErrorKind::kLibrary, inst->describe() + ": the back end dropped the frame");
    if (allocates) {
      for (std::size_t i = 0; i < tmp.size(); ++i) {
        if (tmp[i].size != outm[i].size) {
          if (used) used->free_output(tmp[i].data);
          nns::fail(ErrorKind::kLibrary, inst->describe() + ": output " + std::to_string(i) +
                                             " has " + std::to_string(tmp[i].size) +
                                             " bytes, expected " + std::to_string(outm[i].size));
        }
        std::memcpy(outm[i].data, tmp[i].data, tmp[i].size);
        if (used) used->free_output(tmp[i].data);
      }
    }
  }

  void worker_loop() {
    std::unique_lock<std::mutex> lk(mu);
    for (;;) {
      cv.wait(lk, [&] { return quit || (job && !job->done); });
      if (quit) return;
      std::shared_ptr<Job> j = job;
      lk.unlock();
      std::vector<GstTensorMemory> inm, outm;
      for (auto &b : j->in) inm.push_back({b.data(), b.size()});
      for (auto &b : j->out) outm.push_back({b.data(), b.size()});
      try {
        run(inm, outm);
      } catch (const std::exception &e) {
        j->rc = ML_ERROR_STREAMS_PIPE;
        j->error = e.what();
      }
      lk.lock();
      j->done = true;
      cv.notify_all();
    }
  }
};

SingleHandle *as_single(ml_single_h h) {
  auto *p = static_cast<SingleHandle *>(h);
  return p && p->magic == kSingleMagic ? p : nullptr;
}

int map_error(const Error &e) {
  switch (e.kind()) {
    case ErrorKind::kSettings: return ML_ERROR_INVALID_PARAMETER;
    case ErrorKind::kNotFound: return ML_ERROR_INVALID_PARAMETER;
    case ErrorKind::kNegotiation: return ML_ERROR_INVALID_PARAMETER;
    default: return ML_ERROR_STREAMS_PIPE;
  }
}

// Opens the model and settles its input/output info. Throws nns::Error.
void open_handle(SingleHandle &h, const TensorsInfo *in_given, const TensorsInfo *out_given) {
  auto conf = current_filter_conf();
  BackendRef be = FilterRegistry::get().resolve(h.spec.framework, h.spec.models, *conf);
  h.inst = FilterInstance::open(be, h.spec);
  TensorsInfo mi, mo;
  bool known = h.inst->model_info(mi, mo);
  if (known && (!in_given || in_given->same_as(mi))) {
    h.in = mi;
    h.out = mo;
  } else if (in_given) {
    TensorsInfo out;
    if (h.inst->set_input_info(*in_given, out)) {
      h.in = *in_given;
      h.out = out;
    } else if (!known && out_given) {
      h.in = *in_given;
      h.out = *out_given;
    } else {
      fail(ErrorKind::kNegotiation,
           h.inst->describe() + ": the given input info (" + in_given->to_string() +
               ") does not match the model's input (" + (known ? mi.to_string() : "unknown") +
               ") and the back end cannot change its input");
    }
  } else {
    fail(ErrorKind::kSettings, h.inst->describe() +
                                   ": the model does not declare its input and output; give "
                                   "input_info and output_info");
  }
  if (out_given && !out_given->same_as(h.out))
    fail(ErrorKind::kNegotiation, h.inst->describe() + ": the given output info (" +
                                      out_given->to_string() + ") does not match the model's (" +
                                      h.out.to_string() + ")");
  if (!h.in.valid() || !h.out.valid())
    fail(ErrorKind::kSettings, h.inst->describe() + ": incomplete tensor info (input " +
                                   h.in.to_string() + ", output " + h.out.to_string() + ")");
}

int open_common(ml_single_h *single, const char *models, const char *framework,
                TensorsInfoHandle *in, TensorsInfoHandle *out, const char *custom,
                const char *accel) {
  if (!single) return report(ML_ERROR_INVALID_PARAMETER, "ml_single_open: single is NULL");
  *single = nullptr;
  if (!models || !*models)
    return report(ML_ERROR_INVALID_PARAMETER, "ml_single_open: no model path given");
  auto h = std::make_unique<SingleHandle>();
  h->spec.framework = framework ? framework : "auto";
  h->spec.models = split(models, ",");
  if (in) h->spec.input = in->info;
  if (out) h->spec.output = out->info;
  h->spec.custom = custom ? custom : "";
  h->spec.accelerator = accel ? accel : "";
  try {
    open_handle(*h, in ? &in->info : nullptr, out ? &out->info : nullptr);
  } catch (const Error &e) {
    return report(map_error(e), std::string("ml_single_open: ") + e.what());
  } catch (const std::exception &e) {
    return report(ML_ERROR_STREAMS_PIPE, std::string("ml_single_open: ") + e.what());
  }
  *single = h.release();
  clear_error();
  return ML_ERROR_NONE;
}

int invoke_into(SingleHandle &h, TensorsDataHandle &in, TensorsDataHandle &out) {
  if (in.buffers.size() != h.in.size())
    return h.fail(ML_ERROR_INVALID_PARAMETER,
                  "ml_single_invoke: input has " + std::to_string(in.buffers.size()) +
                      " tensors, the model takes " + std::to_string(h.in.size()) + " (" +
                      h.in.to_string() + ")");
  for (std::size_t i = 0; i < in.sizes.size(); ++i)
    if (in.sizes[i] != h.in[i].byte_size())
      return h.fail(ML_ERROR_INVALID_PARAMETER,
                    "ml_single_invoke: input tensor " + std::to_string(i) + " has " +
                        std::to_string(in.sizes[i]) + " bytes, the model takes " +
                        std::to_string(h.in[i].byte_size()) + " (" + h.in[i].to_string() + ")");
  std::unique_lock<std::mutex> lk(h.mu);
  if (h.timeout_ms == 0) {
    std::vector<GstTensorMemory> inm, outm;
    for (std::size_t i = 0; i < in.buffers.size(); ++i) inm.push_back({in.buffers[i].get(), in.sizes[i]});
    for (std::size_t i = 0; i < out.buffers.size(); ++i)
      outm.push_back({out.buffers[i].get(), out.sizes[i]});
    try {
      h.run(inm, outm);
    } catch (const std::exception &e) {
      return h.fail(ML_ERROR_STREAMS_PIPE, std::string("ml_single_invoke: ") + e.what());
    }
    return ML_ERROR_NONE;
  }
  if (h.job && !h.job->done)
    return h.fail(ML_ERROR_TRY_AGAIN,
                  "ml_single_invoke: the previous invoke timed out and is still running");
  if (!h.worker.joinable()) h.worker = std::thread([&h] { h.worker_loop(); });
  auto j = std::make_shared<Job>();
  for (std::size_t i = 0; i < in.buffers.size(); ++i)
    j->in.emplace_back(in.buffers[i].get(), in.buffers[i].get() + in.sizes[i]);
  for (std::size_t s : out.sizes) j->out.emplace_back(s);
  h.job = j;
  h.cv.notify_all();
  if (!h.cv.wait_for(lk, std::chrono::milliseconds(h.timeout_ms), [&] { return j->done; }))
    return h.fail(ML_ERROR_TIMED_OUT, "ml_single_invoke: " + h.inst->describe() +
                                          " did not finish within " +
                                          std::to_string(h.timeout_ms) + " ms");
  if (j->rc) return h.fail(j->rc, "ml_single_invoke: " + j->error);
  for (std::size_t i = 0; i < out.buffers.size(); ++i)
    std::memcpy(out.buffers[i].get(), j->out[i].data(), out.sizes[i]);
  return ML_ERROR_NONE;
}

}  // namespace

#define REQUIRE_SINGLE(var, h)                                                            \
  SingleHandle *var = as_single(h);                                                       \
  if (!var)                                                                               \
    return report(ML_ERROR_INVALID_PARAMETER,                                             \
                  std::string(__func__) + ": the single handle is NULL or invalid")

NNS_API int ml_single_open_full(ml_single_h *single, const char *model,
                                const ml_tensors_info_h input_info,
                                const ml_tensors_info_h output_info, ml_nnfw_type_e nnfw,
                                ml_nnfw_hw_e hw, const char *custom_option) {
  const char *fw = framework_name(nnfw);
  if (!fw)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_single_open: nnfw " + std::to_string(nnfw) + " is not a framework type");
  const char *accel = accelerator_for(hw);
  if (!accel)
    return report(ML_ERROR_INVALID_PARAMETER,
                  "ml_single_open: hw " + std::to_string(hw) + " is not a hardware type");
  TensorsInfoHandle *in = input_info ? as_info(input_info) : nullptr;
  TensorsInfoHandle *out = output_info ? as_info(output_info) : nullptr;
  if ((input_info && !in) || (output_info && !out))
    return report(ML_ERROR_INVALID_PARAMETER, "ml_single_open: invalid tensors-info handle");
  return open_common(single, model, fw, in, out, custom_option, accel);
}

NNS_API int ml_single_open(ml_single_h *single, const char *model,
                           const ml_tensors_info_h input_info, const ml_tensors_info_h output_info,
                           ml_nnfw_type_e nnfw, ml_nnfw_hw_e hw) {
  return ml_single_open_full(single, model, input_info, output_info, nnfw, hw, nullptr);
}

NNS_API int ml_single_open_with_option(ml_single_h *single, const ml_option_h option) {
  void *v = nullptr;
  auto get = [&](const char *key) -> void * {
    return ml_option_get(option, key, &v) == ML_ERROR_NONE ? v : nullptr;
  };
  if (!option) return report(ML_ERROR_INVALID_PARAMETER, "ml_single_open_with_option: option is NULL");
  const char *models = static_cast<const char *>(get("models"));
  const char *fw = static_cast<const char *>(get("framework_name"));
  if (!fw) {
    auto *nnfw = static_cast<ml_nnfw_type_e *>(get("nnfw"));
    fw = framework_name(nnfw ? *nnfw : ML_NNFW_TYPE_ANY);
    if (!fw) return report(ML_ERROR_INVALID_PARAMETER, "ml_single_open_with_option: bad nnfw");
  }
  auto *hw = static_cast<ml_nnfw_hw_e *>(get("hw"));
  const char *accel = accelerator_for(hw ? *hw : ML_NNFW_HW_ANY);
  if (!accel) return report(ML_ERROR_INVALID_PARAMETER, "ml_single_open_with_option: bad hw");
  TensorsInfoHandle *in = as_info(get("input_info"));
  TensorsInfoHandle *out = as_info(get("output_info"));
  return open_common(single, models, fw, in, out, static_cast<const char *>(get("custom")),
                     accel);
}

NNS_API int ml_single_close(ml_single_h single) {
  REQUIRE_SINGLE(h, single);
  h->magic = 0;
  delete h;  // waits for a timed-out invoke still running
  return ML_ERROR_NONE;
}

NNS_API int ml_single_invoke(ml_single_h single, const ml_tensors_data_h input,
                             ml_tensors_data_h *output) {
  REQUIRE_SINGLE(h, single);
  TensorsDataHandle *in = as_data(input);
  if (!in || !output)
    return h->fail(ML_ERROR_INVALID_PARAMETER, "ml_single_invoke: invalid input or output");
  std::unique_ptr<TensorsDataHandle> out;
  try {
    out.reset(new_data(h->out));
  } catch (const std::bad_alloc &) {
    return h->fail(ML_ERROR_OUT_OF_MEMORY, "ml_single_invoke: out of memory");
  }
  int rc = invoke_into(*h, *in, *out);
  if (rc == ML_ERROR_NONE) *output = out.release();
  return rc;
}

NNS_API int ml_single_invoke_fast(ml_single_h single, const ml_tensors_data_h input,
                                  ml_tensors_data_h output) {
  REQUIRE_SINGLE(h, single);
  TensorsDataHandle *in = as_data(input);
  TensorsDataHandle *out = as_data(output);
  if (!in || !out)
    return h->fail(ML_ERROR_INVALID_PARAMETER, "ml_single_invoke_fast: invalid input or output");
  if (out->sizes.size() != h->out.size())
    return h->fail(ML_ERROR_INVALID_PARAMETER, "ml_single_invoke_fast: output has " +
                                                   std::to_string(out->sizes.size()) +
                                                   " tensors, the model gives " +
                                                   std::to_string(h->out.size()));
  for (std::size_t i = 0; i < out->sizes.size(); ++i)
    if (out->sizes[i] != h->out[i].byte_size())
      return h->fail(ML_ERROR_INVALID_PARAMETER,
                     "ml_single_invoke_fast: output tensor " + std::to_string(i) + " has " +
                         std::to_string(out->sizes[i]) + " bytes, the model gives " +
                         std::to_string(h->out[i].byte_size()));
  return invoke_into(*h, *in, *out);
}

static int get_info(ml_single_h single, ml_tensors_info_h *info, bool input) {
  REQUIRE_SINGLE(h, single);
  if (!info) return report(ML_ERROR_INVALID_PARAMETER, "ml_single_get_*_info: info is NULL");
  auto *p = new (std::nothrow) TensorsInfoHandle();
  if (!p) return report(ML_ERROR_OUT_OF_MEMORY, "ml_single_get_*_info");
  std::lock_guard<std::mutex> g(h->mu);
  p->info = input ? h->in : h->out;
  *info = p;
  return ML_ERROR_NONE;
}

NNS_API int ml_single_get_input_info(ml_single_h single, ml_tensors_info_h *info) {
  return get_info(single, info, true);
}

NNS_API int ml_single_get_output_info(ml_single_h single, ml_tensors_info_h *info) {
  return get_info(single, info, false);
}

NNS_API int ml_single_set_input_info(ml_single_h single, const ml_tensors_info_h info) {
  REQUIRE_SINGLE(h, single);
  TensorsInfoHandle *p = as_info(info);
  if (!p || !p->info.valid())
    return h->fail(ML_ERROR_INVALID_PARAMETER, "ml_single_set_input_info: invalid info");
  std::lock_guard<std::mutex> g(h->mu);
  if (h->job && !h->job->done)
    return h->fail(ML_ERROR_TRY_AGAIN, "ml_single_set_input_info: an invoke is still running");
  TensorsInfo out;
  try {
    if (!h->inst->set_input_info(p->info, out))
      return h->fail(ML_ERROR_NOT_SUPPORTED, "ml_single_set_input_info: " + h->inst->describe() +
                                                 " cannot change its input to " +
                                                 p->info.to_string());
  } catch (const std::exception &e) {
    return h->fail(ML_ERROR_INVALID_PARAMETER, std::string("ml_single_set_input_info: ") + e.what());
  }
  h->in = p->info;
  h->out = out;
  return ML_ERROR_NONE;
}

NNS_API int ml_single_set_timeout(ml_single_h single, unsigned int timeout) {
  REQUIRE_SINGLE(h, single);
  std::lock_guard<std::mutex> g(h->mu);
  h->timeout_ms = timeout;
  return ML_ERROR_NONE;
}

NNS_API int ml_single_set_property(ml_single_h single, const char *name, const char *value) {
  REQUIRE_SINGLE(h, single);
  if (!name || !value)
    return h->fail(ML_ERROR_INVALID_PARAMETER, "ml_single_set_property: NULL argument");
  std::string n = name;
  if (n != "input" && n != "inputtype")
    return h->fail(ML_ERROR_NOT_SUPPORTED, "ml_single_set_property: property '" + n +
                                               "' cannot be changed after open (input, "
                                               "inputtype can)");
  TensorsInfoHandle tmp;
  tmp.info = h->in;
  try {
    if (n == "input") {
      auto dims = parse_dims_list(value, "input");
      if (dims.size() != tmp.info.size()) tmp.info.tensors.resize(dims.size(), tmp.info[0]);
      for (std::size_t i = 0; i < dims.size(); ++i) tmp.info[i].dims = dims[i];
    } else {
      auto types = parse_types_list(value, "inputtype");
      if (types.size() != tmp.info.size()) tmp.info.tensors.resize(types.size(), tmp.info[0]);
      for (std::size_t i = 0; i < types.size(); ++i) tmp.info[i].type = types[i];
    }
  } catch (const Error &e) {
    return h->fail(ML_ERROR_INVALID_PARAMETER, std::string("ml_single_set_property: ") + e.what());
  }
  return ml_single_set_input_info(single, &tmp);
}

NNS_API int ml_single_get_property(ml_single_h single, const char *name, char **value) {
  REQUIRE_SINGLE(h, single);
  if (!name || !value)
    return h->fail(ML_ERROR_INVALID_PARAMETER, "ml_single_get_property: NULL argument");
  std::lock_guard<std::mutex> g(h->mu);
  std::string n = name, v;
  if (n == "input") v = h->in.dims_string();
  else if (n == "inputtype") v = h->in.types_string();
  else if (n == "inputname") v = h->in.names_string();
  else if (n == "output") v = h->out.dims_string();
  else if (n == "outputtype") v = h->out.types_string();
  else if (n == "outputname") v = h->out.names_string();
  else if (n == "framework") v = h->inst->name();
  else if (n == "custom") v = h->spec.custom;
  else if (n == "accelerator") v = h->spec.accelerator;
  else if (n == "model") {
    for (std::size_t i = 0; i < h->spec.models.size(); ++i) v += (i ? "," : "") + h->spec.models[i];
  } else {
    return h->fail(ML_ERROR_NOT_SUPPORTED, "ml_single_get_property: unknown property '" + n + "'");
  }
  *value = strdup(v.c_str());
  return ML_ERROR_NONE;
}

NNS_API const char *ml_single_get_last_error(ml_single_h single) {
  SingleHandle *h = as_single(single);
  return h ? h->last_error.c_str() : "invalid handle";
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter back end "pytorch": runs TorchScript models (.pt) with libtorch.
//
//   gst-launch-1.0 filesrc location=9.raw ! application/octet-stream !
//     tensor_converter input-dim=1:28:28:1 input-type=uint8 !
//     tensor_filter framework=pytorch model=pytorch_lenet5.pt input=1:28:28:1 inputtype=uint8
//       output=10:1 outputtype=uint8 ! tensor_sink
//
// TorchScript does not record tensor shapes, so the input (and normally the output) comes from
// the element's input=/inputtype=/output=/outputtype=. When only the input is given, the output
// is found by running the model once on zeros (set_input_info). NNStreamer dims are innermost
// first, torch shapes outermost first: the order is reversed both ways.
//
// Zero copy: inputs are wrapped with torch::from_blob over the caller's memory. Outputs are
// copied into the caller's buffers unless the result tensor already lives there; with
// invoke-dynamic the result tensor itself is handed out (and kept alive until free_output)
// when nothing else shares its storage.
//
// custom= keys (case-insensitive): use_gpu:true|false, NumThreads:N (process-wide intra-op
// threads of libtorch), OptimizeForInference:true|false (freeze + optimize_for_inference at
// load, default true). Unknown keys are rejected.
#include <glib.h>
#include <torch/script.h>

#include <ATen/Parallel.h>
#include <torch/version.h>
#include <c10/core/InferenceMode.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <unordered_map>
#include <vector>

#include "../common/backend_common.h"
#include "core/filter_accl.h"
#include "nnstreamer/nns_filter_backend.hh"
#include "pytorch_stats.h"

namespace nns::pytorch {
namespace {

using backend::desc_rank;
using backend::desc_to_string;

constexpr const char *kName = "pytorch";

std::string prefix() {
  return std::string(kName) + ": ";
}

// NNStreamer tensor_type -> torch dtype; nullopt for types libtorch 1.13 lacks (uint16/32/64).
std::optional<at::ScalarType> to_torch(uint32_t t) {
  switch (t) {
    case _NNS_UINT8:
      return at::kByte;
    case _NNS_INT8:
      return at::kChar;
    case _NNS_INT16:
      return at::kShort;
    case _NNS_INT32:
      return at::kInt;
    case _NNS_INT64:
      return at::kLong;
    case _NNS_FLOAT16:
      return at::kHalf;
    case _NNS_FLOAT32:
      return at::kFloat;
    case _NNS_FLOAT64:
      return at::kDouble;
    default:
      return std::nullopt;
  }
}

// torch dtype -> NNStreamer type; bool travels as uint8 (one byte, 0 or 1).
uint32_t from_torch(at::ScalarType t) {
  switch (t) {
    case at::kByte:
    case at::kBool:
      return _NNS_UINT8;
    case at::kChar:
      return _NNS_INT8;
    case at::kShort:
      return _NNS_INT16;
    case at::kInt:
      return _NNS_INT32;
    case at::kLong:
      return _NNS_INT64;
    case at::kHalf:
      return _NNS_FLOAT16;
    case at::kFloat:
      return _NNS_FLOAT32;
    case at::kDouble:
      return _NNS_FLOAT64;
    default:
      return _NNS_END;
  }
}

std::string shape_str(at::IntArrayRef s) {
  std::string r = "[";
  for (std::size_t i = 0; i < s.size(); ++i) r += (i ? "," : "") + std::to_string(s[i]);
  return r + "]";
}

// The useful part of a libtorch exception: no C++ backtrace, and for TorchScript interpreter
// errors the final "...Error: ..." line rather than the serialized-code traceback.
std::string torch_message(const std::exception &e) {
  std::string m;
  if (auto *ce = dynamic_cast<const c10::Error *>(&e))
    m = ce->what_without_backtrace();
  else
    m = e.what();
  if (m.find("TorchScript interpreter") != std::string::npos) {
    // Last line of the form "SomethingError: message".
    std::size_t end = m.find_last_not_of("\n ");
    std::size_t pos = end == std::string::npos ? std::string::npos : m.rfind('\n', end);
    std::size_t best = std::string::npos;
    for (std::size_t p = pos; p != std::string::npos && p > 0; p = m.rfind('\n', p - 1)) {
      std::size_t colon = m.find("Error: ", p);
      std::size_t eol = m.find('\n', p + 1);
      if (colon != std::string::npos && (eol == std::string::npos || colon < eol)) {
        best = p + 1;
        break;
      }
    }
    if (best != std::string::npos) m = m.substr(best);
  }
  return backend::one_line(m);
}

bool is_inside(const void *p, const GstTensorMemory &m) {
  auto *b = static_cast<const char *>(m.data);
  auto *c = static_cast<const char *>(p);
  return b && c >= b && c < b + m.size;
}

class TorchBackend final : public FilterBackend {
 public:
  explicit TorchBackend(const nns_filter_props &props) {
    apply_options(props);
    path_ = backend::single_model_path(props, kName);
    module_ = load(path_);
    if (props.input && props.input->num_tensors > 0) configure_input(*props.input);
    if (props.output && props.output->num_tensors > 0) {
      if (props.output->num_tensors > NNS_TENSOR_SIZE_LIMIT)
        throw FilterError(prefix() + "too many output tensors");
      out_ = *props.output;
      have_out_ = user_out_ = true;
      for (uint32_t i = 0; i < out_.num_tensors; ++i) {
        if (desc_rank(out_.tensors[i]) == 0 || backend::type_size(out_.tensors[i].type) == 0)
          throw FilterError(prefix() + "model '" + model_path() + "': output tensor #" +
                            std::to_string(i) +
                            " needs output= dims and outputtype= ("
                            "got " +
                            desc_to_string(out_.tensors[i]) + ")");
      }
    }
  }

  ~TorchBackend() override = default;

  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    if (!have_in_) return false;  // TorchScript has no declared shapes
    // One run on zeros finds the output (or checks output= against it) before any buffer.
    if (!probed_) probe_output();
    in = in_;
    out = out_;
    return true;
  }

  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    configure_input(in);
    if (!user_out_) have_out_ = false;
    probe_output();
    out = out_;
    return true;
  }

  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    if (!have_in_)
      throw FilterError(prefix() + "model '" + model_path() +
                        "': the input tensors are unknown (set input= and inputtype=)");
    if (num_in != plans_.size())
      throw FilterError(prefix() + "model '" + model_path() + "' is configured for " +
                        std::to_string(plans_.size()) + " input tensor(s), got " +
                        std::to_string(num_in));
    c10::InferenceMode guard;
    std::vector<c10::IValue> feeds;
    feeds.reserve(num_in);
    for (uint32_t i = 0; i < num_in; ++i) {
      const Plan &p = plans_[i];
      if (in[i].size != p.bytes)
        throw FilterError(prefix() + "model '" + model_path() + "': input tensor #" +
                          std::to_string(i) + " has " + std::to_string(in[i].size) +
                          " bytes, but " + desc_to_string(in_.tensors[i]) + " needs " +
                          std::to_string(p.bytes));
      feeds.emplace_back(torch::from_blob(in[i].data, p.shape, at::TensorOptions(p.dtype)));
    }
    std::vector<at::Tensor> results = run(std::move(feeds), in_);
    if (results.size() != num_out)
      throw FilterError(prefix() + "model '" + model_path() + "' returned " +
                        std::to_string(results.size()) + " tensor(s), but " +
                        std::to_string(num_out) + " output tensor(s) are configured" +
                        (have_out_ ? " (output=/outputtype=)" : ""));
    uint64_t copies = 0, zero = 0;
    for (uint32_t i = 0; i < num_out; ++i) {
      at::Tensor t = to_host(results[i]);
      check_output(i, t, out[i].size);
      if (t.data_ptr() == out[i].data) {
        ++zero;  // the model wrote into the caller's buffer (e.g. in-place on a shared buffer)
      } else {
        if (t.nbytes() > 0) std::memcpy(out[i].data, t.data_ptr(), t.nbytes());
        ++copies;
      }
    }
    std::lock_guard<std::mutex> lk(stats_mu_);
    stats_.invokes++;
    stats_.output_copies += copies;
    stats_.output_zero_copy += zero;
  }

  void invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                      nns_tensors_desc &out_info, GstTensorMemory *out) override {
    c10::InferenceMode guard;
    std::vector<c10::IValue> feeds;
    feeds.reserve(in_info.num_tensors);
    for (uint32_t i = 0; i < in_info.num_tensors; ++i) {
      Plan p = make_plan(in_info.tensors[i], i);
      if (in[i].size != p.bytes)
        throw FilterError(prefix() + "model '" + model_path() + "': input tensor #" +
                          std::to_string(i) + " has " + std::to_string(in[i].size) +
                          " bytes, but " + desc_to_string(in_info.tensors[i]) + " needs " +
                          std::to_string(p.bytes));
      feeds.emplace_back(torch::from_blob(in[i].data, p.shape, at::TensorOptions(p.dtype)));
    }
    std::vector<at::Tensor> results = run(std::move(feeds), in_info);
    if (results.size() > NNS_TENSOR_SIZE_LIMIT)
      throw FilterError(prefix() + "model '" + model_path() + "' returned too many tensors");
    nns_tensors_desc desc{};
    desc.num_tensors = static_cast<uint32_t>(results.size());
    desc.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
    std::vector<at::Tensor> keep(results.size());
    uint64_t copies = 0, zero = 0;
    for (std::size_t i = 0; i < results.size(); ++i) {
      at::Tensor t = std::move(results[i]);
      t = to_host(t);
      describe(t, static_cast<uint32_t>(i), desc.tensors[i]);
      // Hand the tensor's own memory out only when nothing else can see or change it: not an
      // input (the caller frees those), not a parameter, not shared with another output.
      bool shared = t.use_count() > 1 || t.storage().use_count() > 1 || t.nbytes() == 0;
      for (uint32_t k = 0; !shared && k < in_info.num_tensors; ++k)
        shared = is_inside(t.data_ptr(), in[k]);
      for (std::size_t k = 0; !shared && k < i; ++k) shared = keep[k].is_alias_of(t);
      if (shared) {
        t = t.clone(at::MemoryFormat::Contiguous);
        ++copies;
      } else {
        ++zero;
      }
      keep[i] = t;
    }
    results.clear();
    {
      std::lock_guard<std::mutex> lk(held_mu_);
      for (std::size_t i = 0; i < keep.size(); ++i) {
        out[i].data = keep[i].data_ptr();
        out[i].size = keep[i].nbytes();
        held_.emplace(out[i].data, std::move(keep[i]));
      }
    }
    out_info = desc;
    std::lock_guard<std::mutex> lk(stats_mu_);
    stats_.invokes++;
    stats_.output_copies += copies;
    stats_.output_zero_copy += zero;
  }

  void free_output(void *data) override {
    std::lock_guard<std::mutex> lk(held_mu_);
    auto it = held_.find(data);
    if (it != held_.end()) held_.erase(it);
  }

  void reload(const nns_filter_props &props) override {
    std::string path = backend::single_model_path(props, kName);
    auto m = load(path);
    std::lock_guard<std::mutex> lk(module_mu_);
    module_ = std::move(m);
    path_ = path;
  }

  nns_pytorch_stats stats() {
    std::lock_guard<std::mutex> lk(stats_mu_);
    nns_pytorch_stats s = stats_;
    s.optimized = optimized_ ? 1 : 0;
    return s;
  }

 private:
  struct Plan {
    std::vector<int64_t> shape;  // torch order (outermost first)
    at::ScalarType dtype = at::kByte;
    std::size_t bytes = 0;
  };

  void apply_options(const nns_filter_props &props) {
    // custom= first; its errors are reported after the accelerator line below, which NNStreamer
    // prints at every open whatever follows.
    int threads = props.num_threads;
    std::optional<bool> custom_gpu;
    std::optional<FilterError> custom_error;
    try {
      for (const backend::CustomOption &o : backend::parse_custom(props.custom, kName)) {
        if (backend::iequals(o.key, "use_gpu")) {
          custom_gpu = backend::parse_bool_option(kName, o);
        } else if (backend::iequals(o.key, "NumThreads")) {
          threads = static_cast<int>(backend::parse_int_option(kName, o, 0, 1024));
        } else if (backend::iequals(o.key, "OptimizeForInference")) {
          optimize_ = backend::parse_bool_option(kName, o);
        } else {
          throw FilterError(prefix() + "unknown custom option '" + o.key +
                            "' (known: use_gpu, NumThreads, OptimizeForInference)");
        }
      }
    } catch (const FilterError &e) {
      custom_error = e;
    }
    // accelerator= read as NNStreamer's pytorch sub-plugin reads it (parse_accl_hw with cpu and
    // gpu supported): unset gives cpu, "true:..." the first of cpu/gpu it names (none: cpu),
    // anything else none (NNStreamer then reads [pytorch] enable_use_gpu, not read here).
    static const char *const kSupported[] = {"cpu", "gpu", nullptr};
    const char *asked = props.accelerator && *props.accelerator ? props.accelerator : nullptr;
    accl_hw hw = nns::accl::parse(asked, kSupported, nullptr, nullptr);
    bool want_gpu = hw == ACCL_GPU;
    if (custom_gpu) {
      want_gpu = *custom_gpu;
      hw = want_gpu ? ACCL_GPU : ACCL_CPU;
    }
    // Without a usable CUDA device, a list that also names cpu falls back to it (ours).
    const backend::AcceleratorRequest acc = backend::parse_accelerator(props.accelerator);
    const bool cpu_listed =
        std::find(acc.wanted.begin(), acc.wanted.end(), "cpu") != acc.wanted.end();
    if (want_gpu && !custom_gpu && cpu_listed && !at::hasCUDA()) {
      want_gpu = false;
      hw = ACCL_CPU;
    }
    // The line NNStreamer's pytorch sub-plugin prints at every open (scripts grep for it).
    g_message("gpu = %d, accl = %s", want_gpu ? 1 : 0, nns::accl::name_of(hw));
    if (custom_error) throw *custom_error;
    if (want_gpu && !at::hasCUDA()) {
      if (custom_gpu)
        throw FilterError(prefix() +
                              "custom option use_gpu:true asks for a GPU, but this libtorch "
                              "has no usable CUDA device",
                          -ENODEV);
      throw FilterError(prefix() + "accelerator=" + props.accelerator +
                            " asks for a GPU, but this libtorch has no usable CUDA device; "
                            "use accelerator=true:gpu,cpu to fall back to the CPU",
                        -ENODEV);
    }
    device_ = want_gpu ? at::Device(at::kCUDA) : at::Device(at::kCPU);
    threads_ = threads;
    apply_threads();
  }

  // libtorch's OpenMP thread count is per calling thread (the element opens the model in one
  // thread and invokes it from the streaming thread): apply it where the work runs.
  void apply_threads() const {
    if (threads_ > 0 && at::get_num_threads() != threads_) at::set_num_threads(threads_);
  }

  std::shared_ptr<torch::jit::Module> load(const std::string &path) {
    std::shared_ptr<torch::jit::Module> m;
    try {
      m = std::make_shared<torch::jit::Module>(torch::jit::load(path, device_));
      m->eval();
    } catch (const std::exception &e) {
      throw FilterError(
          prefix() + "cannot load TorchScript model '" + path + "': " + torch_message(e), -EINVAL);
    }
    if (optimize_) {
      // torch.jit.freeze + optimize_for_inference: parameters become constants, conv weights are
      // prepacked, methods inlined. A model that cannot be frozen (e.g. forward mutates an
      // attribute) runs as loaded.
      try {
        torch::jit::Module frozen = torch::jit::freeze(*m);
        *m = torch::jit::optimize_for_inference(frozen);
        optimized_ = true;
      } catch (const std::exception &) {
        optimized_ = false;
      }
    }
    return m;
  }

  Plan make_plan(const nns_tensor_desc &t, uint32_t idx) const {
    Plan p;
    uint32_t r = desc_rank(t);
    if (r == 0)
      throw FilterError(prefix() + "model '" + model_path() + "': input tensor #" +
                        std::to_string(idx) + " has no dimensions (set input=)");
    auto dt = to_torch(t.type);
    if (!dt)
      throw FilterError(prefix() + "model '" + model_path() + "': input tensor #" +
                        std::to_string(idx) + " has type " + backend::type_name(t.type) +
                        ", which libtorch " TORCH_VERSION " does not support");
    p.dtype = *dt;
    p.shape.resize(r);
    std::size_t n = 1;
    for (uint32_t k = 0; k < r; ++k) {
      p.shape[k] = t.dims[r - 1 - k];
      n *= t.dims[k];
    }
    p.bytes = n * backend::type_size(t.type);
    return p;
  }

  void configure_input(const nns_tensors_desc &in) {
    if (in.num_tensors == 0 || in.num_tensors > NNS_TENSOR_SIZE_LIMIT)
      throw FilterError(prefix() + "model '" + model_path() + "': bad number of input tensors (" +
                        std::to_string(in.num_tensors) + ")");
    std::vector<Plan> plans;
    for (uint32_t i = 0; i < in.num_tensors; ++i) plans.push_back(make_plan(in.tensors[i], i));
    plans_ = std::move(plans);
    in_ = in;
    have_in_ = true;
    probed_ = false;
  }

  // Runs the model once on zeros of the configured input to learn the output tensors.
  void probe_output() {
    c10::InferenceMode guard;
    std::vector<c10::IValue> feeds;
    for (const Plan &p : plans_) feeds.emplace_back(at::zeros(p.shape, at::TensorOptions(p.dtype)));
    std::vector<at::Tensor> results = run(std::move(feeds), in_);
    if (results.size() > NNS_TENSOR_SIZE_LIMIT)
      throw FilterError(prefix() + "model '" + model_path() + "' returned too many tensors");
    nns_tensors_desc desc{};
    desc.num_tensors = static_cast<uint32_t>(results.size());
    for (std::size_t i = 0; i < results.size(); ++i)
      describe(results[i], static_cast<uint32_t>(i), desc.tensors[i]);
    if (user_out_) {
      // Keep the user's output= when it is compatible (same type and element count).
      if (desc.num_tensors != out_.num_tensors)
        throw FilterError(prefix() + "model '" + model_path() + "' returns " +
                          std::to_string(desc.num_tensors) + " tensor(s), but output= has " +
                          std::to_string(out_.num_tensors));
      for (uint32_t i = 0; i < desc.num_tensors; ++i) {
        if (desc.tensors[i].type != out_.tensors[i].type ||
            backend::desc_elements(desc.tensors[i]) != backend::desc_elements(out_.tensors[i]))
          throw FilterError(prefix() + "model '" + model_path() + "': output tensor #" +
                            std::to_string(i) + " is " + desc_to_string(desc.tensors[i]) +
                            ", but output=/outputtype= say " + desc_to_string(out_.tensors[i]));
      }
    } else {
      out_ = desc;
      have_out_ = true;
    }
    probed_ = true;
  }

  void describe(const at::Tensor &t, uint32_t idx, nns_tensor_desc &d) const {
    d = nns_tensor_desc{};
    d.type = from_torch(t.scalar_type());
    if (d.type == _NNS_END)
      throw FilterError(prefix() + "model '" + model_path() + "': output tensor #" +
                        std::to_string(idx) + " has torch type " +
                        std::string(c10::toString(t.scalar_type())) +
                        ", which has no NNStreamer tensor type");
    auto s = t.sizes();
    if (s.size() > NNS_TENSOR_RANK_LIMIT)
      throw FilterError(prefix() + "model '" + model_path() + "': output tensor #" +
                        std::to_string(idx) + " has rank " + std::to_string(s.size()) + " (limit " +
                        std::to_string(NNS_TENSOR_RANK_LIMIT) + ")");
    if (s.empty()) {
      d.dims[0] = 1;  // a scalar is one element
      return;
    }
    for (std::size_t k = 0; k < s.size(); ++k) {
      if (s[k] <= 0 || s[k] > UINT32_MAX)
        throw FilterError(prefix() + "model '" + model_path() + "': output tensor #" +
                          std::to_string(idx) + " has shape " + shape_str(s) +
                          ", which NNStreamer dims cannot express");
      d.dims[s.size() - 1 - k] = static_cast<uint32_t>(s[k]);
    }
  }

  static void flatten(const c10::IValue &v, std::vector<at::Tensor> &out,
                      const TorchBackend &self) {
    if (v.isTensor()) {
      out.push_back(v.toTensor());
    } else if (v.isTuple()) {
      for (const auto &e : v.toTuple()->elements()) flatten(e, out, self);
    } else if (v.isList()) {
      for (const auto &e : v.toListRef()) flatten(e, out, self);
    } else {
      throw FilterError(prefix() + "model '" + self.model_path() + "' returned a " + v.tagKind() +
                        "; only tensors and tuples/lists of tensors are supported");
    }
  }

  std::string model_path() const {
    std::lock_guard<std::mutex> lk(module_mu_);
    return path_;
  }

  std::vector<at::Tensor> run(std::vector<c10::IValue> feeds, const nns_tensors_desc &info) {
    std::shared_ptr<torch::jit::Module> m;
    {
      std::lock_guard<std::mutex> lk(module_mu_);
      m = module_;
    }
    apply_threads();
    if (device_.is_cuda())
      for (auto &f : feeds) f = f.toTensor().to(device_);
    c10::IValue result;
    try {
      c10::InferenceMode guard;
      result = m->forward(std::move(feeds));
    } catch (const std::exception &e) {
      std::string ins;
      for (uint32_t i = 0; i < info.num_tensors; ++i)
        ins += (i ? ", " : "") + desc_to_string(info.tensors[i]);
      throw FilterError(prefix() + "model '" + model_path() + "' failed on input [" + ins +
                            "]: " + torch_message(e),
                        -EIO);
    }
    std::vector<at::Tensor> out;
    flatten(result, out, *this);
    return out;
  }

  at::Tensor to_host(const at::Tensor &t) {
    at::Tensor h = t.device().is_cpu() ? t : t.to(at::kCPU);
    if (!h.is_contiguous()) h = h.contiguous();
    if (h.scalar_type() == at::kBool) h = h.view(at::kByte);
    return h;
  }

  void check_output(uint32_t i, const at::Tensor &t, std::size_t size) const {
    uint32_t type = from_torch(t.scalar_type());
    const nns_tensor_desc *want = have_out_ && i < out_.num_tensors ? &out_.tensors[i] : nullptr;
    if (want &&
        (type != want->type || static_cast<uint64_t>(t.numel()) != backend::desc_elements(*want)))
      throw FilterError(prefix() + "model '" + model_path() + "': output tensor #" +
                        std::to_string(i) + " is " + backend::type_name(type) + " " +
                        shape_str(t.sizes()) + " (" + std::to_string(t.numel()) +
                        " elements), but output=/outputtype= say " + desc_to_string(*want) + " (" +
                        std::to_string(backend::desc_elements(*want)) + " elements)");
    if (t.nbytes() != size)
      throw FilterError(prefix() + "model '" + model_path() + "': output tensor #" +
                        std::to_string(i) + " " + shape_str(t.sizes()) + " has " +
                        std::to_string(t.nbytes()) + " bytes, but the output buffer has " +
                        std::to_string(size));
  }

  std::string path_;
  at::Device device_{at::kCPU};
  int threads_ = 0;         // NumThreads / num_threads; 0 = libtorch's default
  bool optimize_ = true;    // custom OptimizeForInference
  bool optimized_ = false;  // the loaded module is frozen and optimized
  mutable std::mutex module_mu_;
  std::shared_ptr<torch::jit::Module> module_;

  nns_tensors_desc in_{}, out_{};
  bool have_in_ = false, have_out_ = false;
  bool user_out_ = false;  // output= came from the element's properties
  bool probed_ = false;    // out_ checked against one run of the model
  std::vector<Plan> plans_;

  std::mutex held_mu_;
  std::unordered_multimap<void *, at::Tensor> held_;

  std::mutex stats_mu_;
  nns_pytorch_stats stats_{};
};

const char *const kExtensions[] = {".pt", ".pth", nullptr};

int check_accelerator(const char *accl) {
  if (!accl) return -EINVAL;
  std::string a = backend::lower(backend::trim(accl));
  if (a == "cpu" || a == "cpu.simd" || a == "default" || a == "auto" || a == "none") return 0;
  if (a == "gpu") return at::hasCUDA() ? 0 : -ENODEV;
  return -ENOENT;
}

}  // namespace
}  // namespace nns::pytorch

extern "C" __attribute__((visibility("default"))) const nns_filter_backend_i *
nns_filter_backend_entry(void) {
  static const nns_filter_backend_i table = [] {
    nns_filter_backend_i t = nns::FilterBackendAdapter<nns::pytorch::TorchBackend>::make(
        nns::pytorch::kName, NNS_FILTER_FLAG_DYNAMIC, nns::pytorch::kExtensions);
    t.check_accelerator = &nns::pytorch::check_accelerator;
    return t;
  }();
  return &table;
}

extern "C" __attribute__((visibility("default"))) int nns_filter_pytorch_get_stats(
    void *priv, nns_pytorch_stats *out) {
  if (!priv || !out) return -EINVAL;
  auto *b = dynamic_cast<nns::pytorch::TorchBackend *>(static_cast<nns::FilterBackend *>(priv));
  if (!b) return -EINVAL;
  *out = b->stats();
  return 0;
}

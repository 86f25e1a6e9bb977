// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter back end "armnn": runs TensorFlow Lite flatbuffers (.tflite) with Arm NN
// (Debian libarmnn + TfLiteParser). On x86 only the CpuRef reference back end exists, which is
// exact but slow; CpuAcc/GpuAcc are used where Arm NN registers them.
//
//   gst-launch-1.0 filesrc location=orange.raw ! application/octet-stream !
//     tensor_converter input-dim=3:224:224:1 input-type=uint8 !
//     tensor_filter framework=armnn model=mobilenet_v2_1.0_224_quant.tflite ! tensor_sink
//
// The model gives every input/output name, type and shape (quantized tensors are uint8/int8,
// NNStreamer dims are the reversed tflite shape). Inputs and outputs are bound to the caller's
// memory directly (ConstTensor/Tensor over the buffers): nothing is copied by this back end.
//
// Arm NN device choice: custom=Backend:<CpuRef|CpuAcc|GpuAcc> wins; otherwise accelerator=
// maps cpu -> CpuRef, cpu.neon/cpu.simd -> CpuAcc, gpu -> GpuAcc (first registered one in the
// list); with neither, the fastest registered device (CpuAcc, then CpuRef). Unknown custom keys
// are rejected.
//
// Threads: every instance shares one process-wide IRuntime (created on the first open, never
// destroyed). Arm NN registers its dynamic devices (Debian's CpuRef) when a runtime is created
// and unregisters them when that runtime is destroyed, so one runtime per instance made a close
// in one thread pull CpuRef from under an open in another ("CpuRef has no IBackend factory
// registered"). Each instance loads its own network into the shared runtime and unloads it on
// close; loads and unloads are serialized.
#include <armnn/ArmNN.hpp>
#include <armnn/BackendRegistry.hpp>
#include <armnnTfLiteParser/ITfLiteParser.hpp>

#include <algorithm>
#include <cerrno>
#include <mutex>
#include <string>
#include <vector>

#include "../common/backend_common.h"
#include "nnstreamer/nns_filter_backend.hh"

namespace nns::armnn_backend {
namespace {

using backend::desc_to_string;

constexpr const char *kName = "armnn";

std::string prefix() {
  return std::string(kName) + ": ";
}

uint32_t from_armnn(armnn::DataType t) {
  switch (t) {
    case armnn::DataType::Float32:
      return _NNS_FLOAT32;
    case armnn::DataType::Float16:
      return _NNS_FLOAT16;
    case armnn::DataType::QAsymmU8:
      return _NNS_UINT8;
    case armnn::DataType::QAsymmS8:
    case armnn::DataType::QSymmS8:
      return _NNS_INT8;
    case armnn::DataType::QSymmS16:
      return _NNS_INT16;
    case armnn::DataType::Signed32:
      return _NNS_INT32;
    case armnn::DataType::Boolean:
      return _NNS_UINT8;
    default:
      return _NNS_END;
  }
}

// Process-wide: Arm NN logs to stdout; only fatal messages are printed, since every error
// reaches the caller (and the bus) through this back end's own messages.
void configure_logging_once() {
  static std::once_flag once;
  std::call_once(once, [] { armnn::ConfigureLogging(true, false, armnn::LogSeverity::Fatal); });
}

// The one runtime of the process. Created once (its creation loads and registers the dynamic
// devices) and deliberately never destroyed: destroying it would unregister the devices under
// any other user, and the registry is a static of libarmnn whose destruction order at exit is
// not ours. Throws FilterError when Arm NN cannot create it (retried on the next open).
armnn::IRuntime &shared_runtime() {
  static std::mutex mu;
  static armnn::IRuntime *runtime = nullptr;
  std::lock_guard lk(mu);
  if (!runtime) {
    configure_logging_once();
    try {
      runtime = armnn::IRuntime::CreateRaw(armnn::IRuntime::CreationOptions());
    } catch (const std::exception &e) {
      throw FilterError(prefix() + "cannot create the Arm NN runtime: " + e.what(), -EIO);
    }
    if (!runtime) throw FilterError(prefix() + "cannot create the Arm NN runtime", -EIO);
  }
  return *runtime;
}

// Serializes LoadNetwork/UnloadNetwork on the shared runtime.
std::mutex &load_mutex() {
  static std::mutex mu;
  return mu;
}

std::string registered_backends() {
  std::vector<std::string> ids;
  for (const armnn::BackendId &id : armnn::BackendRegistryInstance().GetBackendIds())
    ids.push_back(id.Get());
  std::sort(ids.begin(), ids.end());
  std::string s;
  for (const auto &i : ids) s += (s.empty() ? "" : ", ") + i;
  return s.empty() ? "none" : s;
}

bool is_registered(const std::string &id) {
  return armnn::BackendRegistryInstance().IsBackendRegistered(armnn::BackendId(id));
}

// accelerator= name -> Arm NN device id ("" when Arm NN has no device for it).
std::string device_for(const std::string &accl) {
  if (accl == "cpu") return "CpuRef";
  if (accl == "cpu.neon" || accl == "cpu.simd") return "CpuAcc";
  if (accl == "gpu") return "GpuAcc";
  return "";
}

class ArmnnBackend final : public FilterBackend {
 public:
  explicit ArmnnBackend(const nns_filter_props &props) {
    configure_logging_once();
    path_ = backend::single_model_path(props, kName);
    std::string forced = parse_options(props);
    runtime_ = &shared_runtime();  // registers the devices before choose_devices looks
    std::vector<armnn::BackendId> devices = choose_devices(props, forced);
    armnn::INetworkPtr network{nullptr, nullptr};
    try {
      auto parser = armnnTfLiteParser::ITfLiteParser::Create();
      network = parser->CreateNetworkFromBinaryFile(path_.c_str());
      if (!network) throw std::runtime_error("the parser returned no network");
      if (parser->GetSubgraphCount() < 1) throw std::runtime_error("the model has no subgraph");
      for (const auto &n : parser->GetSubgraphInputTensorNames(0)) {
        in_bind_.push_back(parser->GetNetworkInputBindingInfo(0, n));
        in_names_.push_back(n);
      }
      for (const auto &n : parser->GetSubgraphOutputTensorNames(0)) {
        out_bind_.push_back(parser->GetNetworkOutputBindingInfo(0, n));
        out_names_.push_back(n);
      }
    } catch (const std::exception &e) {
      throw FilterError(prefix() + "cannot parse TensorFlow Lite model '" + path_ +
                            "': " + backend::one_line(e.what()),
                        -EINVAL);
    }
    in_ = describe(in_bind_, in_names_, "input");
    out_ = describe(out_bind_, out_names_, "output");
    check_against(props.input, in_, "input", "input=/inputtype=");
    check_against(props.output, out_, "output", "output=/outputtype=");
    try {
      std::vector<std::string> messages;
      armnn::IOptimizedNetworkPtr opt =
          armnn::Optimize(*network, devices, runtime_->GetDeviceSpec(), armnn::OptimizerOptions(),
                          armnn::Optional<std::vector<std::string> &>(messages));
      if (!opt) {
        std::string why;
        for (const auto &m : messages) why += (why.empty() ? "" : "; ") + m;
        throw std::runtime_error("optimization failed" + (why.empty() ? "" : ": " + why));
      }
      std::string err;
      std::lock_guard lk(load_mutex());
      if (runtime_->LoadNetwork(net_id_, std::move(opt), err) != armnn::Status::Success)
        throw std::runtime_error("LoadNetwork failed" + (err.empty() ? "" : ": " + err));
      loaded_ = true;
    } catch (const std::exception &e) {
      throw FilterError(prefix() + "cannot prepare model '" + path_ + "' for " +
                            device_list(devices) + ": " + backend::one_line(e.what()),
                        -EINVAL);
    }
  }

  ~ArmnnBackend() override {
    if (!loaded_) return;
    std::lock_guard lk(load_mutex());
    runtime_->UnloadNetwork(net_id_);
  }

  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    in = in_;
    out = out_;
    return true;
  }

  // Arm NN networks have fixed shapes: only the model's own input is accepted.
  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    if (in.num_tensors != in_.num_tensors) return false;
    for (uint32_t i = 0; i < in.num_tensors; ++i)
      if (!backend::desc_equal(in.tensors[i], in_.tensors[i])) return false;
    out = out_;
    return true;
  }

  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    if (num_in != in_bind_.size() || num_out != out_bind_.size())
      throw FilterError(prefix() + "model '" + path_ + "' has " + std::to_string(in_bind_.size()) +
                        " input(s) and " + std::to_string(out_bind_.size()) + " output(s), got " +
                        std::to_string(num_in) + " and " + std::to_string(num_out));
    inputs_.clear();
    outputs_.clear();
    for (uint32_t i = 0; i < num_in; ++i) {
      const armnn::TensorInfo &ti = in_bind_[i].second;
      if (in[i].size != ti.GetNumBytes())
        throw FilterError(prefix() + "model '" + path_ + "': input tensor #" + std::to_string(i) +
                          " has " + std::to_string(in[i].size) + " bytes, but " +
                          desc_to_string(in_.tensors[i]) + " needs " +
                          std::to_string(ti.GetNumBytes()));
      inputs_.emplace_back(in_bind_[i].first, armnn::ConstTensor(ti, in[i].data));
    }
    for (uint32_t i = 0; i < num_out; ++i) {
      const armnn::TensorInfo &ti = out_bind_[i].second;
      if (out[i].size != ti.GetNumBytes())
        throw FilterError(prefix() + "model '" + path_ + "': output tensor #" + std::to_string(i) +
                          " buffer has " + std::to_string(out[i].size) + " bytes, but " +
                          desc_to_string(out_.tensors[i]) + " needs " +
                          std::to_string(ti.GetNumBytes()));
      outputs_.emplace_back(out_bind_[i].first, armnn::Tensor(ti, out[i].data));
    }
    armnn::Status st;
    try {
      st = runtime_->EnqueueWorkload(net_id_, inputs_, outputs_);
    } catch (const std::exception &e) {
      throw FilterError(prefix() + "model '" + path_ + "' failed: " + backend::one_line(e.what()),
                        -EIO);
    }
    if (st != armnn::Status::Success)
      throw FilterError(prefix() + "model '" + path_ + "': EnqueueWorkload failed", -EIO);
  }

 private:
  // Returns the device forced by custom=Backend:..., or "".
  std::string parse_options(const nns_filter_props &props) {
    std::string forced;
    for (const backend::CustomOption &o : backend::parse_custom(props.custom, kName)) {
      if (backend::iequals(o.key, "Backend")) {
        forced = o.value;
        if (forced.empty())
          throw FilterError(prefix() + "custom option Backend needs a value (e.g. Backend:CpuRef)");
      } else {
        throw FilterError(prefix() + "unknown custom option '" + o.key + "' (known: Backend)");
      }
    }
    return forced;
  }

  std::vector<armnn::BackendId> choose_devices(const nns_filter_props &props,
                                               const std::string &forced) {
    if (!forced.empty()) {
      for (const armnn::BackendId &id : armnn::BackendRegistryInstance().GetBackendIds())
        if (backend::iequals(id.Get(), forced)) return {id};
      throw FilterError(prefix() + "custom option Backend:" + forced +
                            ": no such Arm NN device here (registered: " + registered_backends() +
                            ")",
                        -ENODEV);
    }
    backend::AcceleratorRequest acc = backend::parse_accelerator(props.accelerator);
    std::vector<armnn::BackendId> out;
    bool explicit_device = false;
    if (acc.enabled) {
      for (const std::string &a : acc.wanted) {
        std::string dev = device_for(a);
        if (dev.empty()) continue;  // default/auto/npu...: no Arm NN device of its own
        explicit_device = true;
        if (is_registered(dev)) out.emplace_back(dev);
      }
      if (explicit_device && out.empty())
        throw FilterError(prefix() + "accelerator=" + props.accelerator +
                              ": none of these devices is available to Arm NN (registered: " +
                              registered_backends() + ")",
                          -ENODEV);
    }
    if (out.empty()) {
      for (const char *dev : {"CpuAcc", "GpuAcc", "CpuRef"})
        if (is_registered(dev)) out.emplace_back(dev);
      if (out.empty())
        throw FilterError(
            prefix() + "Arm NN has no usable device (registered: " + registered_backends() + ")",
            -ENODEV);
    }
    return out;
  }

  static std::string device_list(const std::vector<armnn::BackendId> &d) {
    std::string s;
    for (const auto &id : d) s += (s.empty() ? "" : ",") + id.Get();
    return s;
  }

  nns_tensors_desc describe(const std::vector<armnn::BindingPointInfo> &b,
                            const std::vector<std::string> &names, const char *what) const {
    if (b.empty() || b.size() > NNS_TENSOR_SIZE_LIMIT)
      throw FilterError(prefix() + "model '" + path_ + "' has " + std::to_string(b.size()) + " " +
                        what + " tensors");
    nns_tensors_desc d{};
    d.num_tensors = static_cast<uint32_t>(b.size());
    for (std::size_t i = 0; i < b.size(); ++i) {
      const armnn::TensorInfo &ti = b[i].second;
      nns_tensor_desc &t = d.tensors[i];
      backend::set_name(t, names[i]);
      t.type = from_armnn(ti.GetDataType());
      if (t.type == _NNS_END)
        throw FilterError(prefix() + "model '" + path_ + "': " + what + " tensor #" +
                          std::to_string(i) + " ('" + names[i] + "') has Arm NN type " +
                          armnn::GetDataTypeName(ti.GetDataType()) +
                          ", which has no NNStreamer tensor type");
      const armnn::TensorShape &s = ti.GetShape();
      unsigned rank = s.GetNumDimensions();
      if (rank > NNS_TENSOR_RANK_LIMIT)
        throw FilterError(prefix() + "model '" + path_ + "': " + what + " tensor #" +
                          std::to_string(i) + " has rank " + std::to_string(rank));
      if (rank == 0) t.dims[0] = 1;
      for (unsigned k = 0; k < rank; ++k) t.dims[rank - 1 - k] = s[k];
    }
    return d;
  }

  void check_against(const nns_tensors_desc *given, const nns_tensors_desc &model, const char *what,
                     const char *props) const {
    if (!given || given->num_tensors == 0) return;
    if (given->num_tensors != model.num_tensors)
      throw FilterError(prefix() + "model '" + path_ + "' has " +
                        std::to_string(model.num_tensors) + " " + what + " tensor(s), but " +
                        props + " give " + std::to_string(given->num_tensors));
    for (uint32_t i = 0; i < model.num_tensors; ++i) {
      nns_tensor_desc g = given->tensors[i];
      if (g.type == _NNS_END || backend::type_size(g.type) == 0) g.type = model.tensors[i].type;
      if (backend::desc_rank(g) == 0) continue;  // only the type was given
      if (!backend::desc_equal(g, model.tensors[i]))
        throw FilterError(prefix() + "model '" + path_ + "': " + what + " tensor #" +
                          std::to_string(i) + " is " + desc_to_string(model.tensors[i]) + ", but " +
                          props + " say " + desc_to_string(given->tensors[i]));
    }
  }

  std::string path_;
  armnn::IRuntime *runtime_ = nullptr;  // the shared one, not owned
  armnn::NetworkId net_id_ = 0;
  bool loaded_ = false;
  std::vector<armnn::BindingPointInfo> in_bind_, out_bind_;
  std::vector<std::string> in_names_, out_names_;
  nns_tensors_desc in_{}, out_{};
  armnn::InputTensors inputs_;  // reused between invokes (capacity kept)
  armnn::OutputTensors outputs_;
};

const char *const kExtensions[] = {".tflite", nullptr};

int check_accelerator(const char *accl) {
  if (!accl) return -EINVAL;
  std::string a = backend::lower(backend::trim(accl));
  if (a == "default" || a == "auto" || a == "none") return 0;
  std::string dev = device_for(a);
  if (dev.empty()) return -ENOENT;
  // Devices are registered while a runtime that loaded them lives: the shared one does.
  try {
    shared_runtime();
  } catch (const FilterError &) {
    return -ENODEV;
  }
  return is_registered(dev) ? 0 : -ENODEV;
}

}  // namespace
}  // namespace nns::armnn_backend

extern "C" __attribute__((visibility("default"))) const nns_filter_backend_i *
nns_filter_backend_entry(void) {
  static const nns_filter_backend_i table = [] {
    nns_filter_backend_i t = nns::FilterBackendAdapter<nns::armnn_backend::ArmnnBackend>::make(
        nns::armnn_backend::kName, 0, nns::armnn_backend::kExtensions);
    t.check_accelerator = &nns::armnn_backend::check_accelerator;
    return t;
  }();
  return &table;
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter back end for ONNX Runtime (framework=onnxruntime).
//
//   gst-launch-1.0 filesrc location=orange.raw ! application/octet-stream !
//     tensor_converter input-dim=3:224:224:1 input-type=uint8 !
//     tensor_transform mode=arithmetic option=typecast:float32,per-channel:true@0,
//       add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 !
//     tensor_transform mode=transpose option=1:2:0:3 !
//     tensor_filter framework=onnxruntime model=mobilenet_v2_quant.onnx custom=NumThreads:1 !
//     tensor_sink
//   (the option is one word; the model is described in docs/backends/onnxruntime.md)
//
// Input/output names, types and shapes come from the model; ONNX shape [1,224,224,3] is
// NNStreamer dims 3:224:224:1. Free (symbolic) dimensions need input= or invoke-dynamic=true.
// Zero copy: inputs are OrtValues over the caller's memory and outputs are pre-allocated
// OrtValues over the caller's output buffers, so ORT reads and writes them in place. Should ORT
// ever hand back another buffer the bytes are copied and counted
// (nns_filter_onnxruntime_copied_bytes). Session::Run is thread-safe and invoke keeps no
// per-call state in the object, so the back end is marked thread-safe.
// custom= keys: NumThreads, InterOpNumThreads, GraphOptimizationLevel, ExecutionMode,
// AllowSpinning (docs/backends/onnxruntime.md).

#include <onnxruntime_cxx_api.h>

#include <atomic>
#include <cerrno>
#include <cstring>
#include <filesystem>
#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "core/custom_options.h"
#include "core/error.h"
#include "core/backend_desc.h"
#include "nns_filter_backend.hh"

namespace nns {
namespace {

constexpr const char *kName = "onnxruntime";

Ort::Env &ort_env() {
  // Errors only: ORT warns about harmless model details (unused initializers).
  static Ort::Env env(ORT_LOGGING_LEVEL_ERROR, "nnstreamer-onnxruntime");
  return env;
}

bool to_nns_type(ONNXTensorElementDataType t, uint32_t &out) {
  switch (t) {
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_FLOAT:
      out = _NNS_FLOAT32;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_DOUBLE:
      out = _NNS_FLOAT64;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_FLOAT16:
      out = _NNS_FLOAT16;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT8:
      out = _NNS_INT8;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_UINT8:
      out = _NNS_UINT8;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT16:
      out = _NNS_INT16;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_UINT16:
      out = _NNS_UINT16;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT32:
      out = _NNS_INT32;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_UINT32:
      out = _NNS_UINT32;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_INT64:
      out = _NNS_INT64;
      return true;
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_UINT64:
      out = _NNS_UINT64;
      return true;
    default:
      return false;
  }
}

std::string ort_type_name(ONNXTensorElementDataType t) {
  switch (t) {
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_BOOL:
      return "bool";
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_STRING:
      return "string";
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_BFLOAT16:
      return "bfloat16";
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_COMPLEX64:
      return "complex64";
    case ONNX_TENSOR_ELEMENT_DATA_TYPE_COMPLEX128:
      return "complex128";
    default:
      return "ONNX element type " + std::to_string(static_cast<int>(t));
  }
}

// One model input or output as the back end uses it.
struct Port {
  std::string name;
  ONNXTensorElementDataType ort_type{};
  nns_tensor_desc desc{};            // NNStreamer view (free dims as 1 until resolved)
  std::vector<int64_t> model_shape;  // as declared, -1 for free dims
  std::vector<int64_t> shape;        // resolved shape passed to ORT
  std::size_t bytes = 0;             // resolved byte size
  bool has_free_dim() const {
    for (auto v : shape)
      if (v < 0) return true;
    return false;
  }
};

// Everything built from the model file; replaced as a whole by reload().
struct Model {
  std::string path;                       // the model file, for messages
  mutable Ort::Session session{nullptr};  // Run() is thread-safe but not const
  std::vector<Port> in, out;
  std::vector<const char *> in_names, out_names;
  bool resolved = false;  // every shape is known
};

// Data pointer of the first input of the latest invoke in this process (a test hook proving the
// pipeline hands the GstBuffer's memory through unchanged).
std::atomic<const void *> g_last_input{nullptr};

std::string err_prefix(const std::string &model) {
  return std::string(kName) + ": " + model;
}

class OnnxRuntimeFilter final : public FilterBackend {
 public:
  explicit OnnxRuntimeFilter(const nns_filter_props &p) : mem_(make_mem()) { model_ = open(p); }

  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    std::shared_lock lock(mutex_);
    fill(*model_, in, out);
    return true;
  }

  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    std::unique_lock lock(mutex_);
    auto m = model_;
    resolve_inputs(*m, in, "the negotiated input");
    finish(*m);
    nns_tensors_desc ignored{};
    fill(*m, ignored, out);
    return true;
  }

  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    std::shared_lock lock(mutex_);
    const Model &m = *model_;
    if (!m.resolved)
      throw FilterError(
          err_prefix(m.path) + ": the model has free dimensions; give input= or use invoke-dynamic",
          -EINVAL);
    check_count(m, "input", num_in, m.in.size());
    check_count(m, "output", num_out, m.out.size());
    // Reused per thread: no allocation per call once warm (ORT still allocates its OrtValue
    // wrappers, a few small objects).
    thread_local std::vector<Ort::Value> ins, outs;
    struct Clear {  // drop the wrappers on every exit, error paths included
      ~Clear() {
        ins.clear();
        outs.clear();
      }
    } clear;
    for (uint32_t i = 0; i < num_in; ++i) {
      check_size(m, "input", i, m.in[i], in[i].size);
      ins.push_back(Ort::Value::CreateTensor(mem_, in[i].data, in[i].size, m.in[i].shape.data(),
                                             m.in[i].shape.size(), m.in[i].ort_type));
    }
    for (uint32_t i = 0; i < num_out; ++i) {
      check_size(m, "output", i, m.out[i], out[i].size);
      outs.push_back(Ort::Value::CreateTensor(mem_, out[i].data, out[i].size, m.out[i].shape.data(),
                                              m.out[i].shape.size(), m.out[i].ort_type));
    }
    run(m, ins.data(), outs.data());
    g_last_input.store(num_in ? in[0].data : nullptr, std::memory_order_relaxed);
    for (uint32_t i = 0; i < num_out; ++i) {
      const void *got = outs[i].GetTensorRawData();
      if (got != out[i].data && out[i].size) {  // ORT replaced our buffer: copy and count it
        std::memcpy(out[i].data, got, out[i].size);
        copied_.fetch_add(out[i].size, std::memory_order_relaxed);
      }
    }
  }

  void invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                      nns_tensors_desc &out_info, GstTensorMemory *out) override {
    std::shared_lock lock(mutex_);
    const Model &m = *model_;
    check_count(m, "input", in_info.num_tensors, m.in.size());
    std::vector<Ort::Value> ins;
    for (std::size_t i = 0; i < m.in.size(); ++i) {
      const nns_tensor_desc &d = in_info.tensors[i];
      std::vector<int64_t> shape = shape_of_checked(m, d, m.in[i], "input");
      if (d.type != m.in[i].desc.type)
        throw FilterError(err_prefix(m.path) + ": input " + std::to_string(i) + " ('" +
                              m.in[i].name + "') is " + desc_string(d) + " but the model wants " +
                              desc_string(m.in[i].desc, false),
                          -EINVAL);
      Port p = m.in[i];
      p.shape = shape;
      p.bytes = desc_bytes(d);
      check_size(m, "input", static_cast<uint32_t>(i), p, in[i].size);
      ins.push_back(Ort::Value::CreateTensor(mem_, in[i].data, in[i].size, shape.data(),
                                             shape.size(), m.in[i].ort_type));
    }
    std::vector<Ort::Value> outs;
    for (std::size_t i = 0; i < m.out.size(); ++i) outs.emplace_back(nullptr);
    run(m, ins.data(), outs.data());
    out_info = nns_tensors_desc{};
    out_info.num_tensors = static_cast<uint32_t>(m.out.size());
    std::lock_guard g(dyn_mutex_);
    for (std::size_t i = 0; i < m.out.size(); ++i) {
      auto ti = outs[i].GetTensorTypeAndShapeInfo();
      nns_tensor_desc &d = out_info.tensors[i];
      d = m.out[i].desc;
      set_dims(d, ti.GetShape());
      out[i].size = ti.GetElementCount() * type_size(desc_type(d));
      out[i].data = outs[i].GetTensorMutableRawData();
      if (out[i].data) dyn_outputs_.emplace(out[i].data, std::move(outs[i]));
    }
  }

  void free_output(void *data) override {
    std::lock_guard g(dyn_mutex_);
    dyn_outputs_.erase(data);
  }

  void reload(const nns_filter_props &p) override {
    auto m = open(p);  // loads outside the lock; invokes go on with the old model meanwhile
    std::unique_lock lock(mutex_);
    if (model_) {
      // The stream's caps stay as negotiated: the new model must take and give the same.
      nns_tensors_desc oi{}, oo{}, ni{}, no{};
      fill(*model_, oi, oo);
      fill(*m, ni, no);
      if (!same(oi, ni) || !same(oo, no))
        throw FilterError(err_prefix(p.num_models ? p.model_files[0] : "") +
                              ": the reloaded model's inputs/outputs differ from the current "
                              "model's; reload needs the same tensors",
                          -EINVAL);
    }
    model_ = std::move(m);
  }

  uint64_t copied_bytes() const { return copied_.load(); }

 private:
  static Ort::MemoryInfo make_mem() {
    return Ort::MemoryInfo::CreateCpu(OrtDeviceAllocator, OrtMemTypeDefault);
  }

  static bool same(const nns_tensors_desc &a, const nns_tensors_desc &b) {
    if (a.num_tensors != b.num_tensors) return false;
    for (uint32_t i = 0; i < a.num_tensors; ++i)
      if (a.tensors[i].type != b.tensors[i].type || !desc_dims_equal(a.tensors[i], b.tensors[i]))
        return false;
    return true;
  }

  void check_count(const Model &m, const char *what, std::size_t got, std::size_t want) const {
    if (got != want)
      throw FilterError(err_prefix(m.path) + ": got " + std::to_string(got) + " " + what +
                            " tensors, the model has " + std::to_string(want),
                        -EINVAL);
  }

  void check_size(const Model &m, const char *what, uint32_t i, const Port &p,
                  std::size_t got) const {
    if (got != p.bytes)
      throw FilterError(err_prefix(m.path) + ": " + what + " " + std::to_string(i) + " ('" +
                            p.name + "', " + desc_string(p.desc, false) + ") is " +
                            std::to_string(got) + " bytes, expected " + std::to_string(p.bytes),
                        -EINVAL);
  }

  std::vector<int64_t> shape_of_checked(const Model &m, const nns_tensor_desc &d, const Port &p,
                                        const char *what) const {
    std::vector<int64_t> shape;
    try {
      shape = shape_of(d, p.model_shape.size());
    } catch (const Error &e) {
      throw FilterError(err_prefix(m.path) + ": " + what + " '" + p.name + "': " + e.what(),
                        -EINVAL);
    }
    for (std::size_t k = 0; k < shape.size(); ++k)
      if (p.model_shape[k] >= 0 && p.model_shape[k] != shape[k])
        throw FilterError(err_prefix(m.path) + ": " + what + " '" + p.name + "' is " +
                              desc_string(d) + " (shape " + shape_string(shape) +
                              ") but the model's shape is " + shape_string(p.model_shape),
                          -EINVAL);
    return shape;
  }

  void run(const Model &m, const Ort::Value *ins, Ort::Value *outs) const {
    try {
      m.session.Run(run_options_, m.in_names.data(), ins, m.in.size(), m.out_names.data(), outs,
                    m.out.size());
    } catch (const Ort::Exception &e) {
      throw FilterError(err_prefix(m.path) + ": inference failed: " + e.what(), -EIO);
    }
  }

  // Opens the model file named by the properties and reconciles it with input=/output=.
  std::shared_ptr<Model> open(const nns_filter_props &p) {
    if (p.num_models != 1 || !p.model_files || !p.model_files[0])
      throw FilterError(std::string(kName) + ": model= must name exactly one .onnx file (got " +
                            std::to_string(p.num_models) + ")",
                        -EINVAL);
    auto model = std::make_shared<Model>();
    Model &m = *model;
    m.path = p.model_files[0];
    std::error_code ec;
    if (!std::filesystem::is_regular_file(m.path, ec))
      throw FilterError(err_prefix(m.path) + ": model file not found", -ENOENT);

    Ort::SessionOptions so;
    try {
      CustomOptions opts(p.custom, kName,
                         {"NumThreads", "InterOpNumThreads", "GraphOptimizationLevel",
                          "ExecutionMode", "AllowSpinning"});
      int threads = p.num_threads > 0 ? p.num_threads : 0;
      if (auto n = opts.get_int("NumThreads", 0, 1024)) threads = static_cast<int>(*n);
      so.SetIntraOpNumThreads(threads);
      if (auto n = opts.get_int("InterOpNumThreads", 0, 1024))
        so.SetInterOpNumThreads(static_cast<int>(*n));
      if (auto lvl = opts.get_choice("GraphOptimizationLevel", {"disable", "basic", "extended",
                                                                "all", "0", "1", "2", "99"})) {
        static const GraphOptimizationLevel kLevels[] = {ORT_DISABLE_ALL, ORT_ENABLE_BASIC,
                                                         ORT_ENABLE_EXTENDED, ORT_ENABLE_ALL};
        so.SetGraphOptimizationLevel(kLevels[*lvl % 4]);
      }
      if (auto mode = opts.get_choice("ExecutionMode", {"sequential", "parallel"}))
        so.SetExecutionMode(*mode ? ORT_PARALLEL : ORT_SEQUENTIAL);
      if (auto spin = opts.get_bool("AllowSpinning")) {
        so.AddConfigEntry("session.intra_op.allow_spinning", *spin ? "1" : "0");
        so.AddConfigEntry("session.inter_op.allow_spinning", *spin ? "1" : "0");
      }
    } catch (const Error &e) {
      throw FilterError(e.what(), -EINVAL);
    }

    try {
      m.session = Ort::Session(ort_env(), m.path.c_str(), so);
    } catch (const Ort::Exception &e) {
      throw FilterError(err_prefix(m.path) + ": cannot load the model: " + e.what(), -EINVAL);
    }
    read_ports(m, true);
    read_ports(m, false);
    select_outputs(m, p.output);
    if (p.input && p.input->num_tensors)
      resolve_inputs(m, *p.input, desc_names_only(*p.input) ? "inputname=" : "input=");
    check_outputs(m, p.output);
    bool free_in = false;
    for (const auto &port : m.in) free_in = free_in || port.has_free_dim();
    if (free_in && !p.invoke_dynamic) {
      for (const auto &port : m.in)
        if (port.has_free_dim())
          throw FilterError(err_prefix(m.path) + ": model input '" + port.name +
                                "' has free dimensions (shape " + shape_string(port.shape) +
                                "); give the sizes with input= (and inputtype=) or set "
                                "invoke-dynamic=true",
                            -EINVAL);
    }
    set_names(m);
    if (!free_in) finish(m);
    return model;
  }

  void read_ports(Model &m, bool inputs) {
    Ort::AllocatorWithDefaultOptions alloc;
    std::size_t n = inputs ? m.session.GetInputCount() : m.session.GetOutputCount();
    const char *what = inputs ? "input" : "output";
    if (n == 0 || n > NNS_TENSOR_SIZE_LIMIT)
      throw FilterError(err_prefix(m.path) + ": the model has " + std::to_string(n) + " " + what +
                            " tensors; 1.." + std::to_string(NNS_TENSOR_SIZE_LIMIT) +
                            " are supported",
                        -EINVAL);
    auto &ports = inputs ? m.in : m.out;
    for (std::size_t i = 0; i < n; ++i) {
      Port p;
      p.name = (inputs ? m.session.GetInputNameAllocated(i, alloc)
                       : m.session.GetOutputNameAllocated(i, alloc))
                   .get();
      Ort::TypeInfo ti = inputs ? m.session.GetInputTypeInfo(i) : m.session.GetOutputTypeInfo(i);
      if (ti.GetONNXType() != ONNX_TYPE_TENSOR)
        throw FilterError(err_prefix(m.path) + ": " + what + " '" + p.name +
                              "' is not a tensor (sequences and maps are not supported)",
                          -ENOTSUP);
      auto tsi = ti.GetTensorTypeAndShapeInfo();
      p.ort_type = tsi.GetElementType();
      if (!to_nns_type(p.ort_type, p.desc.type))
        throw FilterError(err_prefix(m.path) + ": " + what + " '" + p.name + "' has type " +
                              ort_type_name(p.ort_type) + ", which NNStreamer tensors cannot carry",
                          -ENOTSUP);
      p.model_shape = tsi.GetShape();
      if (p.model_shape.size() > NNS_TENSOR_RANK_LIMIT)
        throw FilterError(err_prefix(m.path) + ": " + what + " '" + p.name + "' has rank " +
                              std::to_string(p.model_shape.size()) + ", the limit is " +
                              std::to_string(NNS_TENSOR_RANK_LIMIT),
                          -ENOTSUP);
      p.shape = p.model_shape;
      set_name(p.desc, p.name);
      set_dims(p.desc, p.shape);
      ports.push_back(std::move(p));
    }
  }

  // output= names pick a subset of the model outputs, in the order given (as upstream).
  void select_outputs(Model &m, const nns_tensors_desc *want) {
    if (!want || !want->num_tensors || !want->tensors[0].name[0]) return;
    std::vector<Port> picked;
    for (uint32_t i = 0; i < want->num_tensors; ++i) {
      std::string name(want->tensors[i].name, strnlen(want->tensors[i].name, NNS_TENSOR_NAME_MAX));
      bool found = false;
      for (const auto &p : m.out)
        if (p.name == name) {
          picked.push_back(p);
          found = true;
        }
      if (!found) {
        std::string names;
        for (const auto &p : m.out) names += (names.empty() ? "'" : ", '") + p.name + "'";
        throw FilterError(err_prefix(m.path) + ": outputname '" + name +
                              "' is not an output of the model (outputs: " + names + ")",
                          -EINVAL);
      }
    }
    m.out = std::move(picked);
  }

  // Applies a caller's input description (input=/inputtype=/inputname= or negotiated caps).
  void resolve_inputs(Model &m, const nns_tensors_desc &given, const char *source) {
    check_count(m, source, given.num_tensors, m.in.size());
    std::vector<Port> ordered(m.in.size());
    for (uint32_t i = 0; i < given.num_tensors; ++i) {
      const nns_tensor_desc &d = given.tensors[i];
      std::size_t k = i;
      if (d.name[0]) {  // by name when named
        std::string name(d.name, strnlen(d.name, NNS_TENSOR_NAME_MAX));
        k = m.in.size();
        for (std::size_t j = 0; j < m.in.size(); ++j)
          if (m.in[j].name == name) k = j;
        if (k == m.in.size()) {
          std::string names;
          for (const auto &q : m.in) names += (names.empty() ? "'" : ", '") + q.name + "'";
          throw FilterError(err_prefix(m.path) + ": inputname '" + name +
                                "' is not an input of the model (inputs: " + names + ")",
                            -EINVAL);
        }
      }
      Port p = m.in[k];
      if (d.type != p.desc.type && d.type < _NNS_END)
        throw FilterError(err_prefix(m.path) + ": " + source + " tensor " + std::to_string(i) +
                              " is " + desc_string(d) + " but model input '" + p.name + "' is " +
                              desc_string(p.desc, false),
                          -EINVAL);
      if (desc_rank(d)) {
        p.shape = shape_of_checked(m, d, p, source);
        set_dims(p.desc, p.shape);
      }
      ordered[i] = std::move(p);
    }
    m.in = std::move(ordered);
    set_names(m);
  }

  static void set_names(Model &m) {
    m.in_names.clear();
    m.out_names.clear();
    for (auto &p : m.in) m.in_names.push_back(p.name.c_str());
    for (auto &p : m.out) m.out_names.push_back(p.name.c_str());
  }

  void check_outputs(const Model &m, const nns_tensors_desc *want) const {
    if (!want || !want->num_tensors) return;
    check_count(m, "output=", want->num_tensors, m.out.size());
    for (uint32_t i = 0; i < want->num_tensors; ++i) {
      const nns_tensor_desc &d = want->tensors[i];
      const Port &p = m.out[i];
      bool type_bad = d.type < _NNS_END && d.type != p.desc.type;
      bool dims_bad = desc_rank(d) && !p.has_free_dim() && !desc_dims_equal(d, p.desc);
      if (type_bad || dims_bad)
        throw FilterError(err_prefix(m.path) + ": output= tensor " + std::to_string(i) + " is " +
                              desc_string(d) + " but model output '" + p.name + "' is " +
                              desc_string(p.desc, false),
                          -EINVAL);
    }
  }

  // Computes byte sizes and, when an output shape depends on the input, learns it from one
  // run on zeros. Free output dims are those the model declares (-1), so a later
  // set_input_info with other sizes learns them again.
  void finish(Model &m) {
    set_names(m);
    for (auto &p : m.in) p.bytes = desc_bytes(p.desc);
    bool free_out = false;
    for (auto &p : m.out)
      for (auto v : p.model_shape) free_out = free_out || v < 0;
    if (free_out) {
      std::vector<std::vector<uint8_t>> zeros;
      std::vector<Ort::Value> ins, outs;
      for (auto &p : m.in) {
        zeros.emplace_back(p.bytes);
        ins.push_back(Ort::Value::CreateTensor(mem_, zeros.back().data(), p.bytes, p.shape.data(),
                                               p.shape.size(), p.ort_type));
      }
      for (std::size_t i = 0; i < m.out.size(); ++i) outs.emplace_back(nullptr);
      run(m, ins.data(), outs.data());
      for (std::size_t i = 0; i < m.out.size(); ++i) {
        m.out[i].shape = outs[i].GetTensorTypeAndShapeInfo().GetShape();
        set_dims(m.out[i].desc, m.out[i].shape);
      }
    }
    for (auto &p : m.out) p.bytes = desc_bytes(p.desc);
    m.resolved = true;
  }

  static void fill(const Model &m, nns_tensors_desc &in, nns_tensors_desc &out) {
    in = nns_tensors_desc{};
    out = nns_tensors_desc{};
    bool free_dims = !m.resolved;
    in.num_tensors = static_cast<uint32_t>(m.in.size());
    for (std::size_t i = 0; i < m.in.size(); ++i) in.tensors[i] = m.in[i].desc;
    out.num_tensors = static_cast<uint32_t>(m.out.size());
    for (std::size_t i = 0; i < m.out.size(); ++i) out.tensors[i] = m.out[i].desc;
    // Free dimensions (invoke-dynamic) are reported as 1 in a flexible stream, as upstream.
    in.format = out.format = free_dims ? _NNS_TENSOR_FORMAT_FLEXIBLE : _NNS_TENSOR_FORMAT_STATIC;
  }

  Ort::MemoryInfo mem_;
  Ort::RunOptions run_options_;
  mutable std::shared_mutex mutex_;  // invoke: shared; reload/set_input_info: exclusive
  std::shared_ptr<Model> model_;
  std::atomic<uint64_t> copied_{0};
  std::mutex dyn_mutex_;
  std::map<void *, Ort::Value> dyn_outputs_;  // invoke_dynamic results until free_output
};

const char *const kExtensions[] = {".onnx", ".ort", nullptr};

}  // namespace
}  // namespace nns

NNS_FILTER_BACKEND_EXPORT(nns::OnnxRuntimeFilter, "onnxruntime",
                          NNS_FILTER_FLAG_THREAD_SAFE | NNS_FILTER_FLAG_DYNAMIC |
                              NNS_FILTER_FLAG_TENSOR_NAMES,
                          nns::kExtensions)

// Bytes of output ORT did not write in place and the back end had to copy (0 in practice);
// tests use it to prove zero copy. `priv` is the instance open() returned.
extern "C" __attribute__((visibility("default"))) uint64_t nns_filter_onnxruntime_copied_bytes(
    void *priv) {
  auto *f = dynamic_cast<nns::OnnxRuntimeFilter *>(static_cast<nns::FilterBackend *>(priv));
  return f ? f->copied_bytes() : 0;
}

// The input pointer the latest invoke gave ONNX Runtime (test hook, see above).
extern "C" __attribute__((visibility("default"))) const void *nns_filter_onnxruntime_last_input(
    void) {
  return nns::g_last_input.load();
}

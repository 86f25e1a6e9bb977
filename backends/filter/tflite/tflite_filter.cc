// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter back end for TensorFlow Lite models (framework=tensorflow2-lite, alias
// tensorflow-lite / tflite; claims .tflite). Built as libnnstreamer_filter_tensorflow2-lite.so,
// upstream's file name.
//
//   gst-launch-1.0 filesrc location=orange.raw ! application/octet-stream !
//     tensor_converter input-dim=3:224:224:1 input-type=uint8 !
//     tensor_filter framework=tensorflow-lite model=mobilenet_v2_1.0_224_quant.tflite
//       custom=NumThreads:2 ! tensor_sink
//
// Debian ships no TensorFlow Lite library: the verified flatbuffer (tflite_model.h) is
// translated into an ONNX graph in memory (tflite_to_onnx.h) and run by ONNX Runtime, whose
// QDQ fusion gives integer kernels for quantized models. Tensors are passed as the model
// declares them (uint8/int8 stay quantized), NNStreamer dims are the reversed TFLite shape.
// Zero copy: inputs are OrtValues over the caller's buffers and outputs are written straight
// into the caller's output buffers. A new input shape (input=, set_input_info, invoke-dynamic)
// re-translates the graph once per distinct shape. custom=: NumThreads:N (default 1, TFLite's
// own default); upstream's Delegate/ExtDelegate* keys are accepted and ignored with a warning,
// unknown keys warn. See docs/backends/tflite.md.

#include <onnxruntime_cxx_api.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <map>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "core/backend_desc.h"
#include "nns_filter_backend.hh"
#include "tflite_model.h"
#include "tflite_to_onnx.h"

namespace nns {
namespace {

constexpr const char *kName = "tensorflow2-lite";

Ort::Env &ort_env() {
  static Ort::Env env(ORT_LOGGING_LEVEL_ERROR, "nnstreamer-tflite");
  return env;
}

void warn(const std::string &msg) {
  std::fprintf(stderr, "nnstreamer %s: warning: %s\n", kName, msg.c_str());
}

uint32_t nns_type_of(int t) {
  switch (t) {
    case tfl::kFloat32:
      return _NNS_FLOAT32;
    case tfl::kFloat16:
      return _NNS_FLOAT16;
    case tfl::kInt32:
      return _NNS_INT32;
    case tfl::kUInt8:
    case tfl::kBool:
      return _NNS_UINT8;
    case tfl::kInt64:
      return _NNS_INT64;
    case tfl::kInt16:
      return _NNS_INT16;
    case tfl::kInt8:
      return _NNS_INT8;
    case tfl::kFloat64:
      return _NNS_FLOAT64;
    case tfl::kUInt64:
      return _NNS_UINT64;
    case tfl::kUInt32:
      return _NNS_UINT32;
    case tfl::kUInt16:
      return _NNS_UINT16;
    default:
      return _NNS_END;
  }
}

struct Port {
  std::string name;  // the TFLite tensor name
  int tfl_type = 0;
  ONNXTensorElementDataType ort_type{};
  nns_tensor_desc desc{};
  std::vector<int64_t> shape;
  std::size_t bytes = 0;
};

// One translated graph for one set of input shapes.
struct Plan {
  std::shared_ptr<const tfl::Model> model;
  tfl::Translation tr;
  mutable Ort::Session session{nullptr};
  std::vector<Port> in, out;
  std::vector<const char *> in_names, run_names;  // run_names: ORT outputs fetched per run
  std::vector<int> out_run;  // per model output: index in run_names, -1 = post-process output
  std::vector<std::vector<int64_t>> post_shapes;  // shapes of the post-process inputs
};

struct Settings {
  int threads = 1;
};

Settings parse_custom(const char *text, int num_threads) {
  Settings s;
  if (num_threads > 0) s.threads = num_threads;
  if (!text || !*text) return s;
  std::string all(text);
  std::size_t pos = 0;
  while (pos <= all.size()) {
    std::size_t comma = all.find(',', pos);
    std::string item =
        all.substr(pos, comma == std::string::npos ? std::string::npos : comma - pos);
    pos = comma == std::string::npos ? all.size() + 1 : comma + 1;
    while (!item.empty() && item.front() == ' ') item.erase(item.begin());
    while (!item.empty() && item.back() == ' ') item.pop_back();
    if (item.empty()) continue;
    std::size_t colon = item.find(':');
    std::string key = item.substr(0, colon),
                value = colon == std::string::npos ? "" : item.substr(colon + 1);
    if (key == "NumThreads") {
      char *end = nullptr;
      long n = std::strtol(value.c_str(), &end, 10);
      if (value.empty() || *end || n < -1 || n > 1024)
        throw FilterError(std::string(kName) + ": custom=NumThreads:" + value +
                              " is not a thread count (-1..1024)",
                          -EINVAL);
      s.threads = n <= 0 ? 1 : static_cast<int>(n);
    } else if (key == "Delegate" || key == "ExtDelegateLib" || key == "ExtDelegateKeyVal") {
      warn("custom=" + key + " is ignored: this back end runs on ONNX Runtime's CPU kernels");
    } else {
      warn("unknown custom option '" + key +
           "' ignored (known: NumThreads, Delegate, ExtDelegateLib, ExtDelegateKeyVal)");
    }
  }
  return s;
}

std::string prefix(const std::string &path) {
  return std::string(kName) + ": " + path;
}

class TfliteFilter final : public FilterBackend {
 public:
  explicit TfliteFilter(const nns_filter_props &p)
      : mem_(Ort::MemoryInfo::CreateCpu(OrtDeviceAllocator, OrtMemTypeDefault)) {
    plan_ = open(p);
  }

  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    std::shared_lock lock(mutex_);
    fill(*plan_, in, out);
    return true;
  }

  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    std::unique_lock lock(mutex_);
    auto shapes = shapes_from(*plan_, in, "the negotiated input");
    if (shapes != current_shapes(*plan_)) plan_ = rebuild(plan_->model, shapes, "set_input_info");
    nns_tensors_desc ignored{};
    fill(*plan_, ignored, out);
    return true;
  }

  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    std::shared_lock lock(mutex_);
    const Plan &pl = *plan_;
    if (num_in != pl.in.size() || num_out != pl.out.size())
      throw FilterError(prefix(pl.model->path) + ": got " + std::to_string(num_in) +
                            " inputs and " + std::to_string(num_out) + " outputs, the model has " +
                            std::to_string(pl.in.size()) + " and " + std::to_string(pl.out.size()),
                        -EINVAL);
    for (uint32_t i = 0; i < num_in; ++i) check_size(pl, "input", i, pl.in[i], in[i].size);
    for (uint32_t i = 0; i < num_out; ++i) check_size(pl, "output", i, pl.out[i], out[i].size);
    run(pl, in, out);
  }

  void invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                      nns_tensors_desc &out_info, GstTensorMemory *out) override {
    std::shared_ptr<Plan> pl;
    {
      std::unique_lock lock(mutex_);
      auto shapes = shapes_from(*plan_, in_info, "the invoke-dynamic input");
      if (shapes != current_shapes(*plan_))
        plan_ = rebuild(plan_->model, shapes, "the invoke-dynamic input");  // re-plan
      pl = plan_;
    }
    for (uint32_t i = 0; i < pl->in.size(); ++i) check_size(*pl, "input", i, pl->in[i], in[i].size);
    out_info = nns_tensors_desc{};
    out_info.num_tensors = static_cast<uint32_t>(pl->out.size());
    std::vector<GstTensorMemory> outs(pl->out.size());
    std::lock_guard g(dyn_mutex_);
    for (std::size_t i = 0; i < pl->out.size(); ++i) {
      auto buf = std::make_unique<uint8_t[]>(pl->out[i].bytes ? pl->out[i].bytes : 1);
      outs[i] = {buf.get(), pl->out[i].bytes};
      out[i] = outs[i];
      out_info.tensors[i] = pl->out[i].desc;
      dyn_outputs_.emplace(buf.get(), std::move(buf));
    }
    run(*pl, in, outs.data());
  }

  void free_output(void *data) override {
    std::lock_guard g(dyn_mutex_);
    dyn_outputs_.erase(data);
  }

  void reload(const nns_filter_props &p) override {
    auto pl = open(p);
    std::unique_lock lock(mutex_);
    nns_tensors_desc oi{}, oo{}, ni{}, no{};
    fill(*plan_, oi, oo);
    fill(*pl, ni, no);
    auto same = [](const nns_tensors_desc &a, const nns_tensors_desc &b) {
      if (a.num_tensors != b.num_tensors) return false;
      for (uint32_t i = 0; i < a.num_tensors; ++i)
        if (a.tensors[i].type != b.tensors[i].type || !desc_dims_equal(a.tensors[i], b.tensors[i]))
          return false;
      return true;
    };
    if (!same(oi, ni) || !same(oo, no))
      throw FilterError(prefix(pl->model->path) +
                            ": the reloaded model's inputs/outputs differ from the current "
                            "model's; reload needs the same tensors",
                        -EINVAL);
    plan_ = std::move(pl);
  }

 private:
  std::shared_ptr<Plan> open(const nns_filter_props &p) {
    if (p.num_models != 1 || !p.model_files || !p.model_files[0])
      throw FilterError(std::string(kName) + ": model= must name exactly one .tflite file (got " +
                            std::to_string(p.num_models) + ")",
                        -EINVAL);
    settings_ = parse_custom(p.custom, p.num_threads);
    std::shared_ptr<tfl::Model> model;
    try {
      model = std::make_shared<tfl::Model>(tfl::load_model(p.model_files[0]));
    } catch (const tfl::ModelError &e) {
      throw FilterError(std::string(kName) + ": " + e.what(), -EINVAL);
    }
    std::vector<std::vector<int64_t>> shapes;
    for (int t : model->inputs)
      shapes.emplace_back(model->tensors[t].shape.begin(), model->tensors[t].shape.end());
    auto pl = build(model, shapes);
    if (p.input && p.input->num_tensors && desc_rank(p.input->tensors[0])) {
      auto want = shapes_from(*pl, *p.input, "input=");
      if (want != shapes) pl = rebuild(model, want, "input=");
    }
    if (p.output && p.output->num_tensors) {
      if (p.output->num_tensors != pl->out.size())
        throw FilterError(prefix(model->path) + ": output= gives " +
                              std::to_string(p.output->num_tensors) + " tensors, the model has " +
                              std::to_string(pl->out.size()),
                          -EINVAL);
      for (uint32_t i = 0; i < p.output->num_tensors; ++i) {
        const nns_tensor_desc &d = p.output->tensors[i];
        bool type_bad = d.type < _NNS_END && d.type != pl->out[i].desc.type;
        bool dims_bad = desc_rank(d) && !desc_dims_equal(d, pl->out[i].desc);
        if (type_bad || dims_bad)
          throw FilterError(prefix(model->path) + ": output= tensor " + std::to_string(i) + " is " +
                                desc_string(d) + " but model output '" + pl->out[i].name + "' is " +
                                desc_string(pl->out[i].desc, false),
                            -EINVAL);
      }
    }
    return pl;
  }

  static std::vector<std::vector<int64_t>> current_shapes(const Plan &pl) {
    std::vector<std::vector<int64_t>> s;
    for (auto &p : pl.in) s.push_back(p.shape);
    return s;
  }

  std::vector<std::vector<int64_t>> shapes_from(const Plan &pl, const nns_tensors_desc &given,
                                                const char *source) const {
    if (given.num_tensors != pl.in.size())
      throw FilterError(prefix(pl.model->path) + ": " + source + " has " +
                            std::to_string(given.num_tensors) + " tensors, the model has " +
                            std::to_string(pl.in.size()) + " inputs",
                        -EINVAL);
    std::vector<std::vector<int64_t>> s;
    for (uint32_t i = 0; i < given.num_tensors; ++i) {
      const nns_tensor_desc &d = given.tensors[i];
      const Port &p = pl.in[i];
      if (d.type < _NNS_END && d.type != p.desc.type)
        throw FilterError(prefix(pl.model->path) + ": " + source + " tensor " + std::to_string(i) +
                              " is " + desc_string(d) + " but model input '" + p.name + "' is " +
                              desc_string(p.desc, false),
                          -EINVAL);
      if (!desc_rank(d)) {
        s.push_back(p.shape);
        continue;
      }
      try {
        s.push_back(shape_of(d, std::max<std::size_t>(p.shape.size(), 1)));
      } catch (const std::exception &e) {
        throw FilterError(prefix(pl.model->path) + ": " + source + " tensor " + std::to_string(i) +
                              ": " + e.what(),
                          -EINVAL);
      }
      if (p.shape.empty() && s.back() == std::vector<int64_t>{1}) s.back().clear();
    }
    return s;
  }

  // "8:8,3:224:224:1": TFLite shapes as NNStreamer dims (innermost first).
  static std::string dims_string(const std::vector<std::vector<int64_t>> &shapes) {
    std::string s;
    for (const auto &shape : shapes) {
      if (!s.empty()) s += ",";
      for (auto d = shape.rbegin(); d != shape.rend(); ++d)
        s += (d == shape.rbegin() ? "" : ":") + std::to_string(*d);
      if (shape.empty()) s += "1";
    }
    return s;
  }

  // build() at input shapes other than the file's: a failure names both (a graph whose
  // RESHAPE or another operator bakes the batch in fails here when the batch grows).
  std::shared_ptr<Plan> rebuild(std::shared_ptr<const tfl::Model> model,
                                const std::vector<std::vector<int64_t>> &shapes,
                                const char *source) {
    try {
      return build(model, shapes);
    } catch (const FilterError &e) {
      std::vector<std::vector<int64_t>> file;
      for (int t : model->inputs)
        file.emplace_back(model->tensors[t].shape.begin(), model->tensors[t].shape.end());
      std::string why = e.what();
      const std::string head = prefix(model->path) + ": ";
      if (why.rfind(head, 0) == 0) why.erase(0, head.size());
      throw FilterError(head + source + " asks the inputs " + dims_string(shapes) +
                            ", the file declares " + dims_string(file) +
                            " and its graph does not run at the new shapes (an operator may "
                            "fix them, such as a RESHAPE to the file's batch): " +
                            why,
                        e.code());
    }
  }

  std::shared_ptr<Plan> build(std::shared_ptr<const tfl::Model> model,
                              const std::vector<std::vector<int64_t>> &shapes) {
    auto pl = std::make_shared<Plan>();
    pl->model = model;
    const tfl::Model &m = *model;
    try {
      pl->tr = tfl::translate(m, shapes);
    } catch (const tfl::ModelError &e) {
      throw FilterError(std::string(kName) + ": " + e.what(), -ENOTSUP);
    }
    Ort::SessionOptions so;
    so.SetIntraOpNumThreads(settings_.threads);
    so.SetInterOpNumThreads(1);
    so.SetGraphOptimizationLevel(ORT_ENABLE_ALL);
    if (const char *dump = std::getenv("NNS_TFLITE_DUMP_ONNX")) {  // debugging aid
      if (FILE *f = std::fopen(dump, "wb")) {
        std::fwrite(pl->tr.onnx.data(), 1, pl->tr.onnx.size(), f);
        std::fclose(f);
      }
    }
    if (const char *opt = std::getenv("NNS_TFLITE_DUMP_OPTIMIZED"))
      so.SetOptimizedModelFilePath(opt);
    try {
      pl->session = Ort::Session(ort_env(), pl->tr.onnx.data(), pl->tr.onnx.size(), so);
    } catch (const Ort::Exception &e) {
      throw FilterError(
          prefix(m.path) + ": ONNX Runtime rejected the translated graph: " + e.what(), -ENOTSUP);
    }
    for (std::size_t i = 0; i < m.inputs.size(); ++i) {
      Port p = port_of(m, m.inputs[i]);
      p.shape = shapes[i];
      finish_port(p);
      pl->in.push_back(std::move(p));
    }
    for (auto &n : pl->tr.in_names) pl->in_names.push_back(n.c_str());
    for (std::size_t i = 0; i < m.outputs.size(); ++i) {
      const std::string &n = pl->tr.out_names[i];
      if (n.empty()) {
        pl->out_run.push_back(-1);
      } else {
        pl->out_run.push_back(static_cast<int>(pl->run_names.size()));
        pl->run_names.push_back(n.c_str());
      }
      pl->out.push_back(port_of(m, m.outputs[i]));
    }
    if (pl->tr.post) {
      pl->run_names.push_back(pl->tr.post->boxes.c_str());
      pl->run_names.push_back(pl->tr.post->scores.c_str());
    }
    learn_output_shapes(*pl);
    return pl;
  }

  static Port port_of(const tfl::Model &m, int t) {
    const tfl::Tensor &x = m.tensors[t];
    Port p;
    p.name = x.name;
    p.tfl_type = x.type;
    p.desc.type = nns_type_of(x.type);
    if (p.desc.type == _NNS_END)
      throw FilterError(prefix(m.path) + ": tensor '" + x.name + "' has type " +
                            tfl::type_name(x.type) + ", which NNStreamer tensors cannot carry",
                        -ENOTSUP);
    p.ort_type = static_cast<ONNXTensorElementDataType>(tfl::onnx_type(x.type));
    p.shape.assign(x.shape.begin(), x.shape.end());
    set_name(p.desc, p.name);
    return p;
  }

  static void finish_port(Port &p) {
    if (p.shape.size() > NNS_TENSOR_RANK_LIMIT)
      throw FilterError(std::string(kName) + ": tensor '" + p.name + "' has rank " +
                            std::to_string(p.shape.size()) + ", the limit is " +
                            std::to_string(NNS_TENSOR_RANK_LIMIT),
                        -ENOTSUP);
    set_dims(p.desc, p.shape.empty() ? std::vector<int64_t>{1} : p.shape);
    std::size_t n = 1;
    for (auto d : p.shape) n *= static_cast<std::size_t>(d);
    p.bytes = n * tfl::type_size(p.tfl_type);
  }

  // Output shapes: the post-process outputs from its options, the rest from one run on zeros
  // (the graph's shapes depend on the input shapes given).
  void learn_output_shapes(Plan &pl) {
    std::vector<std::vector<uint8_t>> zeros;
    std::vector<Ort::Value> ins, outs;
    for (auto &p : pl.in) {
      zeros.emplace_back(std::max<std::size_t>(p.bytes, 1));
      ins.push_back(Ort::Value::CreateTensor(mem_, zeros.back().data(), p.bytes, p.shape.data(),
                                             p.shape.size(), p.ort_type));
    }
    for (std::size_t i = 0; i < pl.run_names.size(); ++i) outs.emplace_back(nullptr);
    try {
      pl.session.Run(Ort::RunOptions{nullptr}, pl.in_names.data(), ins.data(), ins.size(),
                     pl.run_names.data(), outs.data(), outs.size());
    } catch (const Ort::Exception &e) {
      throw FilterError(prefix(pl.model->path) + ": the translated graph does not run: " + e.what(),
                        -ENOTSUP);
    }
    for (std::size_t i = 0; i < pl.out.size(); ++i) {
      Port &p = pl.out[i];
      if (pl.out_run[i] >= 0) {
        p.shape = outs[pl.out_run[i]].GetTensorTypeAndShapeInfo().GetShape();
      } else {
        const auto &post = *pl.tr.post;
        int k = 0;
        for (std::size_t j = 0; j < post.outputs.size(); ++j)
          if (pl.model->outputs[i] == post.outputs[j]) k = static_cast<int>(j);
        int64_t md = post.slots();
        p.shape = k == 0   ? std::vector<int64_t>{1, md, 4}
                  : k == 3 ? std::vector<int64_t>{1}
                           : std::vector<int64_t>{1, md};
        if (p.tfl_type != tfl::kFloat32)
          throw FilterError(
              prefix(pl.model->path) + ": TFLite_Detection_PostProcess outputs must be float32",
              -ENOTSUP);
      }
      finish_port(p);
    }
    if (pl.tr.post) {
      std::size_t base = pl.run_names.size() - 2;
      pl.post_shapes = {outs[base].GetTensorTypeAndShapeInfo().GetShape(),
                        outs[base + 1].GetTensorTypeAndShapeInfo().GetShape()};
    }
  }

  void check_size(const Plan &pl, const char *what, uint32_t i, const Port &p,
                  std::size_t got) const {
    if (got != p.bytes)
      throw FilterError(prefix(pl.model->path) + ": " + what + " " + std::to_string(i) + " ('" +
                            p.name + "', " + desc_string(p.desc, false) + ") is " +
                            std::to_string(got) + " bytes, expected " + std::to_string(p.bytes),
                        -EINVAL);
  }

  void run(const Plan &pl, const GstTensorMemory *in, GstTensorMemory *out) const {
    thread_local std::vector<Ort::Value> ins, outs;
    thread_local std::vector<float> post_boxes, post_scores;
    struct Clear {
      ~Clear() {
        ins.clear();
        outs.clear();
      }
    } clear;
    for (std::size_t i = 0; i < pl.in.size(); ++i)
      ins.push_back(Ort::Value::CreateTensor(mem_, in[i].data, in[i].size, pl.in[i].shape.data(),
                                             pl.in[i].shape.size(), pl.in[i].ort_type));
    for (std::size_t i = 0; i < pl.out.size(); ++i)
      if (pl.out_run[i] >= 0)
        outs.push_back(Ort::Value::CreateTensor(mem_, out[i].data, out[i].size,
                                                pl.out[i].shape.data(), pl.out[i].shape.size(),
                                                pl.out[i].ort_type));
    if (pl.tr.post) {
      auto count = [](const std::vector<int64_t> &s) {
        std::size_t n = 1;
        for (auto d : s) n *= static_cast<std::size_t>(d);
        return n;
      };
      post_boxes.resize(count(pl.post_shapes[0]));
      post_scores.resize(count(pl.post_shapes[1]));
      outs.push_back(Ort::Value::CreateTensor<float>(mem_, post_boxes.data(), post_boxes.size(),
                                                     pl.post_shapes[0].data(),
                                                     pl.post_shapes[0].size()));
      outs.push_back(Ort::Value::CreateTensor<float>(mem_, post_scores.data(), post_scores.size(),
                                                     pl.post_shapes[1].data(),
                                                     pl.post_shapes[1].size()));
    }
    try {
      pl.session.Run(run_options_, pl.in_names.data(), ins.data(), ins.size(), pl.run_names.data(),
                     outs.data(), outs.size());
    } catch (const Ort::Exception &e) {
      throw FilterError(prefix(pl.model->path) + ": inference failed: " + e.what(), -EIO);
    }
    for (std::size_t i = 0; i < pl.out.size(); ++i) {
      if (pl.out_run[i] < 0) continue;
      const void *got = outs[pl.out_run[i]].GetTensorRawData();
      if (got != out[i].data && out[i].size) std::memcpy(out[i].data, got, out[i].size);
    }
    if (pl.tr.post) post_process(pl, post_boxes.data(), post_scores.data(), out);
  }

  void post_process(const Plan &pl, const float *boxes, const float *scores,
                    GstTensorMemory *out) const {
    const tfl::DetectionPost &p = *pl.tr.post;
    float *dst[4] = {};
    for (std::size_t i = 0; i < pl.out.size(); ++i)
      for (std::size_t j = 0; j < 4; ++j)
        if (pl.model->outputs[i] == p.outputs[j]) dst[j] = static_cast<float *>(out[i].data);
    thread_local std::vector<float> scratch;  // outputs the model does not expose
    scratch.resize(static_cast<std::size_t>(p.slots()) * 4);
    for (float *&d : dst)
      if (!d) d = scratch.data();
    detection_postprocess(p.opts, boxes, scores, p.anchors.data(), p.num_anchors, dst[0], dst[1],
                          dst[2], dst[3]);
  }

  static void fill(const Plan &pl, nns_tensors_desc &in, nns_tensors_desc &out) {
    in = nns_tensors_desc{};
    out = nns_tensors_desc{};
    in.num_tensors = static_cast<uint32_t>(pl.in.size());
    for (std::size_t i = 0; i < pl.in.size(); ++i) in.tensors[i] = pl.in[i].desc;
    out.num_tensors = static_cast<uint32_t>(pl.out.size());
    for (std::size_t i = 0; i < pl.out.size(); ++i) out.tensors[i] = pl.out[i].desc;
  }

  Ort::MemoryInfo mem_;
  Ort::RunOptions run_options_;
  Settings settings_;
  mutable std::shared_mutex mutex_;  // invoke: shared; re-plan/reload: exclusive
  std::shared_ptr<Plan> plan_;
  std::mutex dyn_mutex_;
  std::map<void *, std::unique_ptr<uint8_t[]>> dyn_outputs_;
};

const char *const kExtensions[] = {".tflite", nullptr};

int check_accelerator(const char *accl) {
  if (!accl) return -EINVAL;
  std::string a(accl);
  for (auto &c : a) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  if (a == "default" || a == "auto" || a == "none" || a == "cpu" || a == "cpu.simd" ||
      a == "cpu.neon")
    return 0;
  return -ENOENT;
}

}  // namespace
}  // namespace nns

extern "C" __attribute__((visibility("default"))) const nns_filter_backend_i *
nns_filter_backend_entry(void) {
  static const nns_filter_backend_i table = [] {
    nns_filter_backend_i t = nns::FilterBackendAdapter<nns::TfliteFilter>::make(
        nns::kName, NNS_FILTER_FLAG_THREAD_SAFE | NNS_FILTER_FLAG_DYNAMIC, nns::kExtensions);
    t.check_accelerator = &nns::check_accelerator;
    return t;
  }();
  return &table;
}

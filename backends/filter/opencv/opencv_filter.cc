// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter back end for OpenCV DNN (framework=opencv): ONNX, Caffe, TensorFlow and
// Darknet models.
//
//   gst-launch-1.0 filesrc location=9.raw blocksize=784 ! application/octet-stream !
//     tensor_converter input-dim=28:28:1:1 input-type=uint8 !
//     tensor_transform mode=arithmetic option=typecast:float32,add:-127.5,div:127.5 !
//     tensor_filter framework=opencv model=lenet.prototxt,lenet_iter_9000.caffemodel ! tensor_sink
//
// model= is one file (.onnx, frozen .pb) or two (.prototxt + .caffemodel, .cfg + .weights,
// .pb + .pbtxt) in any order. Inputs: ONNX names/types/shapes come from the model file, Darknet
// shapes from the .cfg's [net] section, Caffe input shapes from the network when it declares
// them; otherwise input= (and inputtype=, default float32) are required. Output shapes and types
// are learnt from one run on zeros at open. OpenCV copies the input into its own blob and hands
// back its own output blobs, so the back end copies each output once into the caller's buffer.
// Net::forward is not re-entrant: invokes are serialised (the back end is not marked thread-safe).
// custom= keys: Backend, Target, NumThreads (docs/backends/opencv.md).

#include <opencv2/core/utils/logger.hpp>
#include <opencv2/dnn.hpp>

#include <algorithm>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "core/custom_options.h"
#include "core/error.h"
#include "core/backend_desc.h"
#include "nns_filter_backend.hh"
#include "onnx_model_info.h"

namespace nns {
namespace {

constexpr const char *kName = "opencv";

std::string ext_of(const std::string &path) {
  std::string e = std::filesystem::path(path).extension().string();
  for (auto &c : e) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return e;
}

// NNStreamer type <-> OpenCV depth. Inputs accept float32 and uint8 only.
bool depth_to_type(int depth, uint32_t &t) {
  switch (depth) {
    case CV_32F:
      t = _NNS_FLOAT32;
      return true;
    case CV_8U:
      t = _NNS_UINT8;
      return true;
    case CV_8S:
      t = _NNS_INT8;
      return true;
    case CV_16U:
      t = _NNS_UINT16;
      return true;
    case CV_16S:
      t = _NNS_INT16;
      return true;
    case CV_32S:
      t = _NNS_INT32;
      return true;
    case CV_64F:
      t = _NNS_FLOAT64;
      return true;
    case CV_16F:
      t = _NNS_FLOAT16;
      return true;
    default:
      return false;
  }
}

bool onnx_to_type(int32_t e, uint32_t &t) {
  switch (e) {
    case onnx::kFloat:
      t = _NNS_FLOAT32;
      return true;
    case onnx::kUInt8:
      t = _NNS_UINT8;
      return true;
    default:
      return false;
  }
}

std::string trimmed(const std::string &s) {
  const char *ws = " \t\r\n";
  std::size_t b = s.find_first_not_of(ws);
  if (b == std::string::npos) return "";
  return s.substr(b, s.find_last_not_of(ws) - b + 1);
}

// OpenCV 4.6 does not report a Darknet network's input shape, but the .cfg's [net] section
// declares it: channels, height, width (OpenCV's defaults 3, 416, 416). The batch is 1.
std::vector<int> darknet_input_shape(const std::string &cfg) {
  int width = 416, height = 416, channels = 3;
  std::ifstream f(cfg);
  bool in_net = false;
  for (std::string line; std::getline(f, line);) {
    line = trimmed(line);
    if (line.empty() || line[0] == '#' || line[0] == ';') continue;
    if (line[0] == '[') {
      in_net = line == "[net]";
      continue;
    }
    std::size_t eq = line.find('=');
    if (!in_net || eq == std::string::npos) continue;
    std::string key = trimmed(line.substr(0, eq));
    int value = std::atoi(trimmed(line.substr(eq + 1)).c_str());
    if (key == "width") width = value;
    if (key == "height") height = value;
    if (key == "channels") channels = value;
  }
  return {1, channels, height, width};
}

struct Input {
  std::string name;  // "" = the network's first input
  nns_tensor_desc desc{};
  std::vector<int> shape;  // OpenCV blob shape (outermost first)
  int depth = CV_32F;
  std::size_t bytes = 0;
  bool known = false;  // shape fully known
};

struct Output {
  std::string name;  // layer name given to forward()
  nns_tensor_desc desc{};
  std::size_t bytes = 0;
};

class OpenCvFilter final : public FilterBackend {
 public:
  explicit OpenCvFilter(const nns_filter_props &p) { open(p); }

  bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) override {
    std::lock_guard g(mutex_);
    fill(in, out);
    return true;
  }

  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    std::lock_guard g(mutex_);
    apply_input(in, "the negotiated input");
    probe();
    nns_tensors_desc ignored{};
    fill(ignored, out);
    return true;
  }

  void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
              uint32_t num_out) override {
    std::lock_guard g(mutex_);
    check_count("input", num_in, inputs_.size());
    check_count("output", num_out, outputs_.size());
    for (uint32_t i = 0; i < num_in; ++i) {
      if (in[i].size != inputs_[i].bytes)
        fail_size("input", i, inputs_[i].name, inputs_[i].desc, in[i].size, inputs_[i].bytes);
    }
    for (uint32_t i = 0; i < num_out; ++i)
      if (out[i].size != outputs_[i].bytes)
        fail_size("output", i, outputs_[i].name, outputs_[i].desc, out[i].size, outputs_[i].bytes);
    forward(in);
    for (uint32_t i = 0; i < num_out; ++i) copy_out(i, out[i].data, out[i].size);
  }

  void invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                      nns_tensors_desc &out_info, GstTensorMemory *out) override {
    std::lock_guard g(mutex_);
    apply_input(in_info, "the dynamic input");
    for (std::size_t i = 0; i < inputs_.size(); ++i)
      if (in[i].size != inputs_[i].bytes)
        fail_size("input", static_cast<uint32_t>(i), inputs_[i].name, inputs_[i].desc, in[i].size,
                  inputs_[i].bytes);
    forward(in);
    learn_outputs();
    out_info = nns_tensors_desc{};
    out_info.num_tensors = static_cast<uint32_t>(outputs_.size());
    for (std::size_t i = 0; i < outputs_.size(); ++i) {
      out_info.tensors[i] = outputs_[i].desc;
      out[i].size = outputs_[i].bytes;
      out[i].data = std::malloc(out[i].size ? out[i].size : 1);
      if (!out[i].data) throw FilterError(std::string(kName) + ": out of memory", -ENOMEM);
      copy_out(static_cast<uint32_t>(i), out[i].data, out[i].size);
    }
  }

  void free_output(void *data) override { std::free(data); }

 private:
  [[noreturn]] void fail(const std::string &msg, int code = -EINVAL) const {
    throw FilterError(std::string(kName) + ": " + model_ + ": " + msg, code);
  }

  void check_count(const char *what, std::size_t got, std::size_t want) const {
    if (got != want)
      fail("got " + std::to_string(got) + " " + what + " tensors, the model has " +
           std::to_string(want));
  }

  [[noreturn]] void fail_size(const char *what, uint32_t i, const std::string &name,
                              const nns_tensor_desc &d, std::size_t got, std::size_t want) const {
    fail(std::string(what) + " " + std::to_string(i) + " ('" + name + "', " +
         desc_string(d, false) + ") is " + std::to_string(got) + " bytes, expected " +
         std::to_string(want));
  }

  void forward(const GstTensorMemory *in) {
    try {
      for (std::size_t i = 0; i < inputs_.size(); ++i) {
        const Input &p = inputs_[i];
        cv::Mat m(static_cast<int>(p.shape.size()), p.shape.data(), p.depth, in[i].data);
        net_.setInput(m, p.name);
      }
      net_.forward(results_, out_names_);
    } catch (const cv::Exception &e) {
      fail(std::string("inference failed: ") + e.what(), -EIO);
    }
  }

  void copy_out(uint32_t i, void *dst, std::size_t size) {
    const cv::Mat &m = results_[i];
    if (!m.isContinuous() || m.total() * m.elemSize() != size)
      fail("output '" + outputs_[i].name + "' came out as " +
           std::to_string(m.total() * m.elemSize()) + " bytes, expected " + std::to_string(size));
    std::memcpy(dst, m.data, size);
  }

  void open(const nns_filter_props &p) {
    if (p.num_models < 1 || p.num_models > 2 || !p.model_files)
      throw FilterError(std::string(kName) + ": model= must name one model file or two (" +
                            "weights and config); got " + std::to_string(p.num_models),
                        -EINVAL);
    std::string weights, config;
    for (uint32_t i = 0; i < p.num_models; ++i) {
      std::string f = p.model_files[i];
      std::error_code ec;
      if (!std::filesystem::is_regular_file(f, ec))
        throw FilterError(std::string(kName) + ": " + f + ": model file not found", -ENOENT);
      std::string e = ext_of(f);
      bool is_config = e == ".prototxt" || e == ".cfg" || e == ".pbtxt";
      bool is_weights = e == ".onnx" || e == ".caffemodel" || e == ".weights" || e == ".pb";
      if (!is_config && !is_weights)
        throw FilterError(std::string(kName) + ": " + f + ": unknown model file type '" + e +
                              "' (accepted: .onnx, .pb [+ .pbtxt], .caffemodel + .prototxt, "
                              ".weights + .cfg)",
                          -EINVAL);
      std::string &slot = is_config ? config : weights;
      if (!slot.empty())
        throw FilterError(std::string(kName) + ": model= names two " +
                              (is_config ? "configuration" : "weight") + " files (" + slot + ", " +
                              f + ")",
                          -EINVAL);
      slot = f;
    }
    if (weights.empty())
      throw FilterError(std::string(kName) + ": model= has only the configuration file " + config +
                            "; the weights (.caffemodel/.weights/.pb) are missing",
                        -EINVAL);
    std::string we = ext_of(weights);
    if ((we == ".caffemodel" || we == ".weights") && config.empty())
      throw FilterError(std::string(kName) + ": " + weights + " needs its network description (" +
                            (we == ".caffemodel" ? ".prototxt" : ".cfg") +
                            ") as a second model= file",
                        -EINVAL);
    model_ = weights;

    int backend = cv::dnn::DNN_BACKEND_DEFAULT, target = cv::dnn::DNN_TARGET_CPU;
    try {
      CustomOptions opts(p.custom, kName, {"Backend", "Target", "NumThreads"});
      if (auto b = opts.get_choice("Backend", {"default", "opencv"}))
        backend = *b ? cv::dnn::DNN_BACKEND_OPENCV : cv::dnn::DNN_BACKEND_DEFAULT;
      if (auto t = opts.get_choice("Target", {"cpu", "opencl", "opencl_fp16"})) {
        static const int kTargets[] = {cv::dnn::DNN_TARGET_CPU, cv::dnn::DNN_TARGET_OPENCL,
                                       cv::dnn::DNN_TARGET_OPENCL_FP16};
        target = kTargets[*t];
        bool available = false;
        for (auto x : cv::dnn::getAvailableTargets(cv::dnn::DNN_BACKEND_OPENCV))
          available = available || x == target;
        if (!available)
          throw FilterError(std::string(kName) + ": custom option Target:" + *opts.get("Target") +
                                " is not available on this machine",
                            -ENOTSUP);
      }
      int threads = p.num_threads;
      if (auto n = opts.get_int("NumThreads", 0, 1024)) threads = static_cast<int>(*n);
      if (threads > 0) cv::setNumThreads(threads);  // process-wide in OpenCV
    } catch (const Error &e) {
      throw FilterError(e.what(), -EINVAL);
    }

    cv::utils::logging::setLogLevel(cv::utils::logging::LOG_LEVEL_ERROR);
    try {
      net_ = config.empty() ? cv::dnn::readNet(weights) : cv::dnn::readNet(weights, config);
    } catch (const cv::Exception &e) {
      fail(std::string("cannot load the model: ") + e.what());
    }
    if (net_.empty()) fail("cannot load the model (OpenCV returned an empty network)");
    if (we == ".weights") check_darknet_weights_size();
    net_.setPreferableBackend(backend);
    net_.setPreferableTarget(target);

    read_declared_io(we, config);
    if (p.input && p.input->num_tensors)
      apply_input(*p.input, desc_names_only(*p.input) ? "inputname=" : "input=");
    for (const auto &in : inputs_)
      if (!in.known)
        fail("the shape of input " + (in.name.empty() ? std::string("0") : "'" + in.name + "'") +
             " is not known from the model; give it with input= (and inputtype=)");
    select_outputs(p.output);
    probe();
    check_outputs(p.output);
  }

  // OpenCV reads a Darknet .weights file without checking that it holds every value its .cfg
  // needs: a short file gives a network of uninitialised weights. The file must hold the header
  // (major, minor, revision, then "seen": 8 bytes from version 0.2 on, else 4) and one float32
  // for every value of the layers' blobs (biases, batch-norm scales/means/variances, weights).
  void check_darknet_weights_size() {
    std::ifstream f(model_, std::ios::binary);
    int32_t version[3] = {0, 0, 0};
    f.read(reinterpret_cast<char *>(version), sizeof(version));
    std::error_code ec;
    auto size = std::filesystem::file_size(model_, ec);
    if (!f || ec) fail("not a Darknet weights file (shorter than its 12-byte version header)");
    std::size_t floats = 0;
    try {
      for (const auto &name : net_.getLayerNames())
        for (const cv::Mat &b : net_.getLayer(net_.getLayerId(name))->blobs) floats += b.total();
    } catch (const cv::Exception &e) {
      fail(std::string("cannot list the network's weights: ") + e.what());
    }
    std::size_t need = 12 + (version[0] * 10 + version[1] >= 2 ? 8 : 4) + 4 * floats;
    if (size < need)
      fail("Darknet weights file has " + std::to_string(size) + " bytes, but its .cfg needs " +
           std::to_string(need) + " (header and " + std::to_string(floats) +
           " float32 values): truncated, or written for another .cfg");
  }

  // What the model file declares: ONNX graph inputs/outputs, the Darknet [net] input, or the
  // network's first input.
  void read_declared_io(const std::string &ext, const std::string &config) {
    if (ext == ".onnx") {
      onnx::GraphInfo g;
      try {
        g = onnx::read_graph_info(model_);
      } catch (const std::exception &e) {
        fail(e.what());
      }
      for (const auto &v : g.inputs) {
        Input in;
        in.name = v.name;
        if (!onnx_to_type(v.elem_type, in.desc.type))
          fail("input '" + v.name + "' has ONNX element type " + std::to_string(v.elem_type) +
               "; OpenCV inputs must be float32 or uint8");
        in.depth = in.desc.type == _NNS_UINT8 ? CV_8U : CV_32F;
        set_name(in.desc, v.name);
        std::vector<int64_t> s(v.shape.begin(), v.shape.end());
        set_dims(in.desc, s);
        in.known = !v.shape.empty();
        for (auto d : v.shape) {
          in.known = in.known && d > 0;
          in.shape.push_back(static_cast<int>(d));
        }
        inputs_.push_back(std::move(in));
      }
      for (const auto &v : g.outputs) out_names_.push_back(v.name);
    } else {
      Input in;
      in.desc.type = _NNS_FLOAT32;
      std::vector<cv::dnn::MatShape> ins, outs;
      if (ext == ".weights") {
        outs.push_back(darknet_input_shape(config));
      } else {
        try {
          net_.getLayerShapes(cv::dnn::MatShape(), 0, ins, outs);
        } catch (const cv::Exception &) {
        }
      }
      if (outs.size() == 1 && !outs[0].empty()) {
        in.shape = outs[0];
        in.known = true;
        for (int d : in.shape) in.known = in.known && d > 0;
        std::vector<int64_t> s(in.shape.begin(), in.shape.end());
        set_dims(in.desc, s);
      }
      inputs_.push_back(std::move(in));
    }
    if (out_names_.empty())
      for (const auto &n : net_.getUnconnectedOutLayersNames()) out_names_.push_back(n);
  }

  // input=/inputtype=/inputname= (or negotiated caps) override what the model says.
  void apply_input(const nns_tensors_desc &given, const char *source) {
    if (given.num_tensors != inputs_.size()) {
      if (inputs_.size() == 1 && inputs_[0].name.empty() && given.num_tensors > 1) {
        // The network did not tell its inputs: take them from the property, named.
        inputs_.resize(given.num_tensors);
      } else {
        check_count(source, given.num_tensors, inputs_.size());
      }
    }
    reorder_inputs(given);
    for (uint32_t i = 0; i < given.num_tensors; ++i) {
      const nns_tensor_desc &d = given.tensors[i];
      Input &in = inputs_[i];
      std::string name(d.name, strnlen(d.name, NNS_TENSOR_NAME_MAX));
      if (!name.empty()) in.name = name;
      if (d.type < _NNS_END) {
        if (d.type != _NNS_FLOAT32 && d.type != _NNS_UINT8)
          fail(std::string(source) + " tensor " + std::to_string(i) + " is " + desc_string(d) +
               "; OpenCV DNN takes float32 or uint8 input");
        in.desc.type = d.type;
        in.depth = d.type == _NNS_UINT8 ? CV_8U : CV_32F;
      }
      if (desc_rank(d)) {
        std::size_t rank = in.shape.empty() ? desc_rank(d) : in.shape.size();
        std::vector<int64_t> shape;
        try {
          shape = shape_of(d, rank);
        } catch (const Error &e) {
          fail(std::string(source) + ": " + e.what());
        }
        in.shape.assign(shape.begin(), shape.end());
        set_dims(in.desc, shape);
        in.known = true;
      }
      set_name(in.desc, in.name);
    }
    for (auto &in : inputs_) in.bytes = desc_bytes(in.desc);
  }

  // Named inputs of a model that declares its input names (ONNX) are matched by name, in the
  // order given (inputname=y,x feeds the first tensor to y).
  void reorder_inputs(const nns_tensors_desc &given) {
    bool declared = false;
    for (const auto &in : inputs_) declared = declared || !in.name.empty();
    if (!declared || given.num_tensors != inputs_.size()) return;
    std::vector<Input> ordered;
    for (uint32_t i = 0; i < given.num_tensors; ++i) {
      std::string name(given.tensors[i].name, strnlen(given.tensors[i].name, NNS_TENSOR_NAME_MAX));
      if (name.empty()) return;  // positional
      auto it = std::find_if(inputs_.begin(), inputs_.end(),
                             [&](const Input &in) { return in.name == name; });
      if (it == inputs_.end()) {
        std::string names;
        for (const auto &in : inputs_) names += (names.empty() ? "'" : ", '") + in.name + "'";
        fail("inputname '" + name + "' is not an input of the model (inputs: " + names + ")");
      }
      ordered.push_back(*it);
    }
    inputs_ = std::move(ordered);
  }

  // outputname= picks outputs (any layer name OpenCV knows), in the order given.
  void select_outputs(const nns_tensors_desc *want) {
    if (!want || !want->num_tensors || !want->tensors[0].name[0]) return;
    std::vector<std::string> declared = out_names_;
    out_names_.clear();
    for (uint32_t i = 0; i < want->num_tensors; ++i) {
      std::string name(want->tensors[i].name, strnlen(want->tensors[i].name, NNS_TENSOR_NAME_MAX));
      if (net_.getLayerId(name) < 0) {
        std::string names;
        for (const auto &n : declared) names += (names.empty() ? "'" : ", '") + n + "'";
        fail("outputname '" + name + "' is not a layer of the network (its outputs: " + names +
             ")");
      }
      out_names_.push_back(name);
    }
  }

  void check_outputs(const nns_tensors_desc *want) const {
    if (!want || !want->num_tensors) return;
    check_count("output=", want->num_tensors, outputs_.size());
    for (uint32_t i = 0; i < want->num_tensors; ++i) {
      const nns_tensor_desc &d = want->tensors[i];
      bool type_bad = d.type < _NNS_END && d.type != outputs_[i].desc.type;
      bool dims_bad = desc_rank(d) && !desc_dims_equal(d, outputs_[i].desc);
      if (type_bad || dims_bad)
        fail("output= tensor " + std::to_string(i) + " is " + desc_string(d) +
             " but the network gives " + desc_string(outputs_[i].desc));
    }
  }

  // One run on zeros: output shapes and types.
  void probe() {
    std::vector<std::vector<uint8_t>> zeros;
    std::vector<GstTensorMemory> mem;
    for (auto &in : inputs_) {
      in.bytes = desc_bytes(in.desc);
      zeros.emplace_back(in.bytes);
      mem.push_back({zeros.back().data(), in.bytes});
    }
    forward(mem.data());
    learn_outputs();
  }

  void learn_outputs() {
    outputs_.clear();
    for (std::size_t i = 0; i < results_.size(); ++i) {
      Output o;
      o.name = out_names_[i];
      const cv::Mat &m = results_[i];
      if (!depth_to_type(m.depth(), o.desc.type))
        fail("output '" + o.name + "' has OpenCV depth " + std::to_string(m.depth()) +
             ", which NNStreamer tensors cannot carry");
      std::vector<int64_t> shape;
      for (int k = 0; k < m.dims; ++k) shape.push_back(m.size[k]);
      set_dims(o.desc, shape);
      set_name(o.desc, o.name);
      o.bytes = m.total() * m.elemSize();
      outputs_.push_back(std::move(o));
    }
  }

  void fill(nns_tensors_desc &in, nns_tensors_desc &out) const {
    in = nns_tensors_desc{};
    out = nns_tensors_desc{};
    in.num_tensors = static_cast<uint32_t>(inputs_.size());
    for (std::size_t i = 0; i < inputs_.size(); ++i) in.tensors[i] = inputs_[i].desc;
    out.num_tensors = static_cast<uint32_t>(outputs_.size());
    for (std::size_t i = 0; i < outputs_.size(); ++i) out.tensors[i] = outputs_[i].desc;
  }

  std::string model_;
  std::mutex mutex_;
  cv::dnn::Net net_;
  std::vector<Input> inputs_;
  std::vector<Output> outputs_;
  std::vector<cv::String> out_names_;
  std::vector<cv::Mat> results_;
};

const char *const kExtensions[] = {".onnx",  ".caffemodel", ".prototxt", ".pb",
                                   ".pbtxt", ".weights",    ".cfg",      nullptr};

}  // namespace
}  // namespace nns

NNS_FILTER_BACKEND_EXPORT(nns::OpenCvFilter, "opencv",
                          NNS_FILTER_FLAG_DYNAMIC | NNS_FILTER_FLAG_TENSOR_NAMES, nns::kExtensions)

// SPDX-License-Identifier: LGPL-2.1-only
// Writes small .tflite models in tests (flatbuffers C++ builder over the back end's own schema
// subset, backends/filter/tflite/tflite_schema.fbs), and runs them through the tflite back end.
#pragma once

#include <unistd.h>

#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "tflite_schema_generated.h"

namespace nns::test {

class TfliteBuilder {
 public:
  TfliteBuilder() { buffers_.push_back(tflite::CreateBuffer(fb_)); }

  // A tensor; `data` makes it a constant. scale/zp: quantization (per-channel when > 1).
  int tensor(const std::string &name, tflite::TensorType type, const std::vector<int32_t> &shape,
             const void *data = nullptr, std::size_t bytes = 0, std::vector<float> scale = {},
             std::vector<int64_t> zp = {}, int qdim = 0) {
    uint32_t buf = 0;
    if (data) {
      fb_.ForceVectorAlignment(bytes, 1, 16);
      auto v = fb_.CreateVector(static_cast<const uint8_t *>(data), bytes);
      buffers_.push_back(tflite::CreateBuffer(fb_, v));
      buf = static_cast<uint32_t>(buffers_.size() - 1);
    }
    flatbuffers::Offset<tflite::QuantizationParameters> q;
    if (!scale.empty())
      q = tflite::CreateQuantizationParameters(fb_, 0, 0, fb_.CreateVector(scale),
                                               fb_.CreateVector(zp),
                                               tflite::QuantizationDetails_NONE, 0, qdim);
    tensors_.push_back(
        tflite::CreateTensor(fb_, fb_.CreateVector(shape), type, buf, fb_.CreateString(name), q));
    return static_cast<int>(tensors_.size() - 1);
  }
  template <typename T>
  int constant(const std::string &name, tflite::TensorType type, const std::vector<int32_t> &shape,
               const std::vector<T> &v, std::vector<float> scale = {}, std::vector<int64_t> zp = {},
               int qdim = 0) {
    return tensor(name, type, shape, v.data(), v.size() * sizeof(T), scale, zp, qdim);
  }

  void op(int code, const std::vector<int> &in, const std::vector<int> &out,
          tflite::BuiltinOptions type = tflite::BuiltinOptions_NONE,
          flatbuffers::Offset<void> options = 0, const std::string &custom = "",
          const std::vector<uint8_t> &custom_options = {}) {
    int idx = -1;
    for (std::size_t i = 0; i < code_keys_.size(); ++i)
      if (code_keys_[i] == std::to_string(code) + custom) idx = static_cast<int>(i);
    if (idx < 0) {
      code_keys_.push_back(std::to_string(code) + custom);
      codes_.push_back(tflite::CreateOperatorCode(fb_, static_cast<int8_t>(code < 127 ? code : 127),
                                                  custom.empty() ? 0 : fb_.CreateString(custom), 1,
                                                  code));
      idx = static_cast<int>(codes_.size() - 1);
    }
    flatbuffers::Offset<flatbuffers::Vector<uint8_t>> co;
    if (!custom_options.empty()) co = fb_.CreateVector(custom_options);
    ops_.push_back(tflite::CreateOperator(fb_, static_cast<uint32_t>(idx), fb_.CreateVector(in),
                                          fb_.CreateVector(out), type, options, co));
  }
  flatbuffers::FlatBufferBuilder &fb() { return fb_; }

  std::vector<uint8_t> finish(const std::vector<int> &inputs, const std::vector<int> &outputs) {
    auto sg = tflite::CreateSubGraph(fb_, fb_.CreateVector(tensors_), fb_.CreateVector(inputs),
                                     fb_.CreateVector(outputs), fb_.CreateVector(ops_),
                                     fb_.CreateString("main"));
    std::vector<flatbuffers::Offset<tflite::SubGraph>> sgs{sg};
    auto m = tflite::CreateModel(fb_, 3, fb_.CreateVector(codes_), fb_.CreateVector(sgs),
                                 fb_.CreateString("test"), fb_.CreateVector(buffers_));
    tflite::FinishModelBuffer(fb_, m);
    return {fb_.GetBufferPointer(), fb_.GetBufferPointer() + fb_.GetSize()};
  }

 private:
  flatbuffers::FlatBufferBuilder fb_;
  std::vector<flatbuffers::Offset<tflite::Buffer>> buffers_;
  std::vector<flatbuffers::Offset<tflite::Tensor>> tensors_;
  std::vector<flatbuffers::Offset<tflite::Operator>> ops_;
  std::vector<flatbuffers::Offset<tflite::OperatorCode>> codes_;
  std::vector<std::string> code_keys_;
};

// Writes `bytes` to a fresh file under /tmp and returns its path (removed by the destructor).
class TempModel {
 public:
  explicit TempModel(const std::vector<uint8_t> &bytes, const std::string &tag = "m") {
    char tmpl[] = "/tmp/nns_tflite_XXXXXX";
    int fd = mkstemp(tmpl);
    if (fd >= 0) close(fd);
    path_ = std::string(tmpl) + "_" + tag + ".tflite";
    std::rename(tmpl, path_.c_str());
    std::ofstream(path_, std::ios::binary)
        .write(reinterpret_cast<const char *>(bytes.data()),
               static_cast<std::streamsize>(bytes.size()));
  }
  ~TempModel() { std::remove(path_.c_str()); }
  const std::string &path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// Helpers for the Pipeline API tests (tests/api/ml_pipeline_*.cc): tensors-info and data
// handles, a sink collector that records frames and the threads callbacks ran on, and waits.
#pragma once

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "nnstreamer.h"

namespace capi_test {

using Bytes = std::vector<uint8_t>;

// Info with one tensor per (type, dims) pair; dims innermost first, rest 1... as 4-D.
inline ml_tensors_info_h make_info(
    std::initializer_list<std::pair<ml_tensor_type_e, std::vector<unsigned>>> ts) {
  ml_tensors_info_h info = nullptr;
  EXPECT_EQ(ml_tensors_info_create(&info), ML_ERROR_NONE);
  EXPECT_EQ(ml_tensors_info_set_count(info, static_cast<unsigned>(ts.size())), ML_ERROR_NONE);
  unsigned i = 0;
  for (const auto &[type, dims] : ts) {
    ml_tensor_dimension d;
    for (auto &x : d) x = 1;
    for (std::size_t k = 0; k < dims.size(); ++k) d[k] = dims[k];
    EXPECT_EQ(ml_tensors_info_set_tensor_type(info, i, type), ML_ERROR_NONE);
    EXPECT_EQ(ml_tensors_info_set_tensor_dimension(info, i, d), ML_ERROR_NONE);
    ++i;
  }
  return info;
}

// Data for `info` with tensor `k` filled from bytes[k].
inline ml_tensors_data_h make_data(ml_tensors_info_h info, const std::vector<Bytes> &bytes) {
  ml_tensors_data_h d = nullptr;
  EXPECT_EQ(ml_tensors_data_create(info, &d), ML_ERROR_NONE);
  for (unsigned k = 0; k < bytes.size(); ++k)
    EXPECT_EQ(ml_tensors_data_set_tensor_data(d, k, bytes[k].data(), bytes[k].size()),
              ML_ERROR_NONE);
  return d;
}

struct Frame {
  std::vector<Bytes> tensors;
  std::vector<ml_tensor_type_e> types;
  std::vector<std::vector<unsigned>> dims;  // 4 entries each
};

// Records every frame a sink callback gets.
struct Collector {
  std::mutex m;
  std::condition_variable cv;
  std::vector<Frame> frames;
  std::vector<std::thread::id> threads;
  int sleep_ms = 0;  // time each callback takes

  static void cb(const ml_tensors_data_h data, const ml_tensors_info_h info, void *user) {
    auto *c = static_cast<Collector *>(user);
    Frame f;
    unsigned n = 0;
    ml_tensors_info_get_count(info, &n);
    for (unsigned i = 0; i < n; ++i) {
      void *raw = nullptr;
      size_t size = 0;
      ml_tensors_data_get_tensor_data(data, i, &raw, &size);
      f.tensors.emplace_back(static_cast<uint8_t *>(raw), static_cast<uint8_t *>(raw) + size);
      ml_tensor_type_e t = ML_TENSOR_TYPE_UNKNOWN;
      ml_tensors_info_get_tensor_type(info, i, &t);
      f.types.push_back(t);
      ml_tensor_dimension d{};
      ml_tensors_info_get_tensor_dimension(info, i, d);
      f.dims.emplace_back(d, d + 4);
    }
    if (c->sleep_ms) std::this_thread::sleep_for(std::chrono::milliseconds(c->sleep_ms));
    std::lock_guard lk(c->m);
    c->frames.push_back(std::move(f));
    c->threads.push_back(std::this_thread::get_id());
    c->cv.notify_all();
  }

  bool wait_for(std::size_t n, double seconds = 10) {
    std::unique_lock lk(m);
    return cv.wait_for(lk, std::chrono::duration<double>(seconds),
                       [&] { return frames.size() >= n; });
  }
  std::size_t count() {
    std::lock_guard lk(m);
    return frames.size();
  }
};

inline Bytes f32_bytes(const std::vector<float> &v) {
  Bytes b(v.size() * 4);
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

inline std::vector<float> as_f32(const Bytes &b) {
  std::vector<float> v(b.size() / 4);
  std::memcpy(v.data(), b.data(), v.size() * 4);
  return v;
}

// other/tensors caps of one static tensor.
inline std::string tensor_caps(const std::string &dims, const std::string &type) {
  return "other/tensors,format=static,num_tensors=1,dimensions=" + dims + ",types=" + type +
         ",framerate=0/1";
}

// ../shared/models/upstream (NNS_SHARED_DIR overrides), "" when absent.
inline std::string shared_models_dir() {
  namespace fs = std::filesystem;
  fs::path p = std::getenv("NNS_SHARED_DIR") ? fs::path(std::getenv("NNS_SHARED_DIR"))
                                             : fs::path(NNS_SOURCE_DIR) / ".." / "shared";
  p /= "models/upstream";
  return fs::exists(p) ? fs::canonical(p).string() : std::string();
}

}  // namespace capi_test

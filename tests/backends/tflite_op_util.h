// SPDX-License-Identifier: LGPL-2.1-only
// Shared by the tflite back end tests on generated and real models (tflite_ops_test.cc,
// tflite_ops_data_test.cc, tflite_reference_test.cc): the back end's library, one run of a
// generated model through its C ABI, byte/value conversions and the float tolerance.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "backends/backend_loader.h"
#include "backends/tflite_builder.h"

namespace nns::test::tflite_ops {

using TT = tflite::TensorType;

inline const BackendLib &lib() {
  return backend_lib("tensorflow2-lite");
}

#define REQUIRE_TFLITE()                                                             \
  do {                                                                               \
    if (!lib().ok()) GTEST_SKIP() << "tensorflow2-lite back end: " << lib().error(); \
  } while (0)

template <typename T>
inline std::vector<uint8_t> bytes_of(const std::vector<T> &v) {
  std::vector<uint8_t> b(v.size() * sizeof(T));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}
template <typename T>
inline std::vector<T> values_of(const std::vector<uint8_t> &b) {
  std::vector<T> v(b.size() / sizeof(T));
  std::memcpy(v.data(), b.data(), b.size());
  return v;
}

// Opens `model`, checks the output sizes the back end reports, invokes once.
inline std::vector<std::vector<uint8_t>> run(const std::vector<uint8_t> &model,
                                             const std::vector<std::vector<uint8_t>> &inputs,
                                             std::string *error = nullptr) {
  TempModel f(model);
  Props p;
  p.models = {f.path()};
  Instance inst(lib().api(), p);
  if (inst.rc() != 0) {
    if (error)
      *error = inst.error();
    else
      ADD_FAILURE() << inst.error();
    return {};
  }
  nns_tensors_desc in, out;
  EXPECT_EQ(inst.model_info(in, out), 0) << inst.error();
  std::vector<std::vector<uint8_t>> outs(out.num_tensors);
  std::vector<GstTensorMemory> im, om;
  for (auto &i : inputs) im.push_back({const_cast<uint8_t *>(i.data()), i.size()});
  for (uint32_t k = 0; k < out.num_tensors; ++k) {
    outs[k].resize(desc_bytes(out.tensors[k]));
    om.push_back({outs[k].data(), outs[k].size()});
  }
  EXPECT_EQ(inst.invoke(im, om), 0) << inst.error();
  return outs;
}

inline void expect_near(const std::vector<float> &got, const std::vector<float> &want,
                        float rel = 1e-5f) {
  ASSERT_EQ(got.size(), want.size());
  for (std::size_t i = 0; i < got.size(); ++i)
    EXPECT_NEAR(got[i], want[i], rel * std::max(1.f, std::fabs(want[i]))) << "at " << i;
}

inline std::vector<float> ramp(std::size_t n, float scale = 0.1f, float offset = -1.f) {
  std::vector<float> v(n);
  for (std::size_t i = 0; i < n; ++i) v[i] = offset + scale * static_cast<float>((i * 7) % 23);
  return v;
}

}  // namespace nns::test::tflite_ops

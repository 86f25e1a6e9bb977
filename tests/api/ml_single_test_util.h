// SPDX-License-Identifier: LGPL-2.1-only
// Helpers shared by the single-shot API tests: where models, scripts and back ends are, raw
// file reading, float comparison.
#pragma once

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "nnstreamer-single.hh"

namespace nns::test::ml {

// ../shared/models/upstream, or "" when it is not beside the project.
inline std::string shared_models() {
  std::filesystem::path p =
      std::filesystem::path(NNS_SOURCE_DIR) / ".." / "shared" / "models" / "upstream";
  return std::filesystem::exists(p) ? std::filesystem::canonical(p).string() : "";
}

// build/tests/models (tests/data/generate_models.py, target nns_test_models).
inline std::string generated(const std::string &file) {
  return std::string(NNS_BUILD_DIR) + "/tests/models/" + file;
}

inline std::string python_script(const std::string &name) {
  return std::string(NNS_SOURCE_DIR) + "/tests/data/python/" + name;
}

inline bool backend_built(const std::string &name) {
  return std::filesystem::exists(std::string(NNS_BUILD_DIR) +
                                 "/subplugins/filters/libnnstreamer_filter_" + name + ".so");
}

inline std::vector<uint8_t> read_all(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

inline std::vector<float> read_floats(const std::string &path) {
  auto b = read_all(path);
  std::vector<float> v(b.size() / sizeof(float));
  std::memcpy(v.data(), b.data(), v.size() * sizeof(float));
  return v;
}

#define REQUIRE_BACKEND(name)                                              \
  do {                                                                     \
    if (!nns::test::ml::backend_built(name))                               \
      GTEST_SKIP() << "the " << (name) << " filter back end is not built"; \
  } while (0)

#define REQUIRE_FILE(path)                                                        \
  do {                                                                            \
    if (!std::filesystem::exists(path))                                           \
      GTEST_SKIP() << (path)                                                      \
                   << " is missing (../shared/models beside the project, or the " \
                      "nns_test_models target)";                                  \
  } while (0)

// Element-wise |got - want| <= abs + rel * |want|.
inline void expect_near_all(const float *got, const std::vector<float> &want, float abs = 1e-5f,
                            float rel = 1e-4f) {
  for (std::size_t i = 0; i < want.size(); ++i)
    EXPECT_LE(std::fabs(got[i] - want[i]), abs + rel * std::fabs(want[i])) << "element " << i;
}

inline nns::ml::TensorsInfo info_of(ml_tensor_type_e type,
                                    std::initializer_list<std::initializer_list<unsigned>> dims) {
  nns::ml::TensorsInfo info;
  info.set_count(static_cast<unsigned>(dims.size()));
  unsigned i = 0;
  for (auto &d : dims) info.set(i++, type, d);
  return info;
}

}  // namespace nns::test::ml

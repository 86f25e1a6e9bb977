// SPDX-License-Identifier: LGPL-2.1-only
// Pipeline golden tests: run a gst-launch description whose sink is `filesink location=@OUT@`,
// read the bytes it wrote, and compare them with a golden in tests/pipelines/golden/ or with a
// reference computed in the test (e.g. from the output of a stock-GStreamer pipeline).
//
// Placeholders in descriptions: @OUT@ (a fresh temporary file), @SHARED@
// (../shared/models/upstream; the test is skipped when absent), @SRC@ (the source tree), @GOLDEN@
// (tests/pipelines/golden).
//
// Goldens: golden/<name>.bin (exact bytes, for small outputs) or golden/<name>.sha256
// ("<hex sha256> <byte count>"). Run a test with NNS_UPDATE_GOLDENS=1 to (re)write its goldens
// from the current output; review the diff before committing.
#pragma once

#include <glib.h>
#include <glib/gstdio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <sstream>
#include <string>
#include <vector>

#include "support/harness.h"

namespace nns::test {

inline std::string golden_dir() {
  return std::string(NNS_SOURCE_DIR) + "/tests/pipelines/golden";
}

inline void replace_all(std::string *s, const std::string &from, const std::string &to) {
  for (std::size_t p = s->find(from); p != std::string::npos; p = s->find(from, p + to.size()))
    s->replace(p, from.size(), to);
}

// Result of running a description that writes to @OUT@.
struct PipelineBytes {
  RunResult run;
  std::string desc;  // with placeholders expanded
  std::vector<uint8_t> bytes;
};

// Expands the placeholders and runs the pipeline; `bytes` holds what filesink wrote.
inline PipelineBytes run_to_bytes(const std::string &desc_template, double timeout_s = 30.0) {
  PipelineBytes out;
  std::string dir = make_temp_dir();
  std::string file = dir + "/out.bin";
  out.desc = desc_template;
  replace_all(&out.desc, "@OUT@", file);
  replace_all(&out.desc, "@SHARED@", shared_models_dir());
  replace_all(&out.desc, "@SRC@", NNS_SOURCE_DIR);
  replace_all(&out.desc, "@GOLDEN@", golden_dir());
  out.run = run_pipeline(out.desc, timeout_s);
  out.bytes = read_file(file);
  std::error_code ec;
  std::filesystem::remove_all(dir, ec);
  return out;
}

inline std::string sha256_hex(const std::vector<uint8_t> &b) {
  gchar *h = g_compute_checksum_for_data(G_CHECKSUM_SHA256, b.data(), b.size());
  std::string s(h);
  g_free(h);
  return s;
}

inline bool update_goldens() {
  const char *e = std::getenv("NNS_UPDATE_GOLDENS");
  return e && *e && std::string(e) != "0";
}

// Compares `bytes` with golden/<name>.bin or golden/<name>.sha256 (see the file comment).
inline ::testing::AssertionResult matches_golden(const std::string &name,
                                                 const std::vector<uint8_t> &bytes) {
  namespace fs = std::filesystem;
  fs::path bin = fs::path(golden_dir()) / (name + ".bin");
  fs::path sha = fs::path(golden_dir()) / (name + ".sha256");
  if (update_goldens()) {
    fs::create_directories(golden_dir());
    if (bytes.size() <= 4096) {
      std::ofstream(bin, std::ios::binary)
          .write(reinterpret_cast<const char *>(bytes.data()),
                 static_cast<std::streamsize>(bytes.size()));
    } else {
      std::ofstream(sha) << sha256_hex(bytes) << " " << bytes.size() << "\n";
    }
    return ::testing::AssertionSuccess() << "golden " << name << " written";
  }
  if (fs::exists(bin)) {
    std::vector<uint8_t> want = read_file(bin.string());
    if (want == bytes) return ::testing::AssertionSuccess();
    std::size_t i = 0;
    while (i < want.size() && i < bytes.size() && want[i] == bytes[i]) ++i;
    return ::testing::AssertionFailure()
           << "output differs from " << bin << ": " << bytes.size() << " bytes vs " << want.size()
           << " in the golden, first difference at byte " << i
           << " (re-generate with NNS_UPDATE_GOLDENS=1 only if the change is intended)";
  }
  if (fs::exists(sha)) {
    std::ifstream f(sha);
    std::string want_hex;
    std::size_t want_size = 0;
    f >> want_hex >> want_size;
    std::string got = sha256_hex(bytes);
    if (got == want_hex && bytes.size() == want_size) return ::testing::AssertionSuccess();
    return ::testing::AssertionFailure()
           << "output (" << bytes.size() << " bytes, sha256 " << got << ") differs from " << sha
           << " (" << want_size << " bytes, sha256 " << want_hex << ")";
  }
  return ::testing::AssertionFailure() << "no golden " << name << ".bin/.sha256 in " << golden_dir()
                                       << " (create it with NNS_UPDATE_GOLDENS=1)";
}

// Compares float32 bytes with reference values: every |got - want| <= tol.
inline ::testing::AssertionResult floats_near(const std::vector<uint8_t> &bytes,
                                              const std::vector<float> &want, float tol) {
  if (bytes.size() != want.size() * sizeof(float))
    return ::testing::AssertionFailure()
           << "got " << bytes.size() << " bytes, expected " << want.size() * sizeof(float) << " ("
           << want.size() << " float32 values)";
  std::size_t bad = 0, first = 0, exact = 0;
  double worst = 0;
  for (std::size_t i = 0; i < want.size(); ++i) {
    float g;
    std::memcpy(&g, bytes.data() + i * sizeof(float), sizeof(float));
    double d = std::fabs(static_cast<double>(g) - static_cast<double>(want[i]));
    if (g == want[i]) ++exact;
    if (!(d <= tol)) {  // also catches NaN
      if (bad++ == 0) first = i;
    }
    if (d > worst || std::isnan(d)) worst = d;
  }
  if (bad == 0)
    return ::testing::AssertionSuccess()
           << "max |diff| " << worst << ", " << exact << "/" << want.size() << " exact";
  float g;
  std::memcpy(&g, bytes.data() + first * sizeof(float), sizeof(float));
  return ::testing::AssertionFailure()
         << bad << " of " << want.size() << " values differ by more than " << tol << " (max |diff| "
         << worst << "); first at index " << first << ": got " << g << ", expected " << want[first];
}

// Names of the elements in `names` that are not registered.
inline std::string missing_elements(std::initializer_list<const char *> names) {
  std::string missing;
  for (const char *n : names) {
    GstElementFactory *f = gst_element_factory_find(n);
    if (f)
      gst_object_unref(f);
    else
      missing += (missing.empty() ? "" : ", ") + std::string(n);
  }
  return missing;
}

// GTEST_SKIP()s when an element is not built yet (it lands on main from another branch).
#define NNS_REQUIRE_ELEMENTS(...)                                                \
  do {                                                                           \
    std::string nns_missing_ = ::nns::test::missing_elements({__VA_ARGS__});     \
    if (!nns_missing_.empty())                                                   \
      GTEST_SKIP() << "element(s) not built in this tree yet: " << nns_missing_; \
  } while (0)

}  // namespace nns::test

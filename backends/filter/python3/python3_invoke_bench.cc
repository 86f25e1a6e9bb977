// SPDX-License-Identifier: LGPL-2.1-only
// Per-invoke cost of the python3 filter back end through its C ABI (dlopen, open, invoke +
// free_output in a loop), for tests/data/python/bench_ops.py in each of its modes, on a tiny
// tensor (4 bytes) and on a 640x480 RGB frame. Results go to docs/benchmarks/python3.md.
//   build/bench/python3_invoke_bench [iterations]
#include <dlfcn.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "nns_filter_backend.h"

namespace {

const nns_filter_backend_i *load() {
  void *so = dlopen(NNS_PYTHON3_SO, RTLD_NOW | RTLD_LOCAL);
  if (!so) {
    std::fprintf(stderr, "cannot load %s: %s\n", NNS_PYTHON3_SO, dlerror());
    std::exit(1);
  }
  auto entry = reinterpret_cast<nns_filter_backend_entry_fn>(dlsym(so, NNS_FILTER_BACKEND_ENTRY));
  return entry();
}

// Median ns per invoke (+ free_output) over 5 rounds of `iters`.
double measure(const nns_filter_backend_i *be, const char *mode, const std::vector<uint32_t> &dims,
               int iters) {
  std::string path = std::string(NNS_SOURCE_DIR) + "/tests/data/python/bench_ops.py";
  const char *models[] = {path.c_str()};
  auto in = std::make_unique<nns_tensors_desc>();
  auto none = std::make_unique<nns_tensors_desc>();
  std::memset(in.get(), 0, sizeof *in);
  std::memset(none.get(), 0, sizeof *none);
  in->num_tensors = 1;
  in->tensors[0].type = _NNS_UINT8;
  size_t bytes = 1;
  for (size_t i = 0; i < dims.size(); i++) {
    in->tensors[0].dims[i] = dims[i];
    bytes *= dims[i];
  }
  nns_filter_props p{};
  p.model_files = models;
  p.num_models = 1;
  p.custom = mode;
  p.input = in.get();
  p.output = none.get();
  void *priv = nullptr;
  char err[4096];
  if (be->open(&p, &priv, err, sizeof err) != 0) {
    std::fprintf(stderr, "open: %s\n", err);
    std::exit(1);
  }
  std::vector<uint8_t> data(bytes, 7);
  GstTensorMemory input{data.data(), bytes}, output{};
  auto round = [&](int n) {
    auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; i++) {
      if (be->invoke(priv, &input, 1, &output, 1, err, sizeof err) != 0) {
        std::fprintf(stderr, "invoke: %s\n", err);
        std::exit(1);
      }
      be->free_output(priv, output.data);
    }
    return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - t0).count() /
           n;
  };
  round(iters / 10 + 1);  // warm-up
  std::vector<double> r;
  for (int k = 0; k < 5; k++) r.push_back(round(iters));
  std::sort(r.begin(), r.end());
  be->close(priv);
  return r[2];
}

}  // namespace

int main(int argc, char **argv) {
  int iters = argc > 1 ? std::atoi(argv[1]) : 20000;
  const nns_filter_backend_i *be = load();
  std::printf("| tensor | script returns | ns per invoke (median of 5 x %d) |\n|---|---|---|\n",
              iters);
  for (const char *mode : {"input", "copy", "kept"}) {
    std::printf("| 4 uint8 | %s | %.0f |\n", mode, measure(be, mode, {4}, iters));
  }
  for (const char *mode : {"input", "copy", "kept"}) {
    std::printf("| 3:640:480:1 uint8 | %s | %.0f |\n", mode,
                measure(be, mode, {3, 640, 480, 1}, std::max(iters / 100, 10)));
  }
  return 0;
}

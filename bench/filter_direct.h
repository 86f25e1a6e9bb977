// SPDX-License-Identifier: LGPL-2.1-only
// A filter back end called directly through its C ABI (nns_filter_backend.h), without a
// pipeline: the baseline the back-end benchmarks compare pipelines and other back ends with.
// Header-only, as bench_util.h.
#pragma once

#include <dlfcn.h>

#include <cstdio>
#include <string>

#include "nns_filter_backend.h"

namespace nns::bench {

struct DirectFilter {
  const nns_filter_backend_i *api = nullptr;
  void *priv = nullptr;
};

// The build tree's libnnstreamer_filter_<name>.so.
inline std::string filter_so(const std::string &name) {
  return std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_" + name + ".so";
}

// Loads the back end `so` (kept loaded) and opens `model` as framework `framework` with the
// custom options `custom` (e.g. "NumThreads:1"), shapes from the model. On failure says why on
// stderr and returns false.
inline bool open_direct(const std::string &so, const char *framework, const std::string &model,
                        const std::string &custom, DirectFilter &d) {
  void *h = dlopen(so.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!h) {
    std::fprintf(stderr, "dlopen %s: %s\n", so.c_str(), dlerror());
    return false;
  }
  auto entry = reinterpret_cast<nns_filter_backend_entry_fn>(dlsym(h, NNS_FILTER_BACKEND_ENTRY));
  d.api = entry ? entry() : nullptr;
  if (!d.api) {
    std::fprintf(stderr, "%s: no %s entry\n", so.c_str(), NNS_FILTER_BACKEND_ENTRY);
    return false;
  }
  const char *files[] = {model.c_str()};
  nns_tensors_desc none{};
  tensor_layout layouts[NNS_TENSOR_SIZE_LIMIT] = {};
  nns_filter_props p{};
  p.framework = framework;
  p.model_files = files;
  p.num_models = 1;
  p.input = &none;
  p.output = &none;
  p.custom = custom.c_str();
  p.input_layout = layouts;
  p.output_layout = layouts;
  char err[1024] = {0};
  if (d.api->open(&p, &d.priv, err, sizeof(err)) != 0) {
    std::fprintf(stderr, "open %s: %s\n", model.c_str(), err);
    return false;
  }
  return true;
}

}  // namespace nns::bench

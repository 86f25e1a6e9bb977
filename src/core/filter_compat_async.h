// SPDX-License-Identifier: LGPL-2.1-only
// invoke-async for the NNStreamer-style filters (custom, custom-easy, cpp): they see
// GstTensorFilterProperties, not nns_filter_async_ctx. CompatAsync (one per opened filter,
// inside CompatProps) remembers the context of the input being invoked and serves
// nnstreamer_filter_dispatch_output_async() (NNStreamer's call: outputs belong to the latest
// input, the data is released here) and the nnstreamer-cpp handle extension
// (nnstreamer_filter_async_capture/_dispatch: a copy of one input's context, safe to use at
// any time). Declared in include/nnstreamer/nnstreamer_plugin_api_filter.h.
#pragma once

#include <cstdint>
#include <mutex>
#include <thread>
#include <vector>

#include "nns_filter_backend.h"
#include "nnstreamer_plugin_api_filter.h"

namespace nns {

class CompatAsync {
 public:
  // How dispatched data blocks are released (NNStreamer gives them to tensor_filter).
  using Release = void (*)(void *release_ctx, void *data);

  CompatAsync();
  void set_release(Release fn, void *ctx);

  // Around one invoke of the filter: `ctx` becomes the current input (also for dispatches
  // from other threads until the next invoke). end() tells whether the filter captured a
  // handle during the call (its outputs then follow later).
  void begin(const nns_filter_async_ctx &ctx);
  bool end();

  int dispatch_upstream(GstTensorFilterProperties *prop, GstTensorMemory *output);
  int capture(const GstTensorFilterProperties *prop, GstTensorFilterAsyncHandle *handle);

 private:
  std::mutex mu_;
  nns_filter_async_ctx current_{};
  bool have_ = false;
  bool in_invoke_ = false;
  std::thread::id invoker_;
  bool captured_ = false;
  Release release_ = nullptr;
  void *release_ctx_ = nullptr;
};

// Makes the C functions above (and the rest of this object's default-visibility API) resolvable
// from custom filter objects dlopen()ed afterwards: GStreamer loads plugins with local binding,
// so the object holding them is re-opened with RTLD_NOLOAD | RTLD_GLOBAL (once per process).
void promote_filter_api();

// Output blocks for an invoke whose outputs are ignored (invoke-async): sized from the
// filter's configured output so filters that write them anyway stay in bounds.
class ScratchOutputs {
 public:
  explicit ScratchOutputs(const GstTensorsInfo &out);
  GstTensorMemory *get() { return mem_.data(); }

 private:
  std::vector<std::vector<uint8_t>> blocks_;
  std::vector<GstTensorMemory> mem_;
};

}  // namespace nns

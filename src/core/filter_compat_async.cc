// SPDX-License-Identifier: LGPL-2.1-only
#include "core/filter_compat_async.h"

#include <dlfcn.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>

#include "core/c_tensor_info.h"
#include "core/error.h"
#include "core/filter_desc.h"

namespace nns {
namespace {

constexpr uint64_t kHandleMagic = 0x6e6e732d61737963ull;  // "nns-asyc"
constexpr std::size_t kCtxWords = sizeof(nns_filter_async_ctx) / sizeof(uint64_t);
static_assert(sizeof(nns_filter_async_ctx) % sizeof(uint64_t) == 0);
static_assert(kCtxWords + 2 <= sizeof(GstTensorFilterAsyncHandle) / sizeof(uint64_t),
              "GstTensorFilterAsyncHandle must hold a context, a count and a check word");
constexpr std::size_t kCountWord = kCtxWords;
constexpr std::size_t kMagicWord = kCtxWords + 1;

void free_release(void *, void *data) {
  std::free(data);
}

CompatAsync *compat_of(const GstTensorFilterProperties *prop) {
  if (!prop || !prop->invoke_async) return nullptr;
  return static_cast<CompatAsync *>(prop->async_user_data);
}

}  // namespace

CompatAsync::CompatAsync() : release_(free_release) {}

void CompatAsync::set_release(Release fn, void *ctx) {
  std::lock_guard lk(mu_);
  release_ = fn ? fn : free_release;
  release_ctx_ = ctx;
}

void CompatAsync::begin(const nns_filter_async_ctx &ctx) {
  std::lock_guard lk(mu_);
  current_ = ctx;
  have_ = true;
  in_invoke_ = true;
  invoker_ = std::this_thread::get_id();
  captured_ = false;
}

bool CompatAsync::end() {
  std::lock_guard lk(mu_);
  in_invoke_ = false;
  return captured_;
}

int CompatAsync::dispatch_upstream(GstTensorFilterProperties *prop, GstTensorMemory *output) {
  nns_filter_async_ctx ctx{};
  Release release;
  void *release_ctx;
  bool have;
  {
    std::lock_guard lk(mu_);
    ctx = current_;
    have = have_;
    release = release_;
    release_ctx = release_ctx_;
  }
  unsigned n = prop->output_meta.num_tensors;
  if (n > NNS_TENSOR_SIZE_LIMIT) n = NNS_TENSOR_SIZE_LIMIT;
  int rc = -EINVAL;
  if (have && output) {
    auto desc = new_desc();
    desc_from_gst_info(&prop->output_meta, *desc);
    char err[512];
    err[0] = '\0';
    // desc_from_gst_info stops at a missing extra block; the host then sees the mismatch.
    rc = ctx.dispatch(&ctx, desc.get(), output, n, 0, err, sizeof err);
  }
  // NNStreamer hands the blocks over to tensor_filter: release them whatever happened.
  if (output)
    for (unsigned i = 0; i < n; ++i)
      if (output[i].data) {
        release(release_ctx, output[i].data);
        output[i].data = nullptr;
      }
  return rc;
}

int CompatAsync::capture(const GstTensorFilterProperties *prop,
                         GstTensorFilterAsyncHandle *handle) {
  std::lock_guard lk(mu_);
  if (!in_invoke_ || invoker_ != std::this_thread::get_id()) return -EINVAL;
  captured_ = true;
  std::memset(handle, 0, sizeof *handle);
  std::memcpy(handle->opaque, &current_, sizeof current_);
  handle->opaque[kCountWord] = prop->output_meta.num_tensors;
  handle->opaque[kMagicWord] = kHandleMagic;
  return 0;
}

void promote_filter_api() {
  static std::once_flag once;
  std::call_once(once, [] {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void *>(&nnstreamer_filter_dispatch_output_async), &info) &&
        info.dli_fname)
      if (void *h = dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL)) (void)h;
  });
}

ScratchOutputs::ScratchOutputs(const GstTensorsInfo &out) {
  TensorsInfo info;
  try {
    info = from_c(&out);
  } catch (const Error &) {
    info = TensorsInfo{};
  }
  blocks_.resize(info.size());
  mem_.assign(NNS_TENSOR_SIZE_LIMIT, GstTensorMemory{nullptr, 0});
  for (std::size_t i = 0; i < info.size() && i < mem_.size(); ++i) {
    blocks_[i].assign(info[i].byte_size(), 0);
    mem_[i] = GstTensorMemory{blocks_[i].data(), blocks_[i].size()};
  }
}

}  // namespace nns

extern "C" {

__attribute__((visibility("default"))) int nnstreamer_filter_dispatch_output_async(
    GstTensorFilterProperties *prop, GstTensorMemory *output) {
  nns::CompatAsync *a = nns::compat_of(prop);
  if (!a) {
    // Not an invoke-async filter: nobody else will release the blocks.
    if (prop && output)
      for (unsigned i = 0; i < prop->output_meta.num_tensors && i < NNS_TENSOR_SIZE_LIMIT; ++i)
        std::free(output[i].data), output[i].data = nullptr;
    return -EINVAL;
  }
  return a->dispatch_upstream(prop, output);
}

__attribute__((visibility("default"))) int nnstreamer_filter_async_capture(
    const GstTensorFilterProperties *prop, GstTensorFilterAsyncHandle *handle) {
  nns::CompatAsync *a = nns::compat_of(prop);
  if (!a || !handle) return -EINVAL;
  return a->capture(prop, handle);
}

__attribute__((visibility("default"))) int nnstreamer_filter_async_dispatch(
    const GstTensorFilterAsyncHandle *handle, const GstTensorsInfo *info,
    const GstTensorMemory *output, int last) {
  if (!handle || handle->opaque[nns::kMagicWord] != nns::kHandleMagic) return -EINVAL;
  nns_filter_async_ctx ctx;
  std::memcpy(&ctx, handle->opaque, sizeof ctx);
  if (!ctx.dispatch) return -EINVAL;
  std::unique_ptr<nns_tensors_desc> desc;
  uint32_t n = 0;
  if (info) {
    desc = nns::new_desc();
    nns::desc_from_gst_info(info, *desc);
    n = info->num_tensors;
  } else if (output) {
    n = static_cast<uint32_t>(handle->opaque[nns::kCountWord]);
  }
  if (!output) n = 0;
  char err[512];
  err[0] = '\0';
  return ctx.dispatch(&ctx, desc.get(), output, n, last ? NNS_FILTER_ASYNC_LAST : 0u, err,
                      sizeof err);
}

}  // extern "C"

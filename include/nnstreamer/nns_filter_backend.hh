// SPDX-License-Identifier: LGPL-2.1-only
// C++ convenience layer over nns_filter_backend.h: derive from nns::FilterBackend, give the
// class a constructor taking `const nns_filter_props &` (it opens the model and throws on
// failure), and export it with NNS_FILTER_BACKEND_EXPORT. Exceptions thrown by the back end are
// turned into an error code plus the exception's message; none crosses the C ABI.
#pragma once

#include <cerrno>
#include <cstring>
#include <exception>
#include <stdexcept>
#include <string>

#include "nns_filter_backend.h"

namespace nns {

// Thrown by back ends; `code` is a negative errno value.
class FilterError : public std::runtime_error {
 public:
  explicit FilterError(const std::string &msg, int code = -EINVAL)
      : std::runtime_error(msg), code_(code) {}
  int code() const noexcept { return code_; }

 private:
  int code_;
};

// invoke-async: where the outputs of one input go (wraps nns_filter_async_ctx). A plain value:
// copy it into a worker, keep it after invoke_async returned, use it from any thread (one copy
// per thread: error() is per object). Every call is safe even after the filter stopped (it
// then returns -ESHUTDOWN and does nothing).
class AsyncEmitter {
 public:
  AsyncEmitter() = default;
  explicit AsyncEmitter(const nns_filter_async_ctx &ctx) : ctx_(ctx) {}

  // Emits one output set (copied by the host). `info` describes `out`; nullptr means the
  // negotiated (static) output tensors. last=true ends this input. Returns 0 or a negative
  // errno (see nns_filter_dispatch_fn); error() then holds the host's message.
  int emit(const GstTensorMemory *out, uint32_t num_out, const nns_tensors_desc *info = nullptr,
           bool last = false) const {
    return call(info, out, num_out, last ? NNS_FILTER_ASYNC_LAST : 0u);
  }
  // Ends this input without another output.
  int finish() const { return call(nullptr, nullptr, 0, NNS_FILTER_ASYNC_LAST); }
  const std::string &error() const { return error_; }
  bool valid() const { return ctx_.dispatch != nullptr; }

  // The input's timestamps (NNS_FILTER_TIME_NONE when unset); outputs carry them.
  uint64_t pts() const { return ctx_.pts; }
  void set_timestamps(uint64_t pts, uint64_t dts, uint64_t duration) {
    ctx_.pts = pts;
    ctx_.dts = dts;
    ctx_.duration = duration;
  }
  const nns_filter_async_ctx &ctx() const { return ctx_; }

 private:
  int call(const nns_tensors_desc *info, const GstTensorMemory *out, uint32_t n,
           uint32_t flags) const {
    if (!ctx_.dispatch) {
      error_ = "no invoke-async context";
      return -EINVAL;
    }
    char err[512];
    err[0] = '\0';
    int rc = ctx_.dispatch(&ctx_, info, out, n, flags, err, sizeof err);
    error_ = rc == 0 ? std::string() : std::string(err);
    return rc;
  }

  nns_filter_async_ctx ctx_{};
  mutable std::string error_;
};

class FilterBackend {
 public:
  virtual ~FilterBackend() = default;
  // Fill in/out from the model; return false when the model does not know its shapes.
  virtual bool model_info(nns_tensors_desc &in, nns_tensors_desc &out) {
    (void)in;
    (void)out;
    return false;
  }
  // Accept a new input shape and compute the output; return false if unsupported.
  virtual bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) {
    (void)in;
    (void)out;
    return false;
  }
  virtual void invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
                      uint32_t num_out) = 0;
  virtual void invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                              nns_tensors_desc &out_info, GstTensorMemory *out) {
    (void)in_info;
    (void)in;
    (void)out_info;
    (void)out;
    throw FilterError("this back end does not support invoke-dynamic", -ENOTSUP);
  }
  // invoke-async=true: take the input (in[] valid during the call only) and emit 0..N outputs
  // through `out`, now or later from any thread. Return true when more outputs of this input
  // will follow (end them with out.emit(..., true) or out.finish(): EOS waits for that), false
  // when everything has been emitted. Back ends that do not override this do not support
  // invoke-async; the element then calls invoke() and posts a warning.
  virtual bool invoke_async(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                            uint32_t num_in, const AsyncEmitter &out) {
    (void)in_info;
    (void)in;
    (void)num_in;
    (void)out;
    throw FilterError("this back end does not support invoke-async", -ENOTSUP);
  }
  virtual void free_output(void *data) { (void)data; }
  virtual void reload(const nns_filter_props &props) {
    (void)props;
    throw FilterError("this back end cannot reload its model", -ENOTSUP);
  }
  virtual bool handle_event(nns_filter_event ev) {
    (void)ev;
    return false;
  }
};

namespace detail {

inline void write_err(char *err, std::size_t errlen, const char *msg) {
  if (!err || errlen == 0) return;
  std::strncpy(err, msg, errlen - 1);
  err[errlen - 1] = '\0';
}

template <typename F>
int call(char *err, std::size_t errlen, F &&f) noexcept {
  try {
    f();
    return 0;
  } catch (const FilterError &e) {
    write_err(err, errlen, e.what());
    return e.code() < 0 ? e.code() : -EINVAL;
  } catch (const std::exception &e) {
    write_err(err, errlen, e.what());
    return -EIO;
  } catch (...) {
    write_err(err, errlen, "unknown exception in back end");
    return -EIO;
  }
}

}  // namespace detail

// Builds the C table for back end class T.
template <typename T>
struct FilterBackendAdapter {
  static FilterBackend *self(void *p) { return static_cast<FilterBackend *>(p); }

  static int open(const nns_filter_props *props, void **priv, char *err, std::size_t errlen) {
    return detail::call(err, errlen, [&] { *priv = static_cast<FilterBackend *>(new T(*props)); });
  }
  static void close(void *priv) { delete self(priv); }
  static int get_model_info(void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                            std::size_t errlen) {
    bool known = false;
    int rc = detail::call(err, errlen, [&] { known = self(priv)->model_info(*in, *out); });
    return rc ? rc : (known ? 0 : -ENOTSUP);
  }
  static int set_input_info(void *priv, const nns_tensors_desc *in, nns_tensors_desc *out,
                            char *err, std::size_t errlen) {
    bool ok = false;
    int rc = detail::call(err, errlen, [&] { ok = self(priv)->set_input_info(*in, *out); });
    return rc ? rc : (ok ? 0 : -ENOTSUP);
  }
  static int invoke(void *priv, const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
                    uint32_t num_out, char *err, std::size_t errlen) {
    return detail::call(err, errlen, [&] { self(priv)->invoke(in, num_in, out, num_out); });
  }
  static void free_output(void *priv, void *data) {
    try {
      self(priv)->free_output(data);
    } catch (...) {
    }
  }
  static int invoke_dynamic(void *priv, const nns_tensors_desc *in_info, const GstTensorMemory *in,
                            nns_tensors_desc *out_info, GstTensorMemory *out, char *err,
                            std::size_t errlen) {
    return detail::call(err, errlen,
                        [&] { self(priv)->invoke_dynamic(*in_info, in, *out_info, out); });
  }
  static int reload(void *priv, const nns_filter_props *props, char *err, std::size_t errlen) {
    return detail::call(err, errlen, [&] { self(priv)->reload(*props); });
  }
  static int handle_event(void *priv, nns_filter_event ev, char *err, std::size_t errlen) {
    bool handled = false;
    int rc = detail::call(err, errlen, [&] { handled = self(priv)->handle_event(ev); });
    return rc ? rc : (handled ? 0 : -ENOTSUP);
  }

  static int invoke_async(void *priv, const nns_tensors_desc *in_info, const GstTensorMemory *in,
                          uint32_t num_in, const nns_filter_async_ctx *ctx, char *err,
                          std::size_t errlen) {
    bool pending = false;
    int rc = detail::call(err, errlen, [&] {
      pending = self(priv)->invoke_async(*in_info, in, num_in, AsyncEmitter(*ctx));
    });
    return rc ? rc : (pending ? NNS_FILTER_ASYNC_PENDING : 0);
  }
  // Whether T overrides invoke_async (then the table offers it).
  static constexpr bool kAsync =
      !std::is_same_v<decltype(&T::invoke_async), decltype(&FilterBackend::invoke_async)>;

  static nns_filter_backend_i make(const char *name, uint32_t flags,
                                   const char *const *extensions) {
    nns_filter_backend_i t{};
    t.api_version = NNS_FILTER_BACKEND_API_VERSION;
    t.name = name;
    t.flags = flags;
    t.extensions = extensions;
    t.open = &open;
    t.close = &close;
    t.get_model_info = &get_model_info;
    t.set_input_info = &set_input_info;
    t.invoke = &invoke;
    t.free_output = &free_output;
    t.invoke_dynamic = &invoke_dynamic;
    t.reload = &reload;
    t.handle_event = &handle_event;
    t.check_accelerator = nullptr;
    t.invoke_async = kAsync ? &invoke_async : nullptr;
    return t;
  }
};

}  // namespace nns

// Exports `nns_filter_backend_entry` for back end class T from a shared object.
#define NNS_FILTER_BACKEND_EXPORT(T, name, flags, extensions)                    \
  extern "C" __attribute__((visibility("default"))) const nns_filter_backend_i * \
  nns_filter_backend_entry(void) {                                               \
    static const nns_filter_backend_i table =                                    \
        ::nns::FilterBackendAdapter<T>::make(name, flags, extensions);           \
    return &table;                                                               \
  }

// SPDX-License-Identifier: LGPL-2.1-only
// invoke-async, host side. A running tensor_filter with invoke-async=true owns one
// AsyncDispatcher. Each input gets an nns_filter_async_ctx naming the dispatcher by a
// process-wide id (never reused) and carrying the input's timestamps; the back end calls
// ctx.dispatch from any thread at any time, and each output set becomes one buffer pushed on
// the source pad.
//
// Guarantees:
// - Lifetime: dispatch looks the id up in a global table. After close() (tensor_filter's stop)
//   dispatch returns -ESHUTDOWN without touching the element; close() waits for dispatches
//   already running. A stale context is therefore harmless, whenever it is used.
// - Serialization: pushes and the serialized events the element forwards (caps, segment,
//   EOS, flush-stop, ...) take out_mu_, so an output never interleaves with an event, and
//   outputs of one thread keep their order. Outputs dispatched by the streaming thread itself
//   during invoke_async are checked at once but pushed right after the invoke (push_deferred),
//   when the element holds no lock of its own: downstream may then query back upstream.
// - EOS: inputs whose invoke_async returned NNS_FILTER_ASYNC_PENDING stay pending until a
//   dispatch flagged NNS_FILTER_ASYNC_LAST; EOS is forwarded once none is pending (or the
//   pads flush, or the element stops). Outputs not announced this way may follow EOS and are
//   then refused by downstream (-EPIPE).
// - Flush: outputs of inputs received before a FLUSH_START are dropped (-ECANCELED).
// - Errors: a dispatch whose tensors do not match the negotiated output is not pushed; the
//   first few post a warning on the bus, the caller gets -EINVAL and the message. A fatal flow
//   return of an async push (not-negotiated, error, EOS) is returned by the next transform.
#pragma once

#include <gst/base/gstbasetransform.h>
#include <gst/gst.h>

#include <condition_variable>
#include <cstdint>
#include <memory>
#include <mutex>
#include <set>
#include <string>
#include <thread>
#include <vector>

#include "core/tensor_info.h"
#include "nns_filter_backend.h"

namespace nns::gst {

class AsyncDispatcher : public std::enable_shared_from_this<AsyncDispatcher> {
 public:
  // A new dispatcher for `element`, registered under a fresh id.
  static std::shared_ptr<AsyncDispatcher> create(GstBaseTransform *element);
  ~AsyncDispatcher();
  AsyncDispatcher(const AsyncDispatcher &) = delete;
  AsyncDispatcher &operator=(const AsyncDispatcher &) = delete;

  // Unregisters and waits for running dispatches; later ones get -ESHUTDOWN. Idempotent.
  void close();

  // The negotiated output: static tensors (empty with invoke-dynamic) and whether the source
  // caps are flexible.
  void configure(const TensorsInfo &model_out, bool flexible);

  // Per input: the context handed to invoke_async, then its result (0, PENDING or an error).
  nns_filter_async_ctx begin_input(GstBuffer *inbuf);
  void end_input(const nns_filter_async_ctx &ctx, int rc);
  // Pushes what was dispatched during the last invoke_async from its own thread.
  void push_deferred();

  // FLUSH_START: outputs of earlier inputs are dropped; a waiting EOS is released.
  void flush();
  // EOS: blocks until no announced input is pending, the pads flush, or close().
  void wait_drained();
  // Runs f() with async outputs held back (for serialized events).
  template <typename F>
  auto serialized(F &&f) {
    std::lock_guard lk(out_mu_);
    return f();
  }
  // A fatal flow return of an async push since the last call (GST_FLOW_OK when none).
  GstFlowReturn take_flow();

  std::size_t pending() const;
  uint64_t pushed() const;

  // nns_filter_async_ctx.dispatch.
  static int dispatch(const nns_filter_async_ctx *ctx, const nns_tensors_desc *info,
                      const GstTensorMemory *out, uint32_t num_out, uint32_t flags, char *err,
                      size_t errlen);

 private:
  explicit AsyncDispatcher(GstBaseTransform *element);
  int deliver(const nns_filter_async_ctx &ctx, const nns_tensors_desc *info,
              const GstTensorMemory *out, uint32_t num_out, uint32_t flags, std::string &msg);
  // Checks the tensors against the negotiated output and makes the buffer (nullptr + msg when
  // they do not match).
  GstBuffer *build(const nns_filter_async_ctx &ctx, const nns_tensors_desc *info,
                   const GstTensorMemory *out, uint32_t num_out, std::string &msg);
  int push_buffer(GstBuffer *buf, std::string &msg);  // out_mu_ held
  void finish_input(uint64_t input);
  bool pads_flushing() const;

  GstBaseTransform *element_;
  uint64_t id_ = 0;

  mutable std::mutex mu_;  // everything below except the format
  std::condition_variable cv_;
  bool closed_ = false;
  int in_flight_ = 0;
  uint64_t next_input_ = 1;
  uint64_t first_valid_ = 1;  // inputs below this were flushed
  std::set<uint64_t> pending_;
  GstFlowReturn flow_ = GST_FLOW_OK;
  bool in_invoke_ = false;
  std::thread::id invoker_;
  struct Deferred {
    GstBuffer *buf;  // nullptr: only ends the input
    uint64_t input;
    bool last;
  };
  std::vector<Deferred> deferred_;
  uint64_t pushed_ = 0;
  int warnings_ = 0;

  std::mutex fmt_mu_;
  bool configured_ = false;
  TensorsInfo model_out_;
  bool flexible_ = false;

  std::mutex out_mu_;  // pushes and serialized events
};

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
// The state behind an ml_single_h and the operations the C entry points share: settling the
// input/output info with the back end, running the model (fixed shapes or the back end's
// dynamic invoke), the time-out worker, and reopening with changed properties.
#pragma once

#include <condition_variable>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <thread>
#include <vector>

#include "api/ml_handles.h"
#include "core/error.h"
#include "core/filter_instance.h"
#include "core/filter_registry.h"
#include "nnstreamer-single.h"

namespace nns::api {

// One invoke handed to the time-out worker. The task owns everything it touches: the caller
// may return (timed out) before it ends.
struct Job {
  std::function<void()> task;
  int rc = 0;
  std::string error;
  bool done = false;
};

// The input/output a back end settled on.
struct Settled {
  TensorsInfo in, out;         // out empty: decided per call (dynamic)
  bool out_from_user = false;  // the model does not know its output; the caller described it
  bool dynamic = false;        // invokes go through the back end's dynamic invoke
  bool declared = false;       // the model itself declared its input and output
};

struct SingleHandle {
  uint32_t magic = kSingleMagic;
  BackendRef be;
  std::shared_ptr<FilterInstance> inst;
  FilterOpenSpec spec;  // as opened; custom/accelerator/layouts follow set_property
  TensorsInfo in, out;
  bool out_from_user = false;
  bool dynamic = false;
  bool declared = false;
  bool is_updatable = false;
  std::mutex mu;  // one call at a time; guards everything here
  unsigned timeout_ms = 0;
  std::string last_error;

  // Time-out worker
  std::thread worker;
  std::condition_variable cv;
  std::shared_ptr<Job> job;  // the last job given to the worker
  bool quit = false;

  ~SingleHandle();
  // Records `msg` as this handle's and this thread's last error; returns `code`.
  int fail(int code, const std::string &msg);
  // A timed-out invoke is still running on the worker.
  bool busy() const { return job && !job->done; }
  // Runs `task` on this thread (no time-out) or on the worker, waiting at most timeout_ms.
  // `lk` holds mu. Returns ML_ERROR_NONE, ML_ERROR_TIMED_OUT or the task's error code (the
  // message is recorded with `fn` in front).
  int run_task(std::unique_lock<std::mutex> &lk, const std::string &fn,
               const std::function<void()> &task);
  void apply(const Settled &s);

 private:
  void worker_loop();
};

SingleHandle *as_single(ml_single_h h);
// The back end really has a dynamic invoke (C++ back ends all fill the entry; the ones without
// one throw ENOTSUP from it and do not set NNS_FILTER_FLAG_DYNAMIC).
inline bool supports_dynamic(const FilterInstance &inst) {
  return inst.backend().invoke_dynamic && (inst.backend().flags & NNS_FILTER_FLAG_DYNAMIC);
}
// ml_error_e for an nns::Error.
int error_code(const Error &e);

// Asks the back end for its input/output. in_given/out_given: what the caller described (may
// be null). model_first: a model that declares its own shapes wins over in_given (reload).
// Throws nns::Error naming the framework, the model and both shapes on a mismatch.
Settled settle(FilterInstance &inst, const TensorsInfo *in_given, const TensorsInfo *out_given,
               bool model_first);

// Runs the model on fixed-shape buffers (outm sized from the output info). Throws nns::Error.
void run_static(FilterInstance &inst, const std::vector<GstTensorMemory> &inm,
                std::vector<GstTensorMemory> &outm);
// Runs the back end's dynamic invoke with the shapes `in_info`; returns new data holding the
// outputs and their info. Throws nns::Error.
std::unique_ptr<TensorsDataHandle> run_dynamic(FilterInstance &inst, const TensorsInfo &in_info,
                                               const std::vector<GstTensorMemory> &inm);

// Changes the input info (ml_single_set_input_info): the back end's set-input gives the new
// output info. Same shapes: names only. mu held, no invoke running. Returns an ml_error_e and
// records the message.
int apply_input_info(SingleHandle &h, const TensorsInfo &info, const std::string &fn);

// Opens `spec` again (the same back end) and settles it with the handle's current input; on
// success the new instance replaces the old one. Throws nns::Error and keeps the old one.
void reopen(SingleHandle &h, const FilterOpenSpec &spec);

}  // namespace nns::api

#define NNS_API extern "C" __attribute__((visibility("default")))

#define REQUIRE_SINGLE(var, h)                          \
  nns::api::SingleHandle *var = nns::api::as_single(h); \
  if (!var)                                             \
  return nns::api::report(ML_ERROR_INVALID_PARAMETER,   \
                          std::string(__func__) + ": the single handle is NULL or invalid")

// With mu held: a timed-out invoke still running makes the handle busy.
#define REQUIRE_IDLE(var, fn)          \
  if (var->busy())                     \
  return var->fail(ML_ERROR_TRY_AGAIN, \
                   std::string(fn) + ": the previous invoke timed out and is still running")

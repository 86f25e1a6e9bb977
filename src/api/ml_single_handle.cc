// SPDX-License-Identifier: LGPL-2.1-only
#include "api/ml_single_handle.h"

#include <cstring>

#include "core/filter_desc.h"

namespace nns::api {

SingleHandle::~SingleHandle() {
  {
    std::lock_guard<std::mutex> g(mu);
    quit = true;
  }
  cv.notify_all();
  if (worker.joinable()) worker.join();  // waits for a timed-out invoke still running
}

int SingleHandle::fail(int code, const std::string &msg) {
  last_error = msg;
  return report(code, msg);
}

void SingleHandle::apply(const Settled &s) {
  in = s.in;
  out = s.out;
  out_from_user = s.out_from_user;
  dynamic = s.dynamic;
  declared = s.declared;
}

void SingleHandle::worker_loop() {
  std::unique_lock<std::mutex> lk(mu);
  for (;;) {
    cv.wait(lk, [&] { return quit || (job && !job->done); });
    if (quit) return;
    std::shared_ptr<Job> j = job;
    lk.unlock();
    int rc = ML_ERROR_NONE;
    std::string error;
    try {
      j->task();
    } catch (const Error &e) {
      rc = error_code(e);
      error = e.what();
    } catch (const std::bad_alloc &) {
      rc = ML_ERROR_OUT_OF_MEMORY;
      error = "out of memory";
    } catch (const std::exception &e) {
      rc = ML_ERROR_STREAMS_PIPE;
      error = e.what();
    }
    j->task = nullptr;  // drops the task's data here, not in a caller
    lk.lock();
    j->rc = rc;
    j->error = std::move(error);
    j->done = true;
    cv.notify_all();
  }
}

int SingleHandle::run_task(std::unique_lock<std::mutex> &lk, const std::string &fn,
                           const std::function<void()> &task) {
  if (timeout_ms == 0) {
    try {
      task();
    } catch (const Error &e) {
      return fail(error_code(e), fn + ": " + e.what());
    } catch (const std::bad_alloc &) {
      return fail(ML_ERROR_OUT_OF_MEMORY, fn + ": out of memory");
    } catch (const std::exception &e) {
      return fail(ML_ERROR_STREAMS_PIPE, fn + ": " + e.what());
    }
    return ML_ERROR_NONE;
  }
  if (!worker.joinable()) worker = std::thread([this] { worker_loop(); });
  auto j = std::make_shared<Job>();
  j->task = task;
  job = j;
  cv.notify_all();
  if (!cv.wait_for(lk, std::chrono::milliseconds(timeout_ms), [&] { return j->done; }))
    return fail(ML_ERROR_TIMED_OUT, fn + ": " + inst->describe() + " did not finish within " +
                                        std::to_string(timeout_ms) + " ms");
  if (j->rc) return fail(j->rc, fn + ": " + j->error);
  return ML_ERROR_NONE;
}

SingleHandle *as_single(ml_single_h h) {
  auto *p = static_cast<SingleHandle *>(h);
  return p && p->magic == kSingleMagic ? p : nullptr;
}

int error_code(const Error &e) {
  switch (e.kind()) {
    case ErrorKind::kSettings:
    case ErrorKind::kNotFound:
    case ErrorKind::kNegotiation:
    case ErrorKind::kStream:
      return ML_ERROR_INVALID_PARAMETER;
    default:
      return ML_ERROR_STREAMS_PIPE;
  }
}

Settled settle(FilterInstance &inst, const TensorsInfo *in_given, const TensorsInfo *out_given,
               bool model_first) {
  Settled s;
  TensorsInfo mi, mo;
  bool known = inst.model_info(mi, mo) && mi.size() > 0;
  bool can_dynamic = supports_dynamic(inst);
  if (known && (model_first || !in_given || in_given->same_as(mi))) {
    s.in = mi;
    s.out = mo;
    s.declared = mo.size() > 0;
  } else if (in_given) {
    TensorsInfo out;
    if (inst.set_input_info(*in_given, out)) {
      s.in = *in_given;
      s.out = out;
    } else if (!known && out_given) {
      s.in = *in_given;
      s.out = *out_given;
      s.out_from_user = true;
    } else if (known && mo.size() == 0 && can_dynamic) {
      s.in = *in_given;  // a dynamic model: its output follows each call's input
    } else {
      fail(ErrorKind::kNegotiation,
           inst.describe() + ": the given input info (" + in_given->to_string() +
               ") does not match the model's input (" + (known ? mi.to_string() : "unknown") +
               ") and the back end cannot change its input");
    }
  } else {
    fail(ErrorKind::kSettings, inst.describe() +
                                   ": the model does not declare its input and output; give "
                                   "input_info and output_info");
  }
  // Keep the caller's tensor names where the back end has none.
  if (in_given && in_given->size() == s.in.size())
    for (std::size_t i = 0; i < s.in.size(); ++i)
      if (s.in[i].name.empty()) s.in[i].name = (*in_given)[i].name;
  if (s.out.size() == 0) {
    if (!can_dynamic)
      fail(ErrorKind::kSettings, inst.describe() +
                                     ": the model does not declare its output and "
                                     "the back end has no dynamic invoke");
    s.dynamic = true;
  } else if (out_given && !s.out_from_user) {
    if (!out_given->same_as(s.out))
      fail(ErrorKind::kNegotiation, inst.describe() + ": the given output info (" +
                                        out_given->to_string() + ") does not match the model's (" +
                                        s.out.to_string() + ")");
    if (out_given->size() == s.out.size())
      for (std::size_t i = 0; i < s.out.size(); ++i)
        if (s.out[i].name.empty()) s.out[i].name = (*out_given)[i].name;
  }
  if (!s.in.valid() || (!s.dynamic && !s.out.valid()))
    fail(ErrorKind::kSettings, inst.describe() + ": incomplete tensor info (input " +
                                   s.in.to_string() + ", output " + s.out.to_string() + ")");
  return s;
}

void run_static(FilterInstance &inst, const std::vector<GstTensorMemory> &inm,
                std::vector<GstTensorMemory> &outm) {
  bool allocates = inst.flags() & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE;
  std::vector<GstTensorMemory> tmp = outm;
  std::shared_ptr<FilterSession> used;
  int rc = inst.invoke(inm.data(), static_cast<uint32_t>(inm.size()), tmp.data(),
                       static_cast<uint32_t>(tmp.size()), allocates ? &used : nullptr);
  if (rc > 0) fail(ErrorKind::kLibrary, inst.describe() + ": the back end dropped the frame");
  if (!allocates) return;
  std::string problem;
  for (std::size_t i = 0; i < tmp.size(); ++i) {
    if (problem.empty() && tmp[i].size != outm[i].size)
      problem = inst.describe() + ": output " + std::to_string(i) + " has " +
                std::to_string(tmp[i].size) + " bytes, expected " + std::to_string(outm[i].size) +
                " (use ml_single_invoke_dynamic for outputs whose shape changes)";
    if (problem.empty()) std::memcpy(outm[i].data, tmp[i].data, tmp[i].size);
    if (used && tmp[i].data) used->free_output(tmp[i].data);
  }
  if (!problem.empty()) fail(ErrorKind::kLibrary, problem);
}

std::unique_ptr<TensorsDataHandle> run_dynamic(FilterInstance &inst, const TensorsInfo &in_info,
                                               const std::vector<GstTensorMemory> &inm) {
  auto din = make_desc(in_info);
  auto dout = new_desc();
  std::vector<GstTensorMemory> outm(NNS_TENSOR_SIZE_LIMIT, GstTensorMemory{nullptr, 0});
  std::shared_ptr<FilterSession> used;
  inst.invoke_dynamic(*din, inm.data(), *dout, outm.data(), &used);
  // The back end's output memory goes back to it on every path below.
  struct Release {
    std::shared_ptr<FilterSession> &s;
    std::vector<GstTensorMemory> &m;
    ~Release() {
      for (auto &t : m)
        if (t.data && s) s->free_output(t.data);
    }
  } release{used, outm};
  TensorsInfo info = info_from_desc(*dout);
  info.format = TensorFormat::kStatic;  // each call's shapes are concrete
  for (std::size_t i = 0; i < info.size(); ++i)
    if (outm[i].size != info[i].byte_size() || (outm[i].size && !outm[i].data))
      fail(ErrorKind::kLibrary, inst.describe() + ": dynamic invoke reported output " +
                                    std::to_string(i) + " as " + info[i].to_string() + " (" +
                                    std::to_string(info[i].byte_size()) + " bytes) but gave " +
                                    std::to_string(outm[i].size) + " bytes");
  std::unique_ptr<TensorsDataHandle> data(new_data(info));
  for (std::size_t i = 0; i < info.size(); ++i)
    if (outm[i].size) std::memcpy(data->buffers[i].get(), outm[i].data, outm[i].size);
  return data;
}

void reopen(SingleHandle &h, const FilterOpenSpec &spec) {
  auto fresh = FilterInstance::open(h.be, spec);
  Settled s = settle(*fresh, &h.in, h.out_from_user ? &h.out : nullptr, false);
  // Names given through set_property stay when the back end has none.
  auto keep_names = [](TensorsInfo &to, const TensorsInfo &from) {
    if (to.size() != from.size()) return;
    for (std::size_t i = 0; i < to.size(); ++i)
      if (to[i].name.empty()) to[i].name = from[i].name;
  };
  keep_names(s.in, h.in);
  keep_names(s.out, h.out);
  h.inst = std::move(fresh);
  h.spec = spec;
  h.apply(s);
}

}  // namespace nns::api

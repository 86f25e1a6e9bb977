// SPDX-License-Identifier: LGPL-2.1-only
// One opened filter back end (a model loaded by a framework), GStreamer-free so that
// tensor_filter and the single-shot API share it.
//
// - open() checks the model files, calls the back end's open() and turns every failure into
//   nns::Error whose text names the framework, the model and the back end's own message.
// - acquire() shares one instance among filters with the same shared-tensor-filter-key,
//   framework and model (reference counted through shared_ptr).
// - invoke() is serialized with a mutex unless the back end sets NNS_FILTER_FLAG_THREAD_SAFE.
// - reload() opens the new model beside the old one, lets the caller check its tensors, and
//   only then swaps it in: any failure leaves the old model loaded and running.
// - suspend() sends NNS_FILTER_EVENT_SUSPEND or closes the model, and the next call reopens.
// Each opened back-end state lives in a Session; memory a back end allocated in invoke keeps
// its Session alive, so a reload or suspend never frees state that output buffers still use.
#pragma once

#include <atomic>
#include <functional>
#include <memory>
#include <mutex>
#include <shared_mutex>
#include <string>
#include <vector>

#include "core/filter_registry.h"
#include "core/tensor_info.h"
#include "nns_filter_backend.h"

namespace nns {

// True when `info` holds tensor names only (inputname= without input=/inputtype=).
bool names_only(const TensorsInfo &info);

struct FilterOpenSpec {
  std::string framework;  // framework= as given ("auto", an alias or a name)
  std::vector<std::string> models;
  // From input=/inputtype=/inputname=; empty when not given; names only (type kEnd, no dims)
  // for inputname= alone, which reaches only NNS_FILTER_FLAG_TENSOR_NAMES back ends.
  TensorsInfo input;
  TensorsInfo output;  // from output=/outputtype=/outputname=, the same way
  std::string custom;
  std::string accelerator;
  std::vector<tensor_layout> input_layout;  // empty: ANY
  std::vector<tensor_layout> output_layout;
  bool invoke_dynamic = false;
  bool invoke_async = false;  // invoke-async=true and the back end has invoke_async
  int num_threads = 0;
  bool verbose = false;    // silent=false
  std::string shared_key;  // shared-tensor-filter-key; "" = not shared
};

// One back-end open()/close() pair.
class FilterSession {
 public:
  FilterSession(const nns_filter_backend_i *be, void *priv) : be_(be), priv_(priv) {}
  ~FilterSession();
  FilterSession(const FilterSession &) = delete;
  FilterSession &operator=(const FilterSession &) = delete;
  void *priv() const { return priv_; }
  // Releases memory the back end allocated in invoke (free_output, or free()).
  void free_output(void *data);

 private:
  const nns_filter_backend_i *be_;
  void *priv_;
};

class FilterInstance {
 public:
  // Opens a new instance. Throws nns::Error naming framework, model and cause.
  static std::shared_ptr<FilterInstance> open(const BackendRef &be, const FilterOpenSpec &spec);
  // Same, but returns the instance already open for spec.shared_key + framework + models.
  static std::shared_ptr<FilterInstance> acquire(const BackendRef &be, const FilterOpenSpec &spec);
  // Number of instances currently alive for a shared key (tests, diagnostics).
  static std::size_t shared_use_count(const std::string &key);

  ~FilterInstance();
  FilterInstance(const FilterInstance &) = delete;
  FilterInstance &operator=(const FilterInstance &) = delete;

  const nns_filter_backend_i &backend() const { return *be_; }
  const std::string &name() const { return name_; }  // the back end's framework name
  uint32_t flags() const { return be_->flags; }
  const FilterOpenSpec &spec() const { return spec_; }
  // "framework 'onnxruntime', model '/m.onnx'" for messages.
  std::string describe() const;

  // The model's own shapes; false when the back end does not know them.
  bool model_info(TensorsInfo &in, TensorsInfo &out);
  // Tells the back end its input, gets the output; false when unsupported.
  bool set_input_info(const TensorsInfo &in, TensorsInfo &out);

  // Runs the model. Returns 0, or > 0 when the back end asks to drop the frame. Throws
  // nns::Error(kLibrary) with the back end's message on failure. When `used` is given it
  // receives the session that produced the outputs (for ALLOCATE_IN_INVOKE memory).
  int invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out, uint32_t num_out,
             std::shared_ptr<FilterSession> *used = nullptr);
  // invoke-dynamic; outputs are owned by `used` (release with used->free_output()).
  void invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                      nns_tensors_desc &out_info, GstTensorMemory *out,
                      std::shared_ptr<FilterSession> *used);

  // invoke-async: hands one input to the back end, whose outputs go through ctx.dispatch.
  // Returns 0 or NNS_FILTER_ASYNC_PENDING; throws nns::Error(kLibrary) on failure.
  int invoke_async(const nns_tensors_desc &in_info, const GstTensorMemory *in, uint32_t num_in,
                   const nns_filter_async_ctx &ctx);
  bool supports_async() const { return be_->invoke_async != nullptr; }

  // A model opened by reload() but not swapped in yet, for the caller to inspect.
  class ReloadProbe {
   public:
    ReloadProbe(FilterInstance &inst, void *priv, const std::vector<std::string> &models)
        : inst_(inst), priv_(priv), models_(models) {}
    // As model_info() / set_input_info(), on the new model.
    bool model_info(TensorsInfo &in, TensorsInfo &out) const;
    bool set_input_info(const TensorsInfo &in, TensorsInfo &out) const;

   private:
    FilterInstance &inst_;
    void *priv_;
    const std::vector<std::string> &models_;
  };
  // Throws to refuse the new model.
  using ReloadCheck = std::function<void(const ReloadProbe &)>;

  // Loads `models` in place of the current model (is-updatable): opens them beside the current
  // model (invokes go on meanwhile), runs `check` on the new one, then swaps. Throws on any
  // failure, the current model staying loaded and in use. Reloads are serialized.
  void reload(const std::vector<std::string> &models, const ReloadCheck &check = {});
  // Idle: let the back end free its resources; the next call resumes transparently.
  void suspend();
  // Makes invoke() record the time of each call (for suspend=; one clock read per invoke).
  void track_use();
  // Microseconds since the last invoke (or since open/track_use() when none yet).
  int64_t idle_us() const;
  bool suspended() const { return suspended_.load(std::memory_order_relaxed); }
  // Number of open() calls made so far (1 + reopens after suspend or reload).
  unsigned open_count() const { return open_count_; }

 private:
  FilterInstance(const BackendRef &be, const FilterOpenSpec &spec);
  void check_models(const std::vector<std::string> &models) const;
  std::shared_ptr<FilterSession> open_session(const std::vector<std::string> &models);
  // On one session; messages name `models`.
  bool model_info_of(void *priv, const std::vector<std::string> &models, TensorsInfo &in,
                     TensorsInfo &out) const;
  bool set_input_info_of(void *priv, const std::vector<std::string> &models, const TensorsInfo &in,
                         TensorsInfo &out) const;
  void resume_locked();
  // Runs `call` (a back-end invoke on session_) under mu_: shared for thread-safe back ends,
  // exclusive otherwise; a suspended model is resumed first and the use time recorded after.
  template <typename Call>
  int invoke_locked(Call &&call);
  [[noreturn]] void raise(const std::string &what, int rc, const char *err) const;
  [[noreturn]] void raise(const std::vector<std::string> &models, const std::string &what, int rc,
                          const char *err) const;

  const nns_filter_backend_i *be_;
  std::string origin_;
  std::string name_;
  FilterOpenSpec spec_;
  bool thread_safe_;

  std::shared_mutex mu_;  // invoke: shared (thread-safe back ends) or exclusive
  std::shared_ptr<FilterSession> session_;
  std::atomic<bool> suspended_{false};
  std::atomic<bool> track_use_{false};
  std::atomic<int64_t> last_use_us_{0};
  bool suspended_by_event_ = false;
  std::atomic<unsigned> open_count_{0};
  std::mutex reload_mu_;  // one reload at a time (shared instances: from several filters)
};

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
#include "core/filter_instance.h"

#include <sys/stat.h>
#include <unistd.h>

#include <array>
#include <chrono>
#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <map>
#include <utility>

#include "core/error.h"
#include "core/filter_desc.h"

namespace nns {
namespace {

constexpr std::size_t kErrLen = 1024;

int64_t now_us() {
  return std::chrono::duration_cast<std::chrono::microseconds>(
             std::chrono::steady_clock::now().time_since_epoch())
      .count();
}

// Names alone (inputname= without input=) go only to back ends that pick tensors by name.
TensorsInfo for_backend(const TensorsInfo &info, uint32_t flags) {
  if (!(flags & NNS_FILTER_FLAG_TENSOR_NAMES) && names_only(info)) return TensorsInfo{};
  return info;
}

// nns_filter_props plus the storage its pointers refer to.
struct PropsHolder {
  nns_filter_props p{};
  std::vector<const char *> files;
  std::unique_ptr<nns_tensors_desc> in, out;
  std::array<tensor_layout, NNS_TENSOR_SIZE_LIMIT> il{}, ol{};

  PropsHolder(const std::string &fw, uint32_t flags, const FilterOpenSpec &s,
              const std::vector<std::string> &models)
      : in(make_desc(for_backend(s.input, flags))), out(make_desc(for_backend(s.output, flags))) {
    for (const auto &m : models) files.push_back(m.c_str());
    files.push_back(nullptr);
    for (std::size_t i = 0; i < il.size(); ++i) {
      il[i] = i < s.input_layout.size() ? s.input_layout[i] : _NNS_LAYOUT_ANY;
      ol[i] = i < s.output_layout.size() ? s.output_layout[i] : _NNS_LAYOUT_ANY;
    }
    p.framework = fw.c_str();
    p.model_files = files.data();
    p.num_models = static_cast<uint32_t>(models.size());
    p.input = in.get();
    p.output = out.get();
    p.custom = s.custom.empty() ? nullptr : s.custom.c_str();
    p.accelerator = s.accelerator.empty() ? nullptr : s.accelerator.c_str();
    p.input_layout = il.data();
    p.output_layout = ol.data();
    p.invoke_dynamic = s.invoke_dynamic ? 1 : 0;
    p.num_threads = s.num_threads;
    p.invoke_async = s.invoke_async ? 1 : 0;
    p.verbose = s.verbose ? 1 : 0;
  }
};

std::mutex g_shared_mu;
std::map<std::string, std::weak_ptr<FilterInstance>> g_shared;

std::string shared_map_key(const std::string &key, const std::string &fw,
                           const std::vector<std::string> &models) {
  return key + '\n' + fw + '\n' + join(models, ",");
}

}  // namespace

bool names_only(const TensorsInfo &info) {
  if (info.size() == 0) return false;
  for (const auto &t : info.tensors)
    if (t.type != TensorType::kEnd || t.rank() != 0) return false;
  return true;
}

FilterSession::~FilterSession() {
  be_->close(priv_);
}

void FilterSession::free_output(void *data) {
  if (be_->free_output)
    be_->free_output(priv_, data);
  else
    std::free(data);
}

FilterInstance::FilterInstance(const BackendRef &be, const FilterOpenSpec &spec)
    : be_(be.iface),
      origin_(be.origin),
      name_(be.iface->name),
      spec_(spec),
      thread_safe_((be.iface->flags & NNS_FILTER_FLAG_THREAD_SAFE) != 0) {}

FilterInstance::~FilterInstance() {
  std::unique_lock lk(mu_);
  session_.reset();
}

std::string FilterInstance::describe() const {
  return "framework '" + name_ + "', model '" + join(spec_.models, ",") + "'";
}

void FilterInstance::raise(const std::string &what, int rc, const char *err) const {
  raise(spec_.models, what, rc, err);
}

void FilterInstance::raise(const std::vector<std::string> &models, const std::string &what, int rc,
                           const char *err) const {
  std::string cause = err && *err ? std::string(err)
                                  : std::string("error ") + std::to_string(rc) + " (" +
                                        std::strerror(rc < 0 ? -rc : rc) + ")";
  fail(ErrorKind::kLibrary,
       "framework '" + name_ + "', model '" + join(models, ",") + "': " + what + ": " + cause);
}

void FilterInstance::check_models(const std::vector<std::string> &models) const {
  if (be_->flags & NNS_FILTER_FLAG_RUN_WITHOUT_MODEL) return;
  if (models.empty())
    fail(ErrorKind::kSettings, "framework '" + name_ + "' needs a model file; set model=");
  for (const auto &m : models) {
    struct stat st;
    if (::stat(m.c_str(), &st) != 0)
      fail(ErrorKind::kNotFound, "framework '" + name_ + "': model file '" + m +
                                     "' does not exist (" + std::strerror(errno) + ")");
    if (S_ISDIR(st.st_mode))
      fail(ErrorKind::kNotFound,
           "framework '" + name_ + "': model file '" + m + "' is a directory, not a model file");
    if (::access(m.c_str(), R_OK) != 0)
      fail(ErrorKind::kNotFound, "framework '" + name_ + "': model file '" + m +
                                     "' is not readable (" + std::strerror(errno) + ")");
  }
}

std::shared_ptr<FilterSession> FilterInstance::open_session(
    const std::vector<std::string> &models) {
  check_models(models);
  PropsHolder props(spec_.framework.empty() ? name_ : spec_.framework, be_->flags, spec_, models);
  char err[kErrLen];
  err[0] = '\0';
  void *priv = nullptr;
  int rc = be_->open(&props.p, &priv, err, sizeof err);
  if (rc != 0) {
    std::string cause =
        err[0] ? std::string(err)
               : "error " + std::to_string(rc) + " (" + std::strerror(rc < 0 ? -rc : rc) + ")";
    fail(ErrorKind::kLibrary,
         "framework '" + name_ + "' could not open model '" + join(models, ",") + "': " + cause);
  }
  ++open_count_;
  return std::make_shared<FilterSession>(be_, priv);
}

std::shared_ptr<FilterInstance> FilterInstance::open(const BackendRef &be,
                                                     const FilterOpenSpec &spec) {
  if (!be) fail(ErrorKind::kInternal, "FilterInstance::open without a back end");
  std::shared_ptr<FilterInstance> inst(new FilterInstance(be, spec));
  inst->session_ = inst->open_session(spec.models);
  return inst;
}

std::shared_ptr<FilterInstance> FilterInstance::acquire(const BackendRef &be,
                                                        const FilterOpenSpec &spec) {
  if (spec.shared_key.empty()) return open(be, spec);
  std::string key = shared_map_key(spec.shared_key, be.iface->name, spec.models);
  std::lock_guard lk(g_shared_mu);
  if (auto it = g_shared.find(key); it != g_shared.end())
    if (auto inst = it->second.lock()) return inst;
  auto inst = open(be, spec);
  g_shared[key] = inst;
  return inst;
}

std::size_t FilterInstance::shared_use_count(const std::string &key) {
  std::lock_guard lk(g_shared_mu);
  std::size_t n = 0;
  std::string prefix = key + '\n';
  for (auto it = g_shared.begin(); it != g_shared.end();) {
    if (it->second.expired()) {
      it = g_shared.erase(it);
      continue;
    }
    if (it->first.compare(0, prefix.size(), prefix) == 0)
      n += static_cast<std::size_t>(it->second.use_count());
    ++it;
  }
  return n;
}

void FilterInstance::resume_locked() {
  if (!suspended_.load(std::memory_order_relaxed)) return;
  if (suspended_by_event_) {
    char err[kErrLen];
    err[0] = '\0';
    int rc = be_->handle_event(session_->priv(), NNS_FILTER_EVENT_RESUME, err, sizeof err);
    if (rc != 0 && rc != -ENOTSUP) raise("resume after suspend failed", rc, err);
  } else {
    session_ = open_session(spec_.models);
  }
  suspended_by_event_ = false;
  suspended_.store(false, std::memory_order_relaxed);
}

void FilterInstance::suspend() {
  std::unique_lock lk(mu_);
  if (suspended_.load(std::memory_order_relaxed) || !session_) return;
  if (be_->handle_event) {
    char err[kErrLen];
    err[0] = '\0';
    if (be_->handle_event(session_->priv(), NNS_FILTER_EVENT_SUSPEND, err, sizeof err) == 0) {
      suspended_by_event_ = true;
      suspended_.store(true, std::memory_order_relaxed);
      return;
    }
  }
  session_.reset();  // closes now, or when the last output buffer of it is released
  suspended_by_event_ = false;
  suspended_.store(true, std::memory_order_relaxed);
}

bool FilterInstance::model_info_of(void *priv, const std::vector<std::string> &models,
                                   TensorsInfo &in, TensorsInfo &out) const {
  if (!be_->get_model_info) return false;
  auto din = new_desc(), dout = new_desc();
  char err[kErrLen];
  err[0] = '\0';
  int rc = be_->get_model_info(priv, din.get(), dout.get(), err, sizeof err);
  if (rc == -ENOTSUP) return false;
  if (rc != 0) raise(models, "cannot read the model's tensor shapes", rc, err);
  in = info_from_desc(*din);
  out = info_from_desc(*dout);
  return true;
}

bool FilterInstance::set_input_info_of(void *priv, const std::vector<std::string> &models,
                                       const TensorsInfo &in, TensorsInfo &out) const {
  if (!be_->set_input_info) return false;
  auto din = make_desc(in);
  auto dout = new_desc();
  char err[kErrLen];
  err[0] = '\0';
  int rc = be_->set_input_info(priv, din.get(), dout.get(), err, sizeof err);
  if (rc == -ENOTSUP) return false;
  if (rc != 0) raise(models, "the model does not accept input " + in.to_string(), rc, err);
  out = info_from_desc(*dout);
  return true;
}

bool FilterInstance::model_info(TensorsInfo &in, TensorsInfo &out) {
  std::unique_lock lk(mu_);
  resume_locked();
  return model_info_of(session_->priv(), spec_.models, in, out);
}

bool FilterInstance::set_input_info(const TensorsInfo &in, TensorsInfo &out) {
  std::unique_lock lk(mu_);
  resume_locked();
  return set_input_info_of(session_->priv(), spec_.models, in, out);
}

bool FilterInstance::ReloadProbe::model_info(TensorsInfo &in, TensorsInfo &out) const {
  return inst_.model_info_of(priv_, models_, in, out);
}

bool FilterInstance::ReloadProbe::set_input_info(const TensorsInfo &in, TensorsInfo &out) const {
  return inst_.set_input_info_of(priv_, models_, in, out);
}

template <typename Call>
int FilterInstance::invoke_locked(Call &&call) {
  if (suspended_.load(std::memory_order_relaxed)) {
    std::unique_lock lk(mu_);
    resume_locked();
  }
  int rc;
  if (thread_safe_) {
    std::shared_lock lk(mu_);
    rc = call();
  } else {
    std::unique_lock lk(mu_);
    resume_locked();  // suspended again between the two locks
    rc = call();
  }
  if (track_use_.load(std::memory_order_relaxed))
    last_use_us_.store(now_us(), std::memory_order_relaxed);
  return rc;
}

int FilterInstance::invoke(const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
                           uint32_t num_out, std::shared_ptr<FilterSession> *used) {
  char err[kErrLen];
  err[0] = '\0';
  int rc = invoke_locked([&] {
    if (used) *used = session_;
    return be_->invoke(session_->priv(), in, num_in, out, num_out, err, sizeof err);
  });
  if (rc < 0) raise("invoke failed", rc, err);
  return rc;
}

void FilterInstance::track_use() {
  int64_t zero = 0;
  last_use_us_.compare_exchange_strong(zero, now_us());
  track_use_.store(true, std::memory_order_relaxed);
}

int64_t FilterInstance::idle_us() const {
  int64_t last = last_use_us_.load(std::memory_order_relaxed);
  return last == 0 ? 0 : now_us() - last;
}

void FilterInstance::invoke_dynamic(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                                    nns_tensors_desc &out_info, GstTensorMemory *out,
                                    std::shared_ptr<FilterSession> *used) {
  if (!be_->invoke_dynamic)
    fail(ErrorKind::kSettings, describe() + ": invoke-dynamic=true but framework '" + name_ +
                                   "' does not support dynamic invoke");
  char err[kErrLen];
  err[0] = '\0';
  std::unique_lock lk(mu_);
  resume_locked();
  int rc = be_->invoke_dynamic(session_->priv(), &in_info, in, &out_info, out, err, sizeof err);
  if (track_use_.load(std::memory_order_relaxed))
    last_use_us_.store(now_us(), std::memory_order_relaxed);
  if (used) *used = session_;
  if (rc < 0) raise("invoke (dynamic) failed", rc, err);
}

int FilterInstance::invoke_async(const nns_tensors_desc &in_info, const GstTensorMemory *in,
                                 uint32_t num_in, const nns_filter_async_ctx &ctx) {
  if (!be_->invoke_async)
    fail(ErrorKind::kSettings,
         describe() + ": framework '" + name_ + "' does not support invoke-async");
  char err[kErrLen];
  err[0] = '\0';
  int rc = invoke_locked([&] {
    return be_->invoke_async(session_->priv(), &in_info, in, num_in, &ctx, err, sizeof err);
  });
  if (rc < 0) raise("invoke (async) failed", rc, err);
  return rc == NNS_FILTER_ASYNC_PENDING ? rc : 0;
}

void FilterInstance::reload(const std::vector<std::string> &models, const ReloadCheck &check) {
  std::lock_guard rl(reload_mu_);  // spec_ changes only here, so it is read safely below
  // Opened beside the current model, without the invoke lock: frames go on meanwhile. Any
  // throw from here to the swap leaves the current model as it was (`fresh` closes).
  std::shared_ptr<FilterSession> fresh = open_session(models);
  if (check) check(ReloadProbe(*this, fresh->priv(), models));
  std::shared_ptr<FilterSession> old;
  {
    std::unique_lock lk(mu_);
    old = std::exchange(session_, std::move(fresh));
    spec_.models = models;
    suspended_by_event_ = false;
    suspended_.store(false, std::memory_order_relaxed);
  }
  // `old` closes here, outside the lock, or later when the last output buffer of it goes.
}

}  // namespace nns

// SPDX-License-Identifier: LGPL-2.1-only
// nnsprofile's output: every figure of the profiler as one JSON object (docs/profiler.md,
// "Tracer output"). Runs off the streaming path (sampler thread, pipeline stop, exit).
#include <unistd.h>

#include <fstream>
#include <nlohmann/json.hpp>
#include <sstream>

#include "profile/profiler.h"

namespace nns::profile {

namespace {

using nlohmann::json;

json hist_json(const Hist &h) {
  json a = json::array();
  for (const auto &[lo, c] : h.nonzero()) a.push_back(json::array({lo, c}));
  return a;
}

json acc_json(const LatencyAcc &a) {
  const uint64_t n = a.count.load(std::memory_order_relaxed);
  return json{{"count", n},
              {"total_ns", a.sum.load(std::memory_order_relaxed)},
              {"min_ns", n ? a.min.load(std::memory_order_relaxed) : 0},
              {"max_ns", a.max.load(std::memory_order_relaxed)}};
}

std::string read_small(const std::string &path) {
  std::ifstream f(path);
  std::string s;
  std::getline(f, s);
  return s;
}

// CPU time of a live thread from /proc (the same counter as CLOCK_THREAD_CPUTIME_ID), or -1
// when the thread is gone (or the id now names another thread).
int64_t proc_thread_cpu(pid_t tid, const std::string &name) {
  const std::string dir = "/proc/self/task/" + std::to_string(tid);
  if (read_small(dir + "/comm") != name) return -1;
  std::istringstream in(read_small(dir + "/schedstat"));
  long long ns = -1;
  in >> ns;
  return in ? ns : -1;
}

}  // namespace

std::string Profiler::snapshot_json(const char *reason) {
  std::lock_guard<std::mutex> lk(mu_);
  json out;
  out["format"] = "nnsprofile";
  out["version"] = 1;
  out["pid"] = getpid();
  out["seq"] = ++seq_;
  out["reason"] = reason;
  out["now_ns"] = now_ts();
  out["params"] = json{{"file", params_.file},
                       {"interval_ms", params_.interval_ms},
                       {"sample_ms", params_.sample_ms},
                       {"cpu_ms", params_.cpu_ms}};

  std::unordered_map<const ElementRec *, std::size_t> ids;
  json elements = json::array();
  for (auto &r : elements_) {
    if (auto *e = static_cast<GstElement *>(g_weak_ref_get(&r->weak))) {
      refresh_locked(r.get(), e);
      gst_object_unref(e);
    }
    ids[r.get()] = elements.size();
    json j{{"id", elements.size()},
           {"name", r->name},
           {"factory", r->factory},
           {"pipeline", r->pipeline},
           {"kind", r->kind},
           {"boundary", r->boundary.load(std::memory_order_relaxed)},
           {"spans", r->spans.load(std::memory_order_relaxed)},
           {"self_ns", r->self_ns.load(std::memory_order_relaxed)},
           {"self_max_ns", r->self_max.load(std::memory_order_relaxed)},
           {"self_hist", hist_json(r->self_hist)},
           {"gaps", r->gaps.load(std::memory_order_relaxed)},
           {"gap_ns", r->gap_ns.load(std::memory_order_relaxed)},
           {"pulls", r->pulls.load(std::memory_order_relaxed)},
           {"pull_ns", r->pull_ns.load(std::memory_order_relaxed)},
           {"invokes", r->invokes.load(std::memory_order_relaxed)},
           {"invoke_ns", r->invoke_ns.load(std::memory_order_relaxed)},
           {"invoke_max_ns", r->invoke_max.load(std::memory_order_relaxed)},
           {"invoke_hist", hist_json(r->invoke_hist)},
           {"first_ns", r->first_ns.load(std::memory_order_relaxed)},
           {"last_ns", r->last_ns.load(std::memory_order_relaxed)}};
    if (r->is_queue)
      j["queue"] = json{{"samples", r->q_samples},
                        {"full_samples", r->q_full},
                        {"sum_buffers", r->q_sum_buffers},
                        {"max_buffers", r->q_max_buffers},
                        {"sum_bytes", r->q_sum_bytes},
                        {"max_bytes", r->q_max_bytes},
                        {"sum_time_ns", r->q_sum_time},
                        {"max_time_ns", r->q_max_time},
                        {"max_size_buffers", r->q_cap_buffers},
                        {"max_size_bytes", r->q_cap_bytes},
                        {"max_size_time_ns", r->q_cap_time}};
    elements.push_back(std::move(j));
  }
  out["elements"] = std::move(elements);

  const int nsrc = n_sources_.load(std::memory_order_acquire);
  json sources = json::array();
  for (int i = 0; i < nsrc; ++i)
    sources.push_back(ids[sources_[static_cast<std::size_t>(i)]->element]);
  out["sources"] = sources;

  json links = json::array();
  for (auto &l : links_) {
    const ElementRec *to = l->to.load(std::memory_order_relaxed);
    json by_source = json::array();
    for (int i = 0; i < nsrc; ++i) {
      const LatencyAcc &a = l->by_source[static_cast<std::size_t>(i)];
      if (a.count.load(std::memory_order_relaxed) == 0) continue;
      json s = acc_json(a);
      s["source"] = ids[sources_[static_cast<std::size_t>(i)]->element];
      by_source.push_back(std::move(s));
    }
    // Data flows from `from` to `to`; for a pull link the puller is downstream.
    const bool pull = l->pull;
    json j{{"from", pull ? (to ? json(ids[to]) : json(nullptr)) : json(ids[l->from])},
           {"from_pad", pull ? l->to_pad : l->from_pad},
           {"to", pull ? json(ids[l->from]) : (to ? json(ids[to]) : json(nullptr))},
           {"to_pad", pull ? l->from_pad : l->to_pad},
           {"mode", pull ? "pull" : "push"},
           {"source", l->source_idx >= 0},
           {"buffers", l->buffers.load(std::memory_order_relaxed)},
           {"bytes", l->bytes.load(std::memory_order_relaxed)},
           {"first_ns", l->first_ns.load(std::memory_order_relaxed)},
           {"last_ns", l->last_ns.load(std::memory_order_relaxed)},
           {"latency", acc_json(l->lat)},
           {"latency_hist", hist_json(l->lat_hist)},
           {"latency_by_source", std::move(by_source)}};
    links.push_back(std::move(j));
  }
  out["links"] = std::move(links);

  json threads = json::array();
  for (auto &t : threads_) {
    int64_t cpu = t->cpu_last.load(std::memory_order_relaxed);
    const int64_t live = proc_thread_cpu(t->tid, t->name);
    if (live > cpu) cpu = live;
    const ElementRec *root = t->root.load(std::memory_order_relaxed);
    threads.push_back(json{{"tid", t->tid},
                           {"name", t->name},
                           {"root", root ? json(ids[root]) : json(nullptr)},
                           {"first_ns", t->first_ns.load(std::memory_order_relaxed)},
                           {"last_ns", t->last_ns.load(std::memory_order_relaxed)},
                           {"pushes", t->pushes.load(std::memory_order_relaxed)},
                           {"cpu_ns", cpu - t->cpu_first.load(std::memory_order_relaxed)}});
  }
  out["threads"] = std::move(threads);
  return out.dump();
}

}  // namespace nns::profile

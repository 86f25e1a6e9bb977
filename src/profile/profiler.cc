// SPDX-License-Identifier: LGPL-2.1-only
// nnsprofile's per-buffer bookkeeping (see profiler.h). Spans: a push (or pull) opens a frame on
// the calling thread's stack; when it returns, its duration minus the time of the pushes nested
// in it is the receiving element's own time for that buffer.
#include "profile/profiler.h"

#include <pthread.h>
#include <sys/syscall.h>
#include <time.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>
#include <fstream>
#include <stdexcept>
#include <vector>

#include "profile/invoke_probe.h"

namespace nns::profile {

std::atomic<bool> g_invoke_probe_on{false};

namespace {

std::atomic<Profiler *> g_active{nullptr};
std::atomic<uint64_t> g_generation{0};

struct Tls {
  uint64_t gen = 0;
  ThreadRec *rec = nullptr;
};
thread_local Tls tls;

int64_t thread_cpu_ns() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return static_cast<int64_t>(ts.tv_sec) * 1000000000 + ts.tv_nsec;
}

// The element a pad belongs to: its parent, or for the internal pad of a ghost pad the ghost
// pad's parent.
GstElement *pad_element(GstPad *pad) {
  GstObject *p = GST_OBJECT_PARENT(pad);
  if (p && GST_IS_PAD(p)) p = GST_OBJECT_PARENT(p);
  return p && GST_IS_ELEMENT(p) ? GST_ELEMENT_CAST(p) : nullptr;
}

std::string object_name(gpointer obj) {
  gchar *n = gst_object_get_name(GST_OBJECT_CAST(obj));
  std::string s = n ? n : "";
  g_free(n);
  return s;
}

std::string pad_label(GstPad *pad) {
  GstElement *e = pad_element(pad);
  return (e ? object_name(e) : std::string("?")) + ":" + object_name(pad);
}

uint64_t pts_hash(uint64_t pts) {
  return (pts * 0x9E3779B97F4A7C15ull) >> 40;
}

void acc_add(LatencyAcc &a, int64_t v) {
  a.count.fetch_add(1, std::memory_order_relaxed);
  a.sum.fetch_add(v, std::memory_order_relaxed);
  atomic_max(a.max, v);
  atomic_min(a.min, v);
}

void set_first(std::atomic<int64_t> &slot, int64_t ts) {
  if (slot.load(std::memory_order_relaxed) < 0) {
    int64_t expected = -1;
    slot.compare_exchange_strong(expected, ts, std::memory_order_relaxed);
  }
}

}  // namespace

Profiler *active_profiler() {
  return g_active.load(std::memory_order_acquire);
}

void set_active_profiler(Profiler *p) {
  g_active.store(p, std::memory_order_release);
  g_invoke_probe_on.store(p != nullptr, std::memory_order_relaxed);
}

void note_invoke(GstElement *element, int64_t dur_ns) {
  if (Profiler *p = active_profiler()) p->invoke(element, dur_ns);
}

Params parse_params(const char *text) {
  Params p;
  if (!text || !*text) return p;
  std::string s = std::string("nnsprofile,") + text;
  GstStructure *st = gst_structure_from_string(s.c_str(), nullptr);
  if (!st)
    throw std::invalid_argument(std::string("nnsprofile: cannot parse the parameters '") + text +
                                "' (expected e.g. file=/tmp/p.json,interval=1000)");
  std::string err;
  for (int i = 0; i < gst_structure_n_fields(st); ++i) {
    const char *f = gst_structure_nth_field_name(st, i);
    const GValue *v = gst_structure_get_value(st, f);
    std::string val;
    if (G_VALUE_HOLDS_STRING(v))
      val = g_value_get_string(v);
    else {
      gchar *c = gst_value_serialize(v);
      val = c ? c : "";
      g_free(c);
    }
    auto to_int = [&](int lo) {
      char *end = nullptr;
      long n = std::strtol(val.c_str(), &end, 10);
      if (val.empty() || *end || n < lo || n > 3600000)
        err = std::string("nnsprofile: parameter '") + f +
              "' must be an integer >= " + std::to_string(lo) + ", got '" + val + "'";
      return static_cast<int>(n);
    };
    if (!std::strcmp(f, "file"))
      p.file = val;
    else if (!std::strcmp(f, "interval"))
      p.interval_ms = to_int(0);
    else if (!std::strcmp(f, "sample"))
      p.sample_ms = to_int(1);
    else if (!std::strcmp(f, "cpu"))
      p.cpu_ms = to_int(1);
    else
      err = std::string("nnsprofile: unknown parameter '") + f +
            "' (known: file, interval, sample, cpu)";
    if (!err.empty()) break;
  }
  gst_structure_free(st);
  if (!err.empty()) throw std::invalid_argument(err);
  return p;
}

Profiler::Profiler(Params p) : params_(std::move(p)), generation_(g_generation.fetch_add(1) + 1) {
  std::string g = std::to_string(generation_);
  q_elem_ = g_quark_from_string(("nnsprofile-element-" + g).c_str());
  q_link_ = g_quark_from_string(("nnsprofile-link-" + g).c_str());
  if (params_.file.empty()) params_.file = "nnsprofile-" + std::to_string(getpid()) + ".json";
}

Profiler::~Profiler() {
  {
    std::lock_guard<std::mutex> lk(smu_);
    stop_ = true;
  }
  scv_.notify_all();
  if (sampler_.joinable()) sampler_.join();
  if (sampler_started_) write_file("exit");
  for (auto &e : elements_) g_weak_ref_clear(&e->weak);
}

int64_t Profiler::now_ts() const {
  int64_t off = ts_offset_.load(std::memory_order_relaxed);
  int64_t now = static_cast<int64_t>(gst_util_get_timestamp());
  return off == INT64_MIN ? now : now - off;
}

ThreadRec *Profiler::thread_rec(int64_t ts) {
  if (G_LIKELY(tls.gen == generation_)) return tls.rec;
  auto r = std::make_unique<ThreadRec>();
  r->tid = static_cast<pid_t>(syscall(SYS_gettid));
  char name[32] = {0};
  pthread_getname_np(pthread_self(), name, sizeof name);
  r->name = name;
  r->first_ns = ts;
  r->last_ns = ts;
  int64_t cpu = thread_cpu_ns();
  r->cpu_first = cpu;
  r->cpu_last = cpu;
  r->cpu_sampled_at = ts;
  ThreadRec *raw = r.get();
  {
    std::lock_guard<std::mutex> lk(mu_);
    threads_.push_back(std::move(r));
  }
  if (ts_offset_.load(std::memory_order_relaxed) == INT64_MIN)
    ts_offset_.store(static_cast<int64_t>(gst_util_get_timestamp()) - ts);
  tls = Tls{generation_, raw};
  return raw;
}

void Profiler::sample_cpu(ThreadRec *t, int64_t ts) {
  if (ts - t->cpu_sampled_at.load(std::memory_order_relaxed) <
      static_cast<int64_t>(params_.cpu_ms) * 1000000)
    return;
  t->cpu_last.store(thread_cpu_ns(), std::memory_order_relaxed);
  t->cpu_sampled_at.store(ts, std::memory_order_relaxed);
}

void Profiler::refresh_locked(ElementRec *r, GstElement *e) {
  r->name = object_name(e);
  if (GstElementFactory *f = gst_element_get_factory(e))
    r->factory = gst_plugin_feature_get_name(GST_PLUGIN_FEATURE(f));
  else
    r->factory = G_OBJECT_TYPE_NAME(e);
  GstObject *top = GST_OBJECT(gst_object_ref(e));
  while (GstObject *up = gst_object_get_parent(top)) {
    gst_object_unref(top);
    top = up;
  }
  r->pipeline = top == GST_OBJECT_CAST(e) ? "" : object_name(top);
  gst_object_unref(top);
  r->is_queue =
      g_object_class_find_property(G_OBJECT_GET_CLASS(e), "current-level-buffers") != nullptr;
  GST_OBJECT_LOCK(e);
  const guint16 nsink = e->numsinkpads, nsrc = e->numsrcpads;
  GST_OBJECT_UNLOCK(e);
  if (GST_IS_BIN(e))
    r->kind = "bin";
  else if (r->is_queue)
    r->kind = "queue";
  else if (nsink == 0 && nsrc > 0)
    r->kind = "source";
  else if (nsrc == 0 && nsink > 0)
    r->kind = "sink";
  else
    r->kind = "filter";
}

ElementRec *Profiler::element_rec_locked(GstElement *e) {
  auto *r = static_cast<ElementRec *>(g_object_get_qdata(G_OBJECT(e), q_elem_));
  if (r) return r;
  auto rec = std::make_unique<ElementRec>();
  g_weak_ref_init(&rec->weak, e);
  refresh_locked(rec.get(), e);
  r = rec.get();
  elements_.push_back(std::move(rec));
  g_object_set_qdata(G_OBJECT(e), q_elem_, r);
  return r;
}

ElementRec *Profiler::element_rec(GstElement *e) {
  auto *r = static_cast<ElementRec *>(g_object_get_qdata(G_OBJECT(e), q_elem_));
  if (G_LIKELY(r)) return r;
  std::lock_guard<std::mutex> lk(mu_);
  return element_rec_locked(e);
}

LinkRec *Profiler::link_rec(GstPad *pad, bool pull) {
  auto *l = static_cast<LinkRec *>(g_object_get_qdata(G_OBJECT(pad), q_link_));
  if (G_LIKELY(l)) return l;
  std::lock_guard<std::mutex> lk(mu_);
  l = static_cast<LinkRec *>(g_object_get_qdata(G_OBJECT(pad), q_link_));
  if (l) return l;
  auto rec = std::make_unique<LinkRec>();
  rec->pull = pull;
  GstElement *owner = pad_element(pad);
  if (owner) {
    rec->from = element_rec_locked(owner);
  } else {
    // A pad without an element (e.g. a GstHarness pad): a record of its own.
    auto orphan = std::make_unique<ElementRec>();
    g_weak_ref_init(&orphan->weak, nullptr);
    orphan->name = "(pad " + object_name(pad) + ")";
    orphan->kind = GST_PAD_IS_SRC(pad) ? "source" : "sink";
    rec->from = orphan.get();
    elements_.push_back(std::move(orphan));
  }
  rec->from_pad = pad_label(pad);
  if (!pull && owner) {
    GST_OBJECT_LOCK(owner);
    const bool is_source = owner->numsinkpads == 0;
    GST_OBJECT_UNLOCK(owner);
    int n = n_sources_.load(std::memory_order_relaxed);
    if (is_source && n < kMaxSources) {
      sources_[static_cast<std::size_t>(n)] = std::make_unique<SourceRec>();
      sources_[static_cast<std::size_t>(n)]->element = rec->from;
      rec->source_idx = n;
      n_sources_.store(n + 1, std::memory_order_release);
    }
  }
  l = rec.get();
  links_.push_back(std::move(rec));
  g_object_set_qdata(G_OBJECT(pad), q_link_, l);
  return l;
}

void Profiler::resolve_peer(LinkRec *l, GstPad *, GstPad *peer) {
  std::lock_guard<std::mutex> lk(mu_);
  ElementRec *to = nullptr;
  if (peer) {
    if (GstElement *pe = pad_element(peer)) to = element_rec_locked(pe);
    l->to_pad = pad_label(peer);
  } else {
    l->to_pad.clear();
  }
  l->to.store(to, std::memory_order_relaxed);
  l->peer.store(peer, std::memory_order_relaxed);
}

void Profiler::note_latency(LinkRec *l, GstBuffer *buf, int64_t ts) {
  const uint64_t pts = GST_BUFFER_PTS(buf);
  if (pts == GST_CLOCK_TIME_NONE) return;
  const std::size_t slot = pts_hash(pts) & (kPtsSlots - 1);
  if (l->source_idx >= 0) {
    auto &s = sources_[static_cast<std::size_t>(l->source_idx)]->slots[slot];
    s.pts.store(GST_CLOCK_TIME_NONE, std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_release);
    s.ts.store(ts, std::memory_order_relaxed);
    s.pts.store(pts, std::memory_order_release);
    return;
  }
  const int n = n_sources_.load(std::memory_order_acquire);
  int64_t best = -1;
  for (int i = 0; i < n; ++i) {
    auto &s = sources_[static_cast<std::size_t>(i)]->slots[slot];
    if (s.pts.load(std::memory_order_acquire) != pts) continue;
    const int64_t st = s.ts.load(std::memory_order_relaxed);
    std::atomic_thread_fence(std::memory_order_acquire);
    if (s.pts.load(std::memory_order_relaxed) != pts || st > ts) continue;
    const int64_t lat = ts - st;
    acc_add(l->by_source[static_cast<std::size_t>(i)], lat);
    if (lat > best) best = lat;
  }
  if (best >= 0) {
    acc_add(l->lat, best);
    l->lat_hist.add(best);
  }
}

void Profiler::begin_span(ThreadRec *t, GstPad *pad, LinkRec *l, int64_t ts) {
  if (t->depth >= kStackDepth) return;  // deeper pushes are left in their parent's own time
  t->stack[static_cast<std::size_t>(t->depth++)] = ThreadRec::Frame{pad, l, ts, 0};
}

// Closes the innermost frame when it belongs to `pad` (a hook seen without its pre hook, e.g.
// when the tracer started mid-push, is ignored).
bool Profiler::end_span(ThreadRec *t, GstPad *pad, int64_t ts, LinkRec **l, int64_t *dur,
                        int64_t *excl) {
  if (t->depth == 0 || t->stack[static_cast<std::size_t>(t->depth - 1)].pad != pad) return false;
  const ThreadRec::Frame f = t->stack[static_cast<std::size_t>(--t->depth)];
  *l = f.link;
  *dur = ts - f.start;
  *excl = *dur - f.child;
  if (*excl < 0) *excl = 0;
  if (t->depth > 0) t->stack[static_cast<std::size_t>(t->depth - 1)].child += *dur;
  return true;
}

void Profiler::push_pre(int64_t ts, GstPad *pad, GstBuffer *buf, guint nbuf, uint64_t bytes) {
  ThreadRec *t = thread_rec(ts);
  LinkRec *l = link_rec(pad, false);
  GstPad *peer = GST_PAD_PEER(pad);
  if (G_UNLIKELY(peer != l->peer.load(std::memory_order_relaxed))) resolve_peer(l, pad, peer);
  l->buffers.fetch_add(nbuf, std::memory_order_relaxed);
  l->bytes.fetch_add(bytes, std::memory_order_relaxed);
  set_first(l->first_ns, ts);
  l->last_ns.store(ts, std::memory_order_relaxed);
  if (buf) note_latency(l, buf, ts);
  if (t->depth == 0) {
    ElementRec *from = l->from;
    if (t->last_root == from && t->last_root_post >= 0) {
      from->gaps.fetch_add(1, std::memory_order_relaxed);
      from->gap_ns.fetch_add(ts - t->last_root_post - t->gap_pull, std::memory_order_relaxed);
    }
    t->gap_pull = 0;
    if (t->root.load(std::memory_order_relaxed) != from)
      t->root.store(from, std::memory_order_relaxed);
    if (!from->boundary.load(std::memory_order_relaxed))
      from->boundary.store(true, std::memory_order_relaxed);
  }
  begin_span(t, pad, l, ts);
  t->pushes.store(t->pushes.load(std::memory_order_relaxed) + 1, std::memory_order_relaxed);
  t->last_ns.store(ts, std::memory_order_relaxed);
  sample_cpu(t, ts);
}

void Profiler::push_post(int64_t ts, GstPad *pad) {
  ThreadRec *t = thread_rec(ts);
  LinkRec *l = nullptr;
  int64_t dur = 0, excl = 0;
  if (!end_span(t, pad, ts, &l, &dur, &excl)) return;
  if (ElementRec *to = l->to.load(std::memory_order_relaxed)) {
    to->spans.fetch_add(1, std::memory_order_relaxed);
    to->self_ns.fetch_add(excl, std::memory_order_relaxed);
    atomic_max(to->self_max, excl);
    to->self_hist.add(excl);
    set_first(to->first_ns, ts - dur);
    to->last_ns.store(ts, std::memory_order_relaxed);
  }
  if (t->depth == 0) {
    t->last_root_post = ts;
    t->last_root = l->from;
    t->gap_pull = 0;
  }
  t->last_ns.store(ts, std::memory_order_relaxed);
}

void Profiler::pull_pre(int64_t ts, GstPad *pad) {
  ThreadRec *t = thread_rec(ts);
  LinkRec *l = link_rec(pad, true);
  GstPad *peer = GST_PAD_PEER(pad);
  if (G_UNLIKELY(peer != l->peer.load(std::memory_order_relaxed))) resolve_peer(l, pad, peer);
  begin_span(t, pad, l, ts);
  t->last_ns.store(ts, std::memory_order_relaxed);
}

void Profiler::pull_post(int64_t ts, GstPad *pad, GstBuffer *buf) {
  ThreadRec *t = thread_rec(ts);
  LinkRec *l = nullptr;
  int64_t dur = 0, excl = 0;
  if (!end_span(t, pad, ts, &l, &dur, &excl)) return;
  if (buf) {
    l->buffers.fetch_add(1, std::memory_order_relaxed);
    l->bytes.fetch_add(gst_buffer_get_size(buf), std::memory_order_relaxed);
    set_first(l->first_ns, ts - dur);
    l->last_ns.store(ts, std::memory_order_relaxed);
  }
  if (ElementRec *up = l->to.load(std::memory_order_relaxed)) {
    up->pulls.fetch_add(1, std::memory_order_relaxed);
    up->pull_ns.fetch_add(excl, std::memory_order_relaxed);
    up->self_hist.add(excl);
    set_first(up->first_ns, ts - dur);
    up->last_ns.store(ts, std::memory_order_relaxed);
  }
  // A root-level pull (a demuxer's loop pulling) is not part of the puller's gap.
  if (t->depth == 0) t->gap_pull += dur;
  t->last_ns.store(ts, std::memory_order_relaxed);
}

void Profiler::element_new(GstElement *e) {
  element_rec(e);
}

void Profiler::state_change_pre(GstElement *e, GstStateChange t) {
  if (t == GST_STATE_CHANGE_NULL_TO_READY && GST_OBJECT_PARENT(e) == nullptr) start_sampler();
  if (t == GST_STATE_CHANGE_READY_TO_PAUSED) {
    ElementRec *r = element_rec(e);
    std::lock_guard<std::mutex> lk(mu_);
    refresh_locked(r, e);
  }
}

void Profiler::state_change_post(GstElement *e, GstStateChange t) {
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY && GST_OBJECT_PARENT(e) == nullptr) write_file("stop");
}

void Profiler::invoke(GstElement *e, int64_t dur_ns) {
  ElementRec *r = element_rec(e);
  r->invokes.fetch_add(1, std::memory_order_relaxed);
  r->invoke_ns.fetch_add(dur_ns, std::memory_order_relaxed);
  atomic_max(r->invoke_max, dur_ns);
  r->invoke_hist.add(dur_ns);
}

void Profiler::start_sampler() {
  if (sampler_started_.exchange(true)) return;
  sampler_ = std::thread([this] { sampler_loop(); });
}

void Profiler::sampler_loop() {
  auto next_write = std::chrono::steady_clock::now();
  std::unique_lock<std::mutex> lk(smu_);
  while (!stop_) {
    scv_.wait_for(lk, std::chrono::milliseconds(params_.sample_ms));
    if (stop_) break;
    lk.unlock();
    sample_queues();
    auto now = std::chrono::steady_clock::now();
    if (params_.interval_ms > 0 && now >= next_write) {
      write_file("interval");
      next_write = now + std::chrono::milliseconds(params_.interval_ms);
    }
    lk.lock();
  }
}

void Profiler::sample_queues() {
  std::vector<std::pair<ElementRec *, GstElement *>> queues;
  {
    std::lock_guard<std::mutex> lk(mu_);
    for (auto &r : elements_)
      if (r->is_queue)
        if (auto *e = static_cast<GstElement *>(g_weak_ref_get(&r->weak)))
          queues.emplace_back(r.get(), e);
  }
  for (auto &[r, e] : queues) {
    guint buffers = 0, bytes = 0, cap_buffers = 0, cap_bytes = 0;
    guint64 time = 0, cap_time = 0;
    g_object_get(e, "current-level-buffers", &buffers, "current-level-bytes", &bytes,
                 "current-level-time", &time, "max-size-buffers", &cap_buffers, "max-size-bytes",
                 &cap_bytes, "max-size-time", &cap_time, nullptr);
    gst_object_unref(e);
    std::lock_guard<std::mutex> lk(mu_);
    r->q_samples++;
    r->q_sum_buffers += buffers;
    r->q_max_buffers = std::max<uint64_t>(r->q_max_buffers, buffers);
    r->q_sum_bytes += bytes;
    r->q_max_bytes = std::max<uint64_t>(r->q_max_bytes, bytes);
    r->q_sum_time += time;
    r->q_max_time = std::max<uint64_t>(r->q_max_time, time);
    r->q_cap_buffers = cap_buffers;
    r->q_cap_bytes = cap_bytes;
    r->q_cap_time = cap_time;
    if ((cap_buffers && buffers >= cap_buffers) || (cap_bytes && bytes >= cap_bytes) ||
        (cap_time && time >= cap_time))
      r->q_full++;
  }
}

bool Profiler::write_file(const char *reason) {
  std::string text = snapshot_json(reason);
  std::lock_guard<std::mutex> lk(file_mu_);
  const std::string tmp = params_.file + ".tmp";
  FILE *f = std::fopen(tmp.c_str(), "w");
  if (!f) return false;
  bool ok = std::fwrite(text.data(), 1, text.size(), f) == text.size();
  ok = std::fputc('\n', f) != EOF && ok;
  ok = std::fclose(f) == 0 && ok;
  return ok && std::rename(tmp.c_str(), params_.file.c_str()) == 0;
}

}  // namespace nns::profile

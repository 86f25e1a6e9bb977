// SPDX-License-Identifier: LGPL-2.1-only
// The state of the nnsprofile tracer (tracer.cc is its GObject shell). The tracer hooks run in
// the streaming threads: per buffer they touch only atomics and the calling thread's own span
// stack (no lock, no allocation). Records are created once per element, pad, thread and source,
// under a mutex, and live as long as the profiler. A sampler thread reads queue levels and
// thread CPU times and rewrites the output file (docs/profiler.md).
#pragma once

#include <gst/gst.h>
#include <sys/types.h>

#include <array>
#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <memory>
#include <mutex>
#include <string>
#include <thread>

#include "profile/hist.h"

namespace nns::profile {

constexpr int kMaxSources = 8;           // sources whose PTS are tracked for latency
constexpr int kStackDepth = 48;          // nested pushes followed per thread
constexpr std::size_t kPtsSlots = 1024;  // per source, power of two

struct ElementRec {
  GWeakRef weak;  // the element, while it lives
  // Descriptive fields: written under Profiler::mu_ (creation, refresh), read under it.
  std::string name, factory, pipeline, kind;
  bool is_queue = false;              // has current-level-buffers (queue, queue2)
  std::atomic<bool> boundary{false};  // pushes from its src pad start a thread's stack
  // Chain spans: time inside this element's chain function minus its own downstream pushes.
  std::atomic<uint64_t> spans{0};
  std::atomic<int64_t> self_ns{0}, self_max{0};
  Hist self_hist;
  // Root gaps: time in a streaming thread between two pushes this element starts (sources:
  // producing the next buffer, or waiting for the clock; queues: waiting for data).
  std::atomic<uint64_t> gaps{0};
  std::atomic<int64_t> gap_ns{0};
  // Pull spans: time inside this element's getrange (pull mode).
  std::atomic<uint64_t> pulls{0};
  std::atomic<int64_t> pull_ns{0};
  // tensor_filter invokes (nns::profile::note_invoke).
  std::atomic<uint64_t> invokes{0};
  std::atomic<int64_t> invoke_ns{0}, invoke_max{0};
  Hist invoke_hist;
  std::atomic<int64_t> first_ns{-1}, last_ns{-1};
  // Queue levels (sampler thread; read under Profiler::mu_).
  uint64_t q_samples = 0, q_full = 0;
  uint64_t q_sum_buffers = 0, q_max_buffers = 0, q_sum_bytes = 0, q_max_bytes = 0;
  uint64_t q_sum_time = 0, q_max_time = 0;
  uint64_t q_cap_buffers = 0, q_cap_bytes = 0, q_cap_time = 0;
};

struct SourceRec {
  struct Slot {
    std::atomic<uint64_t> pts{GST_CLOCK_TIME_NONE};
    std::atomic<int64_t> ts{0};
  };
  ElementRec *element = nullptr;
  std::array<Slot, kPtsSlots> slots;
};

struct LatencyAcc {
  std::atomic<uint64_t> count{0};
  std::atomic<int64_t> sum{0}, max{0}, min{INT64_MAX};
};

// One per source pad that pushes (or sink pad that pulls): the link to its peer.
struct LinkRec {
  ElementRec *from = nullptr;
  std::string from_pad;  // "element:pad", refreshed under mu_
  int source_idx = -1;   // >= 0: `from` is a source (no sink pads), its PTS table
  // The peer, re-resolved when GST_PAD_PEER changes (under mu_).
  std::atomic<GstPad *> peer{nullptr};
  std::atomic<ElementRec *> to{nullptr};
  std::string to_pad;
  bool pull = false;  // a pull link: `from` pulls from `to`
  std::atomic<uint64_t> buffers{0}, bytes{0};
  std::atomic<int64_t> first_ns{-1}, last_ns{-1};
  // Latency from the source push of a buffer with the same PTS, per source; `lat` is the one
  // from the earliest matching source push.
  std::array<LatencyAcc, kMaxSources> by_source;
  LatencyAcc lat;
  Hist lat_hist;
};

struct ThreadRec {
  struct Frame {
    GstPad *pad;
    LinkRec *link;
    int64_t start;
    int64_t child;
  };
  pid_t tid = 0;
  std::string name;
  std::atomic<ElementRec *> root{nullptr};  // element whose pushes start this thread's stacks
  std::atomic<int64_t> first_ns{-1}, last_ns{-1};
  std::atomic<int64_t> cpu_first{-1}, cpu_last{-1};  // CLOCK_THREAD_CPUTIME_ID samples
  std::atomic<int64_t> cpu_sampled_at{0};
  std::atomic<uint64_t> pushes{0};
  // Owned by the thread itself.
  std::array<Frame, kStackDepth> stack{};
  int depth = 0;
  int64_t last_root_post = -1;
  int64_t gap_pull = 0;  // root-level pull time since the last root push returned
  ElementRec *last_root = nullptr;
};

struct Params {
  std::string file;        // output JSON, rewritten every `interval_ms` and at stops
  int interval_ms = 1000;  // 0: only at stops and at exit
  int sample_ms = 10;      // queue level sampling period
  int cpu_ms = 20;         // thread CPU clock read at most this often per thread
};

// Parses "file=x,interval=500,sample=5,cpu=20"; throws std::invalid_argument naming the field.
Params parse_params(const char *text);

class Profiler {
 public:
  explicit Profiler(Params p);
  ~Profiler();
  Profiler(const Profiler &) = delete;
  Profiler &operator=(const Profiler &) = delete;

  // Hooks (ts: GStreamer's tracer timestamp, ns since gst_init).
  void push_pre(int64_t ts, GstPad *pad, GstBuffer *buf, guint nbuf, uint64_t bytes);
  void push_post(int64_t ts, GstPad *pad);
  void pull_pre(int64_t ts, GstPad *pad);
  void pull_post(int64_t ts, GstPad *pad, GstBuffer *buf);
  void element_new(GstElement *e);
  void state_change_pre(GstElement *e, GstStateChange t);
  void state_change_post(GstElement *e, GstStateChange t);
  void invoke(GstElement *e, int64_t dur_ns);

  // Every figure as one JSON object (docs/profiler.md, "Tracer output").
  std::string snapshot_json(const char *reason);
  // Rewrites the output file (atomically: temporary file + rename). False on I/O errors.
  bool write_file(const char *reason);
  const Params &params() const { return params_; }

 private:
  ElementRec *element_rec(GstElement *e);  // finds or creates (never nullptr)
  ElementRec *element_rec_locked(GstElement *e);
  LinkRec *link_rec(GstPad *pad, bool pull);
  void resolve_peer(LinkRec *l, GstPad *pad, GstPad *peer);
  ThreadRec *thread_rec(int64_t ts);
  void refresh_locked(ElementRec *r, GstElement *e);
  void sample_cpu(ThreadRec *t, int64_t ts);
  void note_latency(LinkRec *l, GstBuffer *buf, int64_t ts);
  void begin_span(ThreadRec *t, GstPad *pad, LinkRec *l, int64_t ts);
  bool end_span(ThreadRec *t, GstPad *pad, int64_t ts, LinkRec **l, int64_t *dur, int64_t *excl);
  void start_sampler();
  void sampler_loop();
  void sample_queues();
  int64_t now_ts() const;

  Params params_;
  uint64_t generation_;
  GQuark q_elem_, q_link_;
  std::mutex mu_;  // record creation, descriptive strings, queue figures
  std::deque<std::unique_ptr<ElementRec>> elements_;
  std::deque<std::unique_ptr<LinkRec>> links_;
  std::deque<std::unique_ptr<ThreadRec>> threads_;
  std::array<std::unique_ptr<SourceRec>, kMaxSources> sources_;
  std::atomic<int> n_sources_{0};
  std::atomic<int64_t> ts_offset_{INT64_MIN};  // gst_util_get_timestamp() - hook ts
  std::mutex file_mu_;
  uint64_t seq_ = 0;
  // Sampler thread.
  std::mutex smu_;
  std::condition_variable scv_;
  bool stop_ = false;
  std::thread sampler_;
  std::atomic<bool> sampler_started_{false};
};

// The active profiler of the process (at most one), or nullptr.
Profiler *active_profiler();
void set_active_profiler(Profiler *p);

}  // namespace nns::profile

// SPDX-License-Identifier: LGPL-2.1-only
// GstTensorSync, the base of tensor_mux and tensor_merge.
//
// How data moves. Every sink pad has a queue (tensor_sync_queue.h) of the buffers and
// serialized events that arrived on it. The streaming thread that brings a buffer queues it
// and then tries to become the element's combiner: while every pad has a buffer (or has
// reached EOS) the combiner runs the sync policy, builds one output and pushes it downstream,
// in that same thread; when a set is incomplete it returns to its upstream. Only one thread
// combines at a time (`combining`); a thread that finds another one combining just leaves its
// buffer, which the combiner sees before it stops. This is CollectPads' model, which
// NNStreamer's tensor_mux uses, with queues deeper than one buffer: a producer sleeps only
// when its own queue is full, and is woken only then. There is no extra thread, and no
// wake-up or system call per buffer (GstAggregator, used before, cost 5.7 futex calls per
// input buffer and a thread hand-off for every buffer: docs/benchmarks/streams.md).
//
// refresh builds an output for every arriving buffer (once each pad has had one), in arrival
// order over all pads; the other modes wait until every pad has a buffer or is EOS, exactly
// the condition of upstream's CollectPads.
//
// Locking: `mu` guards the pad list, every pad's SyncPadState and the shared run state. The
// combiner drops it while it negotiates, combines and pushes; what it uses then (the chosen
// buffers, the negotiated config, the subclass's state) belongs to the combiner alone.
#include "gst/tensor_sync.h"

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <mutex>
#include <optional>

#include "core/error.h"
#include "core/time_sync.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_sync_queue.h"

GST_DEBUG_CATEGORY_STATIC(tensor_sync_debug);
#define GST_CAT_DEFAULT tensor_sync_debug

using nns::gst::SyncPadState;
using nns::gst::SyncQueue;
using Lock = std::unique_lock<std::mutex>;

namespace {

struct SyncPriv {
  // Settings (properties), under `settings_lock`.
  std::mutex settings_lock;
  std::string mode_name;  // empty: the subclass's default
  std::string option;
  bool option_set = false;
  std::atomic<bool> silent{true};

  GstPad *src = nullptr;

  // Run state, under `mu`.
  std::mutex mu;
  std::vector<GstTensorSyncPad *> pads;  // request order, each with a reference
  guint next_serial = 0;
  bool combining = false;
  GstFlowReturn srcresult = GST_FLOW_FLUSHING;  // what producers get back; OK while running
  uint64_t epoch = 0;          // bumped by flushes: a push result from before is stale
  bool flushing_down = false;  // FLUSH_START went downstream, FLUSH_STOP not yet
  uint64_t seq = 0;            // arrival counter (refresh order)
  nns::TimeSync sync;
  bool refresh = false;
  uint64_t caps_gen = 1;  // bumped by CAPS events at a queue head and by pad changes
  bool segment_pending = true;
  bool eos_sent = false;
  GstBuffer *time_src = nullptr;  // the buffer whose metadata goes on the next output

  // Combiner-only state (used by the thread that holds `combining`, also outside `mu`).
  uint64_t negotiated_gen = 0;
  bool stream_started = false;
  nns::TensorsConfig out_config;
  std::vector<GstBuffer *> out_bufs;
  std::vector<GstEvent *> forward;  // serialized events to pass downstream
  std::vector<nns::TensorsConfig> neg_configs;
  std::vector<std::string> neg_names;
};

struct GstTensorSyncPrivate {
  SyncPriv *p;
};

// Buffers and events to release once `mu` is dropped (freeing may call into pools and other
// elements). Lives on the stack of the thread that collects them.
class Garbage {
 public:
  Garbage() = default;
  Garbage(const Garbage &) = delete;
  Garbage &operator=(const Garbage &) = delete;
  ~Garbage() { release(); }
  void add(GstMiniObject *o) {
    if (!o) return;
    if (n_ < kInline)
      inline_[n_++] = o;
    else
      more_.push_back(o);
  }
  void add(GstBuffer *b) { add(GST_MINI_OBJECT_CAST(b)); }
  void release() {
    for (std::size_t i = 0; i < n_; ++i) gst_mini_object_unref(inline_[i]);
    n_ = 0;
    for (auto *o : more_) gst_mini_object_unref(o);
    more_.clear();
  }

 private:
  static constexpr std::size_t kInline = 16;
  GstMiniObject *inline_[kInline];
  std::size_t n_ = 0;
  std::vector<GstMiniObject *> more_;
};

}  // namespace

struct _GstTensorSyncPad {
  GstPad parent;
  SyncPadState *st;
};

G_DEFINE_TYPE(GstTensorSyncPad, gst_tensor_sync_pad, GST_TYPE_PAD)
G_DEFINE_ABSTRACT_TYPE_WITH_PRIVATE(GstTensorSync, gst_tensor_sync, GST_TYPE_ELEMENT)

static SyncPriv *priv_of(GstTensorSync *self) {
  return static_cast<GstTensorSyncPrivate *>(gst_tensor_sync_get_instance_private(self))->p;
}

static void gst_tensor_sync_pad_finalize(GObject *object) {
  auto *sp = GST_TENSOR_SYNC_PAD(object);
  SyncPadState *st = sp->st;
  while (!st->queue.empty()) gst_mini_object_unref(st->queue.pop().obj);
  if (st->last) gst_buffer_unref(st->last);
  delete st;
  G_OBJECT_CLASS(gst_tensor_sync_pad_parent_class)->finalize(object);
}

static void gst_tensor_sync_pad_class_init(GstTensorSyncPadClass *klass) {
  G_OBJECT_CLASS(klass)->finalize = gst_tensor_sync_pad_finalize;
}

static void gst_tensor_sync_pad_init(GstTensorSyncPad *sp) {
  sp->st = new SyncPadState();
  gst_segment_init(&sp->st->segment, GST_FORMAT_TIME);
}

namespace {

SyncPadState &state(GstTensorSyncPad *pad) {
  return *pad->st;
}

// Empties a pad's queue and forgets its chosen buffer (under `mu`).
void clear_pad(SyncPadState &s, Garbage &g) {
  while (!s.queue.empty()) g.add(s.queue.pop().obj);
  s.buffers = 0;
  s.bytes = 0;
  g.add(s.last);
  s.last = nullptr;
  s.eos_in = false;
  s.eos = false;
  s.has_segment = false;
  gst_segment_init(&s.segment, GST_FORMAT_TIME);
}

// ---------------------------------------------------------------------------------------
// The policy's view of the pads (under `mu`)

GstBuffer *head_buffer(SyncPadState &s) {
  if (s.queue.empty()) return nullptr;
  GstMiniObject *o = s.queue.front().obj;
  return GST_IS_BUFFER(o) ? GST_BUFFER_CAST(o) : nullptr;
}

class QueueInputs final : public nns::SyncInputs {
 public:
  // only: refresh, the one pad whose head the policy may see (the earliest arrival).
  QueueInputs(SyncPriv *p, std::optional<std::size_t> only, Garbage &g)
      : p_(p), only_(only), g_(g) {}

  std::size_t count() const override { return p_->pads.size(); }
  std::optional<uint64_t> head_pts(std::size_t i) override {
    GstBuffer *b = head(i);
    if (!b) return std::nullopt;
    return GST_BUFFER_PTS(b);
  }
  std::optional<uint64_t> last_pts(std::size_t i) override {
    GstBuffer *l = state(p_->pads[i]).last;
    if (!l) return std::nullopt;
    return GST_BUFFER_PTS(l);
  }
  void take_head(std::size_t i) override {
    if (!head(i)) return;
    SyncPadState &s = state(p_->pads[i]);
    SyncQueue::Item it = s.queue.pop();
    s.buffers--;
    s.bytes -= it.bytes;
    g_.add(s.last);
    s.last = GST_BUFFER_CAST(it.obj);
    if (s.wake_producer()) s.room.notify_one();
  }
  void set_time_source(std::size_t i) override {
    GstBuffer *b = head(i);
    if (b) gst_buffer_ref(b);
    g_.add(p_->time_src);
    p_->time_src = b;
  }

 private:
  GstBuffer *head(std::size_t i) {
    if (only_ && i != *only_) return nullptr;
    return head_buffer(state(p_->pads[i]));
  }
  SyncPriv *p_;
  std::optional<std::size_t> only_;
  Garbage &g_;
};

// Takes the events at the head of every queue: CAPS, SEGMENT and EOS change the pad's state,
// other serialized events go downstream (collected in p->forward).
void take_events(GstTensorSync *self, SyncPriv *p, Garbage &g) {
  for (GstTensorSyncPad *pad : p->pads) {
    SyncPadState &s = state(pad);
    while (!s.queue.empty() && GST_IS_EVENT(s.queue.front().obj)) {
      auto *ev = GST_EVENT_CAST(s.queue.pop().obj);
      switch (GST_EVENT_TYPE(ev)) {
        case GST_EVENT_CAPS: {
          GstCaps *caps = nullptr;
          gst_event_parse_caps(ev, &caps);
          try {
            s.config = nns::gst::config_from_caps(caps);  // checked when it arrived
            s.configured = s.config.info.valid();
          } catch (const nns::Error &e) {
            GST_WARNING_OBJECT(self, "%s", e.what());
            s.configured = false;
          }
          p->caps_gen++;
          g.add(GST_MINI_OBJECT_CAST(ev));
          break;
        }
        case GST_EVENT_SEGMENT:
          gst_event_copy_segment(ev, &s.segment);
          s.has_segment = true;
          g.add(GST_MINI_OBJECT_CAST(ev));
          break;
        case GST_EVENT_EOS:
          s.eos = true;
          g.add(GST_MINI_OBJECT_CAST(ev));
          break;
        default:
          p->forward.push_back(ev);
      }
    }
  }
}

enum class Decision { kWait, kNeedData, kOutput, kEos, kError };

// One policy step over the queues (under `mu`). On kOutput the chosen buffers are in
// p->out_bufs (with references); on kError `error` says why.
Decision decide(SyncPriv *p, Garbage &g, std::string *error) {
  const std::size_t n = p->pads.size();
  if (n == 0) return Decision::kWait;
  std::optional<std::size_t> only;
  if (p->refresh) {
    uint64_t best = UINT64_MAX;
    bool all_eos = true;
    for (std::size_t i = 0; i < n; ++i) {
      SyncPadState &s = state(p->pads[i]);
      if (head_buffer(s) && s.queue.front().seq < best) {
        best = s.queue.front().seq;
        only = i;
      }
      all_eos = all_eos && s.eos;
    }
    if (!only && !all_eos) return Decision::kWait;
  } else {
    for (GstTensorSyncPad *pad : p->pads) {
      SyncPadState &s = state(pad);
      if (!head_buffer(s) && !s.eos) return Decision::kWait;
    }
    if (p->sync.mode() == nns::SyncMode::kBasePad && p->sync.option().sink_id >= n) {
      *error = "sync-option: base pad sink_" + std::to_string(p->sync.option().sink_id) +
               " does not exist (the element has " + std::to_string(n) + " sink pads)";
      return Decision::kError;
    }
  }
  QueueInputs in(p, only, g);
  switch (p->sync.step(in)) {
    case nns::SyncResult::kNeedData:
      return Decision::kNeedData;
    case nns::SyncResult::kEos:
      return Decision::kEos;
    case nns::SyncResult::kOutput:
      break;
  }
  const bool steal = p->sync.mode() == nns::SyncMode::kNoSync;  // nosync never reuses a buffer
  p->out_bufs.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    SyncPadState &s = state(p->pads[i]);
    p->out_bufs[i] = steal ? s.last : gst_buffer_ref(s.last);
    if (steal) s.last = nullptr;
  }
  return Decision::kOutput;
}

// ---------------------------------------------------------------------------------------
// Output (combiner thread, without `mu`)

void push_stream_start(GstTensorSync *self, SyncPriv *p) {
  if (p->stream_started) return;
  // gst_pad_create_stream_id() is for elements with one sink pad at most.
  nns::gst::GCharPtr id(g_strdup_printf("%s-%08x", GST_ELEMENT_NAME(self), g_random_int()));
  GstEvent *ev = gst_event_new_stream_start(id.get());
  gst_event_set_group_id(ev, gst_util_group_id_next());
  gst_pad_push_event(p->src, ev);
  p->stream_started = true;
}

// Negotiates the src caps for the configs in p->neg_configs.
void negotiate(GstTensorSync *self, SyncPriv *p) {
  for (std::size_t i = 0; i < p->neg_configs.size(); ++i)
    if (!p->neg_configs[i].info.valid())
      nns::fail(nns::ErrorKind::kNegotiation, p->neg_names[i] + " received data without caps");
  if (p->neg_configs.size() > nns::kTensorLimit)
    nns::fail(nns::ErrorKind::kNegotiation, std::to_string(p->neg_configs.size()) +
                                                " sink pads, more than " +
                                                std::to_string(nns::kTensorLimit));
  auto *klass = GST_TENSOR_SYNC_GET_CLASS(self);
  nns::TensorsConfig out = klass->configure(self, p->neg_configs, p->neg_names);
  // The output caps: our config, in the first form (other/tensors, else other/tensor) that
  // downstream accepts.
  nns::gst::CapsPtr want(nns::gst::caps_from_config(out));
  nns::gst::CapsPtr caps;
  if (gst_pad_is_linked(p->src)) {
    caps.reset(gst_pad_peer_query_caps(p->src, want.get()));
    if (!caps || gst_caps_is_empty(caps.get())) {
      nns::gst::CapsPtr allowed(gst_pad_peer_query_caps(p->src, nullptr));
      nns::fail(nns::ErrorKind::kNegotiation, "downstream does not accept the output caps " +
                                                  nns::gst::caps_to_string(want.get()) +
                                                  " (it accepts " +
                                                  nns::gst::caps_to_string(allowed.get()) + ")");
    }
  } else {
    caps.reset(gst_caps_ref(want.get()));
  }
  caps.reset(gst_caps_fixate(caps.release()));
  p->out_config = out;
  push_stream_start(self, p);
  if (!gst_pad_push_event(p->src, gst_event_new_caps(caps.get())) && !GST_PAD_IS_FLUSHING(p->src) &&
      gst_pad_is_linked(p->src))
    nns::fail(nns::ErrorKind::kNegotiation,
              "downstream refused the output caps " + nns::gst::caps_to_string(caps.get()));
  GST_DEBUG_OBJECT(self, "output %s", out.info.to_string().c_str());
}

struct Emit {
  bool negotiate = false;
  std::optional<GstSegment> segment;
  GstBuffer *time_src = nullptr;
  uint64_t pts = 0;
};

GstFlowReturn emit(GstTensorSync *self, SyncPriv *p, Emit &e) {
  const std::size_t n = p->out_bufs.size();
  nns::gst::BufferPtr time_src(e.time_src);
  GstFlowReturn ret = nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    if (e.negotiate) negotiate(self, p);
    if (e.segment) {
      push_stream_start(self, p);
      gst_pad_push_event(p->src, gst_event_new_segment(&*e.segment));
    }
    auto *klass = GST_TENSOR_SYNC_GET_CLASS(self);
    GstBuffer *out = klass->combine(self, p->out_bufs.data(), n);
    if (time_src) gst_buffer_copy_into(out, time_src.get(), GST_BUFFER_COPY_METADATA, 0, -1);
    GST_BUFFER_PTS(out) = e.pts;
    if (!p->silent)
      GST_INFO_OBJECT(self, "output pts %" GST_TIME_FORMAT, GST_TIME_ARGS(GST_BUFFER_PTS(out)));
    GstFlowReturn r = gst_pad_push(p->src, out);
    if (r == GST_FLOW_NOT_NEGOTIATED) {
      nns::gst::CapsPtr caps(gst_pad_get_current_caps(p->src));
      nns::fail(nns::ErrorKind::kNegotiation, "downstream did not accept the output caps " +
                                                  nns::gst::caps_to_string(caps.get()));
    }
    return r;
  });
  for (GstBuffer *b : p->out_bufs)
    if (b) gst_buffer_unref(b);
  p->out_bufs.clear();
  return ret;
}

void push_eos(GstTensorSync *self, SyncPriv *p, std::optional<GstSegment> segment) {
  push_stream_start(self, p);
  if (segment) gst_pad_push_event(p->src, gst_event_new_segment(&*segment));
  gst_pad_push_event(p->src, gst_event_new_eos());
}

// The segment of the first output after a start or flush: the first pad's, so running times
// are those of the inputs (under `mu`).
std::optional<GstSegment> take_pending_segment(SyncPriv *p) {
  if (!p->segment_pending) return std::nullopt;
  p->segment_pending = false;
  GstSegment seg;
  gst_segment_init(&seg, GST_FORMAT_TIME);
  if (!p->pads.empty()) {
    SyncPadState &s = state(p->pads[0]);
    if (s.has_segment && s.segment.format == GST_FORMAT_TIME)
      gst_segment_copy_into(&s.segment, &seg);
  }
  return seg;
}

// Builds and pushes outputs while the queues allow (see the top of the file). Called with
// `lk` held by a thread that just queued something; returns with `lk` released, and the flow
// that thread's upstream should get.
GstFlowReturn drive(GstTensorSync *self, SyncPriv *p, Lock &lk) {
  if (p->combining) {
    GstFlowReturn ret = p->srcresult;
    lk.unlock();
    return ret;
  }
  p->combining = true;
  Garbage g;
  while (p->srcresult == GST_FLOW_OK) {
    take_events(self, p, g);
    if (!p->forward.empty()) {
      std::vector<GstEvent *> events;
      events.swap(p->forward);
      lk.unlock();
      g.release();
      push_stream_start(self, p);
      for (GstEvent *ev : events) gst_pad_push_event(p->src, ev);
      lk.lock();
      continue;
    }
    std::string error;
    Decision d = decide(p, g, &error);
    if (d == Decision::kWait) break;
    if (d == Decision::kNeedData) continue;
    if (d == Decision::kError) {
      p->srcresult = GST_FLOW_ERROR;
      lk.unlock();
      g.release();
      NNS_POST_ERROR(self, nns::ErrorKind::kSettings, error);
      lk.lock();
      break;
    }
    if (d == Decision::kEos) {
      p->srcresult = GST_FLOW_EOS;
      bool send = !p->eos_sent;
      p->eos_sent = true;
      auto segment = take_pending_segment(p);
      lk.unlock();
      g.release();
      if (send) push_eos(self, p, segment);
      lk.lock();
      break;
    }
    Emit e;
    e.pts = p->sync.time();
    e.time_src = p->time_src;
    p->time_src = nullptr;
    e.segment = take_pending_segment(p);
    bool reconfigure = gst_pad_check_reconfigure(p->src);
    if (p->caps_gen != p->negotiated_gen || reconfigure) {
      e.negotiate = true;
      p->negotiated_gen = p->caps_gen;
      p->neg_configs.clear();
      p->neg_names.clear();
      for (GstTensorSyncPad *pad : p->pads) {
        p->neg_configs.push_back(state(pad).configured ? state(pad).config : nns::TensorsConfig{});
        p->neg_names.push_back(GST_PAD_NAME(pad));
      }
    }
    const uint64_t epoch = p->epoch;
    lk.unlock();
    g.release();
    GstFlowReturn r = emit(self, p, e);
    lk.lock();
    if (r != GST_FLOW_OK && epoch == p->epoch && p->srcresult == GST_FLOW_OK) {
      GST_DEBUG_OBJECT(self, "downstream returned %s", gst_flow_get_name(r));
      p->srcresult = r;
      if (e.negotiate) p->negotiated_gen = 0;
    }
  }
  p->combining = false;
  GstFlowReturn ret = p->srcresult;
  lk.unlock();
  return ret;  // `g` is released here, without the lock
}

// ---------------------------------------------------------------------------------------
// Sink pads

GstFlowReturn sink_chain(GstPad *pad, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_SYNC(parent);
  SyncPriv *p = priv_of(self);
  SyncPadState &s = state(GST_TENSOR_SYNC_PAD(pad));
  Lock lk(p->mu);
  for (;;) {
    GstFlowReturn refuse = GST_FLOW_OK;
    if (s.flushing)
      refuse = GST_FLOW_FLUSHING;
    else if (s.eos_in)
      refuse = GST_FLOW_EOS;
    else if (p->srcresult != GST_FLOW_OK)
      refuse = p->srcresult;
    if (refuse != GST_FLOW_OK) {
      lk.unlock();
      gst_buffer_unref(buf);
      return refuse;
    }
    if (s.has_room()) break;
    s.waiters++;
    s.room.wait(lk);
    s.waiters--;
  }
  std::size_t bytes = gst_buffer_get_size(buf);
  s.queue.push({GST_MINI_OBJECT_CAST(buf), ++p->seq, bytes});
  s.buffers++;
  s.bytes += bytes;
  return drive(self, p, lk);
}

GstFlowReturn sink_chain_list(GstPad *pad, GstObject *parent, GstBufferList *list) {
  GstFlowReturn ret = GST_FLOW_OK;
  guint n = gst_buffer_list_length(list);
  for (guint i = 0; i < n && ret == GST_FLOW_OK; ++i)
    ret = sink_chain(pad, parent, gst_buffer_ref(gst_buffer_list_get(list, i)));
  gst_buffer_list_unref(list);
  return ret;
}

void flush_start(GstTensorSync *self, SyncPriv *p, SyncPadState &s, GstEvent *event) {
  Garbage g;
  Lock lk(p->mu);
  s.flushing = true;
  clear_pad(s, g);
  s.room.notify_all();
  bool forward = !p->flushing_down;
  p->flushing_down = true;
  p->epoch++;
  lk.unlock();
  g.release();
  if (forward)
    gst_pad_push_event(p->src, event);
  else
    gst_event_unref(event);
  GST_DEBUG_OBJECT(self, "flush start");
}

void flush_stop(GstTensorSync *self, SyncPriv *p, SyncPadState &s, GstEvent *event) {
  Garbage g;
  Lock lk(p->mu);
  s.flushing = false;
  clear_pad(s, g);
  bool forward = false;
  bool any_flushing = false;
  for (GstTensorSyncPad *pad : p->pads) any_flushing = any_flushing || state(pad).flushing;
  if (p->flushing_down && !any_flushing) {
    forward = true;
    p->flushing_down = false;
    p->epoch++;
    p->srcresult = GST_FLOW_OK;
    p->sync.reset();
    p->segment_pending = true;
    p->eos_sent = false;
    for (GstTensorSyncPad *pad : p->pads) {
      g.add(state(pad).last);
      state(pad).last = nullptr;
    }
    g.add(p->time_src);
    p->time_src = nullptr;
  }
  lk.unlock();
  g.release();
  if (forward)
    gst_pad_push_event(p->src, event);
  else
    gst_event_unref(event);
  GST_DEBUG_OBJECT(self, "flush stop");
}

gboolean sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_SYNC(parent);
  SyncPriv *p = priv_of(self);
  SyncPadState &s = state(GST_TENSOR_SYNC_PAD(pad));
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_FLUSH_START:
      flush_start(self, p, s, event);
      return TRUE;
    case GST_EVENT_FLUSH_STOP:
      flush_stop(self, p, s, event);
      return TRUE;
    case GST_EVENT_STREAM_START:  // the output has its own stream
    case GST_EVENT_GAP:           // nothing to combine
    case GST_EVENT_TAG:           // several inputs' tags would contradict each other
    case GST_EVENT_STREAM_GROUP_DONE:
      gst_event_unref(event);
      return TRUE;
    case GST_EVENT_CAPS: {
      GstCaps *caps = nullptr;
      gst_event_parse_caps(event, &caps);
      std::string name = GST_PAD_NAME(pad);
      gboolean ok = nns::gst::guard(self, FALSE, [&]() -> gboolean {
        nns::TensorsConfig c;
        try {
          c = nns::gst::config_from_caps(caps);
        } catch (const nns::Error &e) {
          nns::fail(e.kind(), name + ": " + e.what());
        }
        if (!c.info.valid())
          nns::fail(
              nns::ErrorKind::kNegotiation,
              name + ": caps do not describe complete tensors: " + nns::gst::caps_to_string(caps));
        return TRUE;
      });
      if (!ok) {
        gst_event_unref(event);
        return FALSE;
      }
      break;
    }
    default:
      if (!GST_EVENT_IS_SERIALIZED(event)) return gst_pad_event_default(pad, parent, event);
  }
  // Serialized: CAPS, SEGMENT, EOS and others take effect when they reach the queue's head.
  Lock lk(p->mu);
  if (s.flushing || s.eos_in) {
    bool flushing = s.flushing;
    lk.unlock();
    gst_event_unref(event);
    return !flushing;
  }
  if (GST_EVENT_TYPE(event) == GST_EVENT_EOS) s.eos_in = true;
  s.queue.push({GST_MINI_OBJECT_CAST(event), ++p->seq, 0});
  drive(self, p, lk);  // an output error is posted by the combiner; the event was taken
  return TRUE;
}

gboolean sink_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  switch (GST_QUERY_TYPE(query)) {
    case GST_QUERY_CAPS: {
      GstCaps *filter = nullptr;
      gst_query_parse_caps(query, &filter);
      nns::gst::CapsPtr templ(gst_pad_get_pad_template_caps(pad));
      nns::gst::CapsPtr caps(
          filter ? gst_caps_intersect_full(filter, templ.get(), GST_CAPS_INTERSECT_FIRST)
                 : gst_caps_ref(templ.get()));
      gst_query_set_caps_result(query, caps.get());
      return TRUE;
    }
    case GST_QUERY_ACCEPT_CAPS: {
      GstCaps *caps = nullptr;
      gst_query_parse_accept_caps(query, &caps);
      nns::gst::CapsPtr templ(gst_pad_get_pad_template_caps(pad));
      gst_query_set_accept_caps_result(query, gst_caps_is_subset(caps, templ.get()));
      return TRUE;
    }
    case GST_QUERY_ALLOCATION:  // inputs are not what goes downstream
      return FALSE;
    default:
      return gst_pad_query_default(pad, parent, query);
  }
}

// ---------------------------------------------------------------------------------------
// Src pad

// Live when any input is live; the minimum latency is the largest of the inputs'.
gboolean src_latency(GstTensorSync *self, GstQuery *query) {
  SyncPriv *p = priv_of(self);
  std::vector<GstPad *> pads;
  {
    Lock lk(p->mu);
    for (GstTensorSyncPad *pad : p->pads) pads.push_back(GST_PAD(gst_object_ref(pad)));
  }
  gboolean live = FALSE;
  GstClockTime min = 0, max = GST_CLOCK_TIME_NONE;
  for (GstPad *pad : pads) {
    GstQuery *q = gst_query_new_latency();
    if (gst_pad_peer_query(pad, q)) {
      gboolean plive = FALSE;
      GstClockTime pmin = 0, pmax = GST_CLOCK_TIME_NONE;
      gst_query_parse_latency(q, &plive, &pmin, &pmax);
      if (plive) {
        live = TRUE;
        min = std::max(min, pmin);
        if (GST_CLOCK_TIME_IS_VALID(pmax))
          max = GST_CLOCK_TIME_IS_VALID(max) ? std::min(max, pmax) : pmax;
      }
    }
    gst_query_unref(q);
    gst_object_unref(pad);
  }
  gst_query_set_latency(query, live, min, max);
  return TRUE;
}

gboolean src_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  switch (GST_QUERY_TYPE(query)) {
    case GST_QUERY_CAPS: {
      GstCaps *filter = nullptr;
      gst_query_parse_caps(query, &filter);
      nns::gst::CapsPtr caps(gst_pad_get_current_caps(pad));
      if (!caps) caps.reset(gst_pad_get_pad_template_caps(pad));
      if (filter) caps.reset(gst_caps_intersect_full(filter, caps.get(), GST_CAPS_INTERSECT_FIRST));
      gst_query_set_caps_result(query, caps.get());
      return TRUE;
    }
    case GST_QUERY_LATENCY:
      return src_latency(GST_TENSOR_SYNC(parent), query);
    default:
      return gst_pad_query_default(pad, parent, query);
  }
}

// ---------------------------------------------------------------------------------------
// Element

// READY -> PAUSED: reads the settings and empties the pads.
gboolean start(GstTensorSync *self) {
  SyncPriv *p = priv_of(self);
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    std::string mode_name, option;
    {
      std::lock_guard<std::mutex> g(p->settings_lock);
      mode_name =
          p->mode_name.empty() ? GST_TENSOR_SYNC_GET_CLASS(self)->default_sync_mode : p->mode_name;
      option = p->option;
    }
    if (auto check = GST_TENSOR_SYNC_GET_CLASS(self)->check_settings) check(self);
    auto mode = nns::sync_mode_from_name(mode_name);
    if (!mode)
      nns::fail(nns::ErrorKind::kSettings,
                "sync-mode='" + mode_name + "' is not one of nosync, slowest, basepad, refresh");
    nns::TimeSync sync(*mode, nns::parse_sync_option(*mode, option));
    Garbage g;
    Lock lk(p->mu);
    p->sync = sync;
    p->sync.reset();
    p->refresh = *mode == nns::SyncMode::kRefresh;
    p->srcresult = GST_FLOW_OK;
    p->flushing_down = false;
    p->epoch++;
    p->caps_gen++;
    p->segment_pending = true;
    p->eos_sent = false;
    p->negotiated_gen = 0;
    p->stream_started = false;
    for (GstTensorSyncPad *pad : p->pads) {
      clear_pad(state(pad), g);
      state(pad).flushing = false;
    }
    lk.unlock();
    return TRUE;
  });
}

// PAUSED -> READY, before the pads are deactivated: wakes producers waiting for room.
void stop_flushing(GstTensorSync *self) {
  SyncPriv *p = priv_of(self);
  Lock lk(p->mu);
  p->srcresult = GST_FLOW_FLUSHING;
  p->epoch++;
  for (GstTensorSyncPad *pad : p->pads) {
    state(pad).flushing = true;
    state(pad).room.notify_all();
  }
}

// PAUSED -> READY, after the pads were deactivated (no streaming thread is inside).
void stopped(GstTensorSync *self) {
  SyncPriv *p = priv_of(self);
  Garbage g;
  Lock lk(p->mu);
  for (GstTensorSyncPad *pad : p->pads) clear_pad(state(pad), g);
  g.add(p->time_src);
  p->time_src = nullptr;
  for (GstEvent *ev : p->forward) g.add(GST_MINI_OBJECT_CAST(ev));
  p->forward.clear();
  lk.unlock();
}

}  // namespace

static GstStateChangeReturn gst_tensor_sync_change_state(GstElement *element,
                                                         GstStateChange transition) {
  auto *self = GST_TENSOR_SYNC(element);
  if (transition == GST_STATE_CHANGE_READY_TO_PAUSED && !start(self))
    return GST_STATE_CHANGE_FAILURE;
  if (transition == GST_STATE_CHANGE_PAUSED_TO_READY) stop_flushing(self);
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_sync_parent_class)->change_state(element, transition);
  if (transition == GST_STATE_CHANGE_PAUSED_TO_READY) stopped(self);
  return ret;
}

static GstPad *gst_tensor_sync_request_new_pad(GstElement *element, GstPadTemplate *templ,
                                               const gchar *req_name, const GstCaps *) {
  if (GST_PAD_TEMPLATE_DIRECTION(templ) != GST_PAD_SINK) return nullptr;
  auto *self = GST_TENSOR_SYNC(element);
  SyncPriv *p = priv_of(self);
  guint serial = 0;
  {
    Lock lk(p->mu);
    serial = p->next_serial;
    guint asked = 0;
    char tail = 0;
    if (req_name && std::sscanf(req_name, "sink_%u%c", &asked, &tail) == 1) serial = asked;
    p->next_serial = std::max(p->next_serial, serial + 1);
  }
  std::string name = "sink_" + std::to_string(serial);
  auto *pad = GST_PAD(g_object_new(GST_TYPE_TENSOR_SYNC_PAD, "name", name.c_str(), "direction",
                                   GST_PAD_SINK, "template", templ, nullptr));
  gst_pad_set_chain_function(pad, sink_chain);
  gst_pad_set_chain_list_function(pad, sink_chain_list);
  gst_pad_set_event_function(pad, sink_event);
  gst_pad_set_query_function(pad, sink_query);
  {
    Lock lk(p->mu);
    p->pads.push_back(GST_TENSOR_SYNC_PAD(gst_object_ref(pad)));
    p->caps_gen++;
  }
  if (!gst_element_add_pad(element, pad)) {  // e.g. the name is taken
    Lock lk(p->mu);
    p->pads.pop_back();
    lk.unlock();
    gst_object_unref(pad);
    return nullptr;
  }
  return pad;
}

static void gst_tensor_sync_release_pad(GstElement *element, GstPad *pad) {
  auto *self = GST_TENSOR_SYNC(element);
  SyncPriv *p = priv_of(self);
  GstTensorSyncPad *found = nullptr;
  bool running = false;
  Garbage g;
  {
    Lock lk(p->mu);
    for (auto it = p->pads.begin(); it != p->pads.end(); ++it)
      if (GST_PAD(*it) == pad) {
        found = *it;
        p->pads.erase(it);
        break;
      }
    if (found) {
      SyncPadState &s = state(found);
      s.flushing = true;
      clear_pad(s, g);
      s.room.notify_all();
      p->caps_gen++;
    }
    running = p->srcresult == GST_FLOW_OK;
  }
  g.release();
  gst_element_remove_pad(element, pad);
  if (found) gst_object_unref(found);
  if (running) {
    // The other pads may now make a complete set.
    Lock lk(p->mu);
    drive(self, p, lk);
  }
}

static void gst_tensor_sync_constructed(GObject *object);

static void gst_tensor_sync_finalize(GObject *object) {
  SyncPriv *p = priv_of(GST_TENSOR_SYNC(object));
  for (GstTensorSyncPad *pad : p->pads) gst_object_unref(pad);
  if (p->time_src) gst_buffer_unref(p->time_src);
  for (GstEvent *ev : p->forward) gst_event_unref(ev);
  delete p;
  G_OBJECT_CLASS(gst_tensor_sync_parent_class)->finalize(object);
}

static void gst_tensor_sync_class_init(GstTensorSyncClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_sync_debug, "tensor_sync", 0, "tensor_mux/merge core");
  G_OBJECT_CLASS(klass)->finalize = gst_tensor_sync_finalize;
  G_OBJECT_CLASS(klass)->constructed = gst_tensor_sync_constructed;
  auto *element_class = GST_ELEMENT_CLASS(klass);
  element_class->change_state = gst_tensor_sync_change_state;
  element_class->request_new_pad = gst_tensor_sync_request_new_pad;
  element_class->release_pad = gst_tensor_sync_release_pad;
  klass->default_sync_mode = "slowest";
}

static void gst_tensor_sync_init(GstTensorSync *self) {
  auto *pp = static_cast<GstTensorSyncPrivate *>(gst_tensor_sync_get_instance_private(self));
  pp->p = new SyncPriv();  // the class default sync-mode applies until the property is set
}

// The src pad comes from the subclass's template, which instance_init cannot see yet.
static void gst_tensor_sync_constructed(GObject *object) {
  G_OBJECT_CLASS(gst_tensor_sync_parent_class)->constructed(object);
  SyncPriv *p = priv_of(GST_TENSOR_SYNC(object));
  GstPadTemplate *templ = gst_element_class_get_pad_template(GST_ELEMENT_GET_CLASS(object), "src");
  p->src = gst_pad_new_from_template(templ, "src");
  gst_pad_set_query_function(p->src, src_query);
  gst_element_add_pad(GST_ELEMENT(object), p->src);
}

// ---------------------------------------------------------------------------------------
// Shared properties

namespace nns::gst {

void sync_install_properties(GObjectClass *klass, guint first_id, const char *default_mode) {
  GST_TENSOR_SYNC_CLASS(klass)->default_sync_mode = default_mode;
  auto flags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  auto ready = static_cast<GParamFlags>(flags | GST_PARAM_MUTABLE_READY);
  g_object_class_install_property(
      klass, first_id,
      g_param_spec_boolean("silent", "Silent", "Do not log each output buffer", TRUE, flags));
  g_object_class_install_property(
      klass, first_id + 1,
      g_param_spec_string("sync-mode", "Sync mode",
                          "How buffers of the sink pads are matched in time: nosync, slowest, "
                          "basepad or refresh",
                          default_mode, ready));
  g_object_class_install_property(
      klass, first_id + 2,
      g_param_spec_string("sync-option", "Sync option",
                          "Option of the sync mode; basepad: <sink_id>:<duration in ns>", nullptr,
                          ready));
}

bool sync_set_property(GstTensorSync *self, guint first_id, guint id, const GValue *value) {
  SyncPriv *p = priv_of(self);
  if (id == first_id) {
    p->silent = g_value_get_boolean(value);
    return true;
  }
  std::lock_guard<std::mutex> g(p->settings_lock);
  const char *s = g_value_get_string(value);
  if (id == first_id + 1) {
    p->mode_name = s ? s : "";
    return true;
  }
  if (id == first_id + 2) {
    p->option = s ? s : "";
    p->option_set = s != nullptr;
    return true;
  }
  return false;
}

bool sync_get_property(GstTensorSync *self, guint first_id, guint id, GValue *value) {
  SyncPriv *p = priv_of(self);
  if (id == first_id) {
    g_value_set_boolean(value, p->silent);
    return true;
  }
  std::lock_guard<std::mutex> g(p->settings_lock);
  if (id == first_id + 1) {
    g_value_set_string(value, p->mode_name.empty()
                                  ? GST_TENSOR_SYNC_GET_CLASS(self)->default_sync_mode
                                  : p->mode_name.c_str());
    return true;
  }
  if (id == first_id + 2) {
    g_value_set_string(value, p->option_set ? p->option.c_str() : nullptr);
    return true;
  }
  return false;
}

const TensorsConfig &sync_output_config(GstTensorSync *self) {
  return priv_of(self)->out_config;
}

void sync_slowest_rate(const std::vector<TensorsConfig> &in, int *rate_n, int *rate_d) {
  int n = -1, d = -1;
  for (const auto &c : in) {
    if (c.rate_n < 0 || c.rate_d <= 0) continue;
    if (n < 0 || static_cast<int64_t>(c.rate_n) * d < static_cast<int64_t>(n) * c.rate_d) {
      n = c.rate_n;
      d = c.rate_d;
    }
  }
  *rate_n = n < 0 ? 0 : n;
  *rate_d = n < 0 ? 1 : d;
}

std::string sync_pad_name(GstTensorSync *self, std::size_t i) {
  SyncPriv *p = priv_of(self);
  // Inside combine the combiner's own list of names is the one that matches the buffers.
  if (i < p->neg_names.size()) return p->neg_names[i];
  return "sink pad " + std::to_string(i);
}

}  // namespace nns::gst

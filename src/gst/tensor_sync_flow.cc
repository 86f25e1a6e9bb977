// SPDX-License-Identifier: LGPL-2.1-only
// The data path of GstTensorSync (tensor_mux / tensor_merge): queueing, the sync policy over
// the queues, building and pushing outputs, the pads' chain, event and query functions.
// How it works and how it is locked: tensor_sync.cc.
#include <algorithm>
#include <optional>

#include "core/error.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_sync_priv.h"

#define GST_CAT_DEFAULT tensor_sync_debug

namespace nns::gst::sync {

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

namespace {

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
  // Several tensors' fields may also be spelled with '.' downstream (upstream's spelling).
  nns::gst::CapsPtr want(nns::gst::caps_from_config(out, gst_pad_is_linked(p->src)));
  nns::gst::CapsPtr caps;
  if (gst_pad_is_linked(p->src)) {
    caps.reset(gst_pad_peer_query_caps(p->src, want.get()));
    if (!caps || gst_caps_is_empty(caps.get())) {
      nns::gst::CapsPtr allowed(gst_pad_peer_query_caps(p->src, nullptr));
      nns::gst::CapsPtr plain(nns::gst::caps_from_config(out));
      nns::fail(nns::ErrorKind::kNegotiation, "downstream does not accept the output caps " +
                                                  nns::gst::caps_to_string(plain.get()) +
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

}  // namespace

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

namespace {

// How many buffers the pad may queue: few when its upstream is live (see SyncPadState).
std::size_t queue_depth(GstPad *pad) {
  GstQuery *q = gst_query_new_latency();
  gboolean live = FALSE;
  if (gst_pad_peer_query(pad, q)) gst_query_parse_latency(q, &live, nullptr, nullptr);
  gst_query_unref(q);
  return live ? SyncPadState::kLiveBuffers : SyncPadState::kMaxBuffers;
}

}  // namespace

GstFlowReturn sink_chain(GstPad *pad, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_SYNC(parent);
  SyncPriv *p = priv_of(self);
  SyncPadState &s = state(GST_TENSOR_SYNC_PAD(pad));
  // Only this pad's streaming thread sets max_buffers (start() resets it while no data flows).
  std::size_t depth = 0;
  if (s.max_buffers == 0) depth = queue_depth(pad);
  Lock lk(p->mu);
  if (depth) s.max_buffers = depth;
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

namespace {

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

}  // namespace

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

namespace {

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

}  // namespace

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

}  // namespace nns::gst::sync

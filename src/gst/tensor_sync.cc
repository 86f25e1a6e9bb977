// SPDX-License-Identifier: LGPL-2.1-only
// GstAggregator core of tensor_mux / tensor_merge.
//
// nosync, slowest and basepad run in aggregate(), which GstAggregator calls when every sink
// pad has a queued buffer or is EOS, exactly the condition under which NNStreamer's
// CollectPads implementation decides. refresh needs an output whenever *any* pad gets a
// buffer, which a non-live GstAggregator never does (it waits for all pads). So in refresh
// mode the sink pads' chain function hands each buffer to the aggregator's streaming thread
// as a serialized query (a DRAIN query tagged with kRefreshField): GstAggregator queues it,
// wakes its thread even though other pads are empty, runs sink_query() there, and blocks the
// upstream thread until it is handled. Every output thus still leaves from the src thread
// and upstream gets back-pressure, without polling or clocks.
#include "gst/tensor_sync.h"

#include <atomic>
#include <memory>
#include <mutex>
#include <optional>

#include "core/error.h"
#include "core/time_sync.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_sync_debug);
#define GST_CAT_DEFAULT tensor_sync_debug

namespace {

constexpr const char *kRefreshField = "nns-tensor-sync-refresh";

// The sink pads at one moment, each with a reference. Shared by the PadInputs that use it, so
// per output there is one atomic increment instead of a GObject ref/unref per pad; rebuilt when
// the element's pads change (GstElement::pads_cookie).
class PadList {
 public:
  explicit PadList(GstElement *e) {
    for (GList *l = e->sinkpads; l; l = l->next)
      pads.push_back(static_cast<GstPad *>(gst_object_ref(l->data)));
  }
  ~PadList() {
    for (auto *p : pads) gst_object_unref(p);
  }
  PadList(const PadList &) = delete;
  PadList &operator=(const PadList &) = delete;
  std::vector<GstPad *> pads;
};

struct SyncPriv {
  // Settings (properties), under `lock`.
  std::mutex lock;
  std::string mode_name;  // empty: the subclass's default
  std::string option;
  bool option_set = false;
  std::atomic<bool> silent{true};
  // State, on the aggregator's streaming thread unless noted.
  nns::TimeSync sync;
  std::atomic<bool> refresh{false};   // read by the sink pads' chain function
  std::atomic<uint64_t> caps_gen{1};  // bumped by every caps event
  uint64_t negotiated_gen = 0;
  std::size_t negotiated_pads = 0;
  nns::TensorsConfig out_config;
  GstBuffer *time_src = nullptr;  // the buffer whose metadata goes on the output
  bool segment_sent = false;
  bool queue_checked = false;  // deeper input queues considered (see deepen_queues)
  bool queue_auto = false;     // we set GstAggregator:latency ourselves
  // Sink pads as of pads_cookie (under the object lock).
  std::shared_ptr<const PadList> pad_list;
  guint32 pads_cookie = 0;
};

// GstAggregator lets each sink pad queue as much as its `latency` (time) allows; with the
// default 0 every pad holds one buffer, so each input buffer costs a thread hand-off both
// ways (measured ~10 us per buffer). When nothing upstream is live and the buffers carry
// timestamps (the queue is bounded by time), the pads may queue up to this much. Outputs are
// the same (non-live aggregation still waits for every pad); live pipelines keep latency 0.
constexpr GstClockTime kAutoQueueTime = 100 * GST_MSECOND;

struct GstTensorSyncPrivate {
  SyncPriv *p;
};

}  // namespace

struct _GstTensorSyncPad {
  GstAggregatorPad parent;
  GstBuffer *last;     // chosen for the next output
  GstBuffer *pending;  // refresh: handed over by the chain function (under the object lock)
  nns::TensorsConfig *config;
  gboolean configured;
  GstFlowReturn refresh_ret;
  GstPadChainFunction agg_chain;  // GstAggregatorPad's chain function
};

G_DEFINE_TYPE(GstTensorSyncPad, gst_tensor_sync_pad, GST_TYPE_AGGREGATOR_PAD)
G_DEFINE_ABSTRACT_TYPE_WITH_PRIVATE(GstTensorSync, gst_tensor_sync, GST_TYPE_AGGREGATOR)

static SyncPriv *priv_of(GstTensorSync *self) {
  return static_cast<GstTensorSyncPrivate *>(gst_tensor_sync_get_instance_private(self))->p;
}

// ---------------------------------------------------------------------------------------
// Sink pad

static GstFlowReturn gst_tensor_sync_pad_chain(GstPad *pad, GstObject *parent, GstBuffer *buf) {
  auto *sp = GST_TENSOR_SYNC_PAD(pad);
  SyncPriv *p = priv_of(GST_TENSOR_SYNC(parent));
  if (!p->refresh) return sp->agg_chain(pad, parent, buf);
  GST_OBJECT_LOCK(pad);
  gst_buffer_replace(&sp->pending, nullptr);
  sp->pending = buf;
  sp->refresh_ret = GST_FLOW_OK;
  GST_OBJECT_UNLOCK(pad);
  GstQuery *q = gst_query_new_drain();
  gst_structure_set(gst_query_writable_structure(q), kRefreshField, G_TYPE_BOOLEAN, TRUE, nullptr);
  gboolean handled = gst_pad_query(pad, q);
  gst_query_unref(q);
  GST_OBJECT_LOCK(pad);
  GstBuffer *left = sp->pending;  // not taken: flushing or stopping
  sp->pending = nullptr;
  GstFlowReturn ret = handled ? sp->refresh_ret : GST_FLOW_FLUSHING;
  GST_OBJECT_UNLOCK(pad);
  if (left) gst_buffer_unref(left);
  return ret;
}

static GstFlowReturn gst_tensor_sync_pad_chain_list(GstPad *pad, GstObject *parent,
                                                    GstBufferList *list) {
  GstFlowReturn ret = GST_FLOW_OK;
  guint n = gst_buffer_list_length(list);
  for (guint i = 0; i < n && ret == GST_FLOW_OK; ++i)
    ret = gst_tensor_sync_pad_chain(pad, parent, gst_buffer_ref(gst_buffer_list_get(list, i)));
  gst_buffer_list_unref(list);
  return ret;
}

static void gst_tensor_sync_pad_constructed(GObject *object) {
  G_OBJECT_CLASS(gst_tensor_sync_pad_parent_class)->constructed(object);
  GstPad *pad = GST_PAD(object);
  auto *sp = GST_TENSOR_SYNC_PAD(object);
  sp->agg_chain = GST_PAD_CHAINFUNC(pad);
  gst_pad_set_chain_function(pad, gst_tensor_sync_pad_chain);
  gst_pad_set_chain_list_function(pad, gst_tensor_sync_pad_chain_list);
}

static void gst_tensor_sync_pad_clear(GstTensorSyncPad *sp) {
  gst_buffer_replace(&sp->last, nullptr);
  GST_OBJECT_LOCK(sp);
  gst_buffer_replace(&sp->pending, nullptr);
  GST_OBJECT_UNLOCK(sp);
}

static void gst_tensor_sync_pad_finalize(GObject *object) {
  auto *sp = GST_TENSOR_SYNC_PAD(object);
  gst_tensor_sync_pad_clear(sp);
  delete sp->config;
  G_OBJECT_CLASS(gst_tensor_sync_pad_parent_class)->finalize(object);
}

static void gst_tensor_sync_pad_class_init(GstTensorSyncPadClass *klass) {
  G_OBJECT_CLASS(klass)->constructed = gst_tensor_sync_pad_constructed;
  G_OBJECT_CLASS(klass)->finalize = gst_tensor_sync_pad_finalize;
}

static void gst_tensor_sync_pad_init(GstTensorSyncPad *sp) {
  sp->config = new nns::TensorsConfig();
  sp->refresh_ret = GST_FLOW_OK;
}

// ---------------------------------------------------------------------------------------
// The policy's view of the pads

namespace {

// The current pad snapshot (rebuilt when pads were added or removed).
std::shared_ptr<const PadList> current_pads(GstTensorSync *self) {
  SyncPriv *p = priv_of(self);
  GstElement *e = GST_ELEMENT(self);
  GST_OBJECT_LOCK(self);
  if (!p->pad_list || p->pads_cookie != e->pads_cookie) {
    p->pad_list = std::make_shared<const PadList>(e);
    p->pads_cookie = e->pads_cookie;
  }
  std::shared_ptr<const PadList> list = p->pad_list;
  GST_OBJECT_UNLOCK(self);
  return list;
}

class PadInputs final : public nns::SyncInputs {
 public:
  // refresh_pad/refresh_buf: in refresh mode the only "queued" buffer is the arriving one.
  PadInputs(GstTensorSync *self, std::optional<std::size_t> refresh_pad = std::nullopt,
            GstBuffer *refresh_buf = nullptr)
      : self_(self),
        list_(current_pads(self)),
        n_(list_->pads.size()),
        refresh_pad_(refresh_pad),
        refresh_buf_(refresh_buf) {
    // Per-pad scratch inline for the usual few pads; no allocation per output.
    if (n_ > kInline) {
      heap_.resize(n_);
      heads_ = heap_.data();
    } else {
      heads_ = inline_;
    }
    for (std::size_t i = 0; i < n_; ++i) heads_[i] = Head{};
  }
  ~PadInputs() override {
    for (std::size_t i = 0; i < n_; ++i)
      if (heads_[i].buf) gst_buffer_unref(heads_[i].buf);
    if (refresh_buf_) gst_buffer_unref(refresh_buf_);
  }
  PadInputs(const PadInputs &) = delete;
  PadInputs &operator=(const PadInputs &) = delete;

  std::size_t count() const override { return n_; }
  std::optional<uint64_t> head_pts(std::size_t i) override {
    GstBuffer *h = head(i);
    if (!h) return std::nullopt;
    return GST_BUFFER_PTS(h);
  }
  std::optional<uint64_t> last_pts(std::size_t i) override {
    GstBuffer *last = pad(i)->last;
    if (!last) return std::nullopt;
    return GST_BUFFER_PTS(last);
  }
  void take_head(std::size_t i) override {
    GstBuffer *b;
    if (refresh_pad_) {
      b = refresh_buf_;
      refresh_buf_ = nullptr;
    } else {
      b = gst_aggregator_pad_pop_buffer(agg_pad(i));
      if (heads_[i].buf) gst_buffer_unref(heads_[i].buf);
      heads_[i] = Head{};
    }
    GstTensorSyncPad *sp = pad(i);
    if (sp->last) gst_buffer_unref(sp->last);
    sp->last = b;
  }
  void set_time_source(std::size_t i) override {
    SyncPriv *p = priv_of(self_);
    gst_buffer_replace(&p->time_src, head(i));
  }

  GstTensorSyncPad *pad(std::size_t i) const {
    return reinterpret_cast<GstTensorSyncPad *>(list_->pads[i]);
  }
  // A pad that has no buffer yet but is not EOS (the aggregator was woken early).
  bool waiting_for_data() {
    for (std::size_t i = 0; i < n_; ++i)
      if (!head(i) && !gst_aggregator_pad_is_eos(agg_pad(i))) return true;
    return false;
  }
  bool all_eos() const {
    for (std::size_t i = 0; i < n_; ++i)
      if (!gst_aggregator_pad_is_eos(agg_pad(i))) return false;
    return true;
  }

 private:
  struct Head {
    GstBuffer *buf = nullptr;
    bool peeked = false;
  };
  static constexpr std::size_t kInline = 16;

  GstAggregatorPad *agg_pad(std::size_t i) const {
    return reinterpret_cast<GstAggregatorPad *>(list_->pads[i]);
  }
  GstBuffer *head(std::size_t i) {
    if (refresh_pad_) return i == *refresh_pad_ ? refresh_buf_ : nullptr;
    Head &h = heads_[i];
    if (!h.peeked) {
      h.buf = gst_aggregator_pad_peek_buffer(agg_pad(i));
      h.peeked = true;
    }
    return h.buf;
  }

  GstTensorSync *self_;
  std::shared_ptr<const PadList> list_;
  std::size_t n_;
  Head inline_[kInline];
  std::vector<Head> heap_;
  Head *heads_;
  std::optional<std::size_t> refresh_pad_;
  GstBuffer *refresh_buf_;
};

std::string pad_name(GstTensorSyncPad *p) {
  nns::gst::GCharPtr n(gst_pad_get_name(GST_PAD(p)));
  return n ? n.get() : "?";
}

// Negotiates the src caps when the inputs changed since the last output.
void negotiate(GstTensorSync *self, PadInputs &in) {
  SyncPriv *p = priv_of(self);
  uint64_t gen = p->caps_gen.load();
  if (gen == p->negotiated_gen && in.count() == p->negotiated_pads) return;
  std::vector<nns::TensorsConfig> configs;
  std::vector<std::string> names;
  for (std::size_t i = 0; i < in.count(); ++i) {
    names.push_back(pad_name(in.pad(i)));
    if (!in.pad(i)->configured)
      nns::fail(nns::ErrorKind::kNegotiation, names.back() + " received data without caps");
    configs.push_back(*in.pad(i)->config);
  }
  auto *klass = GST_TENSOR_SYNC_GET_CLASS(self);
  nns::TensorsConfig out = klass->configure(self, configs, names);
  // The output caps: our config, in the first form (other/tensors, else other/tensor)
  // that downstream accepts.
  nns::gst::CapsPtr want(nns::gst::caps_from_config(out));
  GstPad *src = GST_AGGREGATOR_SRC_PAD(self);
  nns::gst::CapsPtr caps;
  if (gst_pad_is_linked(src)) {
    caps.reset(gst_pad_peer_query_caps(src, want.get()));
    if (!caps || gst_caps_is_empty(caps.get())) {
      nns::gst::CapsPtr allowed(gst_pad_peer_query_caps(src, nullptr));
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
  gst_aggregator_set_src_caps(GST_AGGREGATOR(self), caps.get());
  p->negotiated_gen = gen;
  p->negotiated_pads = in.count();
  GST_DEBUG_OBJECT(self, "output %s", out.info.to_string().c_str());
}

GstFlowReturn produce(GstTensorSync *self, PadInputs &in) {
  SyncPriv *p = priv_of(self);
  negotiate(self, in);
  const std::size_t n = in.count();
  GstBuffer *bufs[nns::kTensorLimit];
  if (n > nns::kTensorLimit) nns::fail(nns::ErrorKind::kNegotiation, "too many sink pads");
  for (std::size_t i = 0; i < n; ++i) bufs[i] = in.pad(i)->last;
  auto *klass = GST_TENSOR_SYNC_GET_CLASS(self);
  GstBuffer *out = klass->combine(self, bufs, n);
  if (p->time_src) gst_buffer_copy_into(out, p->time_src, GST_BUFFER_COPY_METADATA, 0, -1);
  GST_BUFFER_PTS(out) = p->sync.time();
  gst_buffer_replace(&p->time_src, nullptr);
  if (p->sync.mode() == nns::SyncMode::kNoSync)
    for (std::size_t i = 0; i < n; ++i) gst_buffer_replace(&in.pad(i)->last, nullptr);
  auto *agg = GST_AGGREGATOR(self);
  if (!p->segment_sent && n > 0) {
    // Keep the first input's segment, so running times are those of the inputs.
    GstSegment seg;
    GST_OBJECT_LOCK(in.pad(0));
    gst_segment_copy_into(&GST_AGGREGATOR_PAD(in.pad(0))->segment, &seg);
    GST_OBJECT_UNLOCK(in.pad(0));
    if (seg.format == GST_FORMAT_TIME) gst_aggregator_update_segment(agg, &seg);
    p->segment_sent = true;
  }
  if (!p->silent)
    GST_INFO_OBJECT(self, "output pts %" GST_TIME_FORMAT, GST_TIME_ARGS(GST_BUFFER_PTS(out)));
  gst_aggregator_selected_samples(agg, GST_BUFFER_PTS(out), GST_BUFFER_DTS(out),
                                  GST_BUFFER_DURATION(out), nullptr);
  return gst_aggregator_finish_buffer(agg, out);
}

void deepen_queues(GstTensorSync *self, PadInputs &in) {
  SyncPriv *p = priv_of(self);
  p->queue_checked = true;
  GstClockTime latency = 0;
  g_object_get(self, "latency", &latency, nullptr);
  if (latency != 0) return;
  for (std::size_t i = 0; i < in.count(); ++i) {
    auto pts = in.head_pts(i);
    if (pts && *pts == nns::kNoTime) return;  // untimed: a time limit would not bound the queue
    GstQuery *q = gst_query_new_latency();
    gboolean live = FALSE;
    if (gst_pad_peer_query(GST_PAD(in.pad(i)), q))
      gst_query_parse_latency(q, &live, nullptr, nullptr);
    gst_query_unref(q);
    if (live) return;
  }
  g_object_set(self, "latency", kAutoQueueTime, nullptr);
  p->queue_auto = true;
}

void check_basepad(GstTensorSync *self, std::size_t pads) {
  SyncPriv *p = priv_of(self);
  if (p->sync.mode() == nns::SyncMode::kBasePad && p->sync.option().sink_id >= pads)
    nns::fail(nns::ErrorKind::kSettings,
              "sync-option: base pad sink_" + std::to_string(p->sync.option().sink_id) +
                  " does not exist (the element has " + std::to_string(pads) + " sink pads)");
}

// Runs one refresh step for a buffer that arrived on `pad`.
GstFlowReturn refresh_arrival(GstTensorSync *self, GstTensorSyncPad *pad, GstBuffer *buf) {
  std::optional<std::size_t> index;
  {
    std::size_t i = 0;
    GST_OBJECT_LOCK(self);
    for (GList *l = GST_ELEMENT(self)->sinkpads; l; l = l->next, ++i)
      if (l->data == pad) index = i;
    GST_OBJECT_UNLOCK(self);
  }
  if (!index) {
    gst_buffer_unref(buf);
    return GST_FLOW_FLUSHING;  // released meanwhile
  }
  PadInputs in(self, index, buf);
  switch (priv_of(self)->sync.step(in)) {
    case nns::SyncResult::kOutput:
      return produce(self, in);
    case nns::SyncResult::kEos:
      return GST_FLOW_EOS;
    case nns::SyncResult::kNeedData:
      break;
  }
  return GST_FLOW_OK;
}

}  // namespace

// ---------------------------------------------------------------------------------------
// Aggregator vfuncs

static GstFlowReturn gst_tensor_sync_aggregate(GstAggregator *agg, gboolean /*timeout*/) {
  auto *self = GST_TENSOR_SYNC(agg);
  return nns::gst::guard(agg, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    SyncPriv *p = priv_of(self);
    if (p->refresh) {
      // Buffers never queue in refresh mode (the chain function hands them over), so this
      // runs when every pad is EOS. Anything queued regardless is handled as an arrival.
      bool any = false;
      {
        PadInputs in(self);
        for (std::size_t i = 0; i < in.count(); ++i) {
          GstBuffer *b = gst_aggregator_pad_pop_buffer(GST_AGGREGATOR_PAD(in.pad(i)));
          if (!b) continue;
          any = true;
          GstFlowReturn r = refresh_arrival(self, in.pad(i), b);
          if (r != GST_FLOW_OK) return r;
        }
        if (!any && in.all_eos()) return GST_FLOW_EOS;
      }
      return GST_AGGREGATOR_FLOW_NEED_DATA;
    }
    PadInputs in(self);
    if (in.waiting_for_data()) return GST_AGGREGATOR_FLOW_NEED_DATA;
    if (!p->queue_checked) deepen_queues(self, in);
    check_basepad(self, in.count());
    switch (p->sync.step(in)) {
      case nns::SyncResult::kOutput:
        return produce(self, in);
      case nns::SyncResult::kEos:
        return GST_FLOW_EOS;
      case nns::SyncResult::kNeedData:
        break;
    }
    return GST_AGGREGATOR_FLOW_NEED_DATA;
  });
}

static gboolean gst_tensor_sync_sink_query(GstAggregator *agg, GstAggregatorPad *pad,
                                           GstQuery *query) {
  if (GST_QUERY_TYPE(query) == GST_QUERY_DRAIN) {
    const GstStructure *s = gst_query_get_structure(query);
    if (s && gst_structure_has_field(s, kRefreshField)) {
      auto *sp = GST_TENSOR_SYNC_PAD(pad);
      GST_OBJECT_LOCK(pad);
      GstBuffer *buf = sp->pending;
      sp->pending = nullptr;
      GST_OBJECT_UNLOCK(pad);
      if (!buf) return FALSE;
      GstFlowReturn ret = nns::gst::guard(
          agg, GST_FLOW_ERROR, [&] { return refresh_arrival(GST_TENSOR_SYNC(agg), sp, buf); });
      sp->refresh_ret = ret;
      return TRUE;
    }
  }
  return GST_AGGREGATOR_CLASS(gst_tensor_sync_parent_class)->sink_query(agg, pad, query);
}

static gboolean gst_tensor_sync_sink_event(GstAggregator *agg, GstAggregatorPad *pad,
                                           GstEvent *event) {
  if (GST_EVENT_TYPE(event) == GST_EVENT_CAPS) {
    GstCaps *caps = nullptr;
    gst_event_parse_caps(event, &caps);
    auto *sp = GST_TENSOR_SYNC_PAD(pad);
    gboolean ok = nns::gst::guard(agg, FALSE, [&]() -> gboolean {
      nns::TensorsConfig c;
      try {
        c = nns::gst::config_from_caps(caps);
      } catch (const nns::Error &e) {
        nns::fail(e.kind(), pad_name(sp) + ": " + e.what());
      }
      if (!c.info.valid())
        nns::fail(nns::ErrorKind::kNegotiation,
                  pad_name(sp) +
                      ": caps do not describe complete tensors: " + nns::gst::caps_to_string(caps));
      *sp->config = c;
      sp->configured = TRUE;
      return TRUE;
    });
    priv_of(GST_TENSOR_SYNC(agg))->caps_gen++;
    if (!ok) {
      gst_event_unref(event);
      return FALSE;
    }
  }
  return GST_AGGREGATOR_CLASS(gst_tensor_sync_parent_class)->sink_event(agg, pad, event);
}

static void clear_pads(GstTensorSync *self) {
  GST_OBJECT_LOCK(self);
  for (GList *l = GST_ELEMENT(self)->sinkpads; l; l = l->next)
    gst_buffer_replace(&GST_TENSOR_SYNC_PAD(l->data)->last, nullptr);
  GST_OBJECT_UNLOCK(self);
  gst_buffer_replace(&priv_of(self)->time_src, nullptr);
}

static gboolean gst_tensor_sync_start(GstAggregator *agg) {
  auto *self = GST_TENSOR_SYNC(agg);
  return nns::gst::guard(agg, FALSE, [&]() -> gboolean {
    SyncPriv *p = priv_of(self);
    std::string mode_name, option;
    {
      std::lock_guard<std::mutex> g(p->lock);
      mode_name =
          p->mode_name.empty() ? GST_TENSOR_SYNC_GET_CLASS(self)->default_sync_mode : p->mode_name;
      option = p->option;
    }
    if (auto check = GST_TENSOR_SYNC_GET_CLASS(self)->check_settings) check(self);
    auto mode = nns::sync_mode_from_name(mode_name);
    if (!mode)
      nns::fail(nns::ErrorKind::kSettings,
                "sync-mode='" + mode_name + "' is not one of nosync, slowest, basepad, refresh");
    p->sync = nns::TimeSync(*mode, nns::parse_sync_option(*mode, option));
    p->sync.reset();
    p->refresh = *mode == nns::SyncMode::kRefresh;
    p->negotiated_gen = 0;
    p->negotiated_pads = 0;
    p->segment_sent = false;
    p->queue_checked = false;
    clear_pads(self);
    return TRUE;
  });
}

static gboolean gst_tensor_sync_stop(GstAggregator *agg) {
  SyncPriv *p = priv_of(GST_TENSOR_SYNC(agg));
  if (p->queue_auto) g_object_set(agg, "latency", GstClockTime(0), nullptr);
  p->queue_auto = false;
  clear_pads(GST_TENSOR_SYNC(agg));
  GST_OBJECT_LOCK(agg);
  p->pad_list.reset();
  GST_OBJECT_UNLOCK(agg);
  return TRUE;
}

static GstFlowReturn gst_tensor_sync_flush(GstAggregator *agg) {
  auto *self = GST_TENSOR_SYNC(agg);
  priv_of(self)->sync.reset();
  priv_of(self)->segment_sent = false;
  clear_pads(self);
  return GST_FLOW_OK;
}

// Caps are decided in aggregate from the inputs; GstAggregator's default negotiation (which
// would offer downstream's caps) is not used.
static gboolean gst_tensor_sync_negotiate(GstAggregator *) {
  return TRUE;
}

static void gst_tensor_sync_finalize(GObject *object) {
  auto *self = GST_TENSOR_SYNC(object);
  SyncPriv *p = priv_of(self);
  gst_buffer_replace(&p->time_src, nullptr);
  p->pad_list.reset();
  delete p;
  G_OBJECT_CLASS(gst_tensor_sync_parent_class)->finalize(object);
}

static void gst_tensor_sync_class_init(GstTensorSyncClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_sync_debug, "tensor_sync", 0, "tensor_mux/merge core");
  G_OBJECT_CLASS(klass)->finalize = gst_tensor_sync_finalize;
  auto *agg = GST_AGGREGATOR_CLASS(klass);
  agg->aggregate = gst_tensor_sync_aggregate;
  agg->sink_event = gst_tensor_sync_sink_event;
  agg->sink_query = gst_tensor_sync_sink_query;
  agg->start = gst_tensor_sync_start;
  agg->stop = gst_tensor_sync_stop;
  agg->flush = gst_tensor_sync_flush;
  agg->negotiate = gst_tensor_sync_negotiate;
  klass->default_sync_mode = "slowest";
}

static void gst_tensor_sync_init(GstTensorSync *self) {
  auto *pp = static_cast<GstTensorSyncPrivate *>(gst_tensor_sync_get_instance_private(self));
  pp->p = new SyncPriv();  // the class default sync-mode applies until the property is set
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
  std::lock_guard<std::mutex> g(p->lock);
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
  std::lock_guard<std::mutex> g(p->lock);
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
  std::string name = "sink pad " + std::to_string(i);
  GST_OBJECT_LOCK(self);
  if (GList *l = g_list_nth(GST_ELEMENT(self)->sinkpads, static_cast<guint>(i)))
    name = GST_OBJECT_NAME(l->data);
  GST_OBJECT_UNLOCK(self);
  return name;
}

}  // namespace nns::gst

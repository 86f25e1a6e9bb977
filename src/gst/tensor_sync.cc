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
#include <cstdio>
#include <mutex>

#include "core/error.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_sync_priv.h"

GST_DEBUG_CATEGORY(tensor_sync_debug);
#define GST_CAT_DEFAULT tensor_sync_debug

using nns::gst::SyncPadState;
using namespace nns::gst::sync;

namespace {

struct GstTensorSyncPrivate {
  SyncPriv *p;
};

}  // namespace

G_DEFINE_TYPE(GstTensorSyncPad, gst_tensor_sync_pad, GST_TYPE_PAD)
G_DEFINE_ABSTRACT_TYPE_WITH_PRIVATE(GstTensorSync, gst_tensor_sync, GST_TYPE_ELEMENT)

SyncPriv *nns::gst::sync::priv_of(GstTensorSync *self) {
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
      state(pad).max_buffers = 0;
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

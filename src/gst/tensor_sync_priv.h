// SPDX-License-Identifier: LGPL-2.1-only
// Internals of GstTensorSync shared by tensor_sync.cc (the GObject element: types, pads,
// state changes, properties) and tensor_sync_flow.cc (the data path). Not installed.
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <mutex>
#include <string>
#include <vector>

#include "core/time_sync.h"
#include "gst/tensor_sync.h"
#include "gst/tensor_sync_queue.h"

GST_DEBUG_CATEGORY_EXTERN(tensor_sync_debug);

struct _GstTensorSyncPad {
  GstPad parent;
  nns::gst::SyncPadState *st;
};

namespace nns::gst::sync {

using Lock = std::unique_lock<std::mutex>;

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

SyncPriv *priv_of(GstTensorSync *self);
inline SyncPadState &state(GstTensorSyncPad *pad) {
  return *pad->st;
}

// Empties a pad's queue and forgets its chosen buffer (under `mu`).
void clear_pad(SyncPadState &s, Garbage &g);
// Builds and pushes outputs while the queues allow. Called with `lk` held by a thread that
// just queued something; returns with `lk` released, and the flow that thread's upstream
// should get.
GstFlowReturn drive(GstTensorSync *self, SyncPriv *p, Lock &lk);

// Pad functions.
GstFlowReturn sink_chain(GstPad *pad, GstObject *parent, GstBuffer *buf);
GstFlowReturn sink_chain_list(GstPad *pad, GstObject *parent, GstBufferList *list);
gboolean sink_event(GstPad *pad, GstObject *parent, GstEvent *event);
gboolean sink_query(GstPad *pad, GstObject *parent, GstQuery *query);
gboolean src_query(GstPad *pad, GstObject *parent, GstQuery *query);

}  // namespace nns::gst::sync

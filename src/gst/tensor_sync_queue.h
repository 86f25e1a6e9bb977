// SPDX-License-Identifier: LGPL-2.1-only
// The per-sink-pad state of GstTensorSync (tensor_mux / tensor_merge): a FIFO of the buffers
// and serialized events that arrived on the pad, and what the sync policy needs to know about
// the pad. Everything here is guarded by the element's lock (see tensor_sync.cc).
#pragma once

#include <gst/gst.h>

#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/tensor_info.h"

namespace nns::gst {

// A FIFO that keeps its storage: once it has grown to the depth a stream needs, queueing and
// dequeueing allocate nothing.
class SyncQueue {
 public:
  struct Item {
    GstMiniObject *obj = nullptr;  // a GstBuffer or a serialized GstEvent (owned)
    uint64_t seq = 0;              // arrival order over all pads of the element
    std::size_t bytes = 0;         // buffer size (0 for events)
  };

  bool empty() const { return n_ == 0; }
  std::size_t size() const { return n_; }
  Item &front() { return v_[head_]; }
  void push(const Item &it) {
    if (n_ == v_.size()) grow();
    v_[(head_ + n_) & (v_.size() - 1)] = it;
    ++n_;
  }
  Item pop() {
    Item it = v_[head_];
    v_[head_] = Item{};
    head_ = (head_ + 1) & (v_.size() - 1);
    --n_;
    return it;
  }

 private:
  void grow() {
    std::vector<Item> nv(v_.empty() ? 16 : v_.size() * 2);  // a power of two
    for (std::size_t i = 0; i < n_; ++i) nv[i] = v_[(head_ + i) & (v_.size() - 1)];
    v_.swap(nv);
    head_ = 0;
  }
  std::vector<Item> v_;
  std::size_t head_ = 0;
  std::size_t n_ = 0;
};

struct SyncPadState {
  SyncQueue queue;
  std::size_t buffers = 0;  // buffers in `queue`
  std::size_t bytes = 0;    // their sizes
  bool flushing = false;    // between FLUSH_START and FLUSH_STOP, or while stopped
  bool eos_in = false;      // EOS received: nothing more is accepted until a flush
  bool eos = false;         // ... and it reached the head of the queue
  bool configured = false;  // a CAPS event reached the head
  TensorsConfig config;     // from that CAPS event
  GstSegment segment{};     // the last SEGMENT that reached the head
  bool has_segment = false;
  GstBuffer *last = nullptr;  // the buffer chosen for the next output
  int waiters = 0;            // producers waiting for room in `queue`
  std::condition_variable room;

  // A pad queues `max_buffers` buffers at most, and stops taking more at kMaxBytes (it always
  // takes one). For inputs that are not live the queue is deep (kMaxBuffers), so producers
  // rarely have to sleep; outputs do not depend on it, as a set is built only when every pad
  // has data. A live input queues kLiveBuffers at most, so that it is held back, not paired
  // with frames from long ago (upstream's CollectPads holds one buffer per pad).
  static constexpr std::size_t kMaxBuffers = 64;
  static constexpr std::size_t kLiveBuffers = 2;
  static constexpr std::size_t kMaxBytes = 8u << 20;
  std::size_t max_buffers = 0;  // 0: not known yet (decided at the pad's first buffer)

  bool has_room() const { return buffers == 0 || (buffers < max_buffers && bytes < kMaxBytes); }
  // A producer waiting for room is woken only once the queue has drained to half, so that it
  // then queues many buffers per wake-up instead of one.
  bool wake_producer() const {
    return waiters > 0 && (buffers == 0 || (buffers <= max_buffers / 2 && bytes <= kMaxBytes / 2));
  }
};

}  // namespace nns::gst

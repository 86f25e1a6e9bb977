// SPDX-License-Identifier: LGPL-2.1-only
// The process-wide tensor repository behind tensor_reposink / tensor_reposrc: numbered slots,
// each a one-buffer hand-off (with the caps it was negotiated with). The sink waits until the
// previous buffer was taken, the source waits until a buffer arrives; EOS, flushing and a
// changed slot index wake both sides, so a pipeline with a cycle through the repository (RNN /
// LSTM state) never deadlocks on EOS or shutdown.
#pragma once

#include <gst/gst.h>

#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>

namespace nns::gst {

class TensorRepo {
 public:
  enum class Status { kOk, kEos, kCancelled };

  static TensorRepo &instance();

  // Clears the slot for a new run: drops a stale buffer and the EOS mark.
  void reset(uint32_t slot);
  // Stores `buf` (a new reference is taken) and `caps` into the slot, waiting while the slot
  // still holds an untaken buffer. `cancelled()` is checked whenever the waiter wakes.
  Status push(uint32_t slot, GstBuffer *buf, GstCaps *caps, const std::function<bool()> &cancelled);
  // Takes the slot's buffer (and a reference to its caps), waiting until there is one.
  Status pop(uint32_t slot, GstBuffer **buf, GstCaps **caps,
             const std::function<bool()> &cancelled);
  // Marks the slot ended: waiting and later pops return kEos, pushes return kEos.
  void set_eos(uint32_t slot);
  // Wakes every waiter of the slot so they re-check cancelled().
  void wake(uint32_t slot);
  // Whether the slot holds an untaken buffer (tests).
  bool has_buffer(uint32_t slot);

 private:
  struct Slot;
  std::shared_ptr<Slot> get(uint32_t slot);
  std::mutex lock_;
  std::map<uint32_t, std::shared_ptr<Slot>> slots_;
};

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
// The process-wide tensor repository behind tensor_reposink / tensor_reposrc: numbered slots,
// each a one-buffer hand-off (with the caps it was negotiated with). The sink waits until the
// previous buffer was taken, the source waits until a buffer arrives; EOS, flushing and a
// changed slot index wake both sides, so a pipeline with a cycle through the repository (RNN /
// LSTM state) never deadlocks on EOS or shutdown.
#pragma once

#include <gst/gst.h>

#include <atomic>
#include <condition_variable>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <mutex>

// Caps both repository elements accept.
#define NNS_REPO_CAPS                                                         \
  "other/tensor, framerate = (fraction) [ 0, max ]; "                         \
  "other/tensors, format = (string) static, num_tensors = (int) [ 1, 256 ], " \
  "framerate = (fraction) [ 0, max ]"

namespace nns::gst {

class TensorRepo {
 public:
  // kFull only from try_push.
  enum class Status { kOk, kEos, kCancelled, kFull };

  static TensorRepo &instance();

  // Clears the slot for a new run: drops a stale buffer and the EOS mark.
  void reset(uint32_t slot);
  // Stores `buf` (a new reference is taken) and `caps` into the slot, waiting while the slot
  // still holds an untaken buffer. `cancelled()` is checked whenever the waiter wakes.
  Status push(uint32_t slot, GstBuffer *buf, GstCaps *caps, const std::function<bool()> &cancelled);
  // Same without waiting: kFull when the slot still holds an untaken buffer.
  Status try_push(uint32_t slot, GstBuffer *buf, GstCaps *caps);
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

// One element's view of its slot (tensor_reposink / tensor_reposrc): the slot-index property,
// cancellation by unlock/unlock_stop, and waits that follow a slot-index change.
//
// Cancellation follows the unlock protocol of GstBaseSink / GstBaseSrc: unlock() may come
// from any thread; unlock_stop() comes once the element has taken the lock the streaming thread
// holds outside its waits. A wait is cancelled when
//   - an unlock() is still pending (made, and unlock_stop() not called yet), or
//   - an unlock() was made since the wait's ticket was taken, even if unlock_stop() followed
//     before the waiter woke up (a generation count, so such a cancel is never lost when the
//     waiter does not hold that lock while it waits, as tensor_reposink's render).
class RepoSlot {
 public:
  static constexpr guint kUnset = G_MAXUINT;
  // `unset_until_set`: the property starts at kUnset, which means slot 0.
  explicit RepoSlot(bool unset_until_set)
      : unset_means_zero_(unset_until_set), index_(unset_until_set ? kUnset : 0) {}

  guint property() const { return index_; }
  // Sets the slot-index property; a wait on the old slot moves to the new one.
  void set_property(guint index);
  guint slot() const;

  // The current unlock generation, to pass to wait().
  uint64_t ticket() const { return generation_; }
  // An unlock() is pending (no unlock_stop() since).
  bool unlocking() const { return unlocking_; }
  void unlock();  // cancels waits (see above) and wakes them
  void unlock_stop() { unlocking_ = false; }

  // Runs `wait_on(slot, cancelled)` (a TensorRepo push or pop) until it is not interrupted by a
  // slot-index change. kCancelled means unlocked since `ticket` (or still unlocking). `*used`
  // receives the slot waited on.
  using WaitFn = std::function<TensorRepo::Status(uint32_t, const std::function<bool()> &)>;
  TensorRepo::Status wait(uint64_t ticket, const WaitFn &wait_on, guint *used);

 private:
  bool cancelled_since(uint64_t ticket) const { return unlocking_ || generation_ != ticket; }

  const bool unset_means_zero_;
  std::atomic<guint> index_;
  std::atomic<uint64_t> generation_{0};
  std::atomic<bool> unlocking_{false};
};

}  // namespace nns::gst

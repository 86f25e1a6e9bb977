// SPDX-License-Identifier: LGPL-2.1-only
// Output memories of one element reused once downstream has let them go, instead of a fresh
// allocation per buffer. Why: glibc serves a large allocation (here MiBs: a batch of 8 MobileNet
// inputs is 1.2 MiB as uint8, 4.8 MiB as float32) from the top of an arena and trims the arena
// when it is freed, so every buffer costs fresh pages (page faults, zeroing by the kernel):
// measured 3 000 page faults per batch of 8 in the query server, ~10 % of its CPU.
//
// The recycler keeps a reference to its last few memories; one whose only reference is the
// recycler's (no buffer, no shared sub-memory, no map holds it any more) is handed out again.
// The extra reference takes no lock on the memory, so a buffer holding it still sees it as
// writable, as with a fresh one.
#pragma once

#include <gst/gst.h>

#include <cstddef>
#include <mutex>
#include <vector>

namespace nns::gst {

class MemoryRecycler {
 public:
  explicit MemoryRecycler(std::size_t keep = 4) : keep_(keep) {}
  ~MemoryRecycler() { clear(); }
  MemoryRecycler(const MemoryRecycler &) = delete;
  MemoryRecycler &operator=(const MemoryRecycler &) = delete;

  // A memory of exactly `size` bytes (contents undefined), system allocator; the caller owns
  // the returned reference.
  GstMemory *alloc(gsize size) {
    std::lock_guard<std::mutex> l(m_);
    for (GstMemory *mem : kept_) {
      gsize offset = 0, max = 0;
      const gsize cur = gst_memory_get_sizes(mem, &offset, &max);
      if (GST_MINI_OBJECT_REFCOUNT_VALUE(mem) == 1 && cur == size && offset == 0 &&
          !GST_MEMORY_IS_READONLY(mem))
        return gst_memory_ref(mem);
    }
    GstMemory *mem = gst_allocator_alloc(nullptr, size, nullptr);
    if (!mem) return nullptr;
    if (kept_.size() >= keep_) {
      gst_memory_unref(kept_.front());
      kept_.erase(kept_.begin());
    }
    kept_.push_back(gst_memory_ref(mem));
    return mem;
  }
  // Drops the kept references (memories still in use live on with their holders).
  void clear() {
    std::lock_guard<std::mutex> l(m_);
    for (GstMemory *mem : kept_) gst_memory_unref(mem);
    kept_.clear();
  }

 private:
  std::mutex m_;
  std::size_t keep_;
  std::vector<GstMemory *> kept_;
};

}  // namespace nns::gst

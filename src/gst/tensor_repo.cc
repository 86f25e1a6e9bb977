// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/tensor_repo.h"

namespace nns::gst {

struct TensorRepo::Slot {
  std::mutex m;
  std::condition_variable cv;
  GstBuffer *buf = nullptr;
  GstCaps *caps = nullptr;
  bool eos = false;
};

TensorRepo &TensorRepo::instance() {
  static auto *repo = new TensorRepo();  // never destroyed: elements may outlive static teardown
  return *repo;
}

std::shared_ptr<TensorRepo::Slot> TensorRepo::get(uint32_t slot) {
  std::lock_guard<std::mutex> l(lock_);
  auto &s = slots_[slot];
  if (!s) s = std::make_shared<Slot>();
  return s;
}

void TensorRepo::reset(uint32_t slot) {
  auto s = get(slot);
  std::lock_guard<std::mutex> l(s->m);
  if (s->buf) gst_buffer_unref(s->buf);
  s->buf = nullptr;
  s->eos = false;
  s->cv.notify_all();
}

TensorRepo::Status TensorRepo::push(uint32_t slot, GstBuffer *buf, GstCaps *caps,
                                    const std::function<bool()> &cancelled) {
  auto s = get(slot);
  std::unique_lock<std::mutex> l(s->m);
  s->cv.wait(l, [&] { return !s->buf || s->eos || cancelled(); });
  if (s->eos) return Status::kEos;
  if (cancelled()) return Status::kCancelled;
  s->buf = gst_buffer_ref(buf);
  if (caps != s->caps) gst_caps_replace(&s->caps, caps);
  s->cv.notify_all();
  return Status::kOk;
}

TensorRepo::Status TensorRepo::try_push(uint32_t slot, GstBuffer *buf, GstCaps *caps) {
  auto s = get(slot);
  std::lock_guard<std::mutex> l(s->m);
  if (s->eos) return Status::kEos;
  if (s->buf) return Status::kFull;
  s->buf = gst_buffer_ref(buf);
  if (caps != s->caps) gst_caps_replace(&s->caps, caps);
  s->cv.notify_all();
  return Status::kOk;
}

TensorRepo::Status TensorRepo::pop(uint32_t slot, GstBuffer **buf, GstCaps **caps,
                                   const std::function<bool()> &cancelled) {
  auto s = get(slot);
  std::unique_lock<std::mutex> l(s->m);
  s->cv.wait(l, [&] { return s->buf || s->eos || cancelled(); });
  if (cancelled()) return Status::kCancelled;
  if (!s->buf) return Status::kEos;
  *buf = s->buf;
  s->buf = nullptr;
  *caps = s->caps ? gst_caps_ref(s->caps) : nullptr;
  s->cv.notify_all();
  return Status::kOk;
}

void TensorRepo::set_eos(uint32_t slot) {
  auto s = get(slot);
  std::lock_guard<std::mutex> l(s->m);
  s->eos = true;
  s->cv.notify_all();
}

void TensorRepo::wake(uint32_t slot) {
  auto s = get(slot);
  std::lock_guard<std::mutex> l(s->m);
  s->cv.notify_all();
}

bool TensorRepo::has_buffer(uint32_t slot) {
  auto s = get(slot);
  std::lock_guard<std::mutex> l(s->m);
  return s->buf != nullptr;
}

guint RepoSlot::slot() const {
  guint s = index_;
  return unset_means_zero_ && s == kUnset ? 0 : s;
}

void RepoSlot::set_property(guint index) {
  guint old = slot();
  index_ = index;
  // A waiter on the old slot sees slot() != the slot it waits on (checked under that slot's
  // lock, which wake() takes after the store) and moves.
  if (old != slot()) TensorRepo::instance().wake(old);
}

void RepoSlot::unlock() {
  unlocking_ = true;
  ++generation_;
  TensorRepo::instance().wake(slot());
}

TensorRepo::Status RepoSlot::wait(uint64_t ticket, const WaitFn &wait_on, guint *used) {
  for (;;) {
    guint s = slot();
    *used = s;
    auto st = wait_on(s, [&] { return cancelled_since(ticket) || slot() != s; });
    if (st != TensorRepo::Status::kCancelled || cancelled_since(ticket)) return st;
    // slot-index changed while waiting: wait on the new slot
  }
}

}  // namespace nns::gst

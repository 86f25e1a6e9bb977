// SPDX-License-Identifier: LGPL-2.1-only
// Lending numpy arrays as output memory; see nns_python_lend.h.
#include "nns_python_lend.h"

#include "nns_numpy.h"

namespace nns::py {
namespace {

std::vector<LentArray> g_lent;  // GIL-guarded

bool overlaps(const char *b, size_t n, const char *ob, size_t on) {
  return n && on && b < ob + on && ob < b + n;
}

}  // namespace

LendBatch::LendBatch(std::vector<LentArray> &scratch, const GstTensorMemory *avoid,
                     size_t num_avoid)
    : pending_(scratch), avoid_(avoid), num_avoid_(num_avoid) {
  pending_.clear();
}

LendBatch::~LendBatch() {
  for (LentArray &l : pending_) Py_XDECREF(l.array);
  pending_.clear();
}

bool LendBatch::add(PyObject *o) {
  auto *arr = reinterpret_cast<PyArrayObject *>(o);
  const char *b = static_cast<const char *>(PyArray_DATA(arr));
  size_t bytes = static_cast<size_t>(PyArray_NBYTES(arr));
  bool copy = !PyArray_IS_C_CONTIGUOUS(arr);
  for (size_t j = 0; !copy && j < num_avoid_; j++)
    copy = overlaps(b, bytes, static_cast<const char *>(avoid_[j].data), avoid_[j].size);
  // g_lent may change during a copy below (numpy can release the GIL), so it is only read here
  // and only written in commit().
  for (const LentArray &l : g_lent)
    if (!copy) copy = overlaps(b, bytes, l.begin, l.size);
  for (const LentArray &l : pending_)
    if (!copy) copy = overlaps(b, bytes, l.begin, l.size);
  PyObject *hold = o;
  if (copy) {
    hold = PyArray_NewCopy(arr, NPY_CORDER);
    if (!hold) return false;
  } else {
    Py_INCREF(hold);
  }
  pending_.push_back(
      {static_cast<const char *>(PyArray_DATA(reinterpret_cast<PyArrayObject *>(hold))), bytes,
       hold});
  return true;
}

void LendBatch::commit(GstTensorMemory *out) {
  for (size_t i = 0; i < pending_.size(); i++) {
    out[i].data = const_cast<char *>(pending_[i].begin);
    out[i].size = pending_[i].size;
    g_lent.push_back(pending_[i]);
  }
  pending_.clear();  // ownership moved to g_lent
}

void release_lent(void *data) noexcept {
  if (!data || !runtime_alive()) return;
  Gil gil;
  for (size_t i = g_lent.size(); i-- > 0;) {
    if (g_lent[i].begin != data) continue;
    PyObject *arr = g_lent[i].array;
    g_lent[i] = g_lent.back();
    g_lent.pop_back();
    Py_DECREF(arr);  // may run arbitrary code: the entry is already gone
    return;
  }
}

}  // namespace nns::py

// SPDX-License-Identifier: LGPL-2.1-only
// Numpy arrays returned by a script, handed to the host as output memory without a copy where
// that is safe, and kept alive until the host gives them back. Shared by the python3 sub-plugins.
//
// An array is lent as is unless it is not C-contiguous, overlaps one of the caller's inputs (the
// script returned its input or a view of it), or overlaps an array still lent (the same array
// twice, or one the script keeps and returns again): then a C-ordered copy is lent instead.
// The table of lent arrays is process-wide, so release_lent() never needs the sub-plugin instance
// (a host may close a filter while its output buffers are still downstream).
#pragma once

#include <cstddef>
#include <vector>

#include "nns_python.h"
#include "tensor_typedef.h"

namespace nns::py {

struct LentArray {
  const char *begin;
  size_t size;
  PyObject *array;  // owned reference
};

// Collects the outputs of one call; nothing is lent until commit(), and a batch destroyed without
// commit() drops what it collected (so a failure half-way lends nothing). GIL held throughout.
class LendBatch {
 public:
  // `scratch` is reused between calls to avoid an allocation per call; `avoid` are the inputs.
  LendBatch(std::vector<LentArray> &scratch, const GstTensorMemory *avoid, size_t num_avoid);
  ~LendBatch();
  LendBatch(const LendBatch &) = delete;
  LendBatch &operator=(const LendBatch &) = delete;

  // Adds a numpy array (the caller checked type and size); copies it when needed (see above).
  // Returns false, with the Python error pending, when the copy fails.
  bool add(PyObject *ndarray);
  // Lends everything added, in order: out[i] = {data, size}.
  void commit(GstTensorMemory *out);

 private:
  std::vector<LentArray> &pending_;
  const GstTensorMemory *avoid_;
  size_t num_avoid_;
};

// Gives back memory lent by any batch; unknown pointers are ignored. Takes the GIL; does nothing
// once the interpreter is finalizing (process exit). Any thread.
void release_lent(void *data) noexcept;

}  // namespace nns::py

// SPDX-License-Identifier: LGPL-2.1-only
// The order in which datareposrc reads samples: the range [start, stop] once per epoch, in file
// order, or shuffled anew for every epoch (Fisher-Yates with a 64-bit Mersenne Twister seeded by
// `seed`, so a seed gives the same order on every machine). GStreamer-free.
#pragma once

#include <cstdint>
#include <random>
#include <vector>

namespace nns::datarepo {

class SampleOrder {
 public:
  SampleOrder(uint32_t start, uint32_t stop, uint32_t epochs, bool shuffle, uint64_t seed);
  // Next sample index; false when every epoch is done.
  bool next(uint32_t *index);
  uint32_t epoch() const { return epoch_; }  // epoch of the last index returned (0-based)

 private:
  void new_epoch();
  std::vector<uint32_t> order_;
  std::size_t pos_ = 0;
  uint32_t epoch_ = 0, epochs_;
  bool started_ = false, shuffle_;
  std::mt19937_64 rng_;
};

}  // namespace nns::datarepo

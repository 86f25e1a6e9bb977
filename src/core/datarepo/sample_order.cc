// SPDX-License-Identifier: LGPL-2.1-only
#include "core/datarepo/sample_order.h"

#include <numeric>

namespace nns::datarepo {

SampleOrder::SampleOrder(uint32_t start, uint32_t stop, uint32_t epochs, bool shuffle,
                         uint64_t seed)
    : order_(stop >= start ? stop - start + 1 : 0), epochs_(epochs), shuffle_(shuffle), rng_(seed) {
  std::iota(order_.begin(), order_.end(), start);
}

void SampleOrder::new_epoch() {
  if (!shuffle_) return;
  // Fisher-Yates; the draw is done with our own modulo-free scaling (not
  // std::uniform_int_distribution, whose algorithm differs between standard libraries).
  for (std::size_t i = order_.size(); i > 1; --i) {
    const uint64_t r = rng_();
    const std::size_t j = static_cast<std::size_t>((static_cast<unsigned __int128>(r) * i) >> 64);
    std::swap(order_[i - 1], order_[j]);
  }
}

bool SampleOrder::next(uint32_t *index) {
  if (order_.empty() || epochs_ == 0) return false;
  if (!started_) {
    started_ = true;
    new_epoch();
  } else if (pos_ == order_.size()) {
    if (epoch_ + 1 >= epochs_) return false;
    ++epoch_;
    pos_ = 0;
    new_epoch();
  }
  *index = order_[pos_++];
  return true;
}

}  // namespace nns::datarepo

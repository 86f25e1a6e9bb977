// SPDX-License-Identifier: LGPL-2.1-only
#include "ros/ros_tensors.h"

#include <algorithm>
#include <limits>

#include "core/error.h"

namespace nns::ros {

std::vector<LayoutDim> layout_for(const TensorInfo &info) {
  const std::size_t rank = std::max(info.rank(), kMinWireRank);
  const std::string label(type_name(info.type));
  std::vector<LayoutDim> out(rank);
  // Innermost first: the stride of dimension i is the bytes of one step along it, i.e. the
  // element size times the dimensions inside and including it.
  uint64_t stride = type_size(info.type);
  for (std::size_t i = 0; i < rank; ++i) {
    const uint32_t d = i < info.rank() ? info.dims[i] : 1;
    stride *= d;
    if (stride > std::numeric_limits<uint32_t>::max())
      fail(ErrorKind::kStream, "tensor " + info.to_string() + " is " + std::to_string(stride) +
                                   " bytes along dimension " + std::to_string(i) +
                                   ": the message's uint32 stride cannot hold it");
    out[rank - 1 - i] = LayoutDim{label, d, static_cast<uint32_t>(stride)};
  }
  return out;
}

TensorInfo info_from_wire(const WireTensor &t, std::size_t index, const std::string &topic) {
  const std::string where = "topic " + topic + ", tensor " + std::to_string(index) + ": ";
  if (t.layout.empty()) fail(ErrorKind::kStream, where + "the message has no layout.dim entries");
  TensorInfo info;
  const std::string &label = t.layout.front().label;
  auto type = type_from_name(label);
  if (!type)
    fail(ErrorKind::kStream,
         where + "layout.dim[0].label '" + label + "' is not a tensor type name (e.g. float32)");
  info.type = *type;
  const std::size_t n = t.layout.size();
  for (std::size_t j = 0; j < n; ++j) {
    const LayoutDim &d = t.layout[j];
    if (d.label != label)
      fail(ErrorKind::kStream, where + "layout.dim[" + std::to_string(j) + "].label '" + d.label +
                                   "' differs from layout.dim[0].label '" + label + "'");
    if (d.size == 0)
      fail(ErrorKind::kStream, where + "layout.dim[" + std::to_string(j) + "].size is 0");
    const std::size_t nns_index = n - 1 - j;  // outermost first on the wire
    if (nns_index >= kRankLimit) {
      if (d.size != 1)
        fail(ErrorKind::kStream, where + "layout.dim has " + std::to_string(n) +
                                     " entries and dimension " + std::to_string(nns_index) +
                                     " is " + std::to_string(d.size) + "; at most " +
                                     std::to_string(kRankLimit) + " dimensions may exceed 1");
      continue;
    }
    info.dims[nns_index] = d.size;
  }
  const std::size_t expected = info.byte_size();
  const std::size_t got = t.data.size() >= t.data_offset ? t.data.size() - t.data_offset : 0;
  if (t.data.size() < t.data_offset || got != expected)
    fail(ErrorKind::kStream, where + "layout says " + info.to_string() + " (" +
                                 std::to_string(expected) + " bytes) but data has " +
                                 std::to_string(t.data.size()) + " bytes with data_offset " +
                                 std::to_string(t.data_offset));
  return info;
}

TensorsInfo info_from_wire(const WireMessage &m, const std::string &topic) {
  if (m.empty()) fail(ErrorKind::kStream, "topic " + topic + ": the message has no tensors");
  if (m.size() > kTensorLimit)
    fail(ErrorKind::kStream, "topic " + topic + ": the message has " + std::to_string(m.size()) +
                                 " tensors, at most " + std::to_string(kTensorLimit) +
                                 " are supported");
  TensorsInfo info;
  info.format = TensorFormat::kStatic;
  for (std::size_t i = 0; i < m.size(); ++i) info.tensors.push_back(info_from_wire(m[i], i, topic));
  return info;
}

bool MessageQueue::push(WireMessage &&m) {
  bool dropped = false;
  {
    std::lock_guard lock(mutex_);
    if (limit_ > 0 && items_.size() >= limit_) {
      items_.pop_front();
      dropped = true;
    }
    items_.push_back(std::move(m));
  }
  cv_.notify_one();
  return dropped;
}

MessageQueue::PopResult MessageQueue::pop(WireMessage &out, std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  cv_.wait_for(lock, timeout, [&] { return unlocked_ || !items_.empty(); });
  if (unlocked_) return PopResult::kUnlocked;
  if (items_.empty()) return PopResult::kTimeout;
  out = std::move(items_.front());
  items_.pop_front();
  return PopResult::kMessage;
}

void MessageQueue::unlock() {
  {
    std::lock_guard lock(mutex_);
    unlocked_ = true;
  }
  cv_.notify_all();
}

void MessageQueue::relock() {
  std::lock_guard lock(mutex_);
  unlocked_ = false;
}

void MessageQueue::clear() {
  std::lock_guard lock(mutex_);
  items_.clear();
}

}  // namespace nns::ros

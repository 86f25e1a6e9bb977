// SPDX-License-Identifier: LGPL-2.1-only
// The transport-independent half of tensor_ros_src / tensor_ros_sink: how a frame of static
// tensors maps onto nnstreamer-ros's message (nns_ros_bridge/Tensors: one
// std_msgs/UInt8MultiArray per tensor), and the interface a ROS transport implements.
// No GStreamer and no ROS headers here; ros1_transport.cc is the roscpp transport, a ROS 2
// transport would be one more file implementing the same three functions.
//
// Layout of one tensor (as nnstreamer-ros writes it): layout.dim lists the dimensions outermost
// first (NNStreamer's last dimension first); every entry's label is the element type name
// ("float32"); size is the dimension; stride is the byte size of one step of that dimension
// (so dim[0].stride is the tensor's byte size and the innermost stride is
// element_size * innermost dimension); data_offset is 0 and data holds the raw bytes.
#pragma once

#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <deque>
#include <functional>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "core/tensor_info.h"

namespace nns::ros {

// Message package, type and the MD5 that ROS computes from src/ros/msg/Tensors.msg.
inline constexpr const char *kMessageType = "nns_ros_bridge/Tensors";
inline constexpr const char *kMessageMd5 = "c55fd4e2c1bd4bdb0a730e17956ba23c";
// nnstreamer-ros (NNStreamer 1.x) always wrote 4 dimensions: we write max(rank, 4).
inline constexpr std::size_t kMinWireRank = 4;

// One std_msgs/MultiArrayDimension.
struct LayoutDim {
  std::string label;
  uint32_t size = 0;
  uint32_t stride = 0;
  // Spelled out: ros1_transport.cc includes this header as C++17 (see src/ros/CMakeLists.txt).
  bool operator==(const LayoutDim &o) const {
    return label == o.label && size == o.size && stride == o.stride;
  }
};

// The layout nnstreamer-ros gives a tensor of `info` (outermost dimension first). Throws
// nns::Error(kStream) when a stride does not fit the message's uint32.
std::vector<LayoutDim> layout_for(const TensorInfo &info);

// One received std_msgs/UInt8MultiArray.
struct WireTensor {
  std::vector<LayoutDim> layout;
  uint32_t data_offset = 0;
  std::vector<uint8_t> data;
};
using WireMessage = std::vector<WireTensor>;

// Reads the type and dimensions of tensor `index` from a received message. Throws
// nns::Error(kStream) naming `topic`, the tensor and what is wrong (no dimensions, unknown or
// mixed labels, a zero size, more than 16 non-1 dimensions, data size not matching).
TensorInfo info_from_wire(const WireTensor &t, std::size_t index, const std::string &topic);
TensorsInfo info_from_wire(const WireMessage &m, const std::string &topic);

// A received message waiting for the streaming thread. Bounded: when full the oldest is dropped
// (ROS's own subscriber-queue policy). pop() waits up to `timeout`; unlock() makes waiting
// pops return at once until relock().
class MessageQueue {
 public:
  explicit MessageQueue(std::size_t limit) : limit_(limit) {}
  // Returns true when an older message had to be dropped.
  bool push(WireMessage &&m);
  enum class PopResult { kMessage, kTimeout, kUnlocked };
  PopResult pop(WireMessage &out, std::chrono::milliseconds timeout);
  void unlock();
  void relock();
  void clear();

 private:
  std::mutex mutex_;
  std::condition_variable cv_;
  std::deque<WireMessage> items_;
  std::size_t limit_;
  bool unlocked_ = false;
};

// --- The transport interface (implemented once per ROS version). ---

// A view of one tensor to publish.
struct TensorView {
  const uint8_t *data = nullptr;
  std::size_t size = 0;
  const std::vector<LayoutDim> *layout = nullptr;
};

class Publisher {
 public:
  virtual ~Publisher() = default;
  virtual void publish(const std::vector<TensorView> &tensors) = 0;
  virtual std::size_t subscriber_count() const = 0;
  virtual const std::string &topic() const = 0;  // resolved name
};

class Subscriber {
 public:
  virtual ~Subscriber() = default;
  virtual const std::string &topic() const = 0;  // resolved name
};

// "ROS 1 (roscpp)": for messages.
const char *transport_name();
// Connects to the ROS master (throws nns::Error(kSettings) naming the variable when it is not
// configured, kNotFound naming the master and the topic when it cannot be reached) and
// advertises / subscribes `topic`. Relative names resolve in the root namespace.
std::unique_ptr<Publisher> make_publisher(const std::string &topic, uint32_t queue_size);
std::unique_ptr<Subscriber> make_subscriber(const std::string &topic, uint32_t queue_size,
                                            std::function<void(WireMessage &&)> on_message);

// Bag files in the transport's own format (rosbag for ROS 1). No master is needed.
class BagWriter {
 public:
  virtual ~BagWriter() = default;
  // Appends one message on `topic`, stamped with the wall-clock time.
  virtual void write(const std::string &topic, const std::vector<TensorView> &tensors) = 0;
};
class BagReader {
 public:
  virtual ~BagReader() = default;
  // The next nns_ros_bridge/Tensors message of any topic (others are skipped); false at the end.
  virtual bool next(WireMessage &out) = 0;
};
// Both throw nns::Error(kNotFound / kSettings) naming the path and the reason.
std::unique_ptr<BagWriter> open_bag_writer(const std::string &path);
std::unique_ptr<BagReader> open_bag_reader(const std::string &path);

}  // namespace nns::ros

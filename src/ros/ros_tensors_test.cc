// SPDX-License-Identifier: LGPL-2.1-only
// The nnstreamer-ros message layout (ros_tensors.h) without ROS: exact dims/labels/strides as
// nnstreamer-ros writes them, decoding, and the errors for bad messages.
#include "ros/ros_tensors.h"

#include <gtest/gtest.h>

#include <thread>

#include "core/error.h"

using nns::ros::LayoutDim;
using nns::ros::WireTensor;

namespace {

nns::TensorInfo info(nns::TensorType t, std::initializer_list<uint32_t> d) {
  nns::TensorInfo i;
  i.type = t;
  i.dims = nns::make_dims(d);
  return i;
}

std::string error_of(const WireTensor &t) {
  try {
    nns::ros::info_from_wire(t, 1, "/t");
  } catch (const nns::Error &e) {
    return e.what();
  }
  return "";
}

}  // namespace

TEST(RosLayout, FourDimsOutermostFirstWithByteStrides) {
  // uint8 3:4:2 (innermost first): padded to 4 dims, outermost first.
  auto l = nns::ros::layout_for(info(nns::TensorType::kUInt8, {3, 4, 2}));
  std::vector<LayoutDim> want{
      {"uint8", 1, 24}, {"uint8", 2, 24}, {"uint8", 4, 12}, {"uint8", 3, 3}};
  EXPECT_EQ(l, want);
}

TEST(RosLayout, StridesAreBytesForWideTypes) {
  auto l = nns::ros::layout_for(info(nns::TensorType::kFloat32, {5}));
  std::vector<LayoutDim> want{
      {"float32", 1, 20}, {"float32", 1, 20}, {"float32", 1, 20}, {"float32", 5, 20}};
  EXPECT_EQ(l, want);
}

TEST(RosLayout, RankAboveFourKeepsEveryDim) {
  auto l = nns::ros::layout_for(info(nns::TensorType::kInt16, {2, 3, 4, 5, 6}));
  ASSERT_EQ(l.size(), 5u);
  EXPECT_EQ(l[0], (LayoutDim{"int16", 6, 1440}));
  EXPECT_EQ(l[4], (LayoutDim{"int16", 2, 4}));
}

TEST(RosLayout, RoundTripThroughWire) {
  for (auto i : {info(nns::TensorType::kFloat64, {1, 7}), info(nns::TensorType::kInt64, {2, 3}),
                 info(nns::TensorType::kFloat16, {4, 4, 4, 4, 2, 1, 3})}) {
    WireTensor w{nns::ros::layout_for(i), 0, std::vector<uint8_t>(i.byte_size())};
    EXPECT_TRUE(nns::ros::info_from_wire(w, 0, "/t").same_as(i)) << i.to_string();
  }
}

TEST(RosLayout, DataOffsetIsSkipped) {
  auto i = info(nns::TensorType::kUInt8, {2});
  WireTensor w{nns::ros::layout_for(i), 3, std::vector<uint8_t>(5)};
  EXPECT_TRUE(nns::ros::info_from_wire(w, 0, "/t").same_as(i));
}

TEST(RosLayout, BadMessagesNameTopicTensorAndField) {
  WireTensor empty;
  EXPECT_EQ(error_of(empty), "topic /t, tensor 1: the message has no layout.dim entries");
  WireTensor badlabel{{{"rgb", 3, 3}}, 0, std::vector<uint8_t>(3)};
  EXPECT_EQ(
      error_of(badlabel),
      "topic /t, tensor 1: layout.dim[0].label 'rgb' is not a tensor type name (e.g. float32)");
  WireTensor mixed{{{"uint8", 1, 3}, {"int8", 3, 3}}, 0, std::vector<uint8_t>(3)};
  EXPECT_EQ(error_of(mixed),
            "topic /t, tensor 1: layout.dim[1].label 'int8' differs from layout.dim[0].label "
            "'uint8'");
  WireTensor zero{{{"uint8", 0, 0}}, 0, {}};
  EXPECT_EQ(error_of(zero), "topic /t, tensor 1: layout.dim[0].size is 0");
  WireTensor size{{{"float32", 2, 8}, {"float32", 3, 12}}, 0, std::vector<uint8_t>(20)};
  EXPECT_EQ(error_of(size),
            "topic /t, tensor 1: layout says float32 3:2 (24 bytes) but data has 20 bytes with "
            "data_offset 0");
  std::vector<LayoutDim> deep(17, LayoutDim{"uint8", 1, 2});
  deep[0].size = 2;
  EXPECT_EQ(error_of(WireTensor{deep, 0, std::vector<uint8_t>(2)}),
            "topic /t, tensor 1: layout.dim has 17 entries and dimension 16 is 2; at most 16 "
            "dimensions may exceed 1");
  deep[0].size = 1;  // outer 1s beyond the limit are fine
  deep[16].size = 2;
  EXPECT_EQ(error_of(WireTensor{deep, 0, std::vector<uint8_t>(2)}), "");
}

TEST(RosLayout, EmptyMessageIsAnError) {
  try {
    nns::ros::info_from_wire(nns::ros::WireMessage{}, "/t");
    FAIL();
  } catch (const nns::Error &e) {
    EXPECT_STREQ(e.what(), "topic /t: the message has no tensors");
  }
}

TEST(RosMessageQueue, DropsOldestWhenFullAndUnlocks) {
  nns::ros::MessageQueue q(2);
  auto msg = [](uint8_t v) { return nns::ros::WireMessage{WireTensor{{}, 0, {v}}}; };
  EXPECT_FALSE(q.push(msg(1)));
  EXPECT_FALSE(q.push(msg(2)));
  EXPECT_TRUE(q.push(msg(3)));
  nns::ros::WireMessage out;
  using R = nns::ros::MessageQueue::PopResult;
  ASSERT_EQ(q.pop(out, std::chrono::milliseconds(0)), R::kMessage);
  EXPECT_EQ(out[0].data[0], 2);
  ASSERT_EQ(q.pop(out, std::chrono::milliseconds(0)), R::kMessage);
  EXPECT_EQ(out[0].data[0], 3);
  EXPECT_EQ(q.pop(out, std::chrono::milliseconds(20)), R::kTimeout);
  std::thread t([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(20));
    q.unlock();
  });
  EXPECT_EQ(q.pop(out, std::chrono::seconds(10)), R::kUnlocked);
  t.join();
  q.relock();
  q.push(msg(4));
  EXPECT_EQ(q.pop(out, std::chrono::milliseconds(0)), R::kMessage);
}

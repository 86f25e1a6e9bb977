// SPDX-License-Identifier: LGPL-2.1-only
// A plain roscpp node (tests/ros): subscribes to nns_ros_bridge/Tensors on IN and republishes
// every message unchanged on OUT, COUNT times, then exits 0 (1 after 10 s without them). It
// subscribes only once OUT has a subscriber, so nothing it forwards is published into the void.
//   ros_cpp_peer IN OUT COUNT
// Built as C++17 with the gencpp header, like any ROS 1 C++ node.
#include <ros/ros.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <string>
#include <thread>

#include "nns_ros_bridge/Tensors.h"

int main(int argc, char **argv) {
  if (argc != 4) {
    std::fprintf(stderr, "usage: ros_cpp_peer IN OUT COUNT\n");
    return 2;
  }
  const std::string in = argv[1], out = argv[2];
  const int count = std::atoi(argv[3]);
  int no_args = 0;
  ros::init(no_args, nullptr, "ros_cpp_peer", ros::init_options::AnonymousName);
  ros::NodeHandle nh;
  ros::Publisher pub = nh.advertise<nns_ros_bridge::Tensors>(out, 100);
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (pub.getNumSubscribers() < 1) {
    if (std::chrono::steady_clock::now() > deadline) {
      std::fprintf(stderr, "ros_cpp_peer: no subscriber on %s within 10 s\n", out.c_str());
      return 1;
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  int forwarded = 0;
  boost::function<void(const nns_ros_bridge::Tensors::ConstPtr &)> cb =
      [&](const nns_ros_bridge::Tensors::ConstPtr &m) {
        pub.publish(*m);
        ++forwarded;
      };
  ros::Subscriber sub = nh.subscribe<nns_ros_bridge::Tensors>(in, 100, cb);
  while (ros::ok() && forwarded < count && std::chrono::steady_clock::now() < deadline) {
    ros::spinOnce();
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(500));  // let the last message leave
  if (forwarded < count) {
    std::fprintf(stderr, "ros_cpp_peer: %d of %d messages on %s within 10 s\n", forwarded, count,
                 in.c_str());
    return 1;
  }
  return 0;
}

// SPDX-License-Identifier: LGPL-2.1-only
// ROS 1 transport (roscpp) of tensor_ros_src / tensor_ros_sink: the three functions of
// ros_tensors.h. The message class nns_ros_bridge::Tensors is generated at build time by gencpp
// from src/ros/msg/Tensors.msg.
//
// roscpp has one node per process: ros::init runs once (node "nnstreamer_<random>", no SIGINT
// handler, no /rosout), the first NodeHandle starts the node and the last one shuts it down, so
// every element holds its own NodeHandle. The master is asked first (ros::master::check), so a
// missing master fails at once instead of roscpp's endless retry; later master calls retry for
// at most kMasterRetry.
#include <ros/callback_queue.h>
#include <ros/ros.h>
#include <rosbag/bag.h>
#include <rosbag/view.h>

#include <mutex>

#include "core/error.h"
#include "nns_ros_bridge/Tensors.h"
#include "ros/ros_tensors.h"

namespace nns::ros {
namespace {

constexpr double kMasterRetrySeconds = 5.0;

static_assert(sizeof(uint32_t) == sizeof(decltype(std_msgs::MultiArrayDimension::size)));

std::mutex &init_mutex() {
  static std::mutex m;
  return m;
}

// Makes sure roscpp is initialised and the master answers; returns the resolved topic name.
std::string connect(const std::string &topic, const char *what) {
  std::lock_guard lock(init_mutex());
  if (topic.empty()) fail(ErrorKind::kSettings, "property 'topic' is empty: give a ROS topic name");
  if (!::ros::isInitialized()) {
    const char *uri = std::getenv("ROS_MASTER_URI");
    if (!uri || !*uri)
      fail(ErrorKind::kSettings, std::string("ROS_MASTER_URI is not set in the environment: "
                                             "cannot reach a ROS master to ") +
                                     what + " topic '" + topic + "'");
    try {
      ::ros::M_string remappings;
      ::ros::init(remappings, "nnstreamer",
                  ::ros::init_options::AnonymousName | ::ros::init_options::NoSigintHandler |
                      ::ros::init_options::NoRosout);
    } catch (const ::ros::Exception &e) {
      fail(ErrorKind::kSettings,
           std::string("ROS initialisation failed (ROS_MASTER_URI=") + uri + "): " + e.what());
    }
    ::ros::master::setRetryTimeout(::ros::WallDuration(kMasterRetrySeconds));
  }
  std::string error;
  if (!::ros::names::validate(topic, error))
    fail(ErrorKind::kSettings,
         "property 'topic': '" + topic + "' is not a valid ROS name: " + error);
  if (!::ros::master::check())
    fail(ErrorKind::kNotFound, "ROS master " + ::ros::master::getURI() + " is not reachable (to " +
                                   what + " topic '" + topic +
                                   "'): start roscore/rosmaster or fix ROS_MASTER_URI");
  std::string resolved = topic.front() == '/' ? topic : "/" + topic;
  return ::ros::names::resolve(resolved);
}

nns_ros_bridge::Tensors to_message(const std::vector<TensorView> &tensors) {
  nns_ros_bridge::Tensors msg;
  msg.tensors.resize(tensors.size());
  for (std::size_t i = 0; i < tensors.size(); ++i) {
    auto &out = msg.tensors[i];
    const TensorView &v = tensors[i];
    out.layout.dim.resize(v.layout->size());
    for (std::size_t j = 0; j < v.layout->size(); ++j) {
      out.layout.dim[j].label = (*v.layout)[j].label;
      out.layout.dim[j].size = (*v.layout)[j].size;
      out.layout.dim[j].stride = (*v.layout)[j].stride;
    }
    out.layout.data_offset = 0;
    out.data.assign(v.data, v.data + v.size);
  }
  return msg;
}

WireMessage from_message(const nns_ros_bridge::Tensors &m) {
  WireMessage out(m.tensors.size());
  for (std::size_t i = 0; i < m.tensors.size(); ++i) {
    const auto &in = m.tensors[i];
    out[i].layout.reserve(in.layout.dim.size());
    for (const auto &d : in.layout.dim)
      out[i].layout.push_back(LayoutDim{d.label, d.size, d.stride});
    out[i].data_offset = in.layout.data_offset;
    out[i].data = in.data;
  }
  return out;
}

class Ros1Publisher final : public Publisher {
 public:
  Ros1Publisher(const std::string &topic, uint32_t queue_size)
      : topic_(connect(topic, "publish")), nh_("/") {
    try {
      pub_ = nh_.advertise<nns_ros_bridge::Tensors>(topic_, queue_size);
    } catch (const ::ros::Exception &e) {
      fail(ErrorKind::kNotFound, "cannot advertise topic '" + topic_ + "': " + e.what());
    }
    if (!pub_)
      fail(ErrorKind::kNotFound,
           "cannot advertise topic '" + topic_ + "' at master " + ::ros::master::getURI());
  }
  ~Ros1Publisher() override { pub_.shutdown(); }

  void publish(const std::vector<TensorView> &tensors) override {
    nns_ros_bridge::Tensors msg = to_message(tensors);
    if (!::ros::ok())
      fail(ErrorKind::kStream, "ROS is shut down: cannot publish on topic '" + topic_ + "'");
    pub_.publish(msg);
  }
  std::size_t subscriber_count() const override { return pub_.getNumSubscribers(); }
  const std::string &topic() const override { return topic_; }

 private:
  std::string topic_;
  ::ros::NodeHandle nh_;
  ::ros::Publisher pub_;
};

class Ros1Subscriber final : public Subscriber {
 public:
  Ros1Subscriber(const std::string &topic, uint32_t queue_size,
                 std::function<void(WireMessage &&)> on_message)
      : topic_(connect(topic, "subscribe to")), nh_("/"), on_message_(std::move(on_message)) {
    nh_.setCallbackQueue(&queue_);
    boost::function<void(const nns_ros_bridge::Tensors::ConstPtr &)> cb =
        [this](const nns_ros_bridge::Tensors::ConstPtr &m) { deliver(*m); };
    try {
      sub_ = nh_.subscribe<nns_ros_bridge::Tensors>(topic_, queue_size, cb);
    } catch (const ::ros::Exception &e) {
      fail(ErrorKind::kNotFound, "cannot subscribe to topic '" + topic_ + "': " + e.what());
    }
    if (!sub_)
      fail(ErrorKind::kNotFound,
           "cannot subscribe to topic '" + topic_ + "' at master " + ::ros::master::getURI());
    spinner_ = std::make_unique<::ros::AsyncSpinner>(1, &queue_);
    spinner_->start();
  }
  ~Ros1Subscriber() override {
    spinner_->stop();
    sub_.shutdown();
    queue_.clear();
  }
  const std::string &topic() const override { return topic_; }

 private:
  void deliver(const nns_ros_bridge::Tensors &m) { on_message_(from_message(m)); }

  std::string topic_;
  ::ros::CallbackQueue queue_;
  ::ros::NodeHandle nh_;
  std::function<void(WireMessage &&)> on_message_;
  ::ros::Subscriber sub_;
  std::unique_ptr<::ros::AsyncSpinner> spinner_;
};

class Ros1BagWriter final : public BagWriter {
 public:
  explicit Ros1BagWriter(const std::string &path) : path_(path) {
    try {
      bag_.open(path, rosbag::bagmode::Write);
    } catch (const rosbag::BagException &e) {
      fail(ErrorKind::kNotFound,
           "property 'location': cannot create the rosbag '" + path + "': " + e.what());
    }
  }
  ~Ros1BagWriter() override {
    try {
      bag_.close();
    } catch (...) {
    }
  }
  void write(const std::string &topic, const std::vector<TensorView> &tensors) override {
    const auto now = std::chrono::system_clock::now().time_since_epoch();
    const auto ns = std::chrono::duration_cast<std::chrono::nanoseconds>(now).count();
    ::ros::Time stamp;
    stamp.fromNSec(static_cast<uint64_t>(ns));
    try {
      bag_.write(topic, stamp, to_message(tensors));
    } catch (const rosbag::BagException &e) {
      fail(ErrorKind::kStream, "cannot write to the rosbag '" + path_ + "': " + e.what());
    }
  }

 private:
  std::string path_;
  rosbag::Bag bag_;
};

class Ros1BagReader final : public BagReader {
 public:
  explicit Ros1BagReader(const std::string &path) : path_(path) {
    try {
      bag_.open(path, rosbag::bagmode::Read);
      view_ = std::make_unique<rosbag::View>(bag_, rosbag::TypeQuery(kMessageType));
      it_ = view_->begin();
    } catch (const rosbag::BagException &e) {
      fail(ErrorKind::kNotFound,
           "property 'location': cannot read the rosbag '" + path + "': " + e.what());
    }
  }
  bool next(WireMessage &out) override {
    if (it_ == view_->end()) return false;
    try {
      auto m = it_->instantiate<nns_ros_bridge::Tensors>();
      if (!m)
        fail(ErrorKind::kStream, "rosbag '" + path_ + "': a message on " + it_->getTopic() +
                                     " is not " + kMessageType + " (MD5 " + it_->getMD5Sum() + ")");
      out = from_message(*m);
      ++it_;
    } catch (const rosbag::BagException &e) {
      fail(ErrorKind::kStream, "rosbag '" + path_ + "': " + e.what());
    }
    return true;
  }

 private:
  std::string path_;
  rosbag::Bag bag_;
  std::unique_ptr<rosbag::View> view_;
  rosbag::View::iterator it_;
};

}  // namespace

std::unique_ptr<BagWriter> open_bag_writer(const std::string &path) {
  return std::make_unique<Ros1BagWriter>(path);
}

std::unique_ptr<BagReader> open_bag_reader(const std::string &path) {
  return std::make_unique<Ros1BagReader>(path);
}

const char *transport_name() {
  return "ROS 1 (roscpp)";
}

std::unique_ptr<Publisher> make_publisher(const std::string &topic, uint32_t queue_size) {
  return std::make_unique<Ros1Publisher>(topic, queue_size);
}

std::unique_ptr<Subscriber> make_subscriber(const std::string &topic, uint32_t queue_size,
                                            std::function<void(WireMessage &&)> on_message) {
  return std::make_unique<Ros1Subscriber>(topic, queue_size, std::move(on_message));
}

}  // namespace nns::ros

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_ros_sink / tensor_ros_src against a real rosmaster (the ctest fixture ros.master_start,
// tests/ros/ros_master.py, writes build/ros-test/master.env) and a plain rospy node
// (tests/ros/ros_peer.py with the generated nns_ros_bridge/Tensors class). The elements are
// loaded from build/plugin/libnnstreamer_ros.so, the module gst-inspect-1.0 sees.
// Registered by tests/ros.cmake (only when the module is built); each case is its own process.
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gtest/gtest.h>

#include <arpa/inet.h>
#include <netinet/in.h>
#include <sys/socket.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

namespace {

using Bytes = std::vector<uint8_t>;
using Clock = std::chrono::steady_clock;

const std::string kBuild = NNS_BUILD_DIR;

// Loads the module and points ROS at the fixture's master (or at `master_uri` if given).
void use_ros(const std::string &master_uri = "") {
  static bool loaded = false;
  if (!loaded) {
    GError *err = nullptr;
    GstPlugin *p = gst_plugin_load_file((kBuild + "/plugin/libnnstreamer_ros.so").c_str(), &err);
    ASSERT_NE(p, nullptr) << (err ? err->message : "?");
    gst_object_unref(p);
    loaded = true;
  }
  setenv("ROS_IP", "127.0.0.1", 1);
  unsetenv("ROS_HOSTNAME");
  setenv("PYTHONPATH", (kBuild + "/ros/python").c_str(), 1);
  // rospy's log files go to the build tree, not ~/.ros.
  setenv("ROS_HOME", (kBuild + "/ros-test").c_str(), 1);
  setenv("ROS_LOG_DIR", (kBuild + "/ros-test/log").c_str(), 1);
  std::string uri = master_uri;
  if (uri.empty()) {
    std::ifstream f(kBuild + "/ros-test/master.env");
    std::string line;
    while (std::getline(f, line))
      if (line.rfind("ROS_MASTER_URI=", 0) == 0) uri = line.substr(15);
    ASSERT_FALSE(uri.empty()) << "no rosmaster: run through ctest (fixture ros.master_start)";
  }
  setenv("ROS_MASTER_URI", uri.c_str(), 1);
}

GstElement *launch(const std::string &desc) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  EXPECT_TRUE(p && !err) << desc << ": " << (err ? err->message : "");
  if (err) g_error_free(err);
  return p;
}

// A deterministic byte pattern per case.
Bytes pattern(std::size_t n, uint8_t seed) {
  Bytes b(n);
  for (std::size_t i = 0; i < n; ++i) b[i] = static_cast<uint8_t>(seed + i * 37 + (i >> 8));
  return b;
}

std::string hex(const Bytes &b) {
  static const char *d = "0123456789abcdef";
  std::string s;
  for (uint8_t v : b) s += {d[v >> 4], d[v & 15]};
  return s;
}

// One frame: the bytes of every tensor.
using Frame = std::vector<Bytes>;

struct Received {
  std::optional<nns::TensorsConfig> config;
  std::vector<Frame> frames;
};

// Pulls up to `count` frames from appsink `out` (5 s each at most).
Received pull(GstElement *pipeline, std::size_t count) {
  Received r;
  GstElement *sink = gst_bin_get_by_name(GST_BIN(pipeline), "out");
  for (std::size_t i = 0; i < count; ++i) {
    GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 5 * GST_SECOND);
    if (!s) break;
    if (!r.config) r.config = nns::gst::config_from_caps(gst_sample_get_caps(s));
    GstBuffer *buf = gst_sample_get_buffer(s);
    Frame f;
    for (std::size_t t = 0; t < nns::gst::buffer_tensor_count(buf); ++t) {
      GstMemory *m = nns::gst::buffer_get_tensor(buf, t);
      GstMapInfo map;
      gst_memory_map(m, &map, GST_MAP_READ);
      f.emplace_back(map.data, map.data + map.size);
      gst_memory_unmap(m, &map);
      gst_memory_unref(m);
    }
    r.frames.push_back(std::move(f));
    gst_sample_unref(s);
  }
  gst_object_unref(sink);
  return r;
}

// Runs `desc` (an appsrc named "in" feeding tensor_ros_sink) with `frames`, one memory per
// tensor, and waits for EOS.
nns::test::RunResult publish(const std::string &desc, const std::vector<Frame> &frames) {
  GstElement *p = launch(desc);
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "in");
  for (const Frame &f : frames) {
    GstBuffer *buf = gst_buffer_new();
    for (const Bytes &t : f) {
      gpointer copy = g_memdup2(t.data(), t.size());
      GstMemory *m = gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, copy, t.size(), 0, t.size(),
                                            copy, g_free);
      gst_buffer_append_memory(buf, m);
    }
    gst_app_src_push_buffer(GST_APP_SRC(src), buf);
  }
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  gst_object_unref(src);
  auto r = nns::test::run_pipeline(p, 15.0);
  gst_object_unref(p);
  return r;
}

// A peer node process (ros_peer.py by default, or any command); finish() returns its exit
// status and stdout.
struct Peer {
  FILE *f = nullptr;
  explicit Peer(const std::string &args, bool python = true) {
    std::string cmd = python ? "/usr/bin/python3 " + std::string(NNS_SOURCE_DIR) +
                                   "/tests/ros/ros_peer.py " + args
                             : args;
    f = popen(cmd.c_str(), "r");
  }
  std::pair<int, std::string> finish() {
    std::string out;
    char chunk[4096];
    std::size_t n;
    while ((n = fread(chunk, 1, sizeof chunk, f)) > 0) out.append(chunk, n);
    int status = pclose(f);
    f = nullptr;
    return {status, out};
  }
  ~Peer() {
    if (f) finish();
  }
};

struct Case {
  const char *topic;
  const char *dims;
  const char *types;
  std::size_t num;
};

}  // namespace

// Several types and shapes (rank 1 to 7, one to three tensors): caps and bytes identical.
TEST(TensorRos, RoundTripKeepsCapsAndBytes) {
  use_ros();
  const Case cases[] = {
      {"/nns_test/rt_u8", "3:4:2", "uint8", 1},
      {"/nns_test/rt_f32_i16", "5.2:3:4:5:6", "float32.int16", 2},
      {"/nns_test/rt_three", "1:7.2:3.3", "float64.int64.uint32", 3},
      {"/nns_test/rt_f16", "2:1:1:1:1:1:3", "float16", 1},
  };
  for (const Case &c : cases) {
    SCOPED_TRACE(c.topic);
    std::string caps = std::string("other/tensors,format=static,num_tensors=") +
                       std::to_string(c.num) + ",dimensions=" + c.dims + ",types=" + c.types +
                       ",framerate=0/1";
    GstCaps *want_caps = gst_caps_from_string(caps.c_str());
    ASSERT_NE(want_caps, nullptr) << caps;
    nns::TensorsConfig want = nns::gst::config_from_caps(want_caps);
    gst_caps_unref(want_caps);
    std::vector<Frame> frames;
    for (uint8_t k = 0; k < 3; ++k) {
      Frame f;
      for (std::size_t t = 0; t < want.info.size(); ++t)
        f.push_back(pattern(want.info[t].byte_size(), static_cast<uint8_t>(k * 16 + t)));
      frames.push_back(f);
    }
    GstElement *rx = launch(std::string("tensor_ros_src topic=") + c.topic +
                            " num-buffers=3 ! appsink name=out sync=false");
    gst_element_set_state(rx, GST_STATE_PLAYING);
    auto r = publish("appsrc name=in format=time caps=\"" + caps +
                         "\" ! tensor_ros_sink topic=" + c.topic + " wait-subscribers=1",
                     frames);
    EXPECT_TRUE(r.eos) << r.error_text;
    Received got = pull(rx, 3);
    gst_element_set_state(rx, GST_STATE_NULL);
    gst_object_unref(rx);
    ASSERT_TRUE(got.config.has_value());
    EXPECT_TRUE(got.config->info.same_as(want.info))
        << got.config->info.to_string() << " vs " << want.info.to_string();
    EXPECT_EQ(got.config->rate_n, 1);  // rate=1 (default) announced as 1/1
    EXPECT_EQ(got.frames, frames);
  }
}

// A plain rospy node receives exactly nnstreamer-ros's layout and the bytes.
TEST(TensorRos, RospyNodeReceivesWhatSinkPublishes) {
  use_ros();
  Peer peer("recv /nns_test/to_py 2");
  Bytes a = pattern(24, 1), b = pattern(4, 2), c = pattern(24, 3), d = pattern(4, 4);
  auto r = publish(
      "appsrc name=in caps=\"other/tensors,format=static,num_tensors=2,dimensions=2:3.2,"
      "types=float32.int16,framerate=0/1\" ! tensor_ros_sink topic=/nns_test/to_py "
      "wait-subscribers=1",
      {{a, b}, {c, d}});
  EXPECT_TRUE(r.eos) << r.error_text;
  auto [status, out] = peer.finish();
  EXPECT_EQ(status, 0);
  auto line = [](const Bytes &x, const Bytes &y) {
    return "{\"tensors\": [{\"dims\": [[\"float32\", 1, 24], [\"float32\", 1, 24], "
           "[\"float32\", 3, 24], [\"float32\", 2, 8]], \"offset\": 0, \"data\": \"" +
           hex(x) +
           "\"}, {\"dims\": [[\"int16\", 1, 4], [\"int16\", 1, 4], [\"int16\", 1, 4], "
           "[\"int16\", 2, 4]], \"offset\": 0, \"data\": \"" +
           hex(y) + "\"}]}\n";
  };
  EXPECT_EQ(out, line(a, b) + line(c, d));
}

// tensor_ros_src takes what a rospy node publishes; EOS `timeout` s after the last message
// (3 s: the rospy node itself needs about 1 s to start and connect).
TEST(TensorRos, SrcReceivesWhatRospyNodePublishes) {
  use_ros();
  Bytes a = pattern(12, 5), b = pattern(3, 6), c = pattern(12, 7), d = pattern(3, 8);
  GstElement *rx =
      launch("tensor_ros_src topic=/nns_test/from_py timeout=3 ! appsink name=out sync=false");
  gst_element_set_state(rx, GST_STATE_PLAYING);
  auto msg = [](const Bytes &x, const Bytes &y) {
    return "[{\"type\": \"int16\", \"dims\": [3, 2], \"data\": \"" + hex(x) +
           "\"}, {\"type\": \"uint8\", \"dims\": [3, 1, 1, 1, 1], \"data\": \"" + hex(y) + "\"}]";
  };
  Peer peer("send /nns_test/from_py '[" + msg(a, b) + ", " + msg(c, d) + "]'");
  Received got = pull(rx, 3);  // the third pull ends at EOS
  EXPECT_EQ(peer.finish().first, 0);
  GstBus *bus = gst_element_get_bus(rx);
  GstMessage *eos = gst_bus_timed_pop_filtered(bus, 5 * GST_SECOND, GST_MESSAGE_EOS);
  EXPECT_NE(eos, nullptr) << "no EOS 3 s after the last message";
  if (eos) gst_message_unref(eos);
  gst_object_unref(bus);
  gst_element_set_state(rx, GST_STATE_NULL);
  gst_object_unref(rx);
  ASSERT_TRUE(got.config.has_value());
  // The wire's rank is kept: 4 dims for int16 3:2 (padded by ros_peer.py), 5 for the uint8.
  EXPECT_EQ(got.config->info.to_string(), "2 tensor(s): [0] int16 3:2:1:1, [1] uint8 3:1:1:1:1");
  EXPECT_EQ(got.frames, (std::vector<Frame>{{a, b}, {c, d}}));
}

// A plain roscpp node (tests/ros/ros_cpp_peer.cc) forwards what the sink publishes to the
// source: bytes and caps unchanged through a separate C++ ROS process.
TEST(TensorRos, RoscppNodeForwardsSinkToSrc) {
  use_ros();
  GstElement *rx =
      launch("tensor_ros_src topic=/nns_test/cpp_out num-buffers=2 ! appsink name=out sync=false");
  gst_element_set_state(rx, GST_STATE_PLAYING);
  Peer peer(std::string(NNS_ROS_CPP_PEER) + " /nns_test/cpp_in /nns_test/cpp_out 2", false);
  std::vector<Frame> frames{{pattern(40, 9), pattern(6, 10)}, {pattern(40, 11), pattern(6, 12)}};
  auto r = publish(
      "appsrc name=in caps=\"other/tensors,format=static,num_tensors=2,dimensions=5:2.3:2,"
      "types=float32.uint8,framerate=0/1\" ! tensor_ros_sink topic=/nns_test/cpp_in "
      "wait-subscribers=1",
      frames);
  EXPECT_TRUE(r.eos) << r.error_text;
  Received got = pull(rx, 2);
  EXPECT_EQ(peer.finish().first, 0);
  gst_element_set_state(rx, GST_STATE_NULL);
  gst_object_unref(rx);
  ASSERT_TRUE(got.config.has_value());
  EXPECT_EQ(got.config->info.to_string(), "2 tensor(s): [0] float32 5:2:1:1, [1] uint8 3:2:1:1");
  EXPECT_EQ(got.frames, frames);
}

// enable-save-rosbag writes a real rosbag (read back by rospy's rosbag module) and
// enable-load-rosbag replays it; neither needs the master (dummy=true).
TEST(TensorRos, RosbagSaveAndLoad) {
  use_ros("http://127.0.0.1:9/");
  const std::string dir = nns::test::make_temp_dir();
  const std::string bag = dir + "/out.bag";
  std::vector<Frame> frames{{pattern(6, 20)}, {pattern(6, 21)}, {pattern(6, 22)}};
  auto r = publish(
      "appsrc name=in caps=\"other/tensors,format=static,num_tensors=1,"
      "dimensions=(string)3:2,types=int8,framerate=0/1\" ! tensor_ros_sink dummy=true "
      "topic=/bagged enable-save-rosbag=true location=" +
          bag,
      frames);
  ASSERT_TRUE(r.eos) << r.error_text;
  auto [status, out] = Peer("bag " + bag).finish();
  EXPECT_EQ(status, 0);
  std::string want;
  for (const Frame &f : frames)
    want +=
        "{\"topic\": \"/bagged\", \"type\": \"nns_ros_bridge/Tensors\", \"tensors\": "
        "[{\"dims\": [[\"int8\", 1, 6], [\"int8\", 1, 6], [\"int8\", 2, 6], [\"int8\", 3, "
        "3]], \"offset\": 0, \"data\": \"" +
        hex(f[0]) + "\"}]}\n";
  EXPECT_EQ(out, want);

  GstElement *rx = launch("tensor_ros_src enable-load-rosbag=true rate=50 location=" + bag +
                          " ! appsink name=out sync=false");
  gst_element_set_state(rx, GST_STATE_PLAYING);
  auto t0 = Clock::now();
  Received got = pull(rx, 4);  // the fourth pull ends at EOS
  auto elapsed = Clock::now() - t0;
  gst_element_set_state(rx, GST_STATE_NULL);
  gst_object_unref(rx);
  ASSERT_TRUE(got.config.has_value());
  EXPECT_EQ(got.config->info.to_string(), "1 tensor(s): [0] int8 3:2:1:1");
  EXPECT_EQ(got.config->rate_n, 50);
  EXPECT_EQ(got.frames, frames);
  EXPECT_GE(elapsed, std::chrono::milliseconds(40));  // 3 messages at 50 Hz: 2 gaps of 20 ms
  std::filesystem::remove_all(dir);

  auto bad = nns::test::run_pipeline(
      "tensor_ros_src enable-load-rosbag=true location=" + dir + "/missing.bag ! fakesink", 10.0);
  ASSERT_TRUE(bad.error);
  EXPECT_NE(
      bad.error_text.find("property 'location': cannot read the rosbag '" + dir + "/missing.bag'"),
      std::string::npos)
      << bad.error_text;
}

// Errors: each names the element, the topic and what was wrong.
static nns::test::RunResult src_with_peer(const std::string &topic, const std::string &json) {
  GstElement *rx = launch("tensor_ros_src topic=" + topic + " timeout=3 ! fakesink");
  Peer peer("send " + topic + " '" + json + "'");
  auto r = nns::test::run_pipeline(rx, 10.0);
  gst_object_unref(rx);
  return r;
}

TEST(TensorRos, SrcRejectsMessageWithOtherCaps) {
  use_ros();
  auto r = src_with_peer("/nns_test/mismatch",
                         "[[{\"type\": \"uint8\", \"dims\": [4], \"data\": \"00010203\"}],"
                         " [{\"type\": \"uint8\", \"dims\": [2], \"data\": \"0001\"}]]");
  ASSERT_TRUE(r.error) << "eos=" << r.eos;
  EXPECT_NE(r.error_text.find("tensorrossrc0: topic /nns_test/mismatch: message 1 carries types "
                              "uint8, dimensions 2:1:1:1 but the caps were set from the first "
                              "message to types uint8, dimensions 4:1:1:1"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorRos, SrcRejectsBadMessage) {
  use_ros();
  auto r = src_with_peer(
      "/nns_test/bad",
      "[[{\"type\": \"uint8\", \"label\": \"rgb\", \"dims\": [3], \"data\": \"000102\"}]]");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("topic /nns_test/bad, tensor 0: layout.dim[0].label 'rgb' is not a "
                              "tensor type name"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorRos, SrcWithoutPublisherFailsAfterTimeout) {
  use_ros();
  auto t0 = Clock::now();
  auto r =
      nns::test::run_pipeline("tensor_ros_src topic=/nns_test/nobody timeout=1 ! fakesink", 10.0);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("no message on topic /nns_test/nobody within 1 s (property "
                              "'timeout')"),
            std::string::npos)
      << r.error_text;
  EXPECT_LT(Clock::now() - t0, std::chrono::seconds(4));
}

// A loopback port nothing listens on: bound to get a free number, then closed.
static int closed_port() {
  int fd = socket(AF_INET, SOCK_STREAM, 0);
  sockaddr_in a{};
  a.sin_family = AF_INET;
  a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof a;
  bind(fd, reinterpret_cast<sockaddr *>(&a), sizeof a);
  getsockname(fd, reinterpret_cast<sockaddr *>(&a), &len);
  close(fd);
  return ntohs(a.sin_port);
}

TEST(TensorRos, UnreachableMasterFailsAtOnce) {
  const std::string uri = "http://127.0.0.1:" + std::to_string(closed_port()) + "/";
  use_ros(uri);
  auto t0 = Clock::now();
  auto r = nns::test::run_pipeline(
      "appsrc caps=\"other/tensors,format=static,num_tensors=1,dimensions=4,types=uint8,"
      "framerate=0/1\" ! tensor_ros_sink topic=/nns_test/x",
      10.0);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("tensorrossink0: ROS master " + uri +
                              " is not reachable (to publish topic '/nns_test/x')"),
            std::string::npos)
      << r.error_text;
  EXPECT_LT(Clock::now() - t0, std::chrono::seconds(3));
}

TEST(TensorRos, MissingMasterUriIsAnError) {
  use_ros();
  unsetenv("ROS_MASTER_URI");
  auto r = nns::test::run_pipeline("tensor_ros_src topic=/nns_test/y ! fakesink", 10.0);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("tensorrossrc0: ROS_MASTER_URI is not set in the environment: cannot "
                              "reach a ROS master to subscribe to topic '/nns_test/y'"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorRos, BadTopicPropertiesAreErrors) {
  use_ros();
  auto r = nns::test::run_pipeline("tensor_ros_src ! fakesink", 10.0);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("property 'topic' is empty"), std::string::npos) << r.error_text;
  r = nns::test::run_pipeline("tensor_ros_src topic=\"/a b\" ! fakesink", 10.0);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("property 'topic': '/a b' is not a valid ROS name"),
            std::string::npos)
      << r.error_text;
}

// dummy=true consumes without ROS (no master needed) and still emits new-data.
TEST(TensorRos, SinkDummyNeedsNoMaster) {
  use_ros("http://127.0.0.1:9/");
  GstElement *p = launch(
      "videotestsrc num-buffers=4 ! video/x-raw,format=GRAY8,width=4,height=2 ! "
      "tensor_converter ! tensor_ros_sink name=s dummy=true");
  GstElement *s = gst_bin_get_by_name(GST_BIN(p), "s");
  int count = 0;
  g_signal_connect(
      s, "new-data",
      G_CALLBACK(+[](GstElement *, GstBuffer *, gpointer n) { ++*static_cast<int *>(n); }), &count);
  auto r = nns::test::run_pipeline(p, 10.0);
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(count, 4);
  gst_object_unref(s);
  gst_object_unref(p);
}

// A sink waiting for subscribers (wait-subscribers) lets the pipeline stop at once.
TEST(TensorRos, SinkWaitingForSubscribersStopsAtOnce) {
  use_ros();
  GstElement *p = launch(
      "appsrc name=in caps=\"other/tensors,format=static,num_tensors=1,dimensions=(string)4,"
      "types=uint8,framerate=0/1\" ! tensor_ros_sink topic=/nns_test/lonely wait-subscribers=1");
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "in");
  gst_app_src_push_buffer(GST_APP_SRC(src), gst_buffer_new_allocate(nullptr, 4, nullptr));
  gst_object_unref(src);
  gst_element_set_state(p, GST_STATE_PLAYING);
  g_usleep(300 * 1000);  // the streaming thread is now in the wait
  auto t0 = Clock::now();
  EXPECT_EQ(gst_element_set_state(p, GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS);
  EXPECT_LT(Clock::now() - t0, std::chrono::seconds(3));  // not the 10 s wait (loaded CI)
  gst_object_unref(p);
}

// Flexible tensors have no fixed layout to announce: refused at negotiation.
TEST(TensorRos, SinkRefusesFlexibleTensors) {
  use_ros();
  GstElement *s = gst_element_factory_make("tensor_ros_sink", nullptr);
  ASSERT_NE(s, nullptr);
  GstPad *pad = gst_element_get_static_pad(s, "sink");
  GstCaps *flex = gst_caps_from_string("other/tensors,format=flexible,framerate=0/1");
  GstCaps *stat = gst_caps_from_string(
      "other/tensors,format=static,num_tensors=1,dimensions=4,types=uint8,framerate=0/1");
  EXPECT_FALSE(gst_pad_query_accept_caps(pad, flex));
  EXPECT_TRUE(gst_pad_query_accept_caps(pad, stat));
  gst_caps_unref(flex);
  gst_caps_unref(stat);
  gst_object_unref(pad);
  gst_object_unref(s);
}

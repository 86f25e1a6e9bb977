// SPDX-License-Identifier: LGPL-2.1-only
// Helpers of the among-device tests: free loopback ports, a second process running a
// pipeline (this test binary re-executed with --gtest_filter=EdgeChild.Run), and appsrc /
// appsink client pipelines.
#pragma once

#include <arpa/inet.h>
#include <fcntl.h>
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gtest/gtest.h>
#include <netinet/in.h>
#include <signal.h>
#include <spawn.h>
#include <sys/socket.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <thread>
#include <vector>

#include "support/net_util.h"

extern char **environ;

namespace edge_test {

using namespace std::chrono_literals;

using nns::test::free_port;
using nns::test::port_open;

inline std::string slurp(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  std::stringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// The helper-process side of Child: every edge test binary has
//   TEST(EdgeChild, Run) { edge_test::run_child(); }
// which runs $NNS_EDGE_CHILD until EOS or ERROR, printing the bus warnings and the error
// ("WARNING: <text>", "ERROR: <text>") for Child::log(); an ERROR fails the process (exit 1).
inline void run_child() {
  const char *desc = std::getenv("NNS_EDGE_CHILD");
  if (!desc) GTEST_SKIP() << "only runs as the helper process of the edge tests";
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc, &err);
  ASSERT_TRUE(p) << (err ? err->message : "");
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstBus *bus = gst_element_get_bus(p);
  for (;;) {
    GstMessage *m = gst_bus_timed_pop_filtered(
        bus, GST_CLOCK_TIME_NONE,
        static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR | GST_MESSAGE_WARNING));
    GError *e = nullptr;
    gchar *dbg = nullptr;
    const GstMessageType t = GST_MESSAGE_TYPE(m);
    if (t == GST_MESSAGE_ERROR) gst_message_parse_error(m, &e, &dbg);
    if (t == GST_MESSAGE_WARNING) gst_message_parse_warning(m, &e, &dbg);
    if (e) printf("%s: %s\n", t == GST_MESSAGE_ERROR ? "ERROR" : "WARNING", e->message);
    fflush(stdout);
    if (t == GST_MESSAGE_ERROR) ADD_FAILURE() << (e ? e->message : "") << " | " << (dbg ? dbg : "");
    if (e) g_error_free(e);
    g_free(dbg);
    gst_message_unref(m);
    if (t != GST_MESSAGE_WARNING) break;
  }
  gst_object_unref(bus);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(p);
}

// A file in the test temp dir, removed when it goes out of scope unless the test failed.
struct TempFile {
  explicit TempFile(const std::string &stem)
      : path(std::string(::testing::TempDir()) + stem + "_" + std::to_string(getpid())) {}
  ~TempFile() {
    if (!::testing::Test::HasFailure()) std::remove(path.c_str());
  }
  std::string path;
};

// A pipeline in another process; its bus warnings/errors go to log().
class Child {
 public:
  Child(const std::string &pipeline, const std::string &tag) {
    log_ = std::string(::testing::TempDir()) + "edge_child_" + tag + "_" +
           std::to_string(getpid()) + ".log";
    std::vector<std::string> env;
    for (char **e = environ; *e; ++e)
      if (std::string(*e).rfind("NNS_EDGE_CHILD=", 0) != 0) env.push_back(*e);
    env.push_back("NNS_EDGE_CHILD=" + pipeline);
    std::vector<char *> envp;
    for (auto &s : env) envp.push_back(s.data());
    envp.push_back(nullptr);
    std::string exe = "/proc/self/exe", filter = "--gtest_filter=EdgeChild.Run";
    char *argv[] = {exe.data(), filter.data(), nullptr};
    posix_spawn_file_actions_t fa;
    posix_spawn_file_actions_init(&fa);
    posix_spawn_file_actions_addopen(&fa, 1, log_.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    posix_spawn_file_actions_adddup2(&fa, 1, 2);
    if (posix_spawn(&pid_, "/proc/self/exe", &fa, nullptr, argv, envp.data()) != 0) pid_ = -1;
    posix_spawn_file_actions_destroy(&fa);
  }
  // The log stays only when the test failed (it is what explains the failure).
  ~Child() {
    kill_now();
    if (!::testing::Test::HasFailure()) std::remove(log_.c_str());
  }
  bool wait_port(uint16_t port, std::chrono::milliseconds t = 10s) {
    const auto end = std::chrono::steady_clock::now() + t;
    while (std::chrono::steady_clock::now() < end) {
      if (port_open(port)) return true;
      if (exited()) return false;
      std::this_thread::sleep_for(20ms);
    }
    return false;
  }
  bool exited() {
    if (pid_ <= 0) return true;
    int st = 0;
    if (waitpid(pid_, &st, WNOHANG) == pid_) {
      status_ = st;
      pid_ = -1;
      return true;
    }
    return false;
  }
  // Waits for a normal exit; returns the exit code (-1 on timeout or signal).
  int wait_exit(std::chrono::milliseconds t = 20s) {
    const auto end = std::chrono::steady_clock::now() + t;
    while (std::chrono::steady_clock::now() < end) {
      if (exited()) return WIFEXITED(status_) ? WEXITSTATUS(status_) : -1;
      std::this_thread::sleep_for(20ms);
    }
    return -1;
  }
  void kill_now() {
    if (pid_ > 0) {
      ::kill(pid_, SIGKILL);
      waitpid(pid_, &status_, 0);
      pid_ = -1;
    }
  }
  std::string log() const { return slurp(log_); }
  pid_t pid() const { return pid_; }

 private:
  pid_t pid_ = -1;
  int status_ = 0;
  std::string log_;
};

inline std::string server_pipeline(uint16_t port, const std::string &middle = "") {
  return "tensor_query_serversrc host=127.0.0.1 port=" + std::to_string(port) + " ! " + middle +
         "tensor_query_serversink";
}

// appsrc ! <element> ! appsink, with collected bus warnings and the first error.
struct AppPipeline {
  GstElement *pipeline = nullptr;
  GstElement *src = nullptr, *sink = nullptr, *mid = nullptr;
  // `middle_is_sink`: the element is itself the sink (no appsink after it).
  AppPipeline(const std::string &middle, const std::string &caps, bool middle_is_sink = false) {
    GError *err = nullptr;
    const std::string d = "appsrc name=src is-live=true format=time caps=\"" + caps + "\" ! " +
                          middle + " name=mid" +
                          (middle_is_sink ? "" : " ! appsink name=sink sync=false max-buffers=0");
    pipeline = gst_parse_launch(d.c_str(), &err);
    if (err) {
      ADD_FAILURE() << err->message;
      g_error_free(err);
    }
    src = gst_bin_get_by_name(GST_BIN(pipeline), "src");
    sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
    mid = gst_bin_get_by_name(GST_BIN(pipeline), "mid");
  }
  ~AppPipeline() {
    stop();
    for (GstMessage *m : all_) gst_message_unref(m);
    gst_object_unref(src);
    if (sink) gst_object_unref(sink);
    gst_object_unref(mid);
    gst_object_unref(pipeline);
  }
  void play() { gst_element_set_state(pipeline, GST_STATE_PLAYING); }
  // Returns how long NULL took.
  std::chrono::milliseconds stop() {
    const auto t0 = std::chrono::steady_clock::now();
    gst_element_set_state(pipeline, GST_STATE_NULL);
    return std::chrono::duration_cast<std::chrono::milliseconds>(std::chrono::steady_clock::now() -
                                                                 t0);
  }
  GstFlowReturn push(const std::vector<uint8_t> &bytes, GstClockTime pts) {
    GstBuffer *b = gst_buffer_new_memdup(bytes.data(), bytes.size());
    GST_BUFFER_PTS(b) = pts;
    return gst_app_src_push_buffer(GST_APP_SRC(src), b);
  }
  void eos() { gst_app_src_end_of_stream(GST_APP_SRC(src)); }
  // Pulls one answer (empty optional on timeout/EOS).
  bool pull(std::vector<uint8_t> *out, GstClockTime *pts = nullptr,
            GstClockTime timeout = 5 * GST_SECOND) {
    GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), timeout);
    if (!s) return false;
    GstBuffer *b = gst_sample_get_buffer(s);
    out->resize(gst_buffer_get_size(b));
    gst_buffer_extract(b, 0, out->data(), out->size());
    if (pts) *pts = GST_BUFFER_PTS(b);
    gst_sample_unref(s);
    return true;
  }
  // Messages of one type seen so far, as "<text> | <debug>".
  std::vector<std::string> messages(GstMessageType type) {
    std::vector<std::string> out;
    GstBus *bus = gst_element_get_bus(pipeline);
    while (GstMessage *m = gst_bus_pop(bus)) {
      all_.push_back(gst_message_ref(m));
      gst_message_unref(m);
    }
    gst_object_unref(bus);
    for (GstMessage *m : all_) {
      if (GST_MESSAGE_TYPE(m) != type) continue;
      GError *e = nullptr;
      gchar *dbg = nullptr;
      if (type == GST_MESSAGE_ERROR) gst_message_parse_error(m, &e, &dbg);
      if (type == GST_MESSAGE_WARNING) gst_message_parse_warning(m, &e, &dbg);
      if (type == GST_MESSAGE_INFO) gst_message_parse_info(m, &e, &dbg);
      out.push_back(std::string(e ? e->message : "") + " | " + (dbg ? dbg : ""));
      if (e) g_error_free(e);
      g_free(dbg);
    }
    return out;
  }
  GstStructure *stats() {
    GstStructure *s = nullptr;
    g_object_get(mid, "stats", &s, nullptr);
    return s;
  }
  std::vector<GstMessage *> all_;
};

// An edgesrc subscriber in this process: edgesrc <props> ! appsink (props may add elements).
struct SubPipeline {
  GstElement *pipe = nullptr, *sink = nullptr;
  explicit SubPipeline(const std::string &props) {
    GError *err = nullptr;
    pipe = gst_parse_launch(
        ("edgesrc name=s " + props + " ! appsink name=k sync=false max-buffers=0").c_str(), &err);
    if (err) {
      ADD_FAILURE() << err->message;
      g_error_free(err);
    }
    sink = gst_bin_get_by_name(GST_BIN(pipe), "k");
  }
  ~SubPipeline() {
    gst_element_set_state(pipe, GST_STATE_NULL);
    gst_object_unref(sink);
    gst_object_unref(pipe);
  }
  // edgesrc subscribes in READY->PAUSED, done when set_state returns (the live appsink then
  // waits for a first buffer asynchronously).
  bool play() { return gst_element_set_state(pipe, GST_STATE_PLAYING) != GST_STATE_CHANGE_FAILURE; }
  // Pulls one buffer; its bytes and (once) caps.
  bool pull(std::string *bytes, std::string *caps = nullptr, GstClockTime t = 5 * GST_SECOND) {
    GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), t);
    if (!s) return false;
    GstBuffer *b = gst_sample_get_buffer(s);
    bytes->resize(gst_buffer_get_size(b));
    gst_buffer_extract(b, 0, bytes->data(), bytes->size());
    if (caps) {
      gchar *c = gst_caps_to_string(gst_sample_get_caps(s));
      *caps = c ? c : "";
      g_free(c);
    }
    gst_sample_unref(s);
    return true;
  }
  // The first ERROR (or "" after `t`), and every WARNING seen before it.
  std::string error(GstClockTime t, std::string *warnings = nullptr) {
    GstBus *bus = gst_element_get_bus(pipe);
    std::string out;
    for (;;) {
      GstMessage *m = gst_bus_timed_pop_filtered(
          bus, t, static_cast<GstMessageType>(GST_MESSAGE_ERROR | GST_MESSAGE_WARNING));
      if (!m) break;
      GError *e = nullptr;
      gchar *dbg = nullptr;
      const bool err = GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR;
      if (err)
        gst_message_parse_error(m, &e, &dbg);
      else
        gst_message_parse_warning(m, &e, &dbg);
      const std::string text = std::string(e->message) + " | " + (dbg ? dbg : "");
      g_error_free(e);
      g_free(dbg);
      gst_message_unref(m);
      if (err) {
        out = text;
        break;
      }
      if (warnings) *warnings += text + "\n";
    }
    gst_object_unref(bus);
    return out;
  }
};

inline guint64 stat(GstStructure *s, const char *field) {
  guint64 v = 0;
  gst_structure_get_uint64(s, field, &v);
  return v;
}

inline std::string joined(const std::vector<std::string> &v) {
  std::string s;
  for (auto &x : v) s += x + "\n";
  return s;
}

}  // namespace edge_test

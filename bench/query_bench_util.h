// SPDX-License-Identifier: LGPL-2.1-only
// What the served-model benchmarks (query_serve_bench, query_lb_bench) share: clocks and CPU
// time, percentiles, the load average, gst_parse_launch or exit, whole-file reads, and child
// processes (this binary again) talking over their stdin/stdout. Header-only.
#pragma once

#include <fcntl.h>
#include <gst/gst.h>
#include <spawn.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <map>
#include <mutex>
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "gst/plugin_init.h"

extern char **environ;

namespace nns::bench::query {

using Clock = std::chrono::steady_clock;  // CLOCK_MONOTONIC: comparable between processes

inline int64_t now_ns() {
  return std::chrono::duration_cast<std::chrono::nanoseconds>(Clock::now().time_since_epoch())
      .count();
}

inline double cpu_s() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

inline double pct(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

inline std::string loadavg() {
  std::ifstream f("/proc/loadavg");
  std::string a, b, c;
  f >> a >> b >> c;
  return a + " " + b + " " + c;
}

inline GstElement *launch(const std::string &d) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(d.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "%s: %s\n", d.c_str(), err ? err->message : "?");
    std::exit(1);
  }
  return p;
}

// Waits (at most 30 s) for EOS or an error on `p`'s bus; an error is printed as "client: ...".
// False when an error came.
inline bool wait_eos(GstElement *p) {
  GstBus *bus = gst_element_get_bus(p);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 30 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  const bool error = m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR;
  if (error) {
    GError *e = nullptr;
    gst_message_parse_error(m, &e, nullptr);
    std::fprintf(stderr, "client: %s\n", e->message);
    g_error_free(e);
  }
  if (m) gst_message_unref(m);
  gst_object_unref(bus);
  return !error;
}

// A child's handshake: prints "ready", then waits for a line from the parent. False when stdin
// closed instead.
inline bool ready_then_wait_go() {
  std::printf("ready\n");
  std::fflush(stdout);
  char go[16];
  return std::fgets(go, sizeof go, stdin) != nullptr;
}

inline std::vector<uint8_t> read_all(const std::string &p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

// gst_init, our elements registered statically, sub-plugins from this build tree; returns
// ../shared/models/upstream (NNS_SHARED_DIR overrides ../shared).
inline std::string init_and_shared_dir(int *argc, char ***argv) {
  gst_init(argc, argv);
  nns_register_static();
  setenv("NNSTREAMER_FILTERS", (std::string(NNS_BUILD_DIR) + "/subplugins/filters").c_str(), 0);
  const char *sd = std::getenv("NNS_SHARED_DIR");
  return (sd ? std::string(sd) : std::string(NNS_SOURCE_DIR) + "/../shared") + "/models/upstream";
}

// Argmax of a float32 score tensor (the model's 1000 classes).
inline int argmax(GstBuffer *b) {
  GstMapInfo m;
  if (!gst_buffer_map(b, &m, GST_MAP_READ)) return -1;
  const auto *f = reinterpret_cast<const float *>(m.data);
  const std::size_t n = m.size / sizeof(float);
  const int best = n ? static_cast<int>(std::max_element(f, f + n) - f) : -1;
  gst_buffer_unmap(b, &m);
  return best;
}

struct ClientProbes {
  std::mutex m;
  std::map<GstClockTime, int64_t> sent;   // pts -> last time offered (a re-offer overwrites)
  std::vector<double> rtt_us;             // timed frames only
  std::atomic<int> answers{0}, timed{0};  // all answers; answers to timed frames
  std::atomic<GstClockTime> timed_from{GST_CLOCK_TIME_NONE};  // first timed frame's pts
  std::atomic<int64_t> last_answer{0};
  std::atomic<int> label{-1};
  static GstPadProbeReturn in(GstPad *, GstPadProbeInfo *i, gpointer d) {
    auto *p = static_cast<ClientProbes *>(d);
    std::lock_guard<std::mutex> l(p->m);
    p->sent[GST_BUFFER_PTS(GST_PAD_PROBE_INFO_BUFFER(i))] = now_ns();
    return GST_PAD_PROBE_OK;
  }
  static GstPadProbeReturn out(GstPad *, GstPadProbeInfo *i, gpointer d) {
    auto *p = static_cast<ClientProbes *>(d);
    const int64_t t = now_ns();
    GstBuffer *b = GST_PAD_PROBE_INFO_BUFFER(i);
    const GstClockTime pts = GST_BUFFER_PTS(b);
    p->label = argmax(b);
    ++p->answers;
    std::lock_guard<std::mutex> l(p->m);
    auto it = p->sent.find(pts);
    if (p->timed_from != GST_CLOCK_TIME_NONE && pts >= p->timed_from) {
      if (it != p->sent.end()) p->rtt_us.push_back((t - it->second) / 1e3);
      p->last_answer = t;
      ++p->timed;
    }
    if (it != p->sent.end()) p->sent.erase(it);
    return GST_PAD_PROBE_OK;
  }
};

// A child process (this binary with `args`): `to` is its stdin, `from` its stdout.
struct Child {
  pid_t pid = -1;
  FILE *to = nullptr, *from = nullptr;
};

inline Child spawn_child(const std::vector<std::string> &args) {
  int in[2], out[2];
  // O_CLOEXEC: a later child must not keep an earlier one's stdin open (its EOF can be a stop).
  if (pipe2(in, O_CLOEXEC) != 0 || pipe2(out, O_CLOEXEC) != 0) std::exit(1);
  posix_spawn_file_actions_t fa;
  posix_spawn_file_actions_init(&fa);
  posix_spawn_file_actions_adddup2(&fa, in[0], 0);
  posix_spawn_file_actions_adddup2(&fa, out[1], 1);
  std::vector<std::string> a = args;
  std::vector<char *> argv;
  for (auto &s : a) argv.push_back(s.data());
  argv.push_back(nullptr);
  Child c;
  if (posix_spawn(&c.pid, "/proc/self/exe", &fa, nullptr, argv.data(), environ) != 0) {
    std::perror("posix_spawn");
    std::exit(1);
  }
  posix_spawn_file_actions_destroy(&fa);
  close(in[0]);
  close(out[1]);
  c.to = fdopen(in[1], "w");
  c.from = fdopen(out[0], "r");
  return c;
}

}  // namespace nns::bench::query

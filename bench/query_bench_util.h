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
#include <chrono>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

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

inline std::vector<uint8_t> read_all(const std::string &p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

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

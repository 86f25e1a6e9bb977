// SPDX-License-Identifier: LGPL-2.1-only
// The measurement helper of the paper experiments (examples/paper): wall clock, process CPU
// time (getrusage: every thread, user + system), peak and current RSS (/proc/self/status),
// latency samples, and the JSON result file each run writes (docs/paper-experiments.md lists
// its fields). The same figures come out of the pipeline runs and the Control programs.
#pragma once

#include <dirent.h>
#include <sched.h>
#include <sys/resource.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace paper {

using Clock = std::chrono::steady_clock;

inline double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

inline double cpu_seconds() {
  rusage ru{};
  getrusage(RUSAGE_SELF, &ru);
  auto s = [](const timeval &t) { return t.tv_sec + t.tv_usec * 1e-6; };
  return s(ru.ru_utime) + s(ru.ru_stime);
}

// A field of /proc/self/status in kB ("VmHWM", "VmRSS"), in MiB; 0 when absent.
inline double proc_status_mib(const char *field) {
  std::ifstream f("/proc/self/status");
  std::string line;
  const std::string key = std::string(field) + ":";
  while (std::getline(f, line))
    if (line.compare(0, key.size(), key) == 0) return std::stod(line.substr(key.size())) / 1024.0;
  return 0;
}

// Where a process's time went besides running: context switches it asked for (voluntary: it
// blocked or slept, i.e. waited) and ones forced on it (involuntary: preempted), and the time
// its threads sat runnable on a run queue while other tasks held the cores
// (/proc/self/task/*/schedstat, second field). A batch run that waits shows voluntary switches;
// one squeezed by other jobs shows run-queue time. Threads: how many the process has now.
struct SchedSnapshot {
  double vcsw = 0, ivcsw = 0, runq_s = 0, threads = 0;
  static SchedSnapshot now() {
    SchedSnapshot s;
    rusage ru{};
    getrusage(RUSAGE_SELF, &ru);
    s.vcsw = static_cast<double>(ru.ru_nvcsw);
    s.ivcsw = static_cast<double>(ru.ru_nivcsw);
    if (DIR *d = opendir("/proc/self/task")) {
      while (dirent *e = readdir(d)) {
        if (e->d_name[0] == '.') continue;
        std::ifstream f(std::string("/proc/self/task/") + e->d_name + "/schedstat");
        unsigned long long run_ns = 0, wait_ns = 0;
        if (f >> run_ns >> wait_ns) s.runq_s += static_cast<double>(wait_ns) * 1e-9;
        s.threads += 1;
      }
      closedir(d);
    }
    return s;
  }
};

// Cores this process may run on (taskset / sched_setaffinity).
inline int allowed_cpus() {
  cpu_set_t set;
  CPU_ZERO(&set);
  return sched_getaffinity(0, sizeof set, &set) == 0 ? CPU_COUNT(&set) : 0;
}

// Wall and CPU time of one measured interval, and its scheduling figures (SchedSnapshot).
class Meter {
 public:
  void start() {
    sched0_ = SchedSnapshot::now();
    t0_ = Clock::now();
    cpu0_ = cpu_seconds();
  }
  void stop() {
    wall_ = seconds_since(t0_);
    cpu_ = cpu_seconds() - cpu0_;
    sched1_ = SchedSnapshot::now();
  }
  double wall() const { return wall_; }
  double cpu() const { return cpu_; }
  Clock::time_point t0() const { return t0_; }
  const SchedSnapshot &sched0() const { return sched0_; }
  const SchedSnapshot &sched1() const { return sched1_; }

 private:
  Clock::time_point t0_{};
  double cpu0_ = 0, wall_ = 0, cpu_ = 0;
  SchedSnapshot sched0_, sched1_;
};

// Latency samples in milliseconds.
struct Samples {
  std::vector<double> ms;
  void add(double v) { ms.push_back(v); }
  double mean() const {
    double s = 0;
    for (double v : ms) s += v;
    return ms.empty() ? 0 : s / static_cast<double>(ms.size());
  }
  double pct(double p) const {
    if (ms.empty()) return 0;
    std::vector<double> v = ms;
    std::sort(v.begin(), v.end());
    return v[std::min(v.size() - 1, static_cast<std::size_t>(p * static_cast<double>(v.size())))];
  }
};

// One run's result: {"exp","mode","config","figures":{...},"latency_ms":{stage:{...}},
// "info":{...}} written to the --out file.
struct Result {
  std::string exp, mode, config;
  std::map<std::string, double> figures;
  std::map<std::string, Samples> latency;
  std::map<std::string, std::string> info;

  // Wall, CPU share (100 % = one core busy) and memory of the measured interval.
  void add_usage(const Meter &m) { add_usage(m.wall(), m.cpu(), m.sched0(), m.sched1()); }
  void add_usage(double wall, double cpu, const SchedSnapshot &a, const SchedSnapshot &b) {
    figures["wall_s"] = wall;
    figures["cpu_s"] = cpu;
    figures["cpu_pct"] = wall > 0 ? 100.0 * cpu / wall : 0;
    figures["rss_peak_mib"] = proc_status_mib("VmHWM");
    figures["rss_mib"] = proc_status_mib("VmRSS");
    // Voluntary switches = waits; run-queue time = CPU the scheduler gave to other tasks.
    figures["vcsw"] = b.vcsw - a.vcsw;
    figures["ivcsw"] = b.ivcsw - a.ivcsw;
    figures["runq_s"] = b.runq_s - a.runq_s;
    figures["threads"] = std::max(a.threads, b.threads);
    figures["cpus"] = allowed_cpus();
  }

  std::string json() const {
    std::ostringstream o;
    auto str = [&](const std::string &s) {
      o << '"';
      for (char c : s) {
        if (c == '"' || c == '\\') o << '\\';
        o << c;
      }
      o << '"';
    };
    o << "{\"exp\":";
    str(exp);
    o << ",\"mode\":";
    str(mode);
    o << ",\"config\":";
    str(config);
    o << ",\"figures\":{";
    const char *sep = "";
    for (const auto &[k, v] : figures) {
      o << sep;
      str(k);
      o << ':' << v;
      sep = ",";
    }
    o << "},\"latency_ms\":{";
    sep = "";
    for (const auto &[k, s] : latency) {
      o << sep;
      str(k);
      o << ":{\"n\":" << s.ms.size() << ",\"mean\":" << s.mean() << ",\"p50\":" << s.pct(0.5)
        << ",\"p95\":" << s.pct(0.95) << '}';
      sep = ",";
    }
    o << "},\"info\":{";
    sep = "";
    for (const auto &[k, v] : info) {
      o << sep;
      str(k);
      o << ':';
      str(v);
      sep = ",";
    }
    o << "}}\n";
    return o.str();
  }
};

}  // namespace paper

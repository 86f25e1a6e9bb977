// SPDX-License-Identifier: LGPL-2.1-only
// What the pipeline benchmarks share: run a gst-launch description from PLAYING to EOS and take
// its wall and process-CPU time, run several descriptions interleaved, take medians; "--name
// value" options; the custom-easy pass-through filter of the filter benchmarks. Header-only;
// every bench/<name>_bench.cc is its own program.
#pragma once

#include <gst/gst.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "tensor_filter_custom_easy.h"

namespace nns::bench {

using Clock = std::chrono::steady_clock;

// Wall and process-CPU seconds (all threads of this process; less sensitive to other processes
// on a shared machine). Negative: not measured (the pipeline failed or was not run).
struct Timing {
  double wall = -1;
  double cpu = -1;
};

inline double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

inline double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? -1 : v[v.size() / 2];
}

// Integer options given as "--name value" pairs (argv[1] argv[2], argv[3] argv[4], ...): each
// pair whose name is listed sets that variable; other pairs are ignored.
inline void int_options(int argc, char **argv,
                        std::initializer_list<std::pair<const char *, int *>> names) {
  for (int i = 1; i + 1 < argc; i += 2)
    for (const auto &[name, value] : names)
      if (!std::strcmp(argv[i], name)) *value = std::atoi(argv[i + 1]);
}

// Plays `p` until EOS or an error (at most `timeout`), then sets it to NULL. True on EOS.
inline bool play_to_eos(GstElement *p, GstClockTime timeout) {
  GstBus *bus = gst_element_get_bus(p);
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, timeout, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  const bool eos = m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_EOS;
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  return eos;
}

// Time from PLAYING to EOS (parsing is not timed; start-up, state changes and negotiation are).
// On a parse error or an error message: says so on stderr and returns Timing{}.
inline Timing time_pipeline(const std::string &desc) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "bench: cannot parse '%s': %s\n", desc.c_str(), err ? err->message : "?");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return {};
  }
  GstBus *bus = gst_element_get_bus(p);
  auto t0 = Clock::now();
  double c0 = cpu_seconds();
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  Timing t{std::chrono::duration<double>(Clock::now() - t0).count(), cpu_seconds() - c0};
  if (!m || GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    if (m) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      std::fprintf(stderr, "bench: error in '%s': %s\n", desc.c_str(), e->message);
      g_error_free(e);
    }
    t = Timing{};
  }
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(p);
  return t;
}

// Runs every description `runs` times, interleaved (run 1 of each, then run 2 of each, ...);
// returns the median wall and CPU seconds of each. An empty description is skipped (its Timing
// stays negative); when one run fails, every Timing is negative.
inline std::vector<Timing> measure(const std::vector<std::string> &descs, int runs) {
  std::vector<std::vector<double>> wall(descs.size()), cpu(descs.size());
  for (int r = 0; r < runs; ++r)
    for (std::size_t i = 0; i < descs.size(); ++i) {
      if (descs[i].empty()) continue;
      Timing t = time_pipeline(descs[i]);
      if (t.wall < 0) return std::vector<Timing>(descs.size());
      wall[i].push_back(t.wall);
      cpu[i].push_back(t.cpu);
    }
  std::vector<Timing> out(descs.size());
  for (std::size_t i = 0; i < descs.size(); ++i)
    if (!wall[i].empty()) out[i] = Timing{median(wall[i]), median(cpu[i])};
  return out;
}

// A custom-easy model that copies every input tensor to its output.
inline int passthrough(void *, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                       GstTensorMemory *out) {
  for (unsigned i = 0; i < prop->input_meta.num_tensors; ++i)
    std::memcpy(out[i].data, in[i].data, in[i].size);
  return 0;
}

// Registers passthrough() as custom-easy model `name` for one uint8 4:1:1:1 tensor in and out
// (the tiny frames of the filter-overhead benchmarks). Returns NNS_custom_easy_register's result.
inline int register_tiny_passthrough(const char *name) {
  GstTensorsInfo one{};
  one.num_tensors = 1;
  one.info[0].type = _NNS_UINT8;
  one.info[0].dimension[0] = 4;
  one.info[0].dimension[1] = one.info[0].dimension[2] = one.info[0].dimension[3] = 1;
  return NNS_custom_easy_register(name, passthrough, nullptr, &one, &one);
}

// True when every run of measure() succeeded (and none was skipped).
inline bool all_measured(const std::vector<Timing> &t) {
  return std::all_of(t.begin(), t.end(), [](const Timing &x) { return x.wall >= 0; });
}

}  // namespace nns::bench

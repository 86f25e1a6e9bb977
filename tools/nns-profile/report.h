// SPDX-License-Identifier: LGPL-2.1-only
// nns-profile's analysis: from the nnsprofile tracer's output (docs/profiler.md) to the derived
// figures (busy share, rates, latency quantiles, bottleneck) and the three reports: a text table,
// a JSON file and a self-contained HTML page. GStreamer-free.
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace nns::profile::report {

struct Quantiles {
  int64_t p50 = -1, p90 = -1, p99 = -1;
};

struct Element {
  int id = -1;
  std::string name, factory, kind;
  uint64_t buffers = 0;      // buffers this element handled (received, or produced by a source)
  int64_t busy_ns = 0;       // own working time (queues: 0, see wait_ns)
  int64_t wait_ns = 0;       // queues: time blocked or waiting (not work)
  double busy = 0;           // busy_ns / duration
  double share = 0;          // busy_ns / sum of every element's busy_ns
  double per_buffer_ns = 0;  // busy_ns / buffers
  int64_t max_ns = 0;
  Quantiles q;
  std::vector<std::pair<int64_t, uint64_t>> hist;
  uint64_t invokes = 0;
  double invoke_mean_ns = 0;
  int64_t invoke_max_ns = 0;
  Quantiles invoke_q;
  std::vector<std::pair<int64_t, uint64_t>> invoke_hist;
  double in_rate = 0, out_rate = 0;  // buffers per second
  nlohmann::json queue;              // queues: mean/max levels, full share (else null)
};

struct Link {
  int from = -1, to = -1;  // element ids
  std::string from_pad, to_pad, mode;
  uint64_t buffers = 0, bytes = 0;
  double rate = 0;  // buffers per second over the link's active time
  double bytes_rate = 0;
  uint64_t latency_count = 0;
  double latency_mean_ns = -1;
  int64_t latency_min_ns = -1, latency_max_ns = -1;
  Quantiles latency_q;
  bool to_sink = false;
};

struct Thread {
  int tid = 0;
  std::string name, root;
  int64_t wall_ns = 0, cpu_ns = 0;
  double cpu_share = 0;  // cpu_ns / wall_ns
  uint64_t pushes = 0;
};

struct Report {
  std::string title;  // the pipeline description or the trace file
  std::string pipeline_filter;
  int64_t duration_ns = 0;
  std::vector<Element> elements;  // sorted by share, highest first
  std::vector<Link> links;
  std::vector<Thread> threads;
  int bottleneck = -1;  // index in elements, -1 when nothing ran
  std::string bottleneck_text;
};

// Builds the report from a tracer output object. `pipeline`: only elements of that top-level
// pipeline ("" = every element that is not a bin). Throws std::runtime_error naming what is
// missing when `trace` is not nnsprofile output.
Report analyse(const nlohmann::json &trace, const std::string &pipeline, const std::string &title);

std::string text_table(const Report &r);
nlohmann::json report_json(const Report &r);
std::string html_page(const Report &r);

// "4.12 ms", "812 us", "95 ns".
std::string fmt_ns(double ns);

}  // namespace nns::profile::report

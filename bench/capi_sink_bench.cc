// SPDX-License-Identifier: LGPL-2.1-only
// Pipeline API sink callback overhead (issue 12, Performance: <= +1 us per buffer): the same
// `videotestsrc num-buffers=N pattern=black ! video/x-raw,format=GRAY8,width=4,height=4,
// framerate=0/1 ! tensor_converter ! tensor_sink` pipeline, once with a plain tensor_sink
// `new-data` signal handler (gst_parse_launch + g_signal_connect) and once through
// ml_pipeline_construct + ml_pipeline_sink_register. Both handlers do the same work (count the
// frame, read its first byte). Reported: process CPU and wall time per buffer of each, and the
// difference (the API's cost per buffer). Configurations alternate; the best round of each counts
// (the machine is shared, so the fastest round is the least disturbed one).
//
// The plugin is loaded from build/plugin (GST_PLUGIN_PATH), as applications of the library do.
//
// usage: capi_sink_bench [--buffers N] [--runs R]
#include <gst/gst.h>
#include <time.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>

#include "nnstreamer.h"

namespace {

struct Timing {
  double wall = 1e9, cpu = 1e9;
};

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

double wall_seconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}

std::atomic<long> g_frames{0};
std::atomic<unsigned> g_sum{0};

void plain_handler(GstElement *, GstBuffer *buf, gpointer) {
  GstMapInfo m;
  GstMemory *mem = gst_buffer_peek_memory(buf, 0);
  if (gst_memory_map(mem, &m, GST_MAP_READ)) {
    g_sum += m.data[0];
    gst_memory_unmap(mem, &m);
  }
  ++g_frames;
}

void api_handler(const ml_tensors_data_h data, const ml_tensors_info_h, void *) {
  void *raw = nullptr;
  size_t size = 0;
  if (ml_tensors_data_get_tensor_data(data, 0, &raw, &size) == ML_ERROR_NONE)
    g_sum += static_cast<unsigned char *>(raw)[0];
  ++g_frames;
}

std::string description(long n) {
  return "videotestsrc num-buffers=" + std::to_string(n) +
         " pattern=black ! video/x-raw,format=GRAY8,width=4,height=4,framerate=0/1 ! "
         "tensor_converter ! tensor_sink name=sink";
}

void wait_frames(long n) {
  while (g_frames.load() < n) std::this_thread::sleep_for(std::chrono::microseconds(200));
}

Timing run_plain(long n) {
  GstElement *p = gst_parse_launch(description(n).c_str(), nullptr);
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  g_signal_connect(sink, "new-data", G_CALLBACK(plain_handler), nullptr);
  gst_element_set_state(p, GST_STATE_PAUSED);
  gst_element_get_state(p, nullptr, nullptr, GST_CLOCK_TIME_NONE);
  g_frames = 0;
  double c0 = cpu_seconds(), w0 = wall_seconds();
  gst_element_set_state(p, GST_STATE_PLAYING);
  wait_frames(n);
  Timing t{wall_seconds() - w0, cpu_seconds() - c0};
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(p);
  return t;
}

Timing run_api(long n) {
  ml_pipeline_h p = nullptr;
  ml_pipeline_sink_h s = nullptr;
  if (ml_pipeline_construct(description(n).c_str(), nullptr, nullptr, &p) != ML_ERROR_NONE ||
      ml_pipeline_sink_register(p, "sink", api_handler, nullptr, &s) != ML_ERROR_NONE) {
    std::fprintf(stderr, "capi_sink_bench: %s\n", ml_error());
    std::exit(1);
  }
  ml_pipeline_state_e st = ML_PIPELINE_STATE_UNKNOWN;
  while (ml_pipeline_get_state(p, &st) == ML_ERROR_NONE && st != ML_PIPELINE_STATE_PAUSED)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  g_frames = 0;
  double c0 = cpu_seconds(), w0 = wall_seconds();
  ml_pipeline_start(p);
  wait_frames(n);
  Timing t{wall_seconds() - w0, cpu_seconds() - c0};
  ml_pipeline_sink_unregister(s);
  ml_pipeline_destroy(p);
  return t;
}

}  // namespace

int main(int argc, char **argv) {
  long n = 100000;
  int runs = 7;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--buffers")) n = std::atol(argv[i + 1]);
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
  }
  const std::string b = NNS_BUILD_DIR;
  setenv("GST_PLUGIN_PATH", (b + "/plugin").c_str(), 0);
  setenv("NNSTREAMER_CONF", (b + "/nnstreamer.ini").c_str(), 0);
  bool av = false;
  if (ml_check_element_availability("tensor_sink", &av) != ML_ERROR_NONE || !av) {
    std::fprintf(stderr, "capi_sink_bench: tensor_sink not found (GST_PLUGIN_PATH=%s)\n",
                 std::getenv("GST_PLUGIN_PATH"));
    return 1;
  }
  Timing plain, api;
  run_plain(n / 10);  // warm-up
  run_api(n / 10);
  for (int r = 0; r < runs; ++r) {
    Timing a = run_plain(n), c = run_api(n);
    plain.wall = std::min(plain.wall, a.wall);
    plain.cpu = std::min(plain.cpu, a.cpu);
    api.wall = std::min(api.wall, c.wall);
    api.cpu = std::min(api.cpu, c.cpu);
  }
  auto us = [n](double s) { return s / n * 1e6; };
  std::printf("capi_sink_bench: %ld buffers of 4x4 GRAY8, best of %d rounds\n", n, runs);
  std::printf("  plain tensor_sink new-data handler : %.3f us/buffer CPU, %.3f us wall\n",
              us(plain.cpu), us(plain.wall));
  std::printf("  ml_pipeline_sink_register callback : %.3f us/buffer CPU, %.3f us wall\n",
              us(api.cpu), us(api.wall));
  std::printf(
      "  Pipeline API overhead              : %+.3f us/buffer CPU, %+.3f us wall "
      "(target <= +1 us)\n",
      us(api.cpu - plain.cpu), us(api.wall - plain.wall));
  return 0;
}

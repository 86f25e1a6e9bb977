// SPDX-License-Identifier: LGPL-2.1-only
// Stream-composition benchmarks:
//  1. tensor_mux of 4 tiny streams (uint8 4) and tensor_demux back: cost per buffer per element,
//     as time above pipelines without the element (4 fakesrc -> 4 fakesink; 4 fakesrc -> mux ->
//     fakesink), divided by the buffers the element handles (target <= 2 us). Wall and
//     process-CPU time; the median of --runs interleaved runs.
//  2. E1: two "models" that each burn ~1 ms of CPU (custom-easy filters): the pipelined
//     `f1 ! queue ! f2` against the same two filters serially in one streaming thread and
//     against calling the two functions in a plain loop (target >= 1.6x on 2 cores).
//
// usage: mux_demux_bench [--buffers N] [--runs R] [--frames F] [--burn-us U] [--sleep]
#include <gst/gst.h>
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.h"
#include "gst/plugin_init.h"
#include "tensor_filter_custom_easy.h"

namespace {

using nns::bench::Clock;
using nns::bench::median;
using nns::bench::time_pipeline;
using nns::bench::Timing;

const char *kTiny =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8,framerate=30/1";

std::string source(int i, int n) {
  // datarate timestamps the buffers (4 bytes per buffer at 30 buffers/s).
  return "fakesrc num-buffers=" + std::to_string(n) +
         " sizetype=fixed sizemax=4 filltype=zero datarate=120 ! capsfilter caps=\"" + kTiny +
         "\" ! " + (i >= 0 ? "mux.sink_" + std::to_string(i) + " " : "");
}

std::string sinks_direct(int n) {
  std::string d;
  for (int i = 0; i < 4; ++i) d += source(-1, n) + "fakesink sync=false async=false ";
  return d;
}

std::string mux_only(int n, const std::string &mode) {
  std::string d = "tensor_mux name=mux sync-mode=" + mode + " ! fakesink sync=false ";
  for (int i = 0; i < 4; ++i) d += source(i, n);
  return d;
}

std::string mux_demux(int n, const std::string &mode) {
  std::string d = "tensor_mux name=mux sync-mode=" + mode + " ! tensor_demux name=d ";
  for (int i = 0; i < 4; ++i)
    d += "d.src_" + std::to_string(i) + " ! fakesink sync=false async=false ";
  for (int i = 0; i < 4; ++i) d += source(i, n);
  return d;
}

// ---- E1: two CPU-bound models --------------------------------------------------------------

int g_burn_us = 1000;
bool g_sleep = false;  // --sleep: the models wait instead of computing (an accelerator)

// Spins for g_burn_us of thread CPU time, then copies input to output.
int burn(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
         GstTensorMemory *out) {
  if (g_sleep) {
    g_usleep(g_burn_us);
    std::memcpy(out[0].data, in[0].data, std::min(in[0].size, out[0].size));
    return 0;
  }
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  const double end = ts.tv_sec + ts.tv_nsec * 1e-9 + g_burn_us * 1e-6;
  volatile double x = 0;
  for (;;) {
    for (int i = 0; i < 1000; ++i) x = x + 1.0;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
    if (ts.tv_sec + ts.tv_nsec * 1e-9 >= end) break;
  }
  std::memcpy(out[0].data, in[0].data, std::min(in[0].size, out[0].size));
  return 0;
}

GstTensorsInfo tiny_info() {
  GstTensorsInfo i{};
  i.num_tensors = 1;
  i.info[0].type = _NNS_UINT8;
  i.info[0].dimension[0] = 4;
  return i;
}

std::string two_models(int frames, bool pipelined) {
  return "fakesrc num-buffers=" + std::to_string(frames) +
         " sizetype=fixed sizemax=4 filltype=zero ! capsfilter caps=\"" + kTiny +
         "\" ! tensor_filter framework=custom-easy model=burn_a ! " +
         (pipelined ? "queue max-size-buffers=4 ! " : "") +
         "tensor_filter framework=custom-easy model=burn_b ! fakesink sync=false";
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  if (!nns_register_static()) {
    std::fprintf(stderr, "cannot register the plugin\n");
    return 1;
  }
  int n = 20000, runs = 5, frames = 400;
  for (int i = 1; i < argc; ++i)
    if (!std::strcmp(argv[i], "--sleep")) g_sleep = true;
  nns::bench::int_options(
      argc, argv,
      {{"--buffers", &n}, {"--runs", &runs}, {"--frames", &frames}, {"--burn-us", &g_burn_us}});

  std::printf("# 1. tensor_mux (4 x uint8 4) + tensor_demux, %d buffers per stream, median of %d\n",
              n, runs);
  for (const std::string mode : {"nosync", "slowest"}) {
    const std::vector<Timing> t =
        nns::bench::measure({sinks_direct(n), mux_only(n, mode), mux_demux(n, mode)}, runs);
    if (!nns::bench::all_measured(t)) return 1;
    const double in_bufs = 4.0 * n;
    std::printf("sync-mode=%s\n", mode.c_str());
    std::printf("  baseline 4 src -> 4 sink     wall %.3f s  cpu %.3f s\n", t[0].wall, t[0].cpu);
    std::printf("  4 src -> mux -> sink         wall %.3f s  cpu %.3f s\n", t[1].wall, t[1].cpu);
    std::printf("  4 src -> mux -> demux -> 4   wall %.3f s  cpu %.3f s\n", t[2].wall, t[2].cpu);
    std::printf(
        "  tensor_mux:   %.2f us wall, %.2f us cpu per input buffer (%.2f / %.2f per "
        "output)\n",
        (t[1].wall - t[0].wall) / in_bufs * 1e6, (t[1].cpu - t[0].cpu) / in_bufs * 1e6,
        (t[1].wall - t[0].wall) / n * 1e6, (t[1].cpu - t[0].cpu) / n * 1e6);
    std::printf(
        "  tensor_demux: %.2f us wall, %.2f us cpu per output buffer (%.2f / %.2f per "
        "input)\n",
        (t[2].wall - t[1].wall) / in_bufs * 1e6, (t[2].cpu - t[1].cpu) / in_bufs * 1e6,
        (t[2].wall - t[1].wall) / n * 1e6, (t[2].cpu - t[1].cpu) / n * 1e6);
  }

  std::printf("\n# 2. E1: two models %s %d us each, %d frames, median of %d\n",
              g_sleep ? "waiting" : "burning CPU for", g_burn_us, frames, runs);
  GstTensorsInfo info = tiny_info();
  if (NNS_custom_easy_register("burn_a", burn, nullptr, &info, &info) != 0 ||
      NNS_custom_easy_register("burn_b", burn, nullptr, &info, &info) != 0) {
    std::fprintf(stderr, "cannot register the custom-easy models\n");
    return 1;
  }
  std::vector<double> ws, wp, wl;
  for (int r = 0; r < runs; ++r) {
    Timing s = time_pipeline(two_models(frames, false));
    Timing p = time_pipeline(two_models(frames, true));
    if (s.wall < 0 || p.wall < 0) return 1;
    ws.push_back(s.wall);
    wp.push_back(p.wall);
    // The same two invokes back to back in one thread, no GStreamer.
    uint8_t a[4] = {0}, b[4] = {0};
    GstTensorMemory ma{a, 4}, mb{b, 4};
    auto t0 = Clock::now();
    for (int f = 0; f < frames; ++f) {
      burn(nullptr, nullptr, &ma, &mb);
      burn(nullptr, nullptr, &mb, &ma);
    }
    wl.push_back(std::chrono::duration<double>(Clock::now() - t0).count());
  }
  std::printf("  plain loop (f1; f2)            %.1f frames/s\n", frames / median(wl));
  std::printf("  pipeline f1 ! f2 (one thread)  %.1f frames/s\n", frames / median(ws));
  std::printf("  pipeline f1 ! queue ! f2       %.1f frames/s\n", frames / median(wp));
  std::printf("  speed-up: %.2fx vs the one-thread pipeline, %.2fx vs the plain loop\n",
              median(ws) / median(wp), median(wl) / median(wp));
  NNS_custom_easy_unregister("burn_a");
  NNS_custom_easy_unregister("burn_b");
  return 0;
}

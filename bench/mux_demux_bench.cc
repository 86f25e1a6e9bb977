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

#include "gst/plugin_init.h"
#include "tensor_filter_custom_easy.h"

namespace {

using Clock = std::chrono::steady_clock;

struct Timing {
  double wall = -1;
  double cpu = -1;
};

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

Timing time_pipeline(const std::string &desc) {
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

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? -1 : v[v.size() / 2];
}

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
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--buffers")) n = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--burn-us")) g_burn_us = std::atoi(argv[i + 1]);
  }

  std::printf("# 1. tensor_mux (4 x uint8 4) + tensor_demux, %d buffers per stream, median of %d\n",
              n, runs);
  for (const std::string mode : {"nosync", "slowest"}) {
    std::vector<double> w0, c0, w1, c1, w2, c2;
    for (int r = 0; r < runs; ++r) {
      Timing a = time_pipeline(sinks_direct(n));
      Timing b = time_pipeline(mux_only(n, mode));
      Timing c = time_pipeline(mux_demux(n, mode));
      if (a.wall < 0 || b.wall < 0 || c.wall < 0) return 1;
      w0.push_back(a.wall), c0.push_back(a.cpu);
      w1.push_back(b.wall), c1.push_back(b.cpu);
      w2.push_back(c.wall), c2.push_back(c.cpu);
    }
    const double in_bufs = 4.0 * n;
    std::printf("sync-mode=%s\n", mode.c_str());
    std::printf("  baseline 4 src -> 4 sink     wall %.3f s  cpu %.3f s\n", median(w0), median(c0));
    std::printf("  4 src -> mux -> sink         wall %.3f s  cpu %.3f s\n", median(w1), median(c1));
    std::printf("  4 src -> mux -> demux -> 4   wall %.3f s  cpu %.3f s\n", median(w2), median(c2));
    std::printf(
        "  tensor_mux:   %.2f us wall, %.2f us cpu per input buffer (%.2f / %.2f per "
        "output)\n",
        (median(w1) - median(w0)) / in_bufs * 1e6, (median(c1) - median(c0)) / in_bufs * 1e6,
        (median(w1) - median(w0)) / n * 1e6, (median(c1) - median(c0)) / n * 1e6);
    std::printf(
        "  tensor_demux: %.2f us wall, %.2f us cpu per output buffer (%.2f / %.2f per "
        "input)\n",
        (median(w2) - median(w1)) / in_bufs * 1e6, (median(c2) - median(c1)) / in_bufs * 1e6,
        (median(w2) - median(w1)) / n * 1e6, (median(c2) - median(c1)) / n * 1e6);
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

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter framework overhead (filter issue):
//  1. microseconds per buffer that a custom-easy pass-through filter adds on tiny tensors
//     (uint8 4:1:1:1), above the same pipeline without the filter (target <= 2 us);
//     also with latency=1 throughput=1 (profiling on);
//  2. input zero-copy: the fraction of invokes whose input pointer is not the upstream
//     buffer's memory (target 0).
// Each configuration runs --runs times, interleaved; the median is reported.
//
// usage: filter_overhead_bench [--buffers N] [--runs R]
#include <gst/gst.h>
#include <time.h>

#include <algorithm>
#include <atomic>
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

int passthrough(void *, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                GstTensorMemory *out) {
  for (unsigned i = 0; i < prop->input_meta.num_tensors; ++i)
    std::memcpy(out[i].data, in[i].data, in[i].size);
  return 0;
}

std::atomic<const void *> g_seen{nullptr};
std::atomic<long> g_checked{0}, g_copied{0};
const void *g_upstream = nullptr;

int record_ptr(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
               GstTensorMemory *out) {
  g_seen = in[0].data;
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// Wall seconds from PLAYING to EOS (negative on error); *cpu receives the process CPU seconds
// spent meanwhile (robust when other processes compete for the cores).
double time_pipeline(const std::string &desc, double *cpu) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "bench: cannot parse '%s': %s\n", desc.c_str(), err ? err->message : "?");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return -1;
  }
  GstBus *bus = gst_element_get_bus(p);
  auto t0 = Clock::now();
  double c0 = cpu_seconds();
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  double s = std::chrono::duration<double>(Clock::now() - t0).count();
  *cpu = cpu_seconds() - c0;
  if (!m || GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    if (m) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      std::fprintf(stderr, "bench: error in '%s': %s\n", desc.c_str(), e->message);
      g_error_free(e);
    }
    s = -1;
  }
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(p);
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? -1 : v[v.size() / 2];
}

GstPadProbeReturn probe_in(GstPad *, GstPadProbeInfo *info, gpointer) {
  GstBuffer *b = GST_PAD_PROBE_INFO_BUFFER(info);
  GstMapInfo map;
  GstMemory *mem = gst_buffer_peek_memory(b, 0);
  if (gst_memory_map(mem, &map, GST_MAP_READ)) {
    g_upstream = map.data;
    gst_memory_unmap(mem, &map);
  }
  return GST_PAD_PROBE_OK;
}

GstPadProbeReturn probe_out(GstPad *, GstPadProbeInfo *, gpointer) {
  g_checked++;
  if (g_seen.load() != g_upstream) g_copied++;
  return GST_PAD_PROBE_OK;
}

void zero_copy_check(int frames) {
  std::string desc = "fakesrc num-buffers=" + std::to_string(frames) +
                     " sizetype=fixed sizemax=150528 filltype=zero ! other/tensors,format=static,"
                     "num_tensors=1,types=(string)uint8,dimensions=(string)3:224:224:1,"
                     "framerate=0/1 ! tensor_filter name=f framework=custom-easy "
                     "model=bench_record ! fakesink";
  GstElement *p = gst_parse_launch(desc.c_str(), nullptr);
  GstElement *f = gst_bin_get_by_name(GST_BIN(p), "f");
  GstPad *sink = gst_element_get_static_pad(f, "sink");
  GstPad *src = gst_element_get_static_pad(f, "src");
  gst_pad_add_probe(sink, GST_PAD_PROBE_TYPE_BUFFER, probe_in, nullptr, nullptr);
  gst_pad_add_probe(src, GST_PAD_PROBE_TYPE_BUFFER, probe_out, nullptr, nullptr);
  gst_object_unref(sink);
  gst_object_unref(src);
  gst_object_unref(f);
  GstBus *bus = gst_element_get_bus(p);
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 60 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(p);
}

std::string caps(int tensors) {  // `tensors` x uint8 4:1:1:1
  std::string types, dims;
  for (int i = 0; i < tensors; ++i) {
    types += (i ? "," : "") + std::string("uint8");
    dims += (i ? "," : "") + std::string("4:1:1:1");
  }
  return "other/tensors,format=static,num_tensors=" + std::to_string(tensors) +
         ",types=(string)\"" + types + "\",dimensions=(string)\"" + dims + "\",framerate=0/1";
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  if (!nns_register_static()) {
    std::fprintf(stderr, "bench: cannot register the nnstreamer elements\n");
    return 1;
  }
  int n = 100000, runs = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    int v = std::atoi(argv[i + 1]);
    if (a == "--buffers") n = v;
    if (a == "--runs") runs = v;
  }
  GstTensorsInfo one{};
  one.num_tensors = 1;
  one.info[0].type = _NNS_UINT8;
  one.info[0].dimension[0] = 4;
  one.info[0].dimension[1] = one.info[0].dimension[2] = one.info[0].dimension[3] = 1;
  NNS_custom_easy_register("bench_pass", passthrough, nullptr, &one, &one);
  GstTensorsInfo big{};
  big.num_tensors = 1;
  big.info[0].type = _NNS_UINT8;
  big.info[0].dimension[0] = 3;
  big.info[0].dimension[1] = big.info[0].dimension[2] = 224;
  big.info[0].dimension[3] = 1;
  NNS_custom_easy_register("bench_record", record_ptr, nullptr, &big, &big);

  const std::string src = "fakesrc num-buffers=" + std::to_string(n) +
                          " sizetype=fixed sizemax=4 filltype=nothing ! " + caps(1) + " ! ";
  std::vector<std::string> d = {
      src + "fakesink sync=false",
      src + "tensor_filter framework=custom-easy model=bench_pass ! fakesink sync=false",
      src +
          "tensor_filter framework=custom-easy model=bench_pass latency=1 throughput=1 ! "
          "fakesink sync=false",
  };
  std::vector<std::vector<double>> t(d.size()), c(d.size());
  for (int r = 0; r < runs; ++r)
    for (std::size_t i = 0; i < d.size(); ++i) {
      double cpu = 0;
      double s = time_pipeline(d[i], &cpu);
      if (s < 0) return 1;
      t[i].push_back(s);
      c[i].push_back(cpu);
    }
  const char *names[] = {"fakesrc ! capsfilter ! fakesink         ",
                         "+ tensor_filter custom-easy pass-through",
                         "+ same with latency=1 throughput=1      "};
  std::printf("filter overhead, %d buffers of uint8 4:1:1:1, median of %d runs\n", n, runs);
  std::printf("  %s    wall us/buf (added)    cpu us/buf (added; target <= 2)\n",
              "                                        ");
  for (std::size_t i = 0; i < d.size(); ++i) {
    double w = median(t[i]) * 1e6 / n, cu = median(c[i]) * 1e6 / n;
    double w0 = median(t[0]) * 1e6 / n, c0 = median(c[0]) * 1e6 / n;
    std::printf("  %s :  %7.3f (%+.3f)       %7.3f (%+.3f)\n", names[i], w, w - w0, cu, cu - c0);
  }

  zero_copy_check(200);
  std::printf(
      "input zero-copy (3:224:224:1 uint8, 200 frames): %ld of %ld invokes saw a copy "
      "(target 0)\n",
      g_copied.load(), g_checked.load());
  return 0;
}

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

#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.h"
#include "gst/plugin_init.h"
#include "tensor_filter_custom_easy.h"

namespace {

using nns::bench::Timing;

std::atomic<const void *> g_seen{nullptr};
std::atomic<long> g_checked{0}, g_copied{0};
const void *g_upstream = nullptr;

int record_ptr(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
               GstTensorMemory *out) {
  g_seen = in[0].data;
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
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
  nns::bench::play_to_eos(p, 60 * GST_SECOND);
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
  nns::bench::int_options(argc, argv, {{"--buffers", &n}, {"--runs", &runs}});
  nns::bench::register_tiny_passthrough("bench_pass");
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
  const std::vector<Timing> t = nns::bench::measure(d, runs);
  if (!nns::bench::all_measured(t)) return 1;
  const char *names[] = {"fakesrc ! capsfilter ! fakesink         ",
                         "+ tensor_filter custom-easy pass-through",
                         "+ same with latency=1 throughput=1      "};
  std::printf("filter overhead, %d buffers of uint8 4:1:1:1, median of %d runs\n", n, runs);
  std::printf("  %s    wall us/buf (added)    cpu us/buf (added; target <= 2)\n",
              "                                        ");
  for (std::size_t i = 0; i < d.size(); ++i) {
    double w = t[i].wall * 1e6 / n, cu = t[i].cpu * 1e6 / n;
    double w0 = t[0].wall * 1e6 / n, c0 = t[0].cpu * 1e6 / n;
    std::printf("  %s :  %7.3f (%+.3f)       %7.3f (%+.3f)\n", names[i], w, w - w0, cu, cu - c0);
  }

  zero_copy_check(200);
  std::printf(
      "input zero-copy (3:224:224:1 uint8, 200 frames): %ld of %ld invokes saw a copy "
      "(target 0)\n",
      g_copied.load(), g_checked.load());
  return 0;
}

// SPDX-License-Identifier: LGPL-2.1-only
// Per-buffer cost of NNStreamer 2.x-ABI filters against our custom-easy pass-through
// (issue 10; target: within 10%), on tiny tensors (uint8 4:1:1:1) where the filter's own
// overhead dominates:
//   - framework=custom-easy, a registered pass-through function (ours, the reference);
//   - framework=custom model=libbench2x_custom_pass.so (NNStreamer_custom, 2.x ABI);
//   - framework=bench2x_pass, an NNStreamer 2.x filter sub-plugin (layout 1) through the bridge.
// Each configuration runs --runs times, interleaved; medians of wall and process CPU time per
// buffer are reported, minus the same pipeline without a filter, and as a ratio to custom-easy.
//
// usage: subplugin2x_bench [--buffers N] [--runs R]
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

int passthrough(void *, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
                GstTensorMemory *out) {
  for (unsigned i = 0; i < prop->input_meta.num_tensors; ++i)
    std::memcpy(out[i].data, in[i].data, in[i].size);
  return 0;
}

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

// Wall seconds from PLAYING to EOS (negative on error); *cpu: process CPU seconds meanwhile.
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
      gchar *dbg = nullptr;
      gst_message_parse_error(m, &e, &dbg);
      std::fprintf(stderr, "bench: error in '%s': %s\n", desc.c_str(), e->message);
      g_error_free(e);
      g_free(dbg);
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

}  // namespace

int main(int argc, char **argv) {
  const std::string b = NNS_BUILD_DIR;
  setenv("NNSTREAMER_CONF", (b + "/nnstreamer.ini").c_str(), 0);
  setenv("NNSTREAMER_FILTERS", (b + "/bench/2x").c_str(), 1);
  gst_init(&argc, &argv);
  if (!nns_register_static()) {
    std::fprintf(stderr, "bench: cannot register the nnstreamer elements\n");
    return 1;
  }
  int n = 100000, runs = 7;
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

  const std::string src =
      "fakesrc num-buffers=" + std::to_string(n) +
      " sizetype=fixed sizemax=4 filltype=nothing ! other/tensors,format=static,num_tensors=1,"
      "types=(string)uint8,dimensions=(string)4:1:1:1,framerate=0/1 ! ";
  std::vector<std::string> d = {
      src + "fakesink sync=false",
      src + "tensor_filter framework=custom-easy model=bench_pass ! fakesink sync=false",
      src + "tensor_filter framework=custom model=" + b +
          "/bench/2x/libbench2x_custom_pass.so ! fakesink sync=false",
      src + "tensor_filter framework=bench2x_pass ! fakesink sync=false",
  };
  const char *names[] = {
      "no filter (fakesrc ! capsfilter ! fakesink)", "custom-easy pass-through (reference)      ",
      "custom, NNStreamer_custom .so (2.x ABI)   ", "2.x filter sub-plugin (layout 1, bridge)  "};
  std::vector<std::vector<double>> t(d.size()), c(d.size());
  for (int r = 0; r < runs; ++r)
    for (std::size_t i = 0; i < d.size(); ++i) {
      double cpu = 0;
      double s = time_pipeline(d[i], &cpu);
      if (s < 0) return 1;
      t[i].push_back(s);
      c[i].push_back(cpu);
    }
  std::printf("2.x-ABI filters, %d buffers of uint8 4:1:1:1, median of %d interleaved runs\n", n,
              runs);
  std::printf(
      "  %-43s  wall us/buf (filter)  cpu us/buf (filter)  cpu vs custom-easy: "
      "per buffer, filter part\n",
      "");
  const double w0 = median(t[0]) * 1e6 / n, c0 = median(c[0]) * 1e6 / n;
  const double ref = median(c[1]) * 1e6 / n;
  for (std::size_t i = 0; i < d.size(); ++i) {
    double w = median(t[i]) * 1e6 / n, cu = median(c[i]) * 1e6 / n;
    std::printf("  %s :  %6.3f (%+.3f)       %6.3f (%+.3f)", names[i], w, w - w0, cu, cu - c0);
    if (i >= 1) std::printf("     %.3f, %.3f (target <= 1.10)", cu / ref, (cu - c0) / (ref - c0));
    std::printf("\n");
  }
  return 0;
}

// SPDX-License-Identifier: LGPL-2.1-only
// Cost per buffer of an NNStreamer 2.x-ABI custom filter (framework=custom, a C .so built against
// the NNStreamer headers and linked to libnnstreamer-single.so: tests/compat/ext/
// ext_passthrough_variable.c, which calls gst_tensors_info_get_size() per tensor) against our
// custom-easy pass-through, on tiny tensors (uint8 4:1:1:1), each above the same pipeline without
// a filter. Runs are interleaved; medians of process CPU time are reported (robust when other
// processes share the cores). Target (issue 10): the 2.x filter within 10% of custom-easy.
//
// usage: compat_custom_bench [--buffers N] [--runs R]
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

// Process CPU seconds from PLAYING to EOS; negative on error.
double run(const std::string &desc) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "bench: cannot parse '%s': %s\n", desc.c_str(), err ? err->message : "?");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return -1;
  }
  GstBus *bus = gst_element_get_bus(p);
  double c0 = cpu_seconds();
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  double s = cpu_seconds() - c0;
  if (!m || GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    std::fprintf(stderr, "bench: '%s' did not reach EOS\n", desc.c_str());
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
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  if (!nns_register_static()) return 1;
  int n = 100000, runs = 7;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (std::string(argv[i]) == "--buffers") n = std::atoi(argv[i + 1]);
    if (std::string(argv[i]) == "--runs") runs = std::atoi(argv[i + 1]);
  }
  GstTensorsInfo one{};
  one.num_tensors = 1;
  one.info[0].type = _NNS_UINT8;
  one.info[0].dimension[0] = 4;
  one.info[0].dimension[1] = one.info[0].dimension[2] = one.info[0].dimension[3] = 1;
  NNS_custom_easy_register("bench_pass", passthrough, nullptr, &one, &one);
  const std::string src = "fakesrc num-buffers=" + std::to_string(n) +
                          " sizetype=fixed sizemax=4 filltype=nothing ! other/tensors,"
                          "format=static,num_tensors=1,types=(string)uint8,"
                          "dimensions=(string)4:1:1:1,framerate=0/1 ! ";
  const std::vector<std::string> d = {
      src + "fakesink sync=false",
      src + "tensor_filter framework=custom-easy model=bench_pass ! fakesink sync=false",
      src + "tensor_filter framework=custom model=" NNS_BENCH_EXT_FILTER " ! fakesink sync=false",
  };
  std::vector<std::vector<double>> c(d.size());
  for (int r = 0; r < runs; ++r)
    for (std::size_t i = 0; i < d.size(); ++i) {
      double s = run(d[i]);
      if (s < 0) return 1;
      c[i].push_back(s * 1e6 / n);
    }
  const double base = median(c[0]), easy = median(c[1]), ext = median(c[2]);
  std::printf("custom filter cost, %d buffers of uint8 4:1:1:1, median of %d runs (cpu us/buf)\n",
              n, runs);
  std::printf("  no filter                          : %7.3f\n", base);
  std::printf("  custom-easy pass-through           : %7.3f (filter adds %.3f)\n", easy,
              easy - base);
  std::printf("  2.x-ABI custom .so pass-through    : %7.3f (filter adds %.3f)\n", ext, ext - base);
  std::printf("  2.x .so / custom-easy: per buffer %.3f, added cost %.3f (target <= 1.10)\n",
              ext / easy, (ext - base) / (easy - base));
  return 0;
}

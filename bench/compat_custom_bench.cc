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

#include <cstdio>
#include <string>
#include <vector>

#include "bench_util.h"
#include "gst/plugin_init.h"

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  if (!nns_register_static()) return 1;
  int n = 100000, runs = 7;
  nns::bench::int_options(argc, argv, {{"--buffers", &n}, {"--runs", &runs}});
  nns::bench::register_tiny_passthrough("bench_pass");
  const std::string src = "fakesrc num-buffers=" + std::to_string(n) +
                          " sizetype=fixed sizemax=4 filltype=nothing ! other/tensors,"
                          "format=static,num_tensors=1,types=(string)uint8,"
                          "dimensions=(string)4:1:1:1,framerate=0/1 ! ";
  const std::vector<std::string> d = {
      src + "fakesink sync=false",
      src + "tensor_filter framework=custom-easy model=bench_pass ! fakesink sync=false",
      src + "tensor_filter framework=custom model=" NNS_BENCH_EXT_FILTER " ! fakesink sync=false",
  };
  // Process CPU time (robust when other processes share the cores), us per buffer.
  const std::vector<nns::bench::Timing> t = nns::bench::measure(d, runs);
  if (!nns::bench::all_measured(t)) return 1;
  const double base = t[0].cpu * 1e6 / n, easy = t[1].cpu * 1e6 / n, ext = t[2].cpu * 1e6 / n;
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

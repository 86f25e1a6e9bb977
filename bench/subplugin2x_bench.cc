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
  nns::bench::int_options(argc, argv, {{"--buffers", &n}, {"--runs", &runs}});
  nns::bench::register_tiny_passthrough("bench_pass");

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
  const std::vector<Timing> t = nns::bench::measure(d, runs);
  if (!nns::bench::all_measured(t)) return 1;
  std::printf("2.x-ABI filters, %d buffers of uint8 4:1:1:1, median of %d interleaved runs\n", n,
              runs);
  std::printf(
      "  %-43s  wall us/buf (filter)  cpu us/buf (filter)  cpu vs custom-easy: "
      "per buffer, filter part\n",
      "");
  const double w0 = t[0].wall * 1e6 / n, c0 = t[0].cpu * 1e6 / n;
  const double ref = t[1].cpu * 1e6 / n;
  for (std::size_t i = 0; i < d.size(); ++i) {
    double w = t[i].wall * 1e6 / n, cu = t[i].cpu * 1e6 / n;
    std::printf("  %s :  %6.3f (%+.3f)       %6.3f (%+.3f)", names[i], w, w - w0, cu, cu - c0);
    if (i >= 1) std::printf("     %.3f, %.3f (target <= 1.10)", cu / ref, (cu - c0) / (ref - c0));
    std::printf("\n");
  }
  return 0;
}

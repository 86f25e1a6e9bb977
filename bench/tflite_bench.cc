// SPDX-License-Identifier: LGPL-2.1-only
// TFLite back end speed (issue 18): MobileNet v2 quant as .tflite through our tensorflow2-lite
// back end (translated to ONNX, run by ONNX Runtime) versus the same network as
// mobilenet_v2_quant.onnx on the onnxruntime back end, both called directly through their C
// ABI, at 1 and 2 threads (custom=NumThreads:N); then the .tflite through a pipeline
// (multifilesrc ! tensor_converter ! tensor_filter ! fakesink) to show the pipeline overhead.
// Rounds interleave the configurations; medians over rounds are printed (the 2-core machine is
// shared). Target: tflite/onnx <= 1.3 at each thread count.
//
// usage: tflite_bench [--frames N] [--runs R]
#include <gst/gst.h>

#include <chrono>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "bench_util.h"
#include "filter_direct.h"
#include "gst/plugin_init.h"

namespace {

using nns::bench::Clock;
using nns::bench::median;

// A back end opened directly, with its input (filled with 100) and output buffers.
struct Direct : nns::bench::DirectFilter {
  std::vector<uint8_t> in, out;
};

bool open_direct(const std::string &backend, const std::string &model, int threads, Direct &d,
                 std::size_t in_bytes, std::size_t out_bytes) {
  if (!nns::bench::open_direct(nns::bench::filter_so(backend), backend.c_str(), model,
                               "NumThreads:" + std::to_string(threads), d))
    return false;
  d.in.assign(in_bytes, 100);
  d.out.assign(out_bytes, 0);
  return true;
}

// Milliseconds per invoke over `frames` invokes (after 3 untimed ones).
double ms_per_frame(Direct &d, int frames) {
  GstTensorMemory i = {d.in.data(), d.in.size()}, o = {d.out.data(), d.out.size()};
  char err[512];
  for (int k = 0; k < 3; ++k)
    if (d.api->invoke(d.priv, &i, 1, &o, 1, err, sizeof(err)) != 0) {
      std::fprintf(stderr, "invoke: %s\n", err);
      return -1;
    }
  auto t0 = Clock::now();
  for (int k = 0; k < frames; ++k) d.api->invoke(d.priv, &i, 1, &o, 1, err, sizeof(err));
  return std::chrono::duration<double, std::milli>(Clock::now() - t0).count() / frames;
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  nns_register_static();
  int frames = 30, runs = 5;
  nns::bench::int_options(argc, argv, {{"--frames", &frames}, {"--runs", &runs}});
  std::string models = std::string(NNS_SOURCE_DIR) + "/../shared/models/upstream/models/";
  std::string tfl = models + "mobilenet_v2_1.0_224_quant.tflite";
  std::string onnx = models + "mobilenet_v2_quant.onnx";
  if (!std::ifstream(tfl) || !std::ifstream(onnx)) {
    std::printf("tflite_bench: ../shared/models missing; skipped\n");
    return 0;
  }
  std::printf("tflite_bench: MobileNet v2 quant, %d frames x %d rounds (median ms/frame)\n", frames,
              runs);
  std::printf("%-8s %12s %12s %8s\n", "threads", "tflite(ms)", "onnx(ms)", "ratio");
  double tfl_direct_1 = 0;
  for (int threads : {1, 2}) {
    Direct t, o;
    if (!open_direct("tensorflow2-lite", tfl, threads, t, 224 * 224 * 3, 1001) ||
        !open_direct("onnxruntime", onnx, threads, o, 224 * 224 * 3 * 4, 1000 * 4))
      return 1;
    std::vector<double> tv, ov, ratio;
    for (int r = 0; r < runs; ++r) {
      double a = ms_per_frame(t, frames), b = ms_per_frame(o, frames);
      tv.push_back(a);
      ov.push_back(b);
      ratio.push_back(a / b);
    }
    std::printf("%-8d %12.2f %12.2f %8.2f\n", threads, median(tv), median(ov), median(ratio));
    if (threads == 1) tfl_direct_1 = median(tv);
    t.api->close(t.priv);
    o.api->close(o.priv);
  }
  // Pipeline at 1 thread: (time of 1 + frames buffers - time of 1 buffer) / frames removes the
  // start-up (model translation, session creation); multifilesrc re-reads orange.raw from the
  // page cache (~20 us per 150 KB frame).
  auto desc = [&](int n) {
    return "multifilesrc location=" + std::string(NNS_SOURCE_DIR) +
           "/../shared/models/upstream/data/orange.raw loop=true num-buffers=" + std::to_string(n) +
           " ! application/octet-stream ! tensor_converter input-dim=3:224:224:1 input-type=uint8 "
           "! tensor_filter framework=tensorflow-lite custom=NumThreads:1 model=" +
           tfl + " ! fakesink sync=false";
  };
  std::vector<double> pv;
  for (int r = 0; r < runs; ++r) {
    nns::bench::Timing one = nns::bench::time_pipeline(desc(1));
    nns::bench::Timing many = nns::bench::time_pipeline(desc(1 + frames));
    if (one.wall < 0 || many.wall < 0) {
      std::fprintf(stderr, "pipeline failed: %s\n", desc(1).c_str());
      return 1;
    }
    pv.push_back((many.wall - one.wall) * 1e3 / frames);
  }
  std::printf("pipeline (1 thread, start-up removed): %.2f ms/frame, %.3fx direct\n", median(pv),
              median(pv) / tfl_direct_1);
  return 0;
}

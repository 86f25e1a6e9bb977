// SPDX-License-Identifier: LGPL-2.1-only
// ONNX Runtime back end: real-model throughput through a pipeline versus the back end called
// directly (mobilenet_v2_quant.onnx from ../shared/models, float32 NCHW input made from
// orange.raw).
//  1. direct: dlopen libnnstreamer_filter_onnxruntime.so, open, invoke N times in a loop;
//  2. pipeline: appsrc (the same input buffer pushed N times) ! tensor_filter
//     framework=onnxruntime ! fakesink; ratio = pipeline fps / direct fps (target >= 0.97);
//  3. parallel: appsrc ! tee ! 2 x (queue ! tensor_filter custom=NumThreads:1 ! fakesink):
//     combined inferences/s over one single-threaded filter (target >= 1.7 on 2 cores), with the
//     same for two direct loops in two threads as the machine's own ceiling.
// --runs short rounds run every configuration in turn; ratios are taken within a round and the
// median over rounds is reported (the 2-core machine is shared).
//
// usage: ort_pipeline_bench [--frames N] [--runs R] [--threads T] [--model PATH]
#include <gst/gst.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <thread>
#include <vector>

#include "bench_util.h"
#include "filter_direct.h"
#include "gst/plugin_init.h"

namespace {

using nns::bench::Clock;
using nns::bench::median;
using nns::bench::open_direct;
// Process CPU seconds (every thread): the figure that stays meaningful when the shared machine
// is loaded.
using nns::bench::cpu_seconds;

// Frames per wall second and process CPU milliseconds per frame.
struct Rate {
  double fps = 0;
  double cpu_ms = 0;
};

constexpr int kWarm = 10;  // untimed invokes before each timed run, pipeline and direct alike

struct Opts {
  int frames = 60;
  int runs = 5;
  int threads = 1;  // NumThreads of the single-filter comparison
  std::string model;
  std::string input;
};

std::vector<uint8_t> read_all(const std::string &p) {
  std::ifstream f(p, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(f), {});
}

// orange.raw (224x224 RGB HWC uint8) -> float32 CHW with torchvision's ImageNet normalisation
// ((x - 255 mean) / (255 std) per channel), the model's input.
std::vector<float> make_input(const std::string &raw_path) {
  std::vector<uint8_t> img = read_all(raw_path);
  std::vector<float> chw(3 * 224 * 224);
  if (img.size() != chw.size()) return {};
  const float mean[3] = {123.675f, 116.28f, 103.53f}, stdev[3] = {58.395f, 57.12f, 57.375f};
  for (int y = 0; y < 224; ++y)
    for (int x = 0; x < 224; ++x)
      for (int c = 0; c < 3; ++c)
        chw[c * 224 * 224 + y * 224 + x] = (img[(y * 224 + x) * 3 + c] - mean[c]) / stdev[c];
  return chw;
}

using Direct = nns::bench::DirectFilter;

// Invokes `frames` times (after kWarm untimed invokes).
Rate direct_rate(Direct &d, std::vector<float> &in, int frames) {
  std::vector<float> out(1000);
  GstTensorMemory i = {in.data(), in.size() * 4}, o = {out.data(), out.size() * 4};
  char err[256];
  for (int k = 0; k < kWarm; ++k) d.api->invoke(d.priv, &i, 1, &o, 1, err, sizeof(err));
  double c0 = cpu_seconds();
  auto t0 = Clock::now();
  for (int k = 0; k < frames; ++k) d.api->invoke(d.priv, &i, 1, &o, 1, err, sizeof(err));
  double s = std::chrono::duration<double>(Clock::now() - t0).count();
  return {frames / s, (cpu_seconds() - c0) * 1e3 / frames};
}

double direct_fps(Direct &d, std::vector<float> &in, int frames) {
  return direct_rate(d, in, frames).fps;
}

const char *kCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=224:224:3:1,types=float32,"
    "framerate=0/1";

void push(GstElement *src, GstBuffer *input, int k) {
  GstBuffer *b = gst_buffer_copy(input);  // shares the memory: no data copy
  GST_BUFFER_PTS(b) = k * GST_MSECOND;
  GstFlowReturn ret;
  g_signal_emit_by_name(src, "push-buffer", b, &ret);  // appsrc action signal (takes a ref)
  gst_buffer_unref(b);
}

// Buffers reaching the sink (counted by a pad probe on the first sink): the timed window runs
// from the kWarm-th buffer to the last one, so model loading, warm-up and EOS handling are out.
struct Window {
  std::atomic<int> n{0};
  int total = 0;
  double c0 = 0, c1 = 0;
  Clock::time_point t0, t1;
};

GstPadProbeReturn count_buffer(GstPad *, GstPadProbeInfo *, gpointer data) {
  auto *w = static_cast<Window *>(data);
  int k = ++w->n;
  if (k == kWarm) {
    w->c0 = cpu_seconds();
    w->t0 = Clock::now();
  }
  if (k == w->total) {
    w->t1 = Clock::now();
    w->c1 = cpu_seconds();
  }
  return GST_PAD_PROBE_OK;
}

// Runs `desc` (with an appsrc named src and a fakesink named sink): kWarm warm-up buffers (the
// model is opened by the pipeline; the direct loop is warmed the same way), then `frames`
// timed buffers, all the same input.
Rate pipeline_rate(const std::string &desc, GstBuffer *input, int frames) {
  GError *e = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &e);
  if (!p) {
    std::fprintf(stderr, "pipeline: %s\n", e ? e->message : "?");
    return {};
  }
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src");
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  Window w;
  w.total = kWarm + frames;
  GstPad *sinkpad = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(sinkpad, GST_PAD_PROBE_TYPE_BUFFER, count_buffer, &w, nullptr);
  gst_object_unref(sinkpad);
  GstCaps *caps = gst_caps_from_string(kCaps);
  g_object_set(src, "caps", caps, "format", GST_FORMAT_TIME, "max-buffers", (guint64)4, "block",
               TRUE, nullptr);
  gst_caps_unref(caps);
  gst_element_set_state(p, GST_STATE_PLAYING);
  for (int k = 0; k < kWarm + frames; ++k) push(src, input, k);
  GstFlowReturn ret;
  g_signal_emit_by_name(src, "end-of-stream", &ret);
  GstBus *bus = gst_element_get_bus(p);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  Rate r;
  if (!m || GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    if (m) {
      GError *err = nullptr;
      gst_message_parse_error(m, &err, nullptr);
      std::fprintf(stderr, "pipeline error: %s\n", err->message);
      g_error_free(err);
    }
  } else if (w.n.load() >= w.total) {
    r.fps = frames / std::chrono::duration<double>(w.t1 - w.t0).count();
    r.cpu_ms = (w.c1 - w.c0) * 1e3 / frames;
  }
  if (m) gst_message_unref(m);
  gst_object_unref(bus);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(p);
  return r;
}

double pipeline_fps(const std::string &desc, GstBuffer *input, int frames) {
  return pipeline_rate(desc, input, frames).fps;
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  Opts o;
  std::string shared = std::string(NNS_SOURCE_DIR) + "/../shared/models/upstream";
  o.model = shared + "/models/mobilenet_v2_quant.onnx";
  o.input = shared + "/data/orange.raw";
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string k = argv[i], v = argv[i + 1];
    if (k == "--frames")
      o.frames = std::atoi(v.c_str());
    else if (k == "--runs")
      o.runs = std::atoi(v.c_str());
    else if (k == "--threads")
      o.threads = std::atoi(v.c_str());
    else if (k == "--model")
      o.model = v;
  }
  std::string so = nns::bench::filter_so("onnxruntime");
  std::vector<float> in = make_input(o.input);
  if (in.empty() || !std::ifstream(o.model) || !std::ifstream(so)) {
    std::printf("ort_pipeline_bench: skipped (needs %s, %s and %s)\n", o.model.c_str(),
                o.input.c_str(), so.c_str());
    return 0;
  }
  if (!nns_register_static()) return 1;
  setenv("NNSTREAMER_FILTERS", (std::string(NNS_BUILD_DIR) + "/subplugins/filters").c_str(), 0);
  GstElementFactory *tf = gst_element_factory_find("tensor_filter");
  bool have_filter = tf != nullptr;
  if (tf) gst_object_unref(tf);

  const std::string custom = "NumThreads:" + std::to_string(o.threads);
  Direct d1, d2, d3;
  if (!open_direct(so, "onnxruntime", o.model, custom, d1) ||
      !open_direct(so, "onnxruntime", o.model, "NumThreads:1", d2) ||
      !open_direct(so, "onnxruntime", o.model, "NumThreads:1", d3))
    return 1;
  GstBuffer *buf = gst_buffer_new_memdup(in.data(), in.size() * 4);
  std::string filter = "tensor_filter framework=onnxruntime model=\"" + o.model + "\"";
  std::string single =
      "appsrc name=src ! " + filter + " custom=" + custom + " ! fakesink name=sink sync=false";
  // Each pipeline has one fakesink named sink: the one whose buffers time the run.
  auto branch = [&](const char *sink_name) {
    return "queue max-size-buffers=2 ! " + filter +
           " custom=NumThreads:1 ! fakesink name=" + sink_name + " sync=false";
  };
  std::string one = "appsrc name=src ! " + branch("sink");
  std::string two =
      "appsrc name=src ! tee name=t t. ! " + branch("sink") + " t. ! " + branch("sink2");

  std::string load;
  if (std::FILE *f = std::fopen("/proc/loadavg", "r")) {
    char b[64] = {0};
    if (std::fgets(b, sizeof(b), f)) load.assign(b, std::strcspn(b, "\n"));
    std::fclose(f);
  }
  direct_fps(d1, in, 10);  // warm-up
  direct_fps(d2, in, 10);
  direct_fps(d3, in, 10);
  // Short interleaved rounds: the machine is shared, so each ratio compares runs made seconds
  // apart, and the median over rounds is reported.
  std::vector<double> direct, direct1, direct2, pipe, one_fps, two_fps;
  std::vector<double> r_pipe, r_direct2, r_two, r_pipe_cpu, cpu_direct, cpu_pipe;
  for (int r = 0; r < o.runs; ++r) {
    Rate dr = direct_rate(d1, in, o.frames);
    direct.push_back(dr.fps);
    cpu_direct.push_back(dr.cpu_ms);
    if (have_filter) {
      Rate pr = pipeline_rate(single, buf, o.frames);
      pipe.push_back(pr.fps);
      cpu_pipe.push_back(pr.cpu_ms);
      r_pipe.push_back(pipe.back() / direct.back());
      r_pipe_cpu.push_back(pr.cpu_ms > 0 ? dr.cpu_ms / pr.cpu_ms : 0);
    }
    direct1.push_back(direct_fps(d2, in, o.frames));
    // Two direct loops in two threads, one instance each: the machine's own ceiling.
    double a = 0, b = 0;
    std::vector<float> in2 = in;
    std::thread th([&] { a = direct_fps(d3, in2, o.frames); });
    b = direct_fps(d2, in, o.frames);
    th.join();
    direct2.push_back(a + b);
    r_direct2.push_back(direct2.back() / direct1.back());
    if (have_filter) {
      one_fps.push_back(pipeline_fps(one, buf, o.frames));
      two_fps.push_back(2 * pipeline_fps(two, buf, o.frames));
      r_two.push_back(two_fps.back() / one_fps.back());
    }
  }
  std::printf("model %s, %d frames x %d rounds, medians (load before: %s)\n", o.model.c_str(),
              o.frames, o.runs, load.c_str());
  std::printf("direct loop (NumThreads:%d):          %7.1f inferences/s (%.2f ms)\n", o.threads,
              median(direct), 1000 / median(direct));
  std::printf("direct, 1 thread x NumThreads:1:      %7.1f inferences/s\n", median(direct1));
  std::printf("direct, 2 threads x NumThreads:1:     %7.1f inferences/s combined, %.2fx\n",
              median(direct2), median(r_direct2));
  if (!have_filter) {
    std::printf("pipeline: skipped (tensor_filter is not built yet)\n");
  } else {
    std::printf(
        "pipeline appsrc ! tensor_filter:      %7.1f inferences/s, ratio %.3f "
        "(target >= 0.97)\n",
        median(pipe), median(r_pipe));
    std::printf(
        "  CPU per frame: direct %.3f ms, pipeline %.3f ms, ratio (direct / pipeline) %.3f "
        "(target >= 0.97)\n",
        median(cpu_direct), median(cpu_pipe), median(r_pipe_cpu));
    std::printf("pipeline, one queue branch:           %7.1f inferences/s\n", median(one_fps));
    std::printf(
        "pipeline, tee ! 2 queue branches:     %7.1f inferences/s combined, %.2fx one "
        "branch (target >= 1.7)\n",
        median(two_fps), median(r_two));
  }
  gst_buffer_unref(buf);
  for (Direct *d : {&d1, &d2, &d3}) d->api->close(d->priv);
  return 0;
}

// SPDX-License-Identifier: LGPL-2.1-only
// LeNet-5 (TorchScript) throughput, three ways, on the same 28x28 digit (9.raw):
//   torch    : libtorch alone (from_blob + forward + copy of the 10 scores), in a loop
//   backend  : the pytorch filter back end (.so) called through its C ABI, in a loop
//   pipeline : appsrc ! tensor_filter framework=pytorch ... ! fakesink, one buffer per invoke
// The figure of merit is pipeline / backend (same back end, with and without GStreamer).
// Rounds alternate the modes so machine load hits them alike; medians are reported.
//
//   build/bench/pytorch_pipeline_bench [iterations=2000] [rounds=5] [threads=1]
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <torch/script.h>

#include <ATen/Parallel.h>
#include <c10/core/InferenceMode.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "../tests/backends/backend_lib.h"
#include "gst/plugin_init.h"

namespace {

using Clock = std::chrono::steady_clock;

std::string g_model, g_digit_path;
std::vector<uint8_t> g_digit;
int g_threads = 1;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

int argmax(const uint8_t *s) {
  return static_cast<int>(std::max_element(s, s + 10) - s);
}

// libtorch alone.
double run_torch(torch::jit::Module &m, int n) {
  std::vector<uint8_t> in = g_digit, out(10);
  auto once = [&] {
    c10::InferenceMode guard;
    std::vector<c10::IValue> feeds;
    feeds.emplace_back(torch::from_blob(in.data(), {1, 28, 28, 1}, at::kByte));
    at::Tensor r = m.forward(std::move(feeds)).toTensor().contiguous();
    std::memcpy(out.data(), r.data_ptr(), 10);
  };
  for (int i = 0; i < 50; ++i) once();
  auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) once();
  double s = seconds_since(t0);
  if (argmax(out.data()) != 9) std::fprintf(stderr, "torch: wrong class %d\n", argmax(out.data()));
  return n / s;
}

// The back end through its C ABI.
double run_backend(nns::test::Instance &inst, int n) {
  std::vector<uint8_t> in = g_digit, out(10);
  std::vector<GstTensorMemory> ins{{in.data(), in.size()}};
  std::vector<GstTensorMemory> outs{{out.data(), out.size()}};
  for (int i = 0; i < 50; ++i) inst.invoke(ins, outs);
  auto t0 = Clock::now();
  for (int i = 0; i < n; ++i)
    if (inst.invoke(ins, outs) != 0) {
      std::fprintf(stderr, "backend: %s\n", inst.error().c_str());
      return 0;
    }
  double s = seconds_since(t0);
  if (argmax(out.data()) != 9) std::fprintf(stderr, "backend: wrong class\n");
  return n / s;
}

struct SinkCount {
  std::atomic<int> n{0};
  std::atomic<int> bad{0};
};

void on_handoff(GstElement *, GstBuffer *buf, GstPad *, gpointer data) {
  auto *c = static_cast<SinkCount *>(data);
  GstMapInfo map;
  if (gst_buffer_map(buf, &map, GST_MAP_READ)) {
    if (map.size != 10 || argmax(map.data) != 9) c->bad++;
    gst_buffer_unmap(buf, &map);
  }
  c->n++;
}

// appsrc ! tensor_filter ! fakesink. Returns buffers per second, 0 on failure.
double run_pipeline(int n) {
  std::string desc =
      "appsrc name=src is-live=false block=true format=time max-bytes=40000 "
      "caps=other/tensors,format=static,num_tensors=1,dimensions=1:28:28:1,types=uint8,"
      "framerate=0/1 ! tensor_filter framework=pytorch model=" +
      g_model + " input=1:28:28:1 inputtype=uint8 output=10:1 outputtype=uint8 custom=NumThreads:" +
      std::to_string(g_threads) + " ! fakesink name=sink sync=false signal-handoffs=true";
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "pipeline: %s\n", err ? err->message : "parse failed");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return 0;
  }
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src");
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  SinkCount count;
  g_signal_connect(sink, "handoff", G_CALLBACK(on_handoff), &count);
  GstBuffer *buf = gst_buffer_new_memdup(g_digit.data(), g_digit.size());
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstBus *bus = gst_element_get_bus(p);
  auto push = [&](int k) {
    for (int i = 0; i < k; ++i) gst_app_src_push_buffer(GST_APP_SRC(src), gst_buffer_ref(buf));
  };
  auto failed = [&]() {
    GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
    if (!m) return false;
    GError *e = nullptr;
    gst_message_parse_error(m, &e, nullptr);
    std::fprintf(stderr, "pipeline error: %s\n", e ? e->message : "?");
    if (e) g_error_free(e);
    gst_message_unref(m);
    return true;
  };
  const int warm = 50;
  push(warm);
  double rate = 0;
  auto wait0 = Clock::now();
  while (count.n.load() < warm && !failed() && seconds_since(wait0) < 60) g_usleep(200);
  if (count.n.load() >= warm) {
    auto t0 = Clock::now();
    push(n);
    gst_app_src_end_of_stream(GST_APP_SRC(src));
    GstMessage *m = gst_bus_timed_pop_filtered(
        bus, 120 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    double s = seconds_since(t0);
    if (m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_EOS && count.n.load() == warm + n)
      rate = n / s;
    else
      std::fprintf(stderr, "pipeline: no EOS or lost buffers (%d of %d)\n", count.n.load(),
                   warm + n);
    if (m) gst_message_unref(m);
    if (count.bad.load()) std::fprintf(stderr, "pipeline: %d wrong results\n", count.bad.load());
  }
  gst_element_set_state(p, GST_STATE_NULL);
  gst_buffer_unref(buf);
  gst_object_unref(bus);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(p);
  return rate;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? 0 : v[v.size() / 2];
}

}  // namespace

int main(int argc, char **argv) {
  int n = argc > 1 ? std::atoi(argv[1]) : 2000;
  int rounds = argc > 2 ? std::atoi(argv[2]) : 5;
  g_threads = argc > 3 ? std::atoi(argv[3]) : 1;
  const char *shared = std::getenv("NNS_SHARED_DIR");
  std::string base = shared ? std::string(shared) + "/models/upstream"
                            : std::string(NNS_SOURCE_DIR) + "/../shared/models/upstream";
  g_model = base + "/models/pytorch_lenet5.pt";
  std::ifstream f(base + "/data/9.raw", std::ios::binary);
  g_digit.assign(std::istreambuf_iterator<char>(f), {});
  if (g_digit.size() != 784) {
    std::fprintf(stderr, "need %s/data/9.raw (784 bytes)\n", base.c_str());
    return 1;
  }
  setenv("NNSTREAMER_CONF", NNS_BUILD_DIR "/nnstreamer.ini", 0);
  setenv("NNSTREAMER_FILTERS", NNS_BUILD_DIR "/subplugins/filters", 0);
  gst_init(&argc, &argv);
  if (!nns_register_static()) {
    std::fprintf(stderr, "cannot register the nnstreamer plugin\n");
    return 1;
  }
  at::set_num_threads(g_threads);

  torch::jit::Module m = torch::jit::load(g_model);
  m.eval();
  nns::test::BackendLib lib("pytorch");
  if (!lib.ok()) {
    std::fprintf(stderr, "%s\n", lib.error().c_str());
    return 1;
  }
  nns::test::Props props;
  props.framework = "pytorch";
  props.models = {g_model};
  props.input = nns::test::tensors_desc({nns::test::tensor_desc(_NNS_UINT8, {1, 28, 28, 1})});
  props.output = nns::test::tensors_desc({nns::test::tensor_desc(_NNS_UINT8, {10, 1})});
  props.set_custom("NumThreads:" + std::to_string(g_threads));
  nns::test::Instance inst(lib.api(), props);
  if (inst.rc() != 0) {
    std::fprintf(stderr, "%s\n", inst.error().c_str());
    return 1;
  }
  GstElementFactory *tf = gst_element_factory_find("tensor_filter");
  bool have_filter = tf != nullptr;
  if (tf) gst_object_unref(tf);
  if (!have_filter) std::printf("tensor_filter is not built in this tree: pipeline skipped\n");

  std::vector<double> rt, rb, rp, ratio;
  for (int r = 0; r < rounds; ++r) {
    rt.push_back(run_torch(m, n));
    rb.push_back(run_backend(inst, n));
    if (have_filter) {
      rp.push_back(run_pipeline(n));
      ratio.push_back(rb.back() > 0 ? rp.back() / rb.back() : 0);
    }
    std::printf("round %d: torch %.0f/s  backend %.0f/s  pipeline %.0f/s\n", r + 1, rt.back(),
                rb.back(), have_filter ? rp.back() : 0.0);
    std::fflush(stdout);
  }
  std::printf("LeNet-5, %d invokes per mode and round, %d rounds, %d intra-op thread(s)\n", n,
              rounds, g_threads);
  std::printf("median torch    %.0f invokes/s (%.1f us)\n", median(rt), 1e6 / median(rt));
  std::printf("median backend  %.0f invokes/s (%.1f us)\n", median(rb), 1e6 / median(rb));
  if (have_filter) {
    std::printf("median pipeline %.0f buffers/s (%.1f us)\n", median(rp), 1e6 / median(rp));
    std::printf("pipeline/backend: median of per-round ratios %.3f, best round %.3f\n",
                median(ratio), *std::max_element(ratio.begin(), ratio.end()));
  }
  std::printf("backend/torch: %.3f\n", median(rb) / median(rt));
  return 0;
}

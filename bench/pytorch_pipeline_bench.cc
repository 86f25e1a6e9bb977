// SPDX-License-Identifier: LGPL-2.1-only
// LeNet-5 (TorchScript) throughput, three ways, on the same 28x28 digit (9.raw):
//   torch    : libtorch alone (from_blob + forward + copy of the 10 scores), in a loop
//   backend  : the pytorch filter back end (.so) called through its C ABI, in a loop
//   pipeline : appsrc ! tensor_filter framework=pytorch ... ! fakesink, one buffer per invoke
//              (appsrc fed from its need-data callback: one streaming thread, no queue hand-off)
// The figure of merit is pipeline / backend (same back end, with and without GStreamer).
// Rounds alternate the modes so machine load hits them alike; medians are reported.
//
//   build/bench/pytorch_pipeline_bench [iterations=2000] [rounds=5] [threads=1] [modes=tbp]
//   (more modes: q = appsrc ! queue ! tensor_filter, i = the back end's invoke time (wall)
//    measured inside the pipeline, f = fresh back-end instance,
//    c = caches cooled between direct invokes, B = direct loop on another thread,
//    S = direct loop inside a GStreamer streaming thread)
// Each direct loop and pipeline also prints its thread's user/system time, minor page faults
// and context switches per invoke (getrusage RUSAGE_THREAD).
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
#include <ctime>
#include <sys/resource.h>
#include <fstream>
#include <functional>
#include <iterator>
#include <string>
#include <thread>
#include <vector>

#include "../tests/backends/backend_loader.h"
#include "gst/plugin_init.h"

namespace {

using Clock = std::chrono::steady_clock;

std::string g_model, g_digit_path;
std::vector<uint8_t> g_digit;
int g_threads = 1;

double seconds_since(Clock::time_point t0) {
  return std::chrono::duration<double>(Clock::now() - t0).count();
}

// CPU seconds used by the whole process (every thread), to judge cost on a busy machine.
double cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

// CPU seconds used by the calling thread.
double thread_cpu_now() {
  timespec ts{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &ts);
  return ts.tv_sec + ts.tv_nsec * 1e-9;
}

// The calling thread's user and system CPU seconds, page faults and context switches.
struct ThreadUse {
  double user = 0, sys = 0;
  long minflt = 0, nvcsw = 0, nivcsw = 0;
};

ThreadUse thread_use() {
  rusage ru{};
  getrusage(RUSAGE_THREAD, &ru);
  return {ru.ru_utime.tv_sec + ru.ru_utime.tv_usec * 1e-6,
          ru.ru_stime.tv_sec + ru.ru_stime.tv_usec * 1e-6, ru.ru_minflt, ru.ru_nvcsw, ru.ru_nivcsw};
}

void print_use(const char *what, const ThreadUse &a, const ThreadUse &b, int n) {
  std::printf(
      "  %s thread: user %.1f us, sys %.1f us, minor faults %.2f, vol/invol switches %.3f/%.3f per "
      "invoke\n",
      what, (b.user - a.user) * 1e6 / n, (b.sys - a.sys) * 1e6 / n, double(b.minflt - a.minflt) / n,
      double(b.nvcsw - a.nvcsw) / n, double(b.nivcsw - a.nivcsw) / n);
}

// One measurement: invokes per wall second and CPU microseconds per invoke.
struct Rate {
  double per_s = 0;
  double cpu_us = 0;         // whole process
  double thread_cpu_us = 0;  // the thread that invokes
};

int argmax(const uint8_t *s) {
  return static_cast<int>(std::max_element(s, s + 10) - s);
}

// libtorch alone.
Rate run_torch(torch::jit::Module &m, int n) {
  std::vector<uint8_t> in = g_digit, out(10);
  auto once = [&] {
    c10::InferenceMode guard;
    std::vector<c10::IValue> feeds;
    feeds.emplace_back(torch::from_blob(in.data(), {1, 28, 28, 1}, at::kByte));
    at::Tensor r = m.forward(std::move(feeds)).toTensor().contiguous();
    std::memcpy(out.data(), r.data_ptr(), 10);
  };
  for (int i = 0; i < 50; ++i) once();
  double c0 = cpu_now(), tc0 = thread_cpu_now();
  auto t0 = Clock::now();
  for (int i = 0; i < n; ++i) once();
  double s = seconds_since(t0);
  double c = cpu_now() - c0, tc = thread_cpu_now() - tc0;
  if (argmax(out.data()) != 9) std::fprintf(stderr, "torch: wrong class %d\n", argmax(out.data()));
  return {n / s, c * 1e6 / n, tc * 1e6 / n};
}

// Bytes of unrelated memory touched between two invokes by run_backend (mode 'c': a stand-in
// for the GStreamer work between invokes in the pipeline, to see what colder caches cost).
std::size_t g_pollute = 0;
std::vector<uint8_t> g_scratch;

void pollute() {
  if (!g_pollute) return;
  g_scratch.resize(g_pollute);
  for (std::size_t i = 0; i < g_pollute; i += 64)
    g_scratch[i] = static_cast<uint8_t>(g_scratch[i] + 1);
}

// The back end through its C ABI.
Rate run_backend(nns::test::Instance &inst, int n) {
  std::vector<uint8_t> in = g_digit, out(10);
  std::vector<GstTensorMemory> ins{{in.data(), in.size()}};
  std::vector<GstTensorMemory> outs{{out.data(), out.size()}};
  for (int i = 0; i < 50; ++i) inst.invoke(ins, outs);
  ThreadUse u0 = thread_use();
  double c0 = cpu_now(), tc0 = thread_cpu_now();
  auto t0 = Clock::now();
  for (int i = 0; i < n; ++i)
    if (pollute(), inst.invoke(ins, outs) != 0) {
      std::fprintf(stderr, "backend: %s\n", inst.error().c_str());
      return {};
    }
  double s = seconds_since(t0);
  double c = cpu_now() - c0, tc = thread_cpu_now() - tc0;
  print_use("backend", u0, thread_use(), n);
  if (argmax(out.data()) != 9) std::fprintf(stderr, "backend: wrong class\n");
  return {n / s, c * 1e6 / n, tc * 1e6 / n};
}

struct SinkCount {
  std::atomic<int> n{0};
  std::atomic<int> bad{0};
  int warm = 0, total = 0;
  // Taken on the streaming thread when the warm-up ends and when the last timed buffer
  // arrives, so the window holds exactly the timed invokes (no EOS handling or bus wake-up).
  double cpu0 = 0, cpu1 = 0, thread_cpu0 = 0, thread_cpu1 = 0;
  ThreadUse use0, use1;
  Clock::time_point t0, t1;
};

// Counts buffers; the result is checked on the last one only (the direct loops check theirs
// once too), so the probe adds no per-buffer map.
GstPadProbeReturn on_buffer(GstPad *, GstPadProbeInfo *info, gpointer data) {
  auto *c = static_cast<SinkCount *>(data);
  int k = ++c->n;
  if (k == c->warm) {
    c->use0 = thread_use();
    c->thread_cpu0 = thread_cpu_now();
    c->cpu0 = cpu_now();
    c->t0 = Clock::now();
  }
  if (k == c->total) {
    c->t1 = Clock::now();
    c->cpu1 = cpu_now();
    c->thread_cpu1 = thread_cpu_now();
    c->use1 = thread_use();
    GstBuffer *buf = GST_PAD_PROBE_INFO_BUFFER(info);
    GstMapInfo map;
    if (gst_buffer_map(buf, &map, GST_MAP_READ)) {
      if (map.size != 10 || argmax(map.data) != 9) c->bad++;
      gst_buffer_unmap(buf, &map);
    }
  }
  return GST_PAD_PROBE_OK;
}

// appsrc ! tensor_filter ! fakesink. appsrc asks for data from its own streaming thread and the
// need-data callback pushes the next buffer right there, so the whole path runs on one thread
// (as a camera source would) and the app thread only waits for EOS.
struct Feeder {
  GstBuffer *buf = nullptr;
  int left = 0;
};

void on_need_data(GstAppSrc *src, guint, gpointer data) {
  auto *f = static_cast<Feeder *>(data);
  if (f->left > 0) {
    f->left--;
    gst_app_src_push_buffer(src, gst_buffer_ref(f->buf));
  } else if (f->left == 0) {
    f->left = -1;
    gst_app_src_end_of_stream(src);
  }
}

// Mean time of the back end's invoke inside the last pipeline (mode 'i': tensor_filter's own
// throughput counter, read at the end), to tell a slower invoke from GStreamer's own cost.
double g_invoke_us_in_pipeline = 0;

Rate run_pipeline(int n, bool queued = false, bool count_invoke = false) {
  std::string desc =
      "appsrc name=src is-live=false format=time max-buffers=4 "
      "caps=other/tensors,format=static,num_tensors=1,dimensions=1:28:28:1,types=uint8,"
      "framerate=0/1 ! " +
      std::string(queued ? "queue max-size-buffers=4 ! " : "") +
      "tensor_filter framework=pytorch model=" + g_model +
      " input=1:28:28:1 inputtype=uint8 output=10:1 outputtype=uint8 custom=NumThreads:" +
      std::to_string(g_threads) + (count_invoke ? " name=f throughput=1" : "") +
      " ! fakesink name=sink sync=false enable-last-sample=false";
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "pipeline: %s\n", err ? err->message : "parse failed");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return {};
  }
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src");
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  SinkCount count;
  GstPad *sinkpad = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(sinkpad, GST_PAD_PROBE_TYPE_BUFFER, on_buffer, &count, nullptr);
  gst_object_unref(sinkpad);
  const int warm = 50;
  Feeder feeder;
  feeder.buf = gst_buffer_new_memdup(g_digit.data(), g_digit.size());
  feeder.left = warm + n;
  GstAppSrcCallbacks cbs{};
  cbs.need_data = on_need_data;
  gst_app_src_set_callbacks(GST_APP_SRC(src), &cbs, &feeder, nullptr);
  GstBus *bus = gst_element_get_bus(p);
  // Warm-up (model load, first invokes) is outside the timed part, as in the direct loops.
  count.warm = warm;
  count.total = warm + n;
  gst_element_set_state(p, GST_STATE_PLAYING);
  Rate rate;
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 300 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  if (m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_EOS && count.n.load() == warm + n) {
    double s = std::chrono::duration<double>(count.t1 - count.t0).count();
    rate = {n / s, (count.cpu1 - count.cpu0) * 1e6 / n,
            (count.thread_cpu1 - count.thread_cpu0) * 1e6 / n};
  } else if (m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    GError *e = nullptr;
    gst_message_parse_error(m, &e, nullptr);
    std::fprintf(stderr, "pipeline error: %s\n", e ? e->message : "?");
    if (e) g_error_free(e);
  } else {
    std::fprintf(stderr, "pipeline: no EOS or lost buffers (%d of %d)\n", count.n.load(), warm + n);
  }
  if (m) gst_message_unref(m);
  print_use("pipeline", count.use0, count.use1, n);
  if (count.bad.load()) std::fprintf(stderr, "pipeline: %d wrong results\n", count.bad.load());
  if (count_invoke) {
    GstElement *f = gst_bin_get_by_name(GST_BIN(p), "f");
    gint milli_fps = 0;
    g_object_get(f, "throughput", &milli_fps, nullptr);
    g_invoke_us_in_pipeline = milli_fps > 0 ? 1e9 / milli_fps : 0;
    gst_object_unref(f);
  }
  gst_element_set_state(p, GST_STATE_NULL);
  gst_buffer_unref(feeder.buf);
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
  std::string modes = argc > 4 ? argv[4] : "tbp";  // t: torch, b: back end, p: pipeline
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

  // Plain libtorch, prepared as the back end prepares it (freeze + optimize_for_inference).
  torch::jit::Module m = torch::jit::load(g_model);
  m.eval();
  m = torch::jit::freeze(m);
  m = torch::jit::optimize_for_inference(m);
  const nns::test::BackendLib &lib = nns::test::backend_lib("pytorch");
  if (!lib.ok()) {
    std::fprintf(stderr, "%s\n", lib.error().c_str());
    return 1;
  }
  nns::test::Props props;
  props.framework = "pytorch";
  props.models = {g_model};
  props.input = nns::test::tensors_desc({nns::test::tensor_desc(_NNS_UINT8, {1, 28, 28, 1})});
  props.output = nns::test::tensors_desc({nns::test::tensor_desc(_NNS_UINT8, {10, 1})});
  props.custom = "NumThreads:" + std::to_string(g_threads);
  nns::test::Instance inst(lib.api(), props);
  if (inst.rc() != 0) {
    std::fprintf(stderr, "%s\n", inst.error().c_str());
    return 1;
  }
  GstElementFactory *tf = gst_element_factory_find("tensor_filter");
  bool have_filter = tf != nullptr;
  if (tf) gst_object_unref(tf);
  if (!have_filter) std::printf("tensor_filter is not built in this tree: pipeline skipped\n");

  std::vector<double> rt, rb, rp, ratio, ct, cb, cp, cratio, rq;
  for (int r = 0; r < rounds; ++r) {
    Rate t, b, p;
    if (modes.find('t') != std::string::npos) t = run_torch(m, n);
    if (modes.find('b') != std::string::npos) b = run_backend(inst, n);
    if (modes.find('f') != std::string::npos) {  // a fresh instance, as each pipeline opens one
      nns::test::Instance fresh(lib.api(), props);
      Rate fr = run_backend(fresh, n);
      std::printf("round %d: fresh backend instance %.0f/s (cpu %.1f us)\n", r + 1, fr.per_s,
                  fr.cpu_us);
    }
    if (modes.find('c') != std::string::npos) {  // the loop with caches cooled between invokes
      for (std::size_t kb : {32, 128, 512}) {
        g_pollute = kb * 1024;
        Rate cr = run_backend(inst, n);
        g_pollute = 0;
        std::printf("round %d: backend, %zu KiB touched between invokes %.0f/s (cpu %.1f us)\n",
                    r + 1, kb, cr.per_s, cr.cpu_us);
      }
    }
    if (modes.find('S') != std::string::npos) {  // the loop on a GStreamer streaming thread
      struct Ctx {
        nns::test::Instance *inst;
        int n;
        Rate r;
      } ctx{&inst, n, {}};
      GstElement *pl = gst_parse_launch("appsrc name=src ! fakesink", nullptr);
      GstElement *src = gst_bin_get_by_name(GST_BIN(pl), "src");
      GstAppSrcCallbacks cbs{};
      cbs.need_data = [](GstAppSrc *s, guint, gpointer d) {
        auto *c = static_cast<Ctx *>(d);
        c->r = run_backend(*c->inst, c->n);
        gst_app_src_end_of_stream(s);
      };
      gst_app_src_set_callbacks(GST_APP_SRC(src), &cbs, &ctx, nullptr);
      gst_element_set_state(pl, GST_STATE_PLAYING);
      GstBus *bus = gst_element_get_bus(pl);
      GstMessage *msg = gst_bus_timed_pop_filtered(bus, 300 * GST_SECOND, GST_MESSAGE_EOS);
      if (msg) gst_message_unref(msg);
      gst_element_set_state(pl, GST_STATE_NULL);
      gst_object_unref(bus);
      gst_object_unref(src);
      gst_object_unref(pl);
      std::printf("round %d: backend loop on a streaming thread %.0f/s (cpu %.1f us)\n", r + 1,
                  ctx.r.per_s, ctx.r.cpu_us);
    }
    if (modes.find('B') != std::string::npos) {  // the same loop on another thread
      std::thread th([&] { b = run_backend(inst, n); });
      th.join();
    }
    rt.push_back(t.per_s);
    ct.push_back(t.cpu_us);
    rb.push_back(b.per_s);
    cb.push_back(b.cpu_us);
    if (have_filter && modes.find('p') != std::string::npos) {
      p = run_pipeline(n);
      rp.push_back(p.per_s);
      cp.push_back(p.cpu_us);
      ratio.push_back(b.per_s > 0 ? p.per_s / b.per_s : 0);
      cratio.push_back(p.cpu_us > 0 ? b.cpu_us / p.cpu_us : 0);
    }
    if (have_filter && modes.find('i') != std::string::npos) {  // the invoke inside the pipeline
      Rate pi = run_pipeline(n, false, true);
      std::printf(
          "round %d: pipeline %.0f/s (cpu %.1f us), of which the back end's invoke %.1f us\n",
          r + 1, pi.per_s, pi.cpu_us, g_invoke_us_in_pipeline);
    }
    if (have_filter && modes.find('q') != std::string::npos) {  // appsrc ! queue ! tensor_filter
      Rate q = run_pipeline(n, true);
      rq.push_back(b.per_s > 0 ? q.per_s / b.per_s : 0);
      std::printf("round %d: pipeline with a queue before the filter %.0f/s (cpu %.1f us)\n", r + 1,
                  q.per_s, q.cpu_us);
    }
    std::printf(
        "round %d: torch %.0f/s (cpu %.1f us, thread %.1f)  backend %.0f/s (cpu %.1f, thread "
        "%.1f)  pipeline %.0f/s (cpu %.1f, thread %.1f)\n",
        r + 1, t.per_s, t.cpu_us, t.thread_cpu_us, b.per_s, b.cpu_us, b.thread_cpu_us, p.per_s,
        p.cpu_us, p.thread_cpu_us);
    std::fflush(stdout);
  }
  std::printf("LeNet-5, %d invokes per mode and round, %d rounds, %d intra-op thread(s)\n", n,
              rounds, g_threads);
  std::printf("median torch    %.0f invokes/s, %.1f us CPU per invoke\n", median(rt), median(ct));
  std::printf("median backend  %.0f invokes/s, %.1f us CPU per invoke\n", median(rb), median(cb));
  if (have_filter) {
    std::printf("median pipeline %.0f buffers/s, %.1f us CPU per buffer\n", median(rp), median(cp));
    std::printf("pipeline/backend throughput (wall): median of per-round ratios %.3f\n",
                median(ratio));
    std::printf(
        "pipeline/backend throughput (CPU cost, backend us / pipeline us): %.3f "
        "(target >= 0.97)\n",
        median(cratio));
    // On a host whose speed drifts between rounds (shared VM), the least-disturbed round of
    // each mode is the steadier estimate.
    auto best = [](const std::vector<double> &v) {
      double m = 0;
      for (double x : v)
        if (x > 0 && (m == 0 || x < m)) m = x;
      return m;
    };
    if (best(cp) > 0)
      std::printf("best round: backend %.1f us, pipeline %.1f us CPU per invoke, ratio %.3f\n",
                  best(cb), best(cp), best(cb) / best(cp));
    if (!rq.empty())
      std::printf(
          "queued pipeline (appsrc ! queue ! tensor_filter)/backend throughput (wall): %.3f "
          "(target >= 0.97)\n",
          median(rq));
  }
  std::printf("backend/torch (wall): %.3f\n", median(rb) / median(rt));
  return 0;
}

// SPDX-License-Identifier: LGPL-2.1-only
// Issue 21: a model served to many clients, (1) by one query server batching requests
// (tensor_query_serversrc max-batch / batch-timeout) and (2) by two servers with the clients
// load balancing (tensor_query_client load-balance=round-robin over a dest-host list).
// MobileNet v2 (mobilenet_v2_quant.onnx, ONNX Runtime, NumThreads:1 per server), the orange
// photo (224x224 RGB uint8) as every frame; preprocessing (typecast, ImageNet normalisation,
// transpose) on the server as in query_serve_bench.
//
// Every server and client is a process of its own (this binary again):
//   --server PORT BATCH TIMEOUT_US MODEL THREADS  serves until its stdin closes, then prints
//                                                  its CPU seconds;
//   --client DEST FRAMES POLICY                    sends FRAMES frames in lockstep (each input
//                                                  waits for its answer: one request in flight
//                                                  per client), prints its round trips.
// Clients start together after a warm-up; frames/s = answers / (first send .. last answer);
// latency = client sink pad (send) -> src pad (answer), p50/p99 over every timed frame of
// every client. CPU per frame = servers' CPU / answers. Batching needs a batch dimension:
// a copy of the model with a free batch dimension is written to the build folder with
// /usr/bin/python3 + onnx (the Reshape's [1,-1] becomes [0,-1]); max-batch=1 runs the original.
//
// --part cost: no network, the server's pipeline fed N stacked frames in one process, CPU and
// wall time per frame at batch 1, 2, 4, 8 (ORT 1 and 2 threads, with and without the
// preprocessing): what batching can give on this model and back end.
//
// usage: query_lb_bench [--frames N] [--clients C] [--part batch|lb|cost|all] [--model PATH]
//                       [--configs B:T[:TH],...]  (--part batch: max-batch:batch-timeout-us[:ORT
//                       threads] runs, in this order)
#include <fcntl.h>
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "../tests/mqtt/mosquitto_broker.h"  // free_port(), port_open()
#include <gst/app/gstappsrc.h>

#include "gst/plugin_init.h"
#include "query_bench_util.h"

extern char **environ;

namespace {

using namespace nns::bench::query;  // NOLINT: now_ns, cpu_s, pct, loadavg, launch, read_all
constexpr std::size_t kFrame = 224 * 224 * 3;
constexpr int kWarm = 4;
const char *kVideoCaps = "video/x-raw,format=RGB,width=224,height=224,framerate=(fraction)0/1";
const char *kPre =
    "tensor_transform mode=arithmetic option=typecast:float32,per-channel:true@0,"
    "add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! "
    "tensor_transform mode=transpose option=1:2:0:3";

// ---------------------------------------------------------------- server process

int server_main(uint16_t port, int batch, const std::string &timeout_us, const std::string &model,
                int threads) {
  const std::string b = std::to_string(batch);
  std::string d = "tensor_query_serversrc name=qsrc host=127.0.0.1 port=" + std::to_string(port) +
                  " max-batch=" + b + " batch-timeout=" + timeout_us +
                  " ! other/tensors,format=static,num_tensors=1,dimensions=(string)3:224:224:" + b +
                  ",types=uint8,framerate=0/1 ! " + kPre +
                  " ! tensor_filter framework=onnxruntime model=\"" + model +
                  "\" custom=NumThreads:" + std::to_string(threads) +
                  // 2 threads beside 8 client processes on 2 cores: no spin-waiting
                  (threads > 1 ? ",AllowSpinning:false" : "");
  if (batch > 1) d += " input=224:224:3:" + b + " inputtype=float32";
  d += " ! tensor_query_serversink sync=false";
  GstElement *p = launch(d);
  gst_element_set_state(p, GST_STATE_PLAYING);
  char line[16];
  while (std::fgets(line, sizeof line, stdin)) {
  }
  guint64 batches = 0, batched = 0;
  GstElement *qsrc = gst_bin_get_by_name(GST_BIN(p), "qsrc");
  GstStructure *st = nullptr;
  g_object_get(qsrc, "stats", &st, nullptr);
  gst_structure_get_uint64(st, "batches", &batches);
  gst_structure_get_uint64(st, "batched", &batched);
  gst_structure_free(st);
  gst_object_unref(qsrc);
  std::printf("cpu %.3f batches %llu batched %llu\n", cpu_s(),
              static_cast<unsigned long long>(batches), static_cast<unsigned long long>(batched));
  std::fflush(stdout);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(p);
  return 0;
}

// ---------------------------------------------------------------- client process

int client_main(const std::string &dest, int frames, const std::string &policy,
                const std::vector<uint8_t> &frame) {
  GstElement *p = launch(
      "appsrc name=src is-live=false format=time block=true max-bytes=1 caps=\"" +
      std::string(kVideoCaps) +
      "\" ! tensor_converter ! tensor_query_client name=q host=127.0.0.1 port=0 dest-host=" + dest +
      " timeout=10000 max-request=1 load-balance=" + policy + " ! fakesink sync=false async=false");
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src"),
             *q = gst_bin_get_by_name(GST_BIN(p), "q");
  ClientProbes pr;
  GstPad *qs = gst_element_get_static_pad(q, "sink"), *qo = gst_element_get_static_pad(q, "src");
  gst_pad_add_probe(qs, GST_PAD_PROBE_TYPE_BUFFER, ClientProbes::in, &pr, nullptr);
  gst_pad_add_probe(qo, GST_PAD_PROBE_TYPE_BUFFER, ClientProbes::out, &pr, nullptr);
  gst_element_set_state(p, GST_STATE_PLAYING);
  uint64_t n = 0;
  auto push = [&] {
    GstBuffer *b = gst_buffer_new_memdup(frame.data(), frame.size());
    GST_BUFFER_PTS(b) = n++ * GST_MSECOND;
    gst_app_src_push_buffer(GST_APP_SRC(src), b);
  };
  for (int i = 0; i < kWarm; ++i) push();
  g_usleep(300000);
  pr.timed_from = n * GST_MSECOND;
  if (!ready_then_wait_go()) return 1;
  const double c0 = cpu_s();
  const int64_t t0 = now_ns();
  for (int i = 0; i < frames; ++i) push();
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  wait_eos(p);  // an error is printed; the answers counted so far are reported all the same
  std::lock_guard<std::mutex> l(pr.m);
  std::printf("result answers=%d t0=%lld t1=%lld cpu=%.3f rtt", pr.timed.load(),
              static_cast<long long>(t0), static_cast<long long>(pr.last_answer.load()),
              cpu_s() - c0);
  for (double r : pr.rtt_us) std::printf(" %.0f", r);
  std::printf("\n");
  std::fflush(stdout);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(qs);
  gst_object_unref(qo);
  gst_object_unref(src);
  gst_object_unref(q);
  gst_object_unref(p);
  return 0;
}

// ---------------------------------------------------------------- parent

using Proc = nns::bench::query::Child;

Proc spawn(const std::vector<std::string> &args) {
  return nns::bench::query::spawn_child(args);
}

void finish(Proc &c) {
  if (c.to) std::fclose(c.to);
  if (c.from) std::fclose(c.from);
  int st = 0;
  waitpid(c.pid, &st, 0);
}

struct Result {
  double fps = 0, p50 = 0, p99 = 0, cpu_ms = 0;
  int answers = 0;
};

// Runs `clients` clients against `dest` (one "host:port" or a list); servers already up.
Result run_clients(const std::string &self, const std::string &dest, const std::string &policy,
                   int clients, int frames, std::vector<Proc> &servers) {
  std::vector<Proc> cs;
  for (int i = 0; i < clients; ++i)
    cs.push_back(spawn({self, "--client", dest, std::to_string(frames), policy}));
  static std::vector<char> line(1 << 20);
  for (auto &c : cs)
    if (!std::fgets(line.data(), static_cast<int>(line.size()), c.from) ||
        std::strncmp(line.data(), "ready", 5) != 0) {
      std::fprintf(stderr, "a client did not get ready\n");
      std::exit(1);
    }
  for (auto &c : cs) {
    std::fputs("go\n", c.to);
    std::fflush(c.to);
  }
  Result r;
  long long t0 = 0, t1 = 0;
  std::vector<double> rtts;
  for (auto &c : cs) {
    if (!std::fgets(line.data(), static_cast<int>(line.size()), c.from)) {
      std::fprintf(stderr, "a client ended without a result\n");
      std::exit(1);
    }
    int answers = 0, used = 0;
    long long a = 0, b = 0;
    double cpu = 0;
    if (std::sscanf(line.data(), "result answers=%d t0=%lld t1=%lld cpu=%lf rtt%n", &answers, &a,
                    &b, &cpu, &used) != 4) {
      std::fprintf(stderr, "client: %s", line.data());
      std::exit(1);
    }
    for (char *s = line.data() + used; *s && *s != '\n';) {
      char *e = nullptr;
      const double v = std::strtod(s, &e);
      if (e == s) break;
      rtts.push_back(v);
      s = e;
    }
    t0 = t0 ? std::min(t0, a) : a;
    t1 = std::max(t1, b);
    r.answers += answers;
    finish(c);
  }
  r.fps = r.answers / ((t1 - t0) / 1e9);
  r.p50 = pct(rtts, 0.5) / 1e3;
  r.p99 = pct(rtts, 0.99) / 1e3;
  (void)servers;
  return r;
}

// Stops the servers; their CPU seconds in total. `fill`: requests per batch (max-batch > 1).
double stop_servers(std::vector<Proc> &servers, double *fill = nullptr) {
  double cpu = 0;
  unsigned long long batches = 0, batched = 0;
  char line[128];
  for (auto &s : servers) {
    std::fclose(s.to);
    s.to = nullptr;
    double c = 0;
    unsigned long long b = 0, r = 0;
    if (std::fgets(line, sizeof line, s.from) &&
        std::sscanf(line, "cpu %lf batches %llu batched %llu", &c, &b, &r) >= 1) {
      cpu += c;
      batches += b;
      batched += r;
    }
    finish(s);
  }
  if (fill) *fill = batches ? static_cast<double>(batched) / batches : 1.0;
  servers.clear();
  return cpu;
}

std::vector<Proc> start_servers(const std::string &self, const std::vector<uint16_t> &ports,
                                int batch, int timeout_us, const std::string &model,
                                int threads = 1) {
  std::vector<Proc> out;
  for (uint16_t p : ports)
    out.push_back(spawn({self, "--server", std::to_string(p), std::to_string(batch),
                         std::to_string(timeout_us), model, std::to_string(threads)}));
  for (uint16_t p : ports)
    for (int i = 0; i < 1000 && !mqtt_test::port_open(p); ++i) g_usleep(10000);
  return out;
}

// A copy of the model with a free batch dimension (Reshape [1,-1] -> [0,-1]).
std::string batched_model(const std::string &model) {
  const std::string out = std::string(NNS_BUILD_DIR) + "/bench/mobilenet_v2_quant_batchN.onnx";
  if (std::ifstream(out)) return out;
  const std::string py =
      "import onnx,sys\n"
      "from onnx import numpy_helper\n"
      "import numpy as np\n"
      "m=onnx.load(sys.argv[1])\n"
      "for v in list(m.graph.input)+list(m.graph.output):\n"
      "    v.type.tensor_type.shape.dim[0].dim_param='N'\n"
      "for i,t in enumerate(m.graph.initializer):\n"
      "    a=numpy_helper.to_array(t)\n"
      "    if a.dtype==np.int64 and a.shape==(2,) and list(a)==[1,-1]:\n"
      "        m.graph.initializer[i].CopyFrom(numpy_helper.from_array(np.array([0,-1],np.int64),"
      "t.name))\n"
      "del m.graph.value_info[:]\n"
      "onnx.save(m,sys.argv[2])\n";
  const std::string script = out + ".py";
  std::ofstream(script) << py;
  const std::string cmd = "/usr/bin/python3 " + script + " '" + model + "' '" + out + "'";
  if (std::system(cmd.c_str()) != 0) return "";
  return out;
}

// The server's work at batch N in one process, no network: appsrc (N stacked frames, as
// tensor_query_serversrc makes them) ! preprocessing ! tensor_filter ! fakesink, `frames`
// buffers after a warm-up; process CPU and wall time per frame (= per slot). With `pre`
// false the preprocessing runs once beforehand (appsrc gives float32 224:224:3:N): the
// filter alone. Bounds what batching can give on this model and back end.
struct Cost {
  double cpu_ms = 0, wall_ms = 0;
};

Cost batch_cost(const std::string &model, int n, int threads, bool pre, int frames,
                const std::vector<uint8_t> &frame) {
  const std::string b = std::to_string(n);
  std::string d = "appsrc name=src is-live=false format=time block=true max-buffers=2 ";
  std::vector<uint8_t> data;
  if (pre) {
    d += "caps=\"other/tensors,format=static,num_tensors=1,dimensions=(string)3:224:224:" + b +
         ",types=uint8,framerate=0/1\" ! " + kPre + " ! ";
    for (int i = 0; i < n; ++i) data.insert(data.end(), frame.begin(), frame.end());
  } else {
    d += "caps=\"other/tensors,format=static,num_tensors=1,dimensions=(string)224:224:3:" + b +
         ",types=float32,framerate=0/1\" ! ";
    const float mean[3] = {123.675f, 116.28f, 103.53f}, sd[3] = {58.395f, 57.12f, 57.375f};
    std::vector<float> chw(kFrame);
    for (std::size_t i = 0; i < kFrame; ++i) {
      const std::size_t c = i % 3, px = i / 3;
      chw[c * 224 * 224 + px] = (frame[i] - mean[c]) / sd[c];
    }
    for (int i = 0; i < n; ++i)
      data.insert(data.end(), reinterpret_cast<uint8_t *>(chw.data()),
                  reinterpret_cast<uint8_t *>(chw.data() + chw.size()));
  }
  d += "tensor_filter framework=onnxruntime model=\"" + model +
       "\" custom=NumThreads:" + std::to_string(threads);
  if (n > 1) d += " input=224:224:3:" + b + " inputtype=float32";
  d += " ! fakesink name=sink sync=false";
  GstElement *p = launch(d);
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src");
  GstBuffer *in = gst_buffer_new_memdup(data.data(), data.size());
  gst_element_set_state(p, GST_STATE_PLAYING);
  std::atomic<int> done{0};
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  GstPad *sp = gst_element_get_static_pad(sink, "sink");
  gst_pad_add_probe(
      sp, GST_PAD_PROBE_TYPE_BUFFER,
      [](GstPad *, GstPadProbeInfo *, gpointer u) {
        ++*static_cast<std::atomic<int> *>(u);
        return GST_PAD_PROBE_OK;
      },
      &done, nullptr);
  auto push_n = [&](int k) {
    for (int i = 0; i < k; ++i) {
      GstBuffer *c = gst_buffer_copy(in);  // shares the memory
      gst_app_src_push_buffer(GST_APP_SRC(src), c);
    }
  };
  push_n(3);
  while (done < 3) g_usleep(1000);
  const double c0 = cpu_s();
  const int64_t t0 = now_ns();
  push_n(frames);
  while (done < 3 + frames) g_usleep(200);
  Cost r;
  r.cpu_ms = (cpu_s() - c0) * 1e3 / (static_cast<double>(frames) * n);
  r.wall_ms = (now_ns() - t0) / 1e6 / (static_cast<double>(frames) * n);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_buffer_unref(in);
  gst_object_unref(sp);
  gst_object_unref(sink);
  gst_object_unref(src);
  gst_object_unref(p);
  return r;
}

}  // namespace

int main(int argc, char **argv) {
  const std::string shared = init_and_shared_dir(&argc, &argv);
  std::string model = shared + "/models/mobilenet_v2_quant.onnx";
  if (argc >= 7 && !std::strcmp(argv[1], "--server"))
    return server_main(static_cast<uint16_t>(std::atoi(argv[2])), std::atoi(argv[3]), argv[4],
                       argv[5], std::atoi(argv[6]));
  const std::vector<uint8_t> frame = read_all(shared + "/data/orange.raw");
  if (argc >= 5 && !std::strcmp(argv[1], "--client"))
    return client_main(argv[2], std::atoi(argv[3]), argv[4], frame);
  int frames = 30, clients = 8;
  std::string part = "all", configs;
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    if (k == "--frames") frames = std::atoi(argv[i + 1]);
    if (k == "--clients") clients = std::atoi(argv[i + 1]);
    if (k == "--part") part = argv[i + 1];
    if (k == "--model") model = argv[i + 1];
    if (k == "--configs") configs = argv[i + 1];
  }
  const std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_onnxruntime.so";
  if (frame.size() != kFrame || !std::ifstream(model) || !std::ifstream(so)) {
    std::printf("query_lb_bench: skipped (needs %s, %s/data/orange.raw and %s)\n", model.c_str(),
                shared.c_str(), so.c_str());
    return 0;
  }
  const std::string self = argv[0];
  std::printf(
      "query_lb_bench: %s, ORT NumThreads:1 per server, %d clients x %d frames "
      "(lockstep), %ld cores\n",
      model.c_str(), clients, frames, sysconf(_SC_NPROCESSORS_ONLN));
  std::fflush(stdout);
  auto report = [&](const char *what, const Result &r, double cpu) {
    std::printf(
        "%-40s %7.1f frames/s  p50 %7.1f ms  p99 %7.1f ms  server CPU %6.1f ms/frame  "
        "(%d answers; load %s)\n",
        what, r.fps, r.p50, r.p99, cpu * 1e3 / std::max(1, r.answers), r.answers,
        loadavg().c_str());
    std::fflush(stdout);
  };
  if (part == "all" || part == "batch") {
    const std::string bm = batched_model(model);
    if (bm.empty()) std::printf("batching: skipped (no /usr/bin/python3 with onnx)\n");
    struct Cfg {
      int batch, timeout_us, threads = 1;
    };
    std::vector<Cfg> cfgs{{1, 0}, {4, 0}, {4, 2000}, {8, 0}, {8, 2000}, {8, 8000}};
    if (!configs.empty()) {  // "1:0,8:2000": max-batch:batch-timeout pairs, in this order
      cfgs.clear();
      for (const char *q = configs.c_str(); *q;) {
        char *e = nullptr;
        Cfg c{static_cast<int>(std::strtol(q, &e, 10)), 0};
        if (*e == ':') c.timeout_us = static_cast<int>(std::strtol(e + 1, &e, 10));
        if (*e == ':') c.threads = static_cast<int>(std::strtol(e + 1, &e, 10));
        cfgs.push_back(c);
        q = *e == ',' ? e + 1 : e;
        if (*e && *e != ',') break;
      }
    }
    for (Cfg c : cfgs) {
      if (c.batch > 1 && bm.empty()) continue;
      const uint16_t port = mqtt_test::free_port();
      auto servers =
          start_servers(self, {port}, c.batch, c.timeout_us, c.batch > 1 ? bm : model, c.threads);
      const Result r =
          run_clients(self, "127.0.0.1:" + std::to_string(port), "none", clients, frames, servers);
      double fill = 1;
      const double cpu = stop_servers(servers, &fill);
      char what[96];
      std::snprintf(
          what, sizeof what, "1 server, max-batch=%d batch-timeout=%d us%s", c.batch, c.timeout_us,
          c.threads != 1 ? (" ORT " + std::to_string(c.threads) + " threads").c_str() : "");
      report(what, r, cpu);
      if (c.batch > 1) std::printf("    %.2f requests per batch (warm-up included)\n", fill);
    }
  }
  if (part == "cost") {
    const std::string bm = batched_model(model);
    if (bm.empty()) {
      std::printf("cost: skipped (no /usr/bin/python3 with onnx)\n");
      return 0;
    }
    for (int threads : {1, 2})
      for (bool pre : {false, true})
        for (int n : {1, 2, 4, 8}) {
          const Cost c = batch_cost(n > 1 ? bm : model, n, threads, pre,
                                    std::max(2, 8 * frames / 5 / n), frame);
          std::printf(
              "%s NumThreads:%d batch %d: %6.2f ms CPU/frame  %6.2f ms wall/frame  (load %s)\n",
              pre ? "preprocessing + filter" : "filter alone          ", threads, n, c.cpu_ms,
              c.wall_ms, loadavg().c_str());
          std::fflush(stdout);
        }
    return 0;
  }
  if (part == "all" || part == "lb") {
    for (int n : {1, 2}) {
      std::vector<uint16_t> ports;
      std::string list;
      for (int i = 0; i < n; ++i) {
        ports.push_back(mqtt_test::free_port());
        list += (i ? "," : "") + std::string("127.0.0.1:") + std::to_string(ports.back());
      }
      auto servers = start_servers(self, ports, 1, 0, model);
      const Result r =
          run_clients(self, list, n > 1 ? "round-robin" : "none", clients, frames, servers);
      const double cpu = stop_servers(servers);
      report(n > 1 ? "2 servers, round-robin, max-batch=1" : "1 server, max-batch=1", r, cpu);
    }
  }
  return 0;
}

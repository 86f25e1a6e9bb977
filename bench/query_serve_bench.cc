// SPDX-License-Identifier: LGPL-2.1-only
// A model served by a query server to 2 clients versus the same model in-process (issue 11,
// target: served >= 0.9x in-process frames/s). mobilenet_v2_quant.onnx on ONNX Runtime, the
// orange photo (224x224 RGB uint8) as every frame.
//  - in-process: video/x-raw ! tensor_converter ! tensor_transform (typecast + ImageNet
//    normalisation) ! tensor_transform (transpose to planar) ! tensor_filter ! fakesink, frames
//    pushed one after the other from this thread (each push returns when the filter is done);
//  - served: this process runs the server `tensor_query_serversrc ! <the same two
//    tensor_transform> ! tensor_filter ! tensor_query_serversink` (preprocessing on the server:
//    the clients send the raw 150528-byte frames); --clients separate client processes (this
//    binary again) each run video/x-raw ! tensor_converter ! tensor_query_client ! fakesink
//    and send --frames frames. Two client modes:
//      window:   timeout=0 max-request=W (--window, default 2, the element's default): a
//                client keeps W requests in flight. The element pushes answers only from its
//                chain (or at EOS), so when W are in flight the client re-offers its next frame
//                every --poll us (default 2000): dropped (counted) until an answer has come
//                back and been pushed out by that re-offer;
//      lockstep: timeout=10000: every input waits for its answer (one request in flight per
//                client; what a plain gst-launch client does).
//    Clients start together (after a few warm-up frames); frames/s = all answers / (first send
//    .. last answer). Round trip: per frame, the client's sink pad (the send) to its src pad.
// Each round runs in-process, window, lockstep and in-process again; the served figures are
// compared with the mean of the two in-process runs of their round, and the median over rounds
// is reported with the spread (the 2-core machine is shared). The server filter's busy share
// (time inside tensor_filter over the run) tells whether the server idles; process CPU per
// answered frame (server process, clients) tells what serving costs. ORT runs with NumThreads:1
// (--threads) in both.
//
// usage: query_serve_bench [--frames N] [--runs R] [--clients C] [--window W] [--threads T]
//                          [--poll US] [--model PATH]
#include <spawn.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <time.h>
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

#include "../tests/mqtt/mosquitto_broker.h"  // free_port()
#include "gst/plugin_init.h"
#include "query_bench_util.h"

extern char **environ;

namespace {

using namespace nns::bench::query;  // NOLINT: now_ns, cpu_s, pct, loadavg, launch, read_all
constexpr std::size_t kFrame = 224 * 224 * 3;
constexpr int kWarm = 5;
constexpr int kOrange = 950;  // ImageNet index of "orange" (imagenet_labels_1000.txt)
const char *kVideoCaps = "video/x-raw,format=RGB,width=224,height=224,framerate=(fraction)0/1";
const char *kPre =
    "tensor_transform mode=arithmetic option=typecast:float32,per-channel:true@0,"
    "add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! "
    "tensor_transform mode=transpose option=1:2:0:3";

GstElement *by_name(GstElement *p, const char *n) {
  return gst_bin_get_by_name(GST_BIN(p), n);
}

// A source pad of our own linked to an element's sink pad: gst_pad_push runs the downstream
// chain functions in this thread and returns when they are done (no appsrc thread in between).
class Feeder {
 public:
  Feeder(GstElement *first, const char *caps) : pad_(gst_pad_new("feed", GST_PAD_SRC)) {
    gst_pad_set_active(pad_, TRUE);
    sink_ = gst_element_get_static_pad(first, "sink");
    gst_pad_link(pad_, sink_);
    gst_pad_push_event(pad_, gst_event_new_stream_start("query-serve-bench"));
    GstCaps *c = gst_caps_from_string(caps);
    gst_pad_push_event(pad_, gst_event_new_caps(c));
    gst_caps_unref(c);
    GstSegment seg;
    gst_segment_init(&seg, GST_FORMAT_TIME);
    gst_pad_push_event(pad_, gst_event_new_segment(&seg));
  }
  ~Feeder() {
    gst_pad_unlink(pad_, sink_);
    gst_pad_set_active(pad_, FALSE);
    gst_object_unref(sink_);
    gst_object_unref(pad_);
  }
  // The same read-only frame every time, wrapped without a copy.
  GstFlowReturn push(const std::vector<uint8_t> &frame, uint64_t n) {
    GstBuffer *b =
        gst_buffer_new_wrapped_full(GST_MEMORY_FLAG_READONLY, const_cast<uint8_t *>(frame.data()),
                                    frame.size(), 0, frame.size(), nullptr, nullptr);
    GST_BUFFER_PTS(b) = n * GST_MSECOND;
    return gst_pad_push(pad_, b);
  }
  void eos() { gst_pad_push_event(pad_, gst_event_new_eos()); }

 private:
  GstPad *pad_;
  GstPad *sink_ = nullptr;
};

// Time spent inside one element (sink pad in -> src pad out), for its busy share.
struct Busy {
  std::atomic<int64_t> in{0}, total{0};
  std::atomic<int> frames{0};
  static GstPadProbeReturn enter(GstPad *, GstPadProbeInfo *, gpointer d) {
    static_cast<Busy *>(d)->in = now_ns();
    return GST_PAD_PROBE_OK;
  }
  static GstPadProbeReturn leave(GstPad *, GstPadProbeInfo *, gpointer d) {
    auto *b = static_cast<Busy *>(d);
    b->total += now_ns() - b->in;
    ++b->frames;
    return GST_PAD_PROBE_OK;
  }
  void attach(GstElement *e) {
    GstPad *s = gst_element_get_static_pad(e, "sink"), *o = gst_element_get_static_pad(e, "src");
    gst_pad_add_probe(s, GST_PAD_PROBE_TYPE_BUFFER, enter, this, nullptr);
    gst_pad_add_probe(o, GST_PAD_PROBE_TYPE_BUFFER, leave, this, nullptr);
    gst_object_unref(s);
    gst_object_unref(o);
  }
  void reset() {
    total = 0;
    frames = 0;
  }
};

// ---------------------------------------------------------------- the client process

guint64 stat(GstElement *q, const char *field) {
  GstStructure *s = nullptr;
  g_object_get(q, "stats", &s, nullptr);
  guint64 v = 0;
  if (s) {
    gst_structure_get_uint64(s, field, &v);
    gst_structure_free(s);
  }
  return v;
}

// Sends `frames` frames; in window mode keeps `window` in flight, re-offering the next frame
// every `poll_us` while the window is full. Returns the frames sent.
int send_frames(Feeder &f, GstElement *q, ClientProbes &p, const std::vector<uint8_t> &frame,
                uint64_t *pts, int frames, bool window, int win, int poll_us) {
  int sent = 0;
  while (sent < frames) {
    if (window && static_cast<int>(stat(q, "sent")) - p.answers >= win) g_usleep(poll_us);
    const guint64 before = stat(q, "sent");
    if (f.push(frame, *pts) != GST_FLOW_OK) break;
    if (stat(q, "sent") > before) {
      ++sent;
      ++*pts;
    }
  }
  return sent;
}

// The child: connects, warms up, prints "ready", waits for a line on stdin, sends, prints
// "result ...".
int client_main(uint16_t port, const std::string &mode, int frames, int win, int poll_us,
                const std::vector<uint8_t> &frame) {
  const bool window = mode == "window";
  const std::string q = window ? "timeout=0 max-request=" + std::to_string(win)
                               : std::string("timeout=10000 max-request=2");
  GstElement *p = launch(
      "tensor_converter name=first ! tensor_query_client name=q host=127.0.0.1 port=0 "
      "dest-host=127.0.0.1 dest-port=" +
      std::to_string(port) + " " + q + " ! fakesink sync=false async=false");
  GstElement *first = by_name(p, "first"), *qc = by_name(p, "q");
  ClientProbes probes;
  GstPad *qs = gst_element_get_static_pad(qc, "sink"), *qo = gst_element_get_static_pad(qc, "src");
  gst_pad_add_probe(qs, GST_PAD_PROBE_TYPE_BUFFER, ClientProbes::in, &probes, nullptr);
  gst_pad_add_probe(qo, GST_PAD_PROBE_TYPE_BUFFER, ClientProbes::out, &probes, nullptr);
  gst_element_set_state(p, GST_STATE_PLAYING);
  int rc = 0;
  {
    Feeder f(first, kVideoCaps);
    uint64_t pts = 0;
    // Warm-up (not counted: only answers to frames from timed_from on are).
    send_frames(f, qc, probes, frame, &pts, kWarm, window, win, poll_us);
    g_usleep(200000);
    const guint64 dropped0 = stat(qc, "dropped");
    probes.timed_from = pts * GST_MSECOND;
    if (!ready_then_wait_go()) return 1;
    const double c0 = cpu_s();
    const int64_t t0 = now_ns();
    const int sent = send_frames(f, qc, probes, frame, &pts, frames, window, win, poll_us);
    f.eos();  // pushes what is still in flight (the client waits for it at EOS)
    if (!wait_eos(p)) rc = 1;
    std::lock_guard<std::mutex> l(probes.m);
    std::printf(
        "result sent=%d answers=%d dropped=%llu t0=%lld t1=%lld p50=%.1f p99=%.1f label=%d "
        "cpu=%.3f\n",
        sent, probes.timed.load(), static_cast<unsigned long long>(stat(qc, "dropped") - dropped0),
        static_cast<long long>(t0), static_cast<long long>(probes.last_answer.load()),
        pct(probes.rtt_us, 0.5), pct(probes.rtt_us, 0.99), probes.label.load(), cpu_s() - c0);
    std::fflush(stdout);
  }
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(qs);
  gst_object_unref(qo);
  gst_object_unref(first);
  gst_object_unref(qc);
  gst_object_unref(p);
  return rc;
}

// ---------------------------------------------------------------- the parent

using nns::bench::query::Child;

Child spawn_client(const std::vector<std::string> &args) {
  return nns::bench::query::spawn_child(args);
}

struct Served {
  double fps = 0, p50 = 0, p99 = 0, busy = 0, server_cpu_ms = 0, client_cpu_ms = 0;
  long long dropped = 0;
  int answers = 0, frames = 0;
  bool labels_ok = true;
};

Served run_served(const std::string &self, uint16_t port, const std::string &mode, int clients,
                  int frames, int win, int poll_us, Busy &busy) {
  std::vector<Child> cs;
  for (int i = 0; i < clients; ++i)
    cs.push_back(spawn_client({self, "--client", std::to_string(port), mode, std::to_string(frames),
                               std::to_string(win), std::to_string(poll_us)}));
  char line[512];
  for (auto &c : cs)
    if (!std::fgets(line, sizeof line, c.from) || std::strncmp(line, "ready", 5) != 0) {
      std::fprintf(stderr, "a client did not get ready\n");
      std::exit(1);
    }
  busy.reset();
  const double c0 = cpu_s();
  for (auto &c : cs) {
    std::fputs("go\n", c.to);
    std::fflush(c.to);
  }
  Served r;
  long long t0 = 0, t1 = 0;
  std::vector<double> p50s, p99s;
  for (auto &c : cs) {
    if (!std::fgets(line, sizeof line, c.from)) {
      std::fprintf(stderr, "a client ended without a result\n");
      std::exit(1);
    }
    int sent = 0, answers = 0, label = -1;
    unsigned long long dropped = 0;
    long long a = 0, b = 0;
    double p50 = 0, p99 = 0, cpu = 0;
    if (std::sscanf(line,
                    "result sent=%d answers=%d dropped=%llu t0=%lld t1=%lld p50=%lf p99=%lf "
                    "label=%d cpu=%lf",
                    &sent, &answers, &dropped, &a, &b, &p50, &p99, &label, &cpu) != 9) {
      std::fprintf(stderr, "client: %s", line);
      std::exit(1);
    }
    t0 = t0 ? std::min(t0, a) : a;
    t1 = std::max(t1, b);
    r.answers += answers;
    r.frames += sent;
    r.dropped += static_cast<long long>(dropped);
    r.client_cpu_ms += cpu * 1e3;
    r.labels_ok = r.labels_ok && label == kOrange;
    p50s.push_back(p50);
    p99s.push_back(p99);
  }
  const double wall = (t1 - t0) / 1e9;
  r.server_cpu_ms = (cpu_s() - c0) * 1e3 / std::max(1, r.answers);
  r.client_cpu_ms /= std::max(1, r.answers);
  r.fps = r.answers / wall;
  r.busy = busy.total / 1e9 / wall;
  r.p50 = pct(p50s, 0.5);  // the clients' medians (2 clients: the larger)
  r.p99 = *std::max_element(p99s.begin(), p99s.end());
  for (auto &c : cs) {
    std::fclose(c.to);
    std::fclose(c.from);
    int st = 0;
    waitpid(c.pid, &st, 0);
  }
  return r;
}

struct InProcess {
  double fps = 0, busy = 0, cpu_ms = 0;
};

InProcess run_in_process(Feeder &f, Busy &busy, const std::vector<uint8_t> &frame, uint64_t *pts,
                         int frames) {
  busy.reset();
  const double c0 = cpu_s();
  const int64_t t0 = now_ns();
  for (int i = 0; i < frames; ++i) f.push(frame, (*pts)++);
  const double wall = (now_ns() - t0) / 1e9;
  return {frames / wall, busy.total / 1e9 / wall, (cpu_s() - c0) * 1e3 / frames};
}

struct Series {
  std::vector<double> v;
  double med() const { return pct(v, 0.5); }
  double lo() const { return v.empty() ? 0 : *std::min_element(v.begin(), v.end()); }
  double hi() const { return v.empty() ? 0 : *std::max_element(v.begin(), v.end()); }
};

}  // namespace

int main(int argc, char **argv) {
  const std::string shared = init_and_shared_dir(&argc, &argv);
  std::string model = shared + "/models/mobilenet_v2_quant.onnx";
  const std::vector<uint8_t> frame = read_all(shared + "/data/orange.raw");
  int frames = 60, runs = 7, clients = 2, win = 2, threads = 1, poll_us = 2000;
  if (argc >= 7 && !std::strcmp(argv[1], "--client"))
    return client_main(static_cast<uint16_t>(std::atoi(argv[2])), argv[3], std::atoi(argv[4]),
                       std::atoi(argv[5]), std::atoi(argv[6]), frame);
  for (int i = 1; i + 1 < argc; i += 2) {
    const std::string k = argv[i];
    const char *v = argv[i + 1];
    if (k == "--frames") frames = std::atoi(v);
    if (k == "--runs") runs = std::atoi(v);
    if (k == "--clients") clients = std::atoi(v);
    if (k == "--window") win = std::atoi(v);
    if (k == "--threads") threads = std::atoi(v);
    if (k == "--poll") poll_us = std::atoi(v);
    if (k == "--model") model = v;
  }
  const std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_onnxruntime.so";
  if (frame.size() != kFrame || !std::ifstream(model) || !std::ifstream(so)) {
    std::printf("query_serve_bench: skipped (needs %s, %s/data/orange.raw and %s)\n", model.c_str(),
                shared.c_str(), so.c_str());
    return 0;
  }
  const std::string filter = "tensor_filter name=f framework=onnxruntime model=\"" + model +
                             "\" custom=NumThreads:" + std::to_string(threads);

  // The server, kept up across rounds.
  const uint16_t port = mqtt_test::free_port();
  GstElement *server =
      launch("tensor_query_serversrc host=127.0.0.1 port=" + std::to_string(port) +
             " ! other/tensors,format=static,num_tensors=1,dimensions=3:224:224:1,types=uint8,"
             "framerate=0/1 ! " +
             kPre + " ! " + filter + " ! tensor_query_serversink sync=false");
  Busy server_busy;
  GstElement *sf = by_name(server, "f");
  server_busy.attach(sf);
  gst_element_set_state(server, GST_STATE_PLAYING);
  // The in-process pipeline, also kept up.
  GstElement *local = launch("tensor_converter name=first ! " + std::string(kPre) + " ! " + filter +
                             " ! fakesink sync=false async=false");
  GstElement *lf = by_name(local, "f"), *lfirst = by_name(local, "first");
  Busy local_busy;
  local_busy.attach(lf);
  gst_element_set_state(local, GST_STATE_PLAYING);
  for (int i = 0; i < 500 && !mqtt_test::port_open(port); ++i) g_usleep(10000);

  std::printf(
      "query_serve_bench: %s, NumThreads:%d; %d clients x %d frames (separate processes), "
      "in-process %d frames; window mode max-request=%d (re-offer every %d us); load before: "
      "%s\n",
      model.c_str(), threads, clients, frames, clients * frames, win, poll_us, loadavg().c_str());
  Series in_fps, win_fps, lock_fps, r_win, r_lock, win_p50, win_p99, lock_p50, lock_p99;
  Series in_busy, win_busy, lock_busy, in_cpu_s, win_scpu, win_ccpu, lock_scpu, lock_ccpu;
  const std::string self = argv[0];
  bool labels_ok = true;
  {
    Feeder lfeed(lfirst, kVideoCaps);
    uint64_t lpts = 0;
    run_in_process(lfeed, local_busy, frame, &lpts, kWarm);
    for (int r = 0; r < runs; ++r) {
      const std::string load = loadavg();
      // In-process before and after the served runs: the served figures are compared with the
      // mean of the two, which follows the shared machine's load drift within the round.
      const InProcess in1 = run_in_process(lfeed, local_busy, frame, &lpts, clients * frames);
      const Served w = run_served(self, port, "window", clients, frames, win, poll_us, server_busy);
      const Served l =
          run_served(self, port, "lockstep", clients, frames, win, poll_us, server_busy);
      const InProcess in2 = run_in_process(lfeed, local_busy, frame, &lpts, clients * frames);
      const double in = (in1.fps + in2.fps) / 2, in_cpu = (in1.cpu_ms + in2.cpu_ms) / 2;
      labels_ok = labels_ok && w.labels_ok && l.labels_ok;
      std::printf(
          "round %d (load %s): in-process %.1f/%.1f frames/s (filter busy %.0f %%, %.2f ms "
          "CPU/frame); window %.1f frames/s = %.3fx, round trip p50 %.1f ms p99 %.1f ms, server "
          "filter busy %.0f %%, CPU/frame server %.2f ms clients %.2f ms, %lld re-offers "
          "dropped; lockstep %.1f frames/s = %.3fx, p50 %.1f ms p99 %.1f ms, busy %.0f %%, "
          "CPU/frame server %.2f ms clients %.2f ms; answers %d+%d of %d+%d\n",
          r, load.c_str(), in1.fps, in2.fps, 50 * (in1.busy + in2.busy), in_cpu, w.fps, w.fps / in,
          w.p50 / 1e3, w.p99 / 1e3, 100 * w.busy, w.server_cpu_ms, w.client_cpu_ms, w.dropped,
          l.fps, l.fps / in, l.p50 / 1e3, l.p99 / 1e3, 100 * l.busy, l.server_cpu_ms,
          l.client_cpu_ms, w.answers, l.answers, w.frames, l.frames);
      std::fflush(stdout);
      in_fps.v.push_back(in);
      in_busy.v.push_back((in1.busy + in2.busy) / 2);
      in_cpu_s.v.push_back(in_cpu);
      win_fps.v.push_back(w.fps);
      lock_fps.v.push_back(l.fps);
      r_win.v.push_back(w.fps / in);
      r_lock.v.push_back(l.fps / in);
      win_p50.v.push_back(w.p50 / 1e3);
      win_p99.v.push_back(w.p99 / 1e3);
      lock_p50.v.push_back(l.p50 / 1e3);
      lock_p99.v.push_back(l.p99 / 1e3);
      win_busy.v.push_back(w.busy);
      lock_busy.v.push_back(l.busy);
      win_scpu.v.push_back(w.server_cpu_ms);
      win_ccpu.v.push_back(w.client_cpu_ms);
      lock_scpu.v.push_back(l.server_cpu_ms);
      lock_ccpu.v.push_back(l.client_cpu_ms);
    }
  }
  std::printf("medians of %d rounds [min-max]:\n", runs);
  std::printf(
      "in-process:              %6.1f frames/s [%.1f-%.1f], filter busy %.0f %%, %.2f ms "
      "CPU/frame\n",
      in_fps.med(), in_fps.lo(), in_fps.hi(), 100 * in_busy.med(), in_cpu_s.med());
  std::printf(
      "served, window (max-request=%d): %6.1f frames/s [%.1f-%.1f], ratio %.3f [%.3f-%.3f] "
      "(target >= 0.9), round trip p50 %.1f ms p99 %.1f ms, server filter busy %.0f %%, "
      "CPU/frame server %.2f ms + clients %.2f ms\n",
      win, win_fps.med(), win_fps.lo(), win_fps.hi(), r_win.med(), r_win.lo(), r_win.hi(),
      win_p50.med(), win_p99.med(), 100 * win_busy.med(), win_scpu.med(), win_ccpu.med());
  std::printf(
      "served, lockstep (timeout>0):  %6.1f frames/s [%.1f-%.1f], ratio %.3f [%.3f-%.3f], round "
      "trip p50 %.1f ms p99 %.1f ms, server filter busy %.0f %%, CPU/frame server %.2f ms + "
      "clients %.2f ms\n",
      lock_fps.med(), lock_fps.lo(), lock_fps.hi(), r_lock.med(), r_lock.lo(), r_lock.hi(),
      lock_p50.med(), lock_p99.med(), 100 * lock_busy.med(), lock_scpu.med(), lock_ccpu.med());
  std::printf("answers labelled orange: %s; load after: %s\n", labels_ok ? "yes" : "NO",
              loadavg().c_str());
  gst_element_set_state(local, GST_STATE_NULL);
  gst_element_set_state(server, GST_STATE_NULL);
  gst_object_unref(lf);
  gst_object_unref(lfirst);
  gst_object_unref(sf);
  gst_object_unref(local);
  gst_object_unref(server);
  return labels_ok ? 0 : 1;
}

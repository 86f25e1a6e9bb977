// SPDX-License-Identifier: LGPL-2.1-only
// Query round trip on loopback (issue 11): 224x224x3 uint8 frames through a pass-through query
// server (`tensor_query_serversrc ! tensor_query_serversink`, its own pipeline) and
// `appsrc ! tensor_query_client ! appsink`.
//  1. latency: one frame in flight (max-request=1, timeout=1000); time from the client's sink
//     pad (chain entry) to its src pad (answer pushed), p50/p99 over --frames frames;
//  2. throughput: max-request=0, timeout=0, --frames frames pushed as fast as appsrc takes them;
//     frames/s from the first push to the last answer.
// Targets: p50 <= 250 us, >= 3000 frames/s. Copies: none in user space (sendmsg from the mapped
// memories, recv into the GstMemory the buffer then owns); the kernel copies once per send and
// once per receive. For scale the bench also times one memcpy of a frame.
//
// usage: query_bench [--frames N] [--runs R]
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <sys/resource.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "../tests/support/net_util.h"
#include "gst/plugin_init.h"

namespace {

using Clock = std::chrono::steady_clock;
constexpr std::size_t kFrame = 224 * 224 * 3;
const char *kCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)3:224:224:1,"
    "types=(string)uint8,framerate=(fraction)0/1";

using nns::test::free_port;

GstElement *launch(const std::string &d) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(d.c_str(), &err);
  if (!p) {
    std::fprintf(stderr, "%s: %s\n", d.c_str(), err ? err->message : "?");
    std::exit(1);
  }
  return p;
}

struct Probes {
  std::mutex m;
  std::map<GstClockTime, Clock::time_point> in;
  std::vector<double> us;
};

GstPadProbeReturn on_in(GstPad *, GstPadProbeInfo *info, gpointer d) {
  auto *p = static_cast<Probes *>(d);
  std::lock_guard<std::mutex> l(p->m);
  p->in[GST_BUFFER_PTS(GST_PAD_PROBE_INFO_BUFFER(info))] = Clock::now();
  return GST_PAD_PROBE_OK;
}

GstPadProbeReturn on_out(GstPad *, GstPadProbeInfo *info, gpointer d) {
  auto *p = static_cast<Probes *>(d);
  const auto now = Clock::now();
  std::lock_guard<std::mutex> l(p->m);
  auto it = p->in.find(GST_BUFFER_PTS(GST_PAD_PROBE_INFO_BUFFER(info)));
  if (it != p->in.end()) {
    p->us.push_back(std::chrono::duration<double, std::micro>(now - it->second).count());
    p->in.erase(it);
  }
  return GST_PAD_PROBE_OK;
}

double pct(std::vector<double> v, double q) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return v[std::min(v.size() - 1, static_cast<std::size_t>(q * v.size()))];
}

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) / 1e6;
}

struct Result {
  double p50 = 0, p99 = 0, fps = 0, cpu_us = 0;
  int answers = 0;
};

Result run(uint16_t port, const std::string &client_opts, int frames, bool lockstep) {
  GstElement *c =
      launch("appsrc name=src format=time caps=\"" + std::string(kCaps) +
             "\" max-bytes=4000000 block=true ! tensor_query_client name=q host=127.0.0.1 port=0 "
             "dest-host=127.0.0.1 dest-port=" +
             std::to_string(port) + " " + client_opts + " ! appsink name=sink sync=false");
  GstElement *src = gst_bin_get_by_name(GST_BIN(c), "src");
  GstElement *sink = gst_bin_get_by_name(GST_BIN(c), "sink");
  GstElement *q = gst_bin_get_by_name(GST_BIN(c), "q");
  Probes probes;
  GstPad *qs = gst_element_get_static_pad(q, "sink"), *qo = gst_element_get_static_pad(q, "src");
  gst_pad_add_probe(qs, GST_PAD_PROBE_TYPE_BUFFER, on_in, &probes, nullptr);
  gst_pad_add_probe(qo, GST_PAD_PROBE_TYPE_BUFFER, on_out, &probes, nullptr);
  gst_element_set_state(c, GST_STATE_PLAYING);
  std::vector<uint8_t> bytes(kFrame);
  for (std::size_t i = 0; i < kFrame; ++i) bytes[i] = static_cast<uint8_t>(i * 31);
  Result r;
  const auto t0 = Clock::now();
  const double c0 = cpu_seconds();
  auto pull = [&](GstClockTime t) {
    GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), t);
    if (!s) return false;
    ++r.answers;
    gst_sample_unref(s);
    return true;
  };
  for (int i = 0; i < frames; ++i) {
    GstBuffer *b = gst_buffer_new_memdup(bytes.data(), bytes.size());
    GST_BUFFER_PTS(b) = static_cast<GstClockTime>(i) * GST_MSECOND;
    gst_app_src_push_buffer(GST_APP_SRC(src), b);
    if (lockstep) pull(5 * GST_SECOND);
  }
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  while (r.answers < frames && pull(5 * GST_SECOND)) {
  }
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  r.fps = r.answers / s;
  r.cpu_us = r.answers ? (cpu_seconds() - c0) * 1e6 / r.answers : 0;
  r.p50 = pct(probes.us, 0.5);
  r.p99 = pct(probes.us, 0.99);
  gst_element_set_state(c, GST_STATE_NULL);
  gst_object_unref(qs);
  gst_object_unref(qo);
  gst_object_unref(q);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(c);
  return r;
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  nns_register_static();
  int frames = 3000, runs = 3;
  for (int i = 1; i + 1 < argc; ++i) {
    if (!std::strcmp(argv[i], "--frames")) frames = std::atoi(argv[++i]);
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[++i]);
  }
  const uint16_t port = free_port();
  GstElement *server = launch("tensor_query_serversrc host=127.0.0.1 port=" + std::to_string(port) +
                              " ! tensor_query_serversink sync=false");
  gst_element_set_state(server, GST_STATE_PLAYING);
  g_usleep(200000);  // a live pipeline reaches PLAYING with its first buffer: do not wait

  std::vector<double> p50s, p99s, fpss, cpus;
  for (int r = 0; r < runs; ++r) {
    Result lat = run(port, "max-request=1 timeout=1000", frames / 2, true);
    Result thr = run(port, "max-request=0 timeout=0", frames, false);
    std::printf(
        "run %d: latency p50 %.1f us p99 %.1f us (%d answers); throughput %.0f frames/s "
        "(%d/%d answers), process CPU %.1f us per frame (client + server)\n",
        r, lat.p50, lat.p99, lat.answers, thr.fps, thr.answers, frames, thr.cpu_us);
    cpus.push_back(thr.cpu_us);
    p50s.push_back(lat.p50);
    p99s.push_back(lat.p99);
    fpss.push_back(thr.fps);
  }
  // One memcpy of a frame, for scale.
  std::vector<uint8_t> a(kFrame, 1), b(kFrame);
  const auto t0 = Clock::now();
  for (int i = 0; i < 2000; ++i) {
    std::memcpy(b.data(), a.data(), kFrame);
    a[i % kFrame] = b[(i * 7) % kFrame];
  }
  const double copy_us =
      std::chrono::duration<double, std::micro>(Clock::now() - t0).count() / 2000;
  std::printf(
      "median of %d runs: p50 %.1f us, p99 %.1f us, %.0f frames/s, %.1f us CPU per frame; "
      "memcpy of one 150528-byte frame: %.1f us; user-space copies per direction: 0\n",
      runs, pct(p50s, 0.5), pct(p99s, 0.5), pct(fpss, 0.5), pct(cpus, 0.5), copy_us);
  gst_element_set_state(server, GST_STATE_NULL);
  gst_object_unref(server);
  return 0;
}

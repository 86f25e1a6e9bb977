// SPDX-License-Identifier: LGPL-2.1-only
// Cost of the nnsprofile tracer (docs/profiler.md): the same pipelines timed in child processes
// without a tracer, with nnsprofile's hooks registered but recording nothing (record=0: what
// GStreamer's tracing machinery costs by itself once any tracer is active, e.g. a hook lookup
// on every buffer and object ref/unref), with nnsprofile, and with GStreamer's own `latency`
// tracer for comparison. Each configuration runs --rounds times, alternating, and the
// median process CPU (and wall) time per buffer is reported.
//
// usage: profiler_overhead_bench [--rounds R] [--buffers N] [--frames M]
#include <glib.h>
#include <gst/gst.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "gst/plugin_init.h"
#include "tensor_filter_custom_easy.h"

namespace {

double cpu_seconds() {
  timespec ts{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
  return static_cast<double>(ts.tv_sec) + static_cast<double>(ts.tv_nsec) * 1e-9;
}

struct Case {
  std::string name;
  std::string desc;
  int buffers;
};

std::vector<Case> cases(int n, int frames) {
  const std::string tiny = "videotestsrc num-buffers=" + std::to_string(n) +
                           " pattern=black ! video/x-raw,format=GRAY8,width=4,height=4,"
                           "framerate=0/1 ! ";
  const std::string rgb = "videotestsrc num-buffers=" + std::to_string(frames) +
                          " pattern=black ! video/x-raw,format=RGB,width=224,height=224,"
                          "framerate=0/1 ! ";
  return {
      {"foundation 4x4: src ! fakesink", tiny + "fakesink", n},
      {"foundation 4x4: converter ! transform",
       tiny + "tensor_converter ! tensor_transform mode=typecast option=float32 ! fakesink", n},
      {"224x224 RGB: converter ! normalise",
       rgb + "tensor_converter ! tensor_transform mode=arithmetic "
             "option=typecast:float32,add:-127.5,div:127.5 ! fakesink",
       frames},
      {"224x224 RGB: ... ! 0.5 ms model",
       rgb + "tensor_converter ! tensor_transform mode=arithmetic "
             "option=typecast:float32,add:-127.5,div:127.5 ! "
             "tensor_filter framework=custom-easy model=bench_half_ms ! fakesink",
       frames},
  };
}

// A stand-in model: 0.5 ms of CPU work per frame.
int half_ms_model(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
                  GstTensorMemory *out) {
  timespec t0{}, t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t0);
  float acc = 0;
  const auto *x = static_cast<const float *>(in[0].data);
  do {
    for (int i = 0; i < 1000; ++i) acc += x[i];
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  } while ((t.tv_sec - t0.tv_sec) * 1000000000L + (t.tv_nsec - t0.tv_nsec) < 500000);
  *static_cast<float *>(out[0].data) = acc;
  return 0;
}

void register_model() {
  GstTensorsInfo in, out;
  std::memset(&in, 0, sizeof in);
  std::memset(&out, 0, sizeof out);
  in.num_tensors = out.num_tensors = 1;
  in.info[0].type = out.info[0].type = _NNS_FLOAT32;
  in.info[0].dimension[0] = 3;
  in.info[0].dimension[1] = 224;
  in.info[0].dimension[2] = 224;
  in.info[0].dimension[3] = 1;
  out.info[0].dimension[0] = 1;
  NNS_custom_easy_register("bench_half_ms", half_ms_model, nullptr, &in, &out);
}

// Child: runs every case once, prints "case-index cpu-seconds wall-seconds".
int child(int n, int frames) {
  for (std::size_t i = 0; const Case &c : cases(n, frames)) {
    GstElement *p = gst_parse_launch(c.desc.c_str(), nullptr);
    if (!p) return 1;
    GstBus *bus = gst_element_get_bus(p);
    const double c0 = cpu_seconds();
    const auto t0 = std::chrono::steady_clock::now();
    gst_element_set_state(p, GST_STATE_PLAYING);
    GstMessage *m = gst_bus_timed_pop_filtered(
        bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    const double cpu = cpu_seconds() - c0;
    const double wall =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    const bool ok = m && GST_MESSAGE_TYPE(m) == GST_MESSAGE_EOS;
    if (m) gst_message_unref(m);
    gst_element_set_state(p, GST_STATE_NULL);
    gst_object_unref(bus);
    gst_object_unref(p);
    if (!ok) return 1;
    std::printf("%zu %.6f %.6f\n", i++, cpu, wall);
  }
  return 0;
}

double median(std::vector<double> v) {
  if (v.empty()) return -1;
  std::sort(v.begin(), v.end());
  return v[v.size() / 2];
}

}  // namespace

int main(int argc, char **argv) {
  int rounds = 5, n = 100000, frames = 1000;
  bool is_child = false;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    if (a == "--child") is_child = true;
    if (i + 1 < argc && a == "--rounds") rounds = std::atoi(argv[++i]);
    if (i + 1 < argc && a == "--buffers") n = std::atoi(argv[++i]);
    if (i + 1 < argc && a == "--frames") frames = std::atoi(argv[++i]);
  }
  if (is_child) {
    gst_init(nullptr, nullptr);
    if (!nns_register_static()) return 1;  // starts nnsprofile when GST_TRACERS names it
    register_model();
    return child(n, frames);
  }
  const std::string trace =
      std::string(g_get_tmp_dir()) + "/nns-profile-bench-" + std::to_string(getpid()) + ".json";
  const std::vector<std::pair<std::string, std::string>> modes = {
      {"no tracer", ""},
      {"nnsprofile record=0", "nnsprofile(file=" + trace + ",interval=0,record=0)"},
      {"nnsprofile", "nnsprofile(file=" + trace + ",interval=0)"},
      {"core latency tracer", "latency"}};
  std::map<std::pair<std::size_t, std::size_t>, std::vector<double>> cpu, wall;
  gchar *self = g_file_read_link("/proc/self/exe", nullptr);
  for (int r = 0; r < rounds; ++r)
    for (std::size_t m = 0; m < modes.size(); ++m) {
      gchar **env = g_get_environ();
      env = g_environ_setenv(env, "GST_PLUGIN_PATH", "", TRUE);
      env = modes[m].second.empty()
                ? g_environ_unsetenv(env, "GST_TRACERS")
                : g_environ_setenv(env, "GST_TRACERS", modes[m].second.c_str(), TRUE);
      std::string sn = std::to_string(n), sf = std::to_string(frames);
      const char *args[] = {self,       "--child",  "--buffers", sn.c_str(),
                            "--frames", sf.c_str(), nullptr};
      gchar *out = nullptr;
      gint status = 0;
      const bool ok = g_spawn_sync(nullptr, const_cast<gchar **>(args), env, G_SPAWN_DEFAULT,
                                   nullptr, nullptr, &out, nullptr, &status, nullptr) &&
                      g_spawn_check_wait_status(status, nullptr);
      g_strfreev(env);
      if (!ok) {
        std::fprintf(stderr, "profiler_overhead_bench: the %s run failed\n",
                     modes[m].first.c_str());
        g_free(out);
        g_free(self);
        return 1;
      }
      std::istringstream in(out);
      std::size_t i;
      double c, w;
      while (in >> i >> c >> w) {
        cpu[{m, i}].push_back(c);
        wall[{m, i}].push_back(w);
      }
      g_free(out);
    }
  g_free(self);
  std::remove(trace.c_str());
  std::printf("== nnsprofile overhead, median of %d rounds, process CPU (wall) per buffer\n",
              rounds);
  std::printf("%-36s %20s %26s %26s %26s\n", "pipeline", "no tracer", "hooks only (record=0)",
              "nnsprofile", "core latency tracer");
  auto cs = cases(n, frames);
  for (std::size_t i = 0; i < cs.size(); ++i) {
    const double b = cs[i].buffers;
    const double c0 = median(cpu[{0, i}]) / b * 1e6, w0 = median(wall[{0, i}]) / b * 1e6;
    std::printf("%-36s %8.3f (%8.3f) us", cs[i].name.c_str(), c0, w0);
    for (std::size_t m = 1; m < modes.size(); ++m) {
      const double c = median(cpu[{m, i}]) / b * 1e6, w = median(wall[{m, i}]) / b * 1e6;
      std::printf("  %8.3f (%8.3f) us %+4.0f%%", c, w, (c / c0 - 1) * 100);
    }
    std::printf("\n");
  }
  return 0;
}

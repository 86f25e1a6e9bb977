// SPDX-License-Identifier: LGPL-2.1-only
// Pipeline-level benchmarks of tensor_converter and tensor_transform (foundation issue):
//  1. per-buffer cost on tiny frames: 4x4 GRAY8, 100 000 buffers from
//     `videotestsrc pattern=black ... framerate=0/1`, in microseconds per buffer above the plain
//     `videotestsrc ! fakesink` pipeline (target <= 1.5 us per element per buffer);
//  2. tensor_transform typecast:float32,add:-127.5,div:127.5 on 224x224x3 uint8: output bytes/s
//     (time above `... ! tensor_converter ! fakesink`) as a ratio of memcpy of the same output
//     size (target >= 0.6);
//  3. tensor_converter on 224x224 RGB: how many buffers had their data copied (target 0).
// Each configuration runs --runs times, interleaved, and the median is reported.
//
// usage: pipeline_overhead_bench [--buffers N] [--frames M] [--runs R]
#include <gst/gst.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "gst/plugin_init.h"

namespace {

using Clock = std::chrono::steady_clock;

bool has_elements(std::initializer_list<const char *> names, std::string *missing) {
  for (const char *n : names) {
    GstElementFactory *f = gst_element_factory_find(n);
    if (!f) {
      *missing = n;
      return false;
    }
    gst_object_unref(f);
  }
  return true;
}

// Seconds from PLAYING to EOS; negative on error.
double time_pipeline(const std::string &desc) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "bench: cannot parse '%s': %s\n", desc.c_str(), err ? err->message : "?");
    if (err) g_error_free(err);
    if (p) gst_object_unref(p);
    return -1;
  }
  // Parsing is not timed; start-up (state changes, negotiation) is, once per run.
  GstBus *bus = gst_element_get_bus(p);
  auto t0 = Clock::now();
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  double s = std::chrono::duration<double>(Clock::now() - t0).count();
  if (!m || GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    if (m) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      std::fprintf(stderr, "bench: error in '%s': %s\n", desc.c_str(), e->message);
      g_error_free(e);
    }
    s = -1;
  }
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(p);
  return s;
}

double median(std::vector<double> v) {
  std::sort(v.begin(), v.end());
  return v.empty() ? -1 : v[v.size() / 2];
}

// Runs every description `runs` times, interleaved; returns the median seconds of each (or -1
// when the configuration is unavailable or failed).
std::vector<double> measure(const std::vector<std::string> &descs, int runs) {
  std::vector<std::vector<double>> t(descs.size());
  for (int r = 0; r < runs; ++r)
    for (std::size_t i = 0; i < descs.size(); ++i) {
      if (descs[i].empty()) continue;
      double s = time_pipeline(descs[i]);
      if (s < 0) return std::vector<double>(descs.size(), -1);
      t[i].push_back(s);
    }
  std::vector<double> out;
  for (auto &v : t) out.push_back(v.empty() ? -1 : median(v));
  return out;
}

// memcpy bandwidth (bytes/s) for blocks of `bytes`, median of 5 batches.
double memcpy_bandwidth(std::size_t bytes) {
  std::vector<uint8_t> src(bytes, 1), dst(bytes);
  const int reps = std::max<int>(50, static_cast<int>((2u << 30) / bytes / 4));
  std::vector<double> bw;
  for (int b = 0; b < 5; ++b) {
    auto t0 = Clock::now();
    for (int i = 0; i < reps; ++i) {
      std::memcpy(dst.data(), src.data(), bytes);
      src[static_cast<std::size_t>(i) % bytes] = dst[(static_cast<std::size_t>(i) * 7) % bytes];
    }
    double s = std::chrono::duration<double>(Clock::now() - t0).count();
    bw.push_back(static_cast<double>(bytes) * reps / s);
  }
  return median(bw);
}

struct CopyCount {
  const void *last_in = nullptr;
  int buffers = 0;
  int copies = 0;
};

const void *data_ptr(GstBuffer *buf) {
  if (gst_buffer_n_memory(buf) == 0) return nullptr;
  GstMapInfo map;
  GstMemory *mem = gst_buffer_peek_memory(buf, 0);
  if (!gst_memory_map(mem, &map, GST_MAP_READ)) return nullptr;
  const void *p = map.data;
  gst_memory_unmap(mem, &map);
  return p;
}

GstPadProbeReturn probe_in(GstPad *, GstPadProbeInfo *info, gpointer user) {
  static_cast<CopyCount *>(user)->last_in = data_ptr(GST_PAD_PROBE_INFO_BUFFER(info));
  return GST_PAD_PROBE_OK;
}
GstPadProbeReturn probe_out(GstPad *, GstPadProbeInfo *info, gpointer user) {
  auto *c = static_cast<CopyCount *>(user);
  ++c->buffers;
  if (data_ptr(GST_PAD_PROBE_INFO_BUFFER(info)) != c->last_in) ++c->copies;
  return GST_PAD_PROBE_OK;
}

// Counts converter output buffers whose data is not the input buffer's data.
CopyCount converter_copies(int frames) {
  CopyCount c;
  std::string desc = "videotestsrc num-buffers=" + std::to_string(frames) +
                     " pattern=black ! video/x-raw,format=RGB,width=224,height=224,"
                     "framerate=0/1 ! tensor_converter name=conv ! fakesink";
  GstElement *p = gst_parse_launch(desc.c_str(), nullptr);
  GstElement *conv = p ? gst_bin_get_by_name(GST_BIN(p), "conv") : nullptr;
  if (!conv) {
    if (p) gst_object_unref(p);
    c.buffers = -1;
    return c;
  }
  GstPad *sink = gst_element_get_static_pad(conv, "sink");
  GstPad *src = gst_element_get_static_pad(conv, "src");
  gst_pad_add_probe(sink, GST_PAD_PROBE_TYPE_BUFFER, probe_in, &c, nullptr);
  gst_pad_add_probe(src, GST_PAD_PROBE_TYPE_BUFFER, probe_out, &c, nullptr);
  gst_object_unref(sink);
  gst_object_unref(src);
  gst_object_unref(conv);
  GstBus *bus = gst_element_get_bus(p);
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 60 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  if (!m || GST_MESSAGE_TYPE(m) != GST_MESSAGE_EOS) c.buffers = -1;
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(p);
  return c;
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  if (!nns_register_static()) {
    std::fprintf(stderr, "bench: cannot register the nnstreamer elements\n");
    return 1;
  }
  int n = 100000, frames = 2000, runs = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    std::string a = argv[i];
    int v = std::atoi(argv[i + 1]);
    if (a == "--buffers") n = v;
    if (a == "--frames") frames = v;
    if (a == "--runs") runs = v;
  }
  std::string missing;
  const bool have_conv = has_elements({"tensor_converter"}, &missing);
  const bool have_trans = have_conv && has_elements({"tensor_transform"}, &missing);

  // 1. Tiny frames.
  std::string src = "videotestsrc num-buffers=" + std::to_string(n) +
                    " pattern=black ! video/x-raw,format=GRAY8,width=4,height=4,framerate=0/1 ! ";
  std::vector<std::string> d1 = {
      src + "fakesink", have_conv ? src + "tensor_converter ! fakesink" : "",
      have_trans ? src +
                       "tensor_converter ! tensor_transform mode=typecast option=float32 ! "
                       "fakesink"
                 : ""};
  auto t1 = measure(d1, runs);
  const double us = 1e6 / n;
  std::printf("== per-buffer cost, 4x4 GRAY8, %d buffers, median of %d runs\n", n, runs);
  std::printf("baseline videotestsrc ! fakesink          : %8.3f us/buffer (%.3f s)\n", t1[0] * us,
              t1[0]);
  if (t1[1] > 0)
    std::printf(
        "tensor_converter                          : %8.3f us/buffer above baseline "
        "(target <= 1.5)\n",
        (t1[1] - t1[0]) * us);
  else
    std::printf("tensor_converter                          : not measured (%s)\n",
                have_conv ? "pipeline failed" : "element not built");
  if (t1[2] > 0)
    std::printf(
        "tensor_transform mode=typecast float32    : %8.3f us/buffer above the converter "
        "pipeline (target <= 1.5)\n",
        (t1[2] - t1[1]) * us);
  else
    std::printf("tensor_transform mode=typecast float32    : not measured (%s)\n",
                have_trans ? "pipeline failed" : "element not built");

  // 2. 224x224x3 normalisation throughput vs memcpy.
  const std::size_t out_bytes = 224u * 224 * 3 * sizeof(float);
  double mbw = memcpy_bandwidth(out_bytes);
  std::printf(
      "\n== tensor_transform typecast:float32,add:-127.5,div:127.5 on 224x224x3 uint8, "
      "%d frames, median of %d runs\n",
      frames, runs);
  std::printf("memcpy of %zu bytes                     : %8.2f GB/s\n", out_bytes, mbw / 1e9);
  if (have_trans) {
    std::string s2 = "videotestsrc num-buffers=" + std::to_string(frames) +
                     " pattern=black ! video/x-raw,format=RGB,width=224,height=224,"
                     "framerate=0/1 ! tensor_converter ! ";
    auto t2 =
        measure({s2 + "fakesink", s2 + "tensor_transform mode=arithmetic "
                                       "option=typecast:float32,add:-127.5,div:127.5 ! fakesink"},
                runs);
    if (t2[0] > 0 && t2[1] > t2[0]) {
      double per = (t2[1] - t2[0]) / frames;
      double bw = out_bytes / per;
      std::printf(
          "transform                                 : %8.1f us/frame, %.2f GB/s output, "
          "ratio to memcpy %.2f (target >= 0.6)\n",
          per * 1e6, bw / 1e9, bw / mbw);
    } else {
      std::printf("transform                                 : not measured (pipeline failed)\n");
    }
  } else {
    std::printf("transform                                 : not measured (%s not built)\n",
                missing.c_str());
  }

  // 3. Converter copies.
  std::printf("\n== tensor_converter on 224x224 RGB: copies\n");
  if (have_conv) {
    CopyCount c = converter_copies(100);
    if (c.buffers > 0)
      std::printf("buffers whose data was copied            : %d of %d (target 0)\n", c.copies,
                  c.buffers);
    else
      std::printf("copies                                    : not measured (pipeline failed)\n");
  } else {
    std::printf("copies                                    : not measured (element not built)\n");
  }
  return 0;
}

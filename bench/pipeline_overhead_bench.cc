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
#include <time.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "bench_util.h"
#include "gst/plugin_init.h"

namespace {

using nns::bench::Clock;
using nns::bench::cpu_seconds;
using nns::bench::measure;
using nns::bench::median;
using nns::bench::Timing;

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

// memcpy bandwidth (bytes/s, wall and process-CPU clocks) for blocks of `bytes`, median of 5
// batches.
Timing memcpy_bandwidth(std::size_t bytes) {
  std::vector<uint8_t> src(bytes, 1), dst(bytes);
  const int reps = std::max<int>(50, static_cast<int>((2u << 30) / bytes / 4));
  std::vector<double> wall, cpu;
  for (int b = 0; b < 5; ++b) {
    auto t0 = Clock::now();
    double c0 = cpu_seconds();
    for (int i = 0; i < reps; ++i) {
      std::memcpy(dst.data(), src.data(), bytes);
      src[static_cast<std::size_t>(i) % bytes] = dst[(static_cast<std::size_t>(i) * 7) % bytes];
    }
    double c = cpu_seconds() - c0;
    double s = std::chrono::duration<double>(Clock::now() - t0).count();
    wall.push_back(static_cast<double>(bytes) * reps / s);
    cpu.push_back(static_cast<double>(bytes) * reps / c);
  }
  return Timing{median(wall), median(cpu)};
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
  if (!nns::bench::play_to_eos(p, 60 * GST_SECOND)) c.buffers = -1;
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
  nns::bench::int_options(argc, argv,
                          {{"--buffers", &n}, {"--frames", &frames}, {"--runs", &runs}});
  std::string missing;
  const bool have_conv = has_elements({"tensor_converter"}, &missing);
  const bool have_trans = have_conv && has_elements({"tensor_transform"}, &missing);

  // 1. Tiny frames.
  std::string src = "videotestsrc num-buffers=" + std::to_string(n) +
                    " pattern=black ! video/x-raw,format=GRAY8,width=4,height=4,framerate=0/1 ! ";
  std::vector<std::string> d1 = {src + "fakesink", "", ""};
  if (have_conv) d1[1] = src + "tensor_converter ! fakesink";
  if (have_trans)
    d1[2] = src + "tensor_converter ! tensor_transform mode=typecast option=float32 ! fakesink";
  auto t1 = measure(d1, runs);
  const double us = 1e6 / n;
  std::printf("== per-buffer cost, 4x4 GRAY8, %d buffers, median of %d runs (wall / process CPU)\n",
              n, runs);
  std::printf("%-42s: %7.3f / %7.3f us/buffer\n", "baseline videotestsrc ! fakesink",
              t1[0].wall * us, t1[0].cpu * us);
  auto row = [&](const char *name, const Timing &with, const Timing &without, bool built) {
    if (with.wall > 0 && without.wall > 0)
      std::printf("%-42s: %7.3f / %7.3f us/buffer added (target <= 1.5)\n", name,
                  (with.wall - without.wall) * us, (with.cpu - without.cpu) * us);
    else
      std::printf("%-42s: not measured (%s)\n", name,
                  built ? "pipeline failed" : "element not built");
  };
  row("tensor_converter", t1[1], t1[0], have_conv);
  row("tensor_transform mode=typecast float32", t1[2], t1[1], have_trans);

  // 2. 224x224x3 normalisation throughput vs memcpy.
  const std::size_t out_bytes = 224u * 224 * 3 * sizeof(float);
  Timing mbw = memcpy_bandwidth(out_bytes);
  std::printf(
      "\n== tensor_transform typecast:float32,add:-127.5,div:127.5 on 224x224x3 uint8, "
      "%d frames, median of %d runs\n",
      frames, runs);
  std::printf("%-42s: %7.2f / %7.2f GB/s (wall / process CPU)\n",
              ("memcpy of " + std::to_string(out_bytes) + " bytes").c_str(), mbw.wall / 1e9,
              mbw.cpu / 1e9);
  if (have_trans) {
    std::string s2 = "videotestsrc num-buffers=" + std::to_string(frames) +
                     " pattern=black ! video/x-raw,format=RGB,width=224,height=224,"
                     "framerate=0/1 ! tensor_converter ! ";
    auto t2 = measure({s2 + "fakesink", s2 + "tensor_transform mode=arithmetic "
                                             "option=typecast:float32,add:-127.5,div:127.5 ! "
                                             "fakesink"},
                      runs);
    if (t2[0].wall > 0 && t2[1].wall > t2[0].wall) {
      for (int k = 0; k < 2; ++k) {
        double per = k == 0 ? (t2[1].wall - t2[0].wall) / frames : (t2[1].cpu - t2[0].cpu) / frames;
        double bw = static_cast<double>(out_bytes) / per;
        std::printf(
            "%-42s: %7.1f us/frame, %.2f GB/s output, ratio to memcpy %.2f "
            "(target >= 0.6)\n",
            k == 0 ? "transform (wall)" : "transform (process CPU)", per * 1e6, bw / 1e9,
            bw / (k == 0 ? mbw.wall : mbw.cpu));
      }
    } else {
      std::printf("%-42s: not measured (pipeline failed)\n", "transform");
    }
  } else {
    std::printf("%-42s: not measured (%s not built)\n", "transform", missing.c_str());
  }

  // 3. Converter copies.
  std::printf("\n== tensor_converter on 224x224 RGB: copies\n");
  if (have_conv) {
    CopyCount c = converter_copies(100);
    if (c.buffers > 0)
      std::printf("%-42s: %d of %d (target 0)\n", "buffers whose data was copied", c.copies,
                  c.buffers);
    else
      std::printf("%-42s: not measured (pipeline failed)\n", "copies");
  } else {
    std::printf("%-42s: not measured (element not built)\n", "copies");
  }
  return 0;
}

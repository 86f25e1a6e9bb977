// SPDX-License-Identifier: LGPL-2.1-only
// datareposrc read rate against filesrc reading the same bytes (issue target: >= 0.8x).
// Writes a data repository of MNIST-like samples (two static tensors, 784 + 10 float32 = 3176
// bytes a sample) to a temp folder, then times, interleaved, best of --runs:
//   filesrc location=F blocksize=3176 ! fakesink
//   datareposrc location=F json=J is-shuffle=false ! fakesink     (one pread, two shared tensors)
//   datareposrc ... is-shuffle=true                                (random order, page cache warm)
// and prints samples/s and the ratios. Both read from the page cache (the file is read once
// before timing).
//
// usage: datarepo_bench [--samples N] [--runs R]
#include <gst/gst.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "gst/plugin_init.h"

namespace {

double run(const std::string &desc) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  if (!p || err) {
    std::fprintf(stderr, "datarepo_bench: cannot parse '%s': %s\n", desc.c_str(),
                 err ? err->message : "?");
    return -1;
  }
  GstBus *bus = gst_element_get_bus(p);
  auto t0 = std::chrono::steady_clock::now();
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstMessage *m = gst_bus_timed_pop_filtered(
      bus, 600 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  double s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!m || GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    std::fprintf(stderr, "datarepo_bench: '%s' failed\n", desc.c_str());
    s = -1;
  }
  if (m) gst_message_unref(m);
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(p);
  return s;
}

}  // namespace

int main(int argc, char **argv) {
  int samples = 50000, runs = 5;
  for (int i = 1; i + 1 < argc; i += 2) {
    if (!std::strcmp(argv[i], "--samples")) samples = std::atoi(argv[i + 1]);
    if (!std::strcmp(argv[i], "--runs")) runs = std::atoi(argv[i + 1]);
  }
  gst_init(&argc, &argv);
  nns_register_static();
  namespace fs = std::filesystem;
  char tmpl[] = "/tmp/nns-datarepo-bench-XXXXXX";
  if (!mkdtemp(tmpl)) return 1;
  const fs::path dir = tmpl;
  const std::string data = (dir / "mnist.dat").string(), json = (dir / "mnist.json").string();
  const std::size_t sample = 3176;
  {
    std::vector<char> buf(sample * 1000);
    for (std::size_t i = 0; i < buf.size(); ++i) buf[i] = static_cast<char>(i * 31);
    std::ofstream f(data, std::ios::binary);
    for (int left = samples; left > 0; left -= 1000)
      f.write(buf.data(), static_cast<std::streamsize>(sample * std::min(left, 1000)));
    std::ofstream(json) << "{\"gst_caps\":\"other/tensors, format=(string)static, "
                           "framerate=(fraction)0/1, num_tensors=(int)2, "
                           "dimensions=(string)1:1:784:1.1:1:10:1, "
                           "types=(string)float32.float32\",\"total_samples\":"
                        << samples << ",\"sample_size\":" << sample << "}";
  }
  const std::string fsrc = "filesrc location=" + data + " blocksize=3176 ! fakesink";
  const std::string drepo = "datareposrc location=" + data + " json=" + json;
  run(fsrc);  // page cache
  double best_file = 1e9, best_repo = 1e9, best_shuf = 1e9;
  for (int r = 0; r < runs; ++r) {
    double a = run(fsrc), b = run(drepo + " is-shuffle=false ! fakesink"),
           c = run(drepo + " is-shuffle=true ! fakesink");
    if (a < 0 || b < 0 || c < 0) return 1;
    best_file = std::min(best_file, a);
    best_repo = std::min(best_repo, b);
    best_shuf = std::min(best_shuf, c);
  }
  std::printf("samples: %d x %zu bytes, best of %d runs\n", samples, sample, runs);
  std::printf("filesrc blocksize=3176      %9.0f samples/s\n", samples / best_file);
  std::printf("datareposrc in order        %9.0f samples/s  ratio %.2f (target >= 0.8)\n",
              samples / best_repo, best_file / best_repo);
  std::printf("datareposrc shuffled        %9.0f samples/s  ratio %.2f\n", samples / best_shuf,
              best_file / best_shuf);
  fs::remove_all(dir);
  return 0;
}

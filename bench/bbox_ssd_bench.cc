// SPDX-License-Identifier: LGPL-2.1-only
// mobilenet-ssd decode + NMS per frame (tensor_decoder mode=bounding_boxes' scheme, nns_bbox)
// on upstream's captured 1917-prior frames (../shared/models/upstream/decoder/
// nnstreamer_decoder_boundingbox), CPU time per frame from getrusage.
//   build/bench/bbox_ssd_bench [iterations]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "box_scheme.h"

namespace {
double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return static_cast<double>(u.ru_utime.tv_sec + u.ru_stime.tv_sec) +
         static_cast<double>(u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}
std::vector<char> slurp(const std::string &p) {
  std::ifstream f(p, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}
}  // namespace

int main(int argc, char **argv) {
  const int iters = argc > 1 ? std::atoi(argv[1]) : 2000;
  const char *env = std::getenv("NNS_SHARED_DIR");
  const std::string dir = std::string(env ? env : NNS_SOURCE_DIR "/../shared") +
                          "/models/upstream/decoder/nnstreamer_decoder_boundingbox";
  if (!std::filesystem::exists(dir + "/box_priors.txt")) {
    std::fprintf(stderr, "bbox_ssd_bench: %s missing; skipping\n", dir.c_str());
    return 77;
  }
  auto scheme = nns::bbox::schemes().make("mobilenet-ssd");
  scheme->set_option3(dir + "/box_priors.txt");
  nns::TensorsInfo info;
  info.tensors = {{"", nns::TensorType::kFloat32, nns::make_dims({4, 1, 1917, 1})},
                  {"", nns::TensorType::kFloat32, nns::make_dims({91, 1917, 1})}};
  nns::bbox::Context ctx;
  ctx.num_labels = 91;
  scheme->check_input(info, ctx);
  std::vector<char> boxes[2], cls[2];
  for (int f = 0; f < 2; ++f) {
    boxes[f] = slurp(dir + "/mobilenetssd_tensors.0." + std::to_string(f));
    cls[f] = slurp(dir + "/mobilenetssd_tensors.1." + std::to_string(f));
  }
  std::vector<nns::bbox::Box> out;
  std::size_t total = 0;
  const double c0 = cpu_seconds();
  const auto t0 = std::chrono::steady_clock::now();
  for (int i = 0; i < iters; ++i) {
    const int f = i & 1;
    nns::bbox::TensorView v[2] = {{boxes[f].data(), boxes[f].size(), &info[0]},
                                  {cls[f].data(), cls[f].size(), &info[1]}};
    scheme->decode(v, ctx, out);
    total += out.size();
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  const double cpu = cpu_seconds() - c0;
  std::printf(
      "bbox_ssd_bench: mobilenet-ssd 1917 priors x 91 classes, %d frames, %.2f boxes/frame\n",
      iters, static_cast<double>(total) / iters);
  std::printf("  cpu %.1f us/frame, wall %.1f us/frame\n", cpu / iters * 1e6, wall / iters * 1e6);
  return 0;
}

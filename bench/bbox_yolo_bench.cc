// SPDX-License-Identifier: LGPL-2.1-only
// CPU time per frame of the YOLO schemes of tensor_decoder mode=bounding_boxes (decode + NMS,
// no drawing), on upstream's captured decoder inputs and on 8400-anchor inputs made from them.
// Run: build/bench/bbox_yolo_bench [seconds per case, default 0.5]
#include <sys/resource.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "box_scheme.h"

namespace {

std::vector<float> load(const std::string &name) {
  const std::string path = std::string(NNS_SOURCE_DIR) +
                           "/../shared/models/upstream/decoder/"
                           "nnstreamer_decoder_boundingbox/" +
                           name;
  std::ifstream f(path, std::ios::binary);
  std::vector<char> b((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::vector<float> v(b.size() / sizeof(float));
  std::memcpy(v.data(), b.data(), v.size() * sizeof(float));
  return v;
}

std::vector<float> transpose(const std::vector<float> &v, std::size_t rows, std::size_t cols) {
  std::vector<float> t(v.size());
  for (std::size_t r = 0; r < rows; ++r)
    for (std::size_t c = 0; c < cols; ++c) t[c * rows + r] = v[r * cols + c];
  return t;
}

double cpu_seconds() {
  rusage u{};
  getrusage(RUSAGE_SELF, &u);
  return u.ru_utime.tv_sec + u.ru_stime.tv_sec + (u.ru_utime.tv_usec + u.ru_stime.tv_usec) * 1e-6;
}

void run(const char *label, const char *scheme, const char *option3, const char *dims,
         unsigned in_w, unsigned in_h, std::size_t labels, const std::vector<float> &data,
         double seconds) {
  auto s = nns::bbox::schemes().make(scheme);
  nns::TensorsInfo in;
  in.tensors.push_back({"", nns::TensorType::kFloat32, nns::parse_dims(dims)});
  nns::bbox::Context ctx;
  ctx.in_w = in_w, ctx.in_h = in_h, ctx.num_labels = labels;
  s->set_option3(option3);
  s->check_input(in, ctx);
  nns::bbox::TensorView v{data.data(), data.size() * sizeof(float), &in[0]};
  std::vector<nns::bbox::Box> out;
  for (int i = 0; i < 20; ++i) s->decode({&v, 1}, ctx, out);  // warm up
  long frames = 0;
  const double c0 = cpu_seconds();
  const auto w0 = std::chrono::steady_clock::now();
  double c1 = c0;
  while (c1 - c0 < seconds) {
    for (int i = 0; i < 50; ++i) s->decode({&v, 1}, ctx, out);
    frames += 50;
    c1 = cpu_seconds();
  }
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - w0).count();
  std::printf("%-44s %-11s %-10s %8.1f us CPU/frame  %8.1f us wall/frame  %3zu boxes\n", label,
              scheme, dims, (c1 - c0) / frames * 1e6, wall / frames * 1e6, out.size());
}

// For comparison: the straightforward loop (argmax over the classes of every box, then the
// threshold), box-major, without NMS or box conversion.
void run_scalar_reference(const char *label, const std::vector<float> &d, std::size_t boxes,
                          std::size_t stride, double seconds) {
  long frames = 0, kept = 0;
  const double c0 = cpu_seconds();
  double c1 = c0;
  while (c1 - c0 < seconds) {
    for (int f = 0; f < 50; ++f) {
      const float *p = d.data();
      kept = 0;
      for (std::size_t i = 0; i < boxes; ++i, p += stride) {
        std::size_t arg = 4;
        for (std::size_t c = 5; c < stride; ++c)
          if (p[c] > p[arg]) arg = c;
        kept += p[arg] > 0.25f;
      }
      asm volatile("" : : "r"(kept) : "memory");
    }
    frames += 50;
    c1 = cpu_seconds();
  }
  std::printf("%-44s %-11s %-10s %8.1f us CPU/frame  (%ld candidates, no NMS)\n", label,
              "reference", "84:N", (c1 - c0) / frames * 1e6, kept);
}

}  // namespace

int main(int argc, char **argv) {
  const double secs = argc > 1 ? std::atof(argv[1]) : 0.5;
  const auto v8 = load("yolov8_decoder_input.raw");       // 2100 boxes x 84
  const auto v5 = load("yolov5_decoder_input.raw");       // 6300 x 85
  const auto obb = load("yolov8_obb_decoder_input.raw");  // 8400 x 20
  const auto v10 = load("yolov10_decoder_input.raw");     // 300 x 6
  if (v8.size() != 2100 * 84 || v5.size() != 6300 * 85 || obb.size() != 8400 * 20) {
    std::fprintf(stderr, "bbox_yolo_bench: ../shared/models decoder inputs not found\n");
    return 1;
  }
  // 8400 anchors (a 640:640 model): the captured 2100 boxes tiled 4 times (same 0..1
  // coordinates, so 4x the candidates and 4x duplicates for NMS to remove).
  std::vector<float> v8x4;
  for (int t = 0; t < 4; ++t) v8x4.insert(v8x4.end(), v8.begin(), v8.end());
  run("yolov8 captured, upstream layout", "yolov8", "0:0.25:0.45", "84:2100:1", 320, 320, 80, v8,
      secs);
  run("yolov8 captured, model layout", "yolov8", "0:0.25:0.45", "2100:84:1", 320, 320, 80,
      transpose(v8, 2100, 84), secs);
  run("yolov8 8400 (captured x4), upstream layout", "yolov8", "0:0.25:0.45", "84:8400:1", 640, 640,
      80, v8x4, secs);
  run("yolov8 8400 (captured x4), model layout", "yolov8", "0:0.25:0.45", "8400:84:1", 640, 640, 80,
      transpose(v8x4, 8400, 84), secs);
  run_scalar_reference("scalar argmax of every box, 2100", v8, 2100, 84, secs);
  run_scalar_reference("scalar argmax of every box, 8400", v8x4, 8400, 84, secs);
  run("yolov5 captured", "yolov5", "0:0.25:0.45", "85:6300:1", 320, 320, 80, v5, secs);
  run("yolov8-obb captured (265 candidates)", "yolov8-obb", "0:0.25:0.45", "20:8400:1", 640, 640,
      15, obb, secs);
  run("yolov8-obb captured, model layout", "yolov8-obb", "0:0.25:0.45", "8400:20:1", 640, 640, 15,
      transpose(obb, 8400, 20), secs);
  run("yolov10 captured", "yolov10", "0:0.25", "6:300:1", 320, 320, 80, v10, secs);
  return 0;
}

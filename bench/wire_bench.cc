// SPDX-License-Identifier: LGPL-2.1-only
// Encode/decode throughput of the wire formats for one 224x224x3 uint8 tensor, against memcpy
// of the same bytes. MB/s = tensor bytes (150528) per second. Usage: wire_bench [iterations]
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <vector>

#ifdef NNS_HAVE_WIRE
#include "wire.h"

namespace {

using Clock = std::chrono::steady_clock;

template <typename F>
double mbps(std::size_t bytes, int iters, F &&f) {
  f();  // warm-up
  const auto t0 = Clock::now();
  for (int i = 0; i < iters; ++i) f();
  const double s = std::chrono::duration<double>(Clock::now() - t0).count();
  return static_cast<double>(bytes) * iters / s / 1e6;
}

}  // namespace

int main(int argc, char **argv) {
  const int iters = argc > 1 ? std::atoi(argv[1]) : 2000;
  std::vector<uint8_t> pixels(224 * 224 * 3);
  for (std::size_t i = 0; i < pixels.size(); ++i) pixels[i] = static_cast<uint8_t>(i * 31);
  nns::wire::Frame f;
  f.rate_n = 30;
  nns::wire::Tensor t;
  t.name = "image";
  t.type = 5;
  t.dims = {3, 224, 224, 1};
  t.data = pixels.data();
  t.size = pixels.size();
  f.tensors.push_back(t);

  std::vector<uint8_t> dst(pixels.size());
  volatile uint8_t sink = 0;
  std::printf("%-10s %12s %12s %12s\n", "format", "encode MB/s", "decode MB/s", "bytes");
  const double copy = mbps(pixels.size(), iters, [&] {
    std::memcpy(dst.data(), pixels.data(), pixels.size());
    sink = sink + dst[dst.size() / 2];
  });
  std::printf("%-10s %12.0f %12s %12zu\n", "memcpy", copy, "-", pixels.size());
  for (auto fmt :
       {nns::wire::Format::kProtobuf, nns::wire::Format::kFlatbuf, nns::wire::Format::kFlexbuf}) {
    std::vector<uint8_t> out;
    const double enc = mbps(pixels.size(), iters, [&] { nns::wire::encode(fmt, f, out); });
    const double dec = mbps(pixels.size(), iters, [&] {
      nns::wire::Frame g = nns::wire::decode(fmt, out.data(), out.size());
      sink = sink + g.tensors[0].data[7];
    });
    std::printf("%-10s %12.0f %12.0f %12zu\n", nns::wire::format_name(fmt), enc, dec, out.size());
  }
  return 0;
}
#else
int main() {
  std::puts("wire_bench: built without the wire-format library");
  return 0;
}
#endif

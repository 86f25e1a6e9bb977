// SPDX-License-Identifier: LGPL-2.1-only
// tensor_transform kernels against memcpy of the same output size (224x224x3), and the
// element's per-buffer cost on tiny frames. Run: build/bench/transform_bench
#include <benchmark/benchmark.h>

#include <cstring>
#include <random>
#include <vector>

#include "core/transform_kernels.h"

namespace {

using nns::TensorInfo;
using nns::TensorType;
using namespace nns::transform;

TensorInfo image(TensorType t) {
  return TensorInfo{"", t, nns::make_dims({3, 224, 224, 1})};
}

std::vector<uint8_t> random_bytes(std::size_t n) {
  std::mt19937 rng(7);
  std::vector<uint8_t> v(n);
  for (auto &b : v) b = static_cast<uint8_t>(rng());
  return v;
}

void BM_Memcpy_OutputSize(benchmark::State &state) {
  const std::size_t bytes = image(TensorType::kFloat32).byte_size();
  std::vector<uint8_t> src = random_bytes(bytes), dst(bytes);
  for (auto _ : state) {
    std::memcpy(dst.data(), src.data(), bytes);
    benchmark::DoNotOptimize(dst.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * bytes));
}
BENCHMARK(BM_Memcpy_OutputSize);

// Output bytes per second of one plan on a 224x224x3 tensor.
void run_plan_bench(benchmark::State &state, Mode mode, const char *option, TensorType in_type,
                    bool accelerate) {
  Plan p = make_plan(parse_options(mode, option), image(in_type), accelerate);
  std::vector<uint8_t> src = random_bytes(p.in.byte_size()), dst(p.out.byte_size());
  for (auto _ : state) {
    p.run(src.data(), dst.data());
    benchmark::DoNotOptimize(dst.data());
    benchmark::ClobberMemory();
  }
  state.SetBytesProcessed(static_cast<int64_t>(state.iterations() * p.out.byte_size()));
  state.SetLabel(accelerate ? simd::target_name() : "scalar reference");
}

BENCHMARK_CAPTURE(run_plan_bench, normalize_u8_f32, Mode::kArithmetic,
                  "typecast:float32,add:-127.5,div:127.5", TensorType::kUInt8, true);
BENCHMARK_CAPTURE(run_plan_bench, normalize_u8_f32_reference, Mode::kArithmetic,
                  "typecast:float32,add:-127.5,div:127.5", TensorType::kUInt8, false);
BENCHMARK_CAPTURE(run_plan_bench, typecast_u8_f32, Mode::kTypecast, "float32", TensorType::kUInt8,
                  true);
BENCHMARK_CAPTURE(run_plan_bench, per_channel_mean_std_u8_f32, Mode::kArithmetic,
                  "typecast:float32,per-channel:true@0,add:-123.68:-116.78:-103.94,"
                  "div:58.4:57.12:57.38",
                  TensorType::kUInt8, true);
BENCHMARK_CAPTURE(run_plan_bench, typecast_f32_u8, Mode::kTypecast, "uint8", TensorType::kFloat32,
                  true);
BENCHMARK_CAPTURE(run_plan_bench, arith_u8_int, Mode::kArithmetic, "mul:2,add:3",
                  TensorType::kUInt8, true);
BENCHMARK_CAPTURE(run_plan_bench, transpose_hwc_chw_u8, Mode::kTranspose, "1:2:0:3",
                  TensorType::kUInt8, true);
BENCHMARK_CAPTURE(run_plan_bench, dimchg_0_2_f32, Mode::kDimchg, "0:2", TensorType::kFloat32, true);
BENCHMARK_CAPTURE(run_plan_bench, clamp_f32, Mode::kClamp, "-1:1", TensorType::kFloat32, true);
BENCHMARK_CAPTURE(run_plan_bench, stand_default_f32, Mode::kStand, "default", TensorType::kFloat32,
                  true);
BENCHMARK_CAPTURE(run_plan_bench, padding_u8, Mode::kPadding, "left:2,right:2,top:2,bottom:2",
                  TensorType::kUInt8, true);

}  // namespace

BENCHMARK_MAIN();

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_transform kernels against memcpy of the same output size (224x224x3), and the
// element's per-buffer cost on tiny frames. Run: build/bench/transform_bench
#include <benchmark/benchmark.h>

#include <cstring>
#include <random>
#include <vector>

#include <gst/gst.h>

#include "core/transform_kernels.h"
#include "gst/plugin_init.h"

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
BENCHMARK_CAPTURE(run_plan_bench, padding_nhwc_u8, Mode::kPadding,
                  "left:2,right:2,top:2,bottom:2,layout:NHWC", TensorType::kUInt8, true);

// Per-buffer cost of an element on a tiny frame: buffers are pushed from a pad straight into
// the element, whose output pad drops them (no queues, no threads).
GstFlowReturn drop_chain(GstPad *, GstObject *, GstBuffer *buf) {
  gst_buffer_unref(buf);
  return GST_FLOW_OK;
}

void run_element_bench(benchmark::State &state, const char *desc, const char *caps_str,
                       std::size_t bytes) {
  GError *err = nullptr;
  GstElement *e = gst_parse_launch(desc, &err);
  if (!e || err) {
    state.SkipWithError(err ? err->message : "cannot create the element");
    if (err) g_error_free(err);
    return;
  }
  GstPad *src = gst_pad_new("src", GST_PAD_SRC), *sink = gst_pad_new("sink", GST_PAD_SINK);
  gst_pad_set_chain_function(sink, drop_chain);
  GstPad *esink = gst_element_get_static_pad(e, "sink"),
         *esrc = gst_element_get_static_pad(e, "src");
  gst_pad_link(src, esink);
  gst_pad_link(esrc, sink);
  gst_pad_set_active(src, TRUE);
  gst_pad_set_active(sink, TRUE);
  gst_element_set_state(e, GST_STATE_PLAYING);
  gst_pad_push_event(src, gst_event_new_stream_start("bench"));
  GstCaps *caps = gst_caps_from_string(caps_str);
  gst_pad_push_event(src, gst_event_new_caps(caps));
  gst_caps_unref(caps);
  GstSegment seg;
  gst_segment_init(&seg, GST_FORMAT_TIME);
  gst_pad_push_event(src, gst_event_new_segment(&seg));
  GstBuffer *buf = gst_buffer_new_allocate(nullptr, bytes, nullptr);
  gst_buffer_memset(buf, 0, 1, bytes);
  for (auto _ : state) {
    if (gst_pad_push(src, gst_buffer_ref(buf)) != GST_FLOW_OK) {
      state.SkipWithError("push failed");
      break;
    }
  }
  gst_buffer_unref(buf);
  gst_element_set_state(e, GST_STATE_NULL);
  gst_pad_set_active(src, FALSE);
  gst_pad_set_active(sink, FALSE);
  gst_object_unref(esink);
  gst_object_unref(esrc);
  gst_object_unref(src);
  gst_object_unref(sink);
  gst_object_unref(e);
  state.SetItemsProcessed(state.iterations());
}

constexpr const char *kTinyCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=4:1:1:1,types=uint8,framerate=0/1";

BENCHMARK_CAPTURE(run_element_bench, identity_baseline, "identity", kTinyCaps, 4);
BENCHMARK_CAPTURE(run_element_bench, transform_arith_tiny,
                  "tensor_transform mode=arithmetic option=typecast:float32,add:-127.5,div:127.5",
                  kTinyCaps, 4);
BENCHMARK_CAPTURE(run_element_bench, transform_typecast_tiny,
                  "tensor_transform mode=typecast option=int16", kTinyCaps, 4);
BENCHMARK_CAPTURE(run_element_bench, transform_identity_plan_tiny,
                  "tensor_transform mode=dimchg option=1:2", kTinyCaps, 4);

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  if (!nns_register_static()) return 1;
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}

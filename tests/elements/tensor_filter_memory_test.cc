// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter memory handling: back ends that allocate their outputs, frames of more than 16
// tensors, flexible output, output-combination across formats, thread-safe shared instances.
#include <atomic>
#include <thread>

#include "core/filter_registry.h"
#include "core/meta_header.h"
#include "elements/filter_test_util.h"
#include "gst/tensor_buffer.h"
#include "nns_filter_backend.hh"

using namespace nns::test;

namespace {

// "nnsalloc": ALLOCATE_IN_INVOKE + THREAD_SAFE back end; output = input + 1 in memory it
// allocates; counts allocations and releases. RUN_WITHOUT_MODEL.
std::atomic<int> g_alloc{0}, g_frees{0}, g_concurrent{0}, g_max_concurrent{0};

class AllocBackend : public nns::FilterBackend {
 public:
  explicit AllocBackend(const nns_filter_props &) {}
  bool set_input_info(const nns_tensors_desc &in, nns_tensors_desc &out) override {
    out = in;
    return true;
  }
  void invoke(const GstTensorMemory *in, uint32_t n_in, GstTensorMemory *out,
              uint32_t n_out) override {
    int now = ++g_concurrent;
    int prev = g_max_concurrent.load();
    while (now > prev && !g_max_concurrent.compare_exchange_weak(prev, now)) {
    }
    std::this_thread::sleep_for(std::chrono::microseconds(200));
    for (uint32_t i = 0; i < n_in && i < n_out; ++i) {
      auto *p = static_cast<uint8_t *>(malloc(in[i].size));
      for (size_t k = 0; k < in[i].size; ++k)
        p[k] = static_cast<uint8_t>(static_cast<const uint8_t *>(in[i].data)[k] + 1);
      out[i].data = p;
      out[i].size = in[i].size;
      g_alloc++;
    }
    --g_concurrent;
  }
  void free_output(void *data) override {
    g_frees++;
    free(data);
  }
};

const nns_filter_backend_i *alloc_table() {
  static const nns_filter_backend_i t = nns::FilterBackendAdapter<AllocBackend>::make(
      "nnsalloc",
      NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE | NNS_FILTER_FLAG_THREAD_SAFE |
          NNS_FILTER_FLAG_RUN_WITHOUT_MODEL,
      nullptr);
  return &t;
}

struct Register {
  Register() { nns::FilterRegistry::get().add_builtin(alloc_table()); }
} g_register;

int easy_add1(void *, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
              GstTensorMemory *out) {
  for (unsigned t = 0; t < prop->input_meta.num_tensors; ++t)
    for (size_t k = 0; k < in[t].size; ++k)
      static_cast<uint8_t *>(out[t].data)[k] =
          static_cast<uint8_t>(static_cast<const uint8_t *>(in[t].data)[k] + 1);
  return 0;
}

}  // namespace

TEST(TensorFilterMemory, AllocateInInvokeOutputIsWrappedAndReleased) {
  int a0 = g_alloc, f0 = g_frees;
  {
    FilterHarness fh("tensor_filter framework=nnsalloc model=x", tensors_caps("uint8", "4"));
    ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{1, 2, 3, 4}})), GST_FLOW_OK)
        << fh.error_text();
    GstBuffer *out = gst_harness_pull(fh.h.get());
    ASSERT_NE(out, nullptr);
    EXPECT_EQ(memory_bytes(out, 0), (std::vector<uint8_t>{2, 3, 4, 5}));
    EXPECT_EQ(g_alloc - a0, 1);
    EXPECT_EQ(g_frees - f0, 0) << "released while the buffer is alive";
    gst_buffer_unref(out);
    EXPECT_EQ(g_frees - f0, 1);
  }
}

TEST(TensorFilterMemory, AllocateInInvokeOutputOutlivesTheFilter) {
  int f0 = g_frees;
  GstBuffer *out = nullptr;
  {
    FilterHarness fh("tensor_filter framework=nnsalloc model=x", tensors_caps("uint8", "4"));
    ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{1, 1, 1, 1}})), GST_FLOW_OK);
    out = gst_harness_pull(fh.h.get());
  }
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(memory_bytes(out, 0), (std::vector<uint8_t>{2, 2, 2, 2}));
  EXPECT_EQ(g_frees - f0, 0);
  gst_buffer_unref(out);
  EXPECT_EQ(g_frees - f0, 1);
}

TEST(TensorFilterMemory, FlexibleOutputWhenDownstreamAsks) {
  FilterHarness fh("tensor_filter framework=nnsalloc model=x", tensors_caps("uint8", "3"));
  gst_harness_set_sink_caps_str(fh.h.get(), "other/tensors,format=flexible");
  ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{1, 2, 3}})), GST_FLOW_OK)
      << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  auto bytes = memory_bytes(out, 0);
  ASSERT_EQ(bytes.size(), nns::kMetaHeaderSize + 3);
  nns::MetaHeader h = nns::parse_meta_header(bytes.data(), bytes.size());
  EXPECT_EQ(h.type, nns::TensorType::kUInt8);
  EXPECT_EQ(h.dims[0], 3u);
  EXPECT_EQ(bytes[nns::kMetaHeaderSize + 2], 4);
  gst_buffer_unref(out);
}

TEST(TensorFilterMemory, OutputCombinationStaticInputToFlexibleOutput) {
  GstTensorsInfo i = gst_info(_NNS_UINT8, {2});
  ASSERT_EQ(NNS_custom_easy_register("tf_mem_add", easy_add1, nullptr, &i, &i), 0);
  {
    FilterHarness fh(
        "tensor_filter framework=custom-easy model=tf_mem_add "
        "output-combination=i0,o0",
        tensors_caps("uint8", "2"));
    gst_harness_set_sink_caps_str(fh.h.get(), "other/tensors,format=flexible");
    ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{5, 6}})), GST_FLOW_OK)
        << fh.error_text();
    GstBuffer *out = gst_harness_pull(fh.h.get());
    ASSERT_NE(out, nullptr);
    ASSERT_EQ(gst_buffer_n_memory(out), 2u);
    auto in_passed = memory_bytes(out, 0), result = memory_bytes(out, 1);
    ASSERT_EQ(in_passed.size(), nns::kMetaHeaderSize + 2);
    ASSERT_EQ(result.size(), nns::kMetaHeaderSize + 2);
    EXPECT_EQ(in_passed[nns::kMetaHeaderSize], 5);
    EXPECT_EQ(result[nns::kMetaHeaderSize], 6);
    gst_buffer_unref(out);
  }
  EXPECT_EQ(NNS_custom_easy_unregister("tf_mem_add"), 0);
}

TEST(TensorFilterMemory, MoreThanSixteenTensors) {
  constexpr unsigned kN = 20;
  GstTensorsInfo info{};
  info.num_tensors = kN;
  info.extra =
      static_cast<GstTensorInfo *>(calloc(NNS_TENSOR_SIZE_EXTRA_LIMIT, sizeof(GstTensorInfo)));
  for (unsigned t = 0; t < kN; ++t) {
    GstTensorInfo *ti = t < NNS_TENSOR_MEMORY_MAX ? &info.info[t] : &info.extra[t - 16];
    ti->type = _NNS_UINT8;
    ti->dimension[0] = 2;
  }
  ASSERT_EQ(NNS_custom_easy_register("tf_mem_20", easy_add1, nullptr, &info, &info), 0);
  free(info.extra);
  std::string types, dims;
  for (unsigned t = 0; t < kN; ++t) {
    types += (t ? "," : "") + std::string("uint8");
    dims += (t ? "," : "") + std::string("2");
  }
  {
    FilterHarness fh("tensor_filter framework=custom-easy model=tf_mem_20",
                     tensors_caps(types, dims, kN));
    GstBuffer *in = gst_buffer_new();
    for (unsigned t = 0; t < kN; ++t) {
      GstMemory *m = gst_allocator_alloc(nullptr, 2, nullptr);
      GstMapInfo map;
      gst_memory_map(m, &map, GST_MAP_WRITE);
      map.data[0] = static_cast<uint8_t>(t);
      map.data[1] = static_cast<uint8_t>(100 + t);
      gst_memory_unmap(m, &map);
      nns::gst::buffer_append_tensor(
          in, m, nns::TensorInfo{"", nns::TensorType::kUInt8, nns::make_dims({2})});
    }
    ASSERT_EQ(gst_harness_push(fh.h.get(), in), GST_FLOW_OK) << fh.error_text();
    GstBuffer *out = gst_harness_pull(fh.h.get());
    ASSERT_NE(out, nullptr);
    EXPECT_EQ(nns::gst::buffer_tensor_count(out), kN);
    GstMemory *m18 = nns::gst::buffer_get_tensor(out, 18);
    ASSERT_NE(m18, nullptr);
    GstMapInfo map;
    ASSERT_TRUE(gst_memory_map(m18, &map, GST_MAP_READ));
    EXPECT_EQ(map.data[0], 19);
    EXPECT_EQ(map.data[1], 119);
    gst_memory_unmap(m18, &map);
    gst_memory_unref(m18);
    gst_buffer_unref(out);
  }
  EXPECT_EQ(NNS_custom_easy_unregister("tf_mem_20"), 0);
}

TEST(TensorFilterMemory, ThreadSafeSharedInstanceRunsConcurrently) {
  g_max_concurrent = 0;
  auto r = run_pipeline(
      fake_source(4, tensors_caps("uint8", "4"), 40) +
      "tee name=t ! queue ! tensor_filter framework=nnsalloc shared-tensor-filter-key=ts "
      "model=x ! fakesink t. ! queue ! tensor_filter framework=nnsalloc "
      "shared-tensor-filter-key=ts model=x ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
  // Not guaranteed to overlap on a loaded machine; never more than the two filters.
  EXPECT_LE(g_max_concurrent.load(), 2);
  EXPECT_GE(g_max_concurrent.load(), 1);
}

TEST(TensorFilterMemory, QosThrottleDropsFramesAndTellsUpstream) {
  FilterHarness fh("tensor_filter framework=nnsalloc model=x", tensors_caps("uint8", "4"));
  // Downstream (e.g. tensor_rate throttle=true) wants at most one frame per 100 ms.
  ASSERT_TRUE(gst_harness_push_upstream_event(
      fh.h.get(), gst_event_new_qos(GST_QOS_TYPE_THROTTLE, 1.0, 100 * GST_MSECOND, 0)));
  for (int k = 0; k < 11; ++k) {
    GstBuffer *b = tensor_buffer({{1, 2, 3, 4}});
    GST_BUFFER_PTS(b) = k * 20 * GST_MSECOND;
    GST_BUFFER_DURATION(b) = 20 * GST_MSECOND;
    ASSERT_EQ(gst_harness_push(fh.h.get(), b), GST_FLOW_OK) << fh.error_text();
  }
  guint got = gst_harness_buffers_received(fh.h.get());
  EXPECT_GE(got, 2u);
  EXPECT_LE(got, 4u);
  EXPECT_GT(gst_harness_upstream_events_received(fh.h.get()), 0u);
  gint latency = -1;
  g_object_get(fh.element(), "latency", &latency, nullptr);
  EXPECT_GE(latency, 0) << "throttling turns latency profiling on";
}

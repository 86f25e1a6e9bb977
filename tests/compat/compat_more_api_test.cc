// SPDX-License-Identifier: LGPL-2.1-only
// More of NNStreamer 2.7's libnnstreamer.so symbols (issue 19 item 3): nns_orc_* element-wise
// helpers, tensor_data.h, the watchdog, the sub-plugin table, tensor_common.h (pad format,
// aggregation adapters, buffer_from_config, config files) and the sparse helpers, with the
// values NNStreamer gives.
#include <gst/base/gstadapter.h>
#include <gtest/gtest.h>

#include <atomic>
#include <cmath>
#include <cstddef>
#include <cstdarg>
#include <cstdint>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "gsttensor_sparseutil.h"
#include "nnstreamer-orc.h"
#include "nnstreamer_plugin_api.h"
#include "nnstreamer_subplugin.h"
#include "nnstreamer_watchdog.h"
#include "support/harness.h"
#include "tensor_common.h"
#include "tensor_data.h"
#include "tensor_filter_single.h"

#define G_TENSOR_FILTER_SINGLE_GET_CLASS_COMPAT(o) \
  (G_TYPE_INSTANCE_GET_CLASS((o), G_TYPE_TENSOR_FILTER_SINGLE, GTensorFilterSingleClass))

namespace {

// ---- nns_orc_* ----------------------------------------------------------------------------

TEST(CompatOrc, AddAndMulSaturateIntegers) {
  int8_t s8[4] = {1, 100, -100, -128};
  nns_orc_add_c_s8(s8, 50, 4);
  EXPECT_EQ(std::vector<int>(s8, s8 + 4), (std::vector<int>{51, 127, -50, -78}));
  uint8_t u8[3] = {1, 200, 255};
  nns_orc_mul_c_u8(u8, 3, 3);
  EXPECT_EQ(std::vector<int>(u8, u8 + 3), (std::vector<int>{3, 255, 255}));
  nns_orc_add_c_u8(u8, 10, 3);
  EXPECT_EQ(std::vector<int>(u8, u8 + 3), (std::vector<int>{13, 255, 255}));
  int16_t s16[2] = {-20000, 300};
  nns_orc_mul_c_s16(s16, 2, 2);
  EXPECT_EQ(s16[0], -32768);
  EXPECT_EQ(s16[1], 600);
  uint32_t u32[2] = {4000000000u, 7};
  nns_orc_add_c_u32(u32, 500000000, 2);
  EXPECT_EQ(u32[0], 0xffffffffu);
  EXPECT_EQ(u32[1], 500000007u);
  int64_t s64[2] = {INT64_MAX, 5};
  nns_orc_add_c_s64(s64, 1, 2);  // 64-bit add wraps
  EXPECT_EQ(s64[0], INT64_MIN);
  EXPECT_EQ(s64[1], 6);
  int64_t m64[2] = {10000000000LL, -3};
  nns_orc_mul_c_s64(m64, 2, 2);  // the element is first saturated to 32 bits
  EXPECT_EQ(m64[0], 2LL * INT32_MAX);
  EXPECT_EQ(m64[1], -6);
  float f[2] = {1.5f, -3.f};
  nns_orc_mul_c_f32(f, 2.f, 2);
  nns_orc_add_c_f32(f, 1.f, 2);
  nns_orc_div_c_f32(f, 4.f, 2);
  EXPECT_FLOAT_EQ(f[0], 1.f);
  EXPECT_FLOAT_EQ(f[1], -1.25f);
  double d[1] = {9.0};
  nns_orc_div_c_f64(d, 2.0, 1);
  EXPECT_DOUBLE_EQ(d[0], 4.5);
}

TEST(CompatOrc, ConversionsFollowNNStreamersSteps) {
  // As NNStreamer's own test checks: f32 -> u8 equals (uint8_t)(int8_t) of the value.
  const float fs[5] = {-3.7f, 12.9f, 100.f, -128.f, 0.f};
  uint8_t u8[5];
  nns_orc_conv_f32_to_u8(u8, fs, 5);
  for (int i = 0; i < 5; ++i)
    EXPECT_EQ(u8[i], static_cast<uint8_t>(static_cast<int8_t>(fs[i]))) << fs[i];
  int8_t s8[3];
  const float big[3] = {1000.f, -1000.f, 5.9f};
  nns_orc_conv_f32_to_s8(s8, big, 3);  // saturated at 16 then 8 bits
  EXPECT_EQ(std::vector<int>(s8, s8 + 3), (std::vector<int>{127, -128, 5}));
  const int32_t s32[3] = {70000, -70000, 12};
  int16_t s16[3];
  nns_orc_conv_s32_to_s16(s16, s32, 3);
  EXPECT_EQ(std::vector<int>(s16, s16 + 3), (std::vector<int>{32767, -32768, 12}));
  uint8_t t8[3];
  nns_orc_conv_s32_to_u8(t8, s32, 3);  // truncated
  EXPECT_EQ(t8[0], static_cast<uint8_t>(70000));
  EXPECT_EQ(t8[2], 12);
  const int8_t n8[2] = {-1, 5};
  uint16_t u16[2];
  nns_orc_conv_s8_to_u16(u16, n8, 2);  // sign-extended
  EXPECT_EQ(u16[0], 0xffffu);
  EXPECT_EQ(u16[1], 5u);
  const float huge[2] = {3e9f, -3e9f};
  int32_t i32[2];
  nns_orc_conv_f32_to_s32(i32, huge, 2);
  EXPECT_EQ(i32[0], INT32_MAX);
  EXPECT_EQ(i32[1], INT32_MIN);
  const uint8_t in_u8[2] = {0, 255};
  double out_d[2];
  nns_orc_conv_u8_to_f64(out_d, in_u8, 2);
  EXPECT_DOUBLE_EQ(out_d[1], 255.0);
  const double dd[1] = {-2.5};
  float ff[1];
  nns_orc_conv_f64_to_f32(ff, dd, 1);
  EXPECT_FLOAT_EQ(ff[0], -2.5f);
}

// ---- tensor_data.h -------------------------------------------------------------------------

TEST(CompatTensorData, SetGetAndTypecastAsC) {
  tensor_data_s td;
  float f = -3.7f;
  ASSERT_TRUE(gst_tensor_data_set(&td, _NNS_FLOAT32, &f));
  EXPECT_EQ(td.type, _NNS_FLOAT32);
  ASSERT_TRUE(gst_tensor_data_typecast(&td, _NNS_UINT8));  // via int8: -3 -> 253
  uint8_t u = 0;
  ASSERT_TRUE(gst_tensor_data_get(&td, &u));
  EXPECT_EQ(u, 253);
  int32_t i = 300;
  uint8_t o = 0;
  ASSERT_TRUE(gst_tensor_data_raw_typecast(&i, _NNS_INT32, &o, _NNS_UINT8));
  EXPECT_EQ(o, 44);
  double d = 0;
  int16_t neg = -7;
  ASSERT_TRUE(gst_tensor_data_raw_typecast(&neg, _NNS_INT16, &d, _NNS_FLOAT64));
  EXPECT_DOUBLE_EQ(d, -7.0);
  uint64_t big = 0;
  ASSERT_TRUE(gst_tensor_data_raw_typecast(&neg, _NNS_INT16, &big, _NNS_UINT64));
  EXPECT_EQ(big, static_cast<uint64_t>(-7));
  EXPECT_FALSE(gst_tensor_data_set(&td, _NNS_END, &i));
  EXPECT_FALSE(gst_tensor_data_set(nullptr, _NNS_INT32, &i));
}

TEST(CompatTensorData, AveragesAndStandardDeviations) {
  uint8_t raw[4] = {1, 10, 3, 30};
  gdouble *avg = nullptr, *per = nullptr, *sd = nullptr, *sdper = nullptr;
  ASSERT_TRUE(gst_tensor_data_raw_average(raw, 4, _NNS_UINT8, &avg));
  EXPECT_DOUBLE_EQ(*avg, 11.0);
  tensor_dim dim = {2, 2, 1, 1};
  ASSERT_TRUE(gst_tensor_data_raw_average_per_channel(raw, 4, _NNS_UINT8, dim, &per));
  EXPECT_DOUBLE_EQ(per[0], 2.0);
  EXPECT_DOUBLE_EQ(per[1], 20.0);
  ASSERT_TRUE(gst_tensor_data_raw_std(raw, 4, _NNS_UINT8, avg, &sd));
  // sqrt(((1-11)^2 + (10-11)^2 + (3-11)^2 + (30-11)^2) / 4)
  EXPECT_NEAR(*sd, std::sqrt((100.0 + 1 + 64 + 361) / 4), 1e-12);
  ASSERT_TRUE(gst_tensor_data_raw_std_per_channel(raw, 4, _NNS_UINT8, dim, per, &sdper));
  EXPECT_DOUBLE_EQ(sdper[0], 1.0);
  EXPECT_DOUBLE_EQ(sdper[1], 10.0);
  uint8_t flat[2] = {5, 5};
  gdouble five = 5.0, *zero = nullptr;
  ASSERT_TRUE(gst_tensor_data_raw_std(flat, 2, _NNS_UINT8, &five, &zero));
  EXPECT_DOUBLE_EQ(*zero, 1e-10);  // NNStreamer's floor
  g_free(avg);
  g_free(per);
  g_free(sd);
  g_free(sdper);
  g_free(zero);
}

// ---- watchdog ------------------------------------------------------------------------------

TEST(CompatWatchdog, FeedRunsOnceAndReleaseCancels) {
  nns_watchdog_h w = nullptr;
  ASSERT_TRUE(nnstreamer_watchdog_create(&w));
  ASSERT_NE(w, nullptr);
  static std::atomic<int> calls{0};
  calls = 0;
  auto cb = [](gpointer) -> gboolean {
    ++calls;
    return G_SOURCE_REMOVE;
  };
  ASSERT_TRUE(nnstreamer_watchdog_feed(w, cb, 10, nullptr));
  for (int i = 0; i < 500 && calls == 0; ++i) g_usleep(2000);
  EXPECT_EQ(calls, 1);
  ASSERT_TRUE(nnstreamer_watchdog_feed(w, cb, 200, nullptr));
  nnstreamer_watchdog_release(w);
  g_usleep(300000);
  EXPECT_EQ(calls, 1) << "a released callback must not run";
  EXPECT_FALSE(nnstreamer_watchdog_feed(nullptr, cb, 1, nullptr));
  EXPECT_FALSE(nnstreamer_watchdog_create(nullptr));
  nnstreamer_watchdog_destroy(w);
}

// ---- sub-plugin table ----------------------------------------------------------------------

void set_desc(subpluginType t, const char *name, const char *prop, ...) {
  va_list ap;
  va_start(ap, prop);
  subplugin_set_custom_property_desc(t, name, prop, ap);
  va_end(ap);
}

TEST(CompatSubplugin, RegisterFindListAndDescribe) {
  static int payload;
  EXPECT_TRUE(register_subplugin(NNS_IF_CUSTOM, "cmp_if", &payload));
  EXPECT_FALSE(register_subplugin(NNS_IF_CUSTOM, "cmp_if", &payload)) << "name taken";
  EXPECT_FALSE(register_subplugin(NNS_IF_CUSTOM, "Auto", &payload)) << "reserved";
  EXPECT_FALSE(register_subplugin(NNS_SUBPLUGIN_END, "x", &payload));
  EXPECT_EQ(get_subplugin(NNS_IF_CUSTOM, "cmp_if"), &payload);
  gchar **all = get_all_subplugins(NNS_IF_CUSTOM);
  ASSERT_NE(all, nullptr);
  EXPECT_TRUE(g_strv_contains(all, "cmp_if"));
  g_strfreev(all);
  set_desc(NNS_IF_CUSTOM, "cmp_if", "alpha", "the first", "beta", "the second", nullptr);
  GData *dl = subplugin_get_custom_property_desc(NNS_IF_CUSTOM, "cmp_if");
  ASSERT_NE(dl, nullptr);
  EXPECT_STREQ(static_cast<const char *>(g_datalist_get_data(&dl, "beta")), "the second");
  EXPECT_TRUE(unregister_subplugin(NNS_IF_CUSTOM, "cmp_if"));
  EXPECT_EQ(get_subplugin(NNS_IF_CUSTOM, "cmp_if"), nullptr);
  EXPECT_FALSE(unregister_subplugin(NNS_IF_CUSTOM, "cmp_if"));
  // Filters are our registry's: a built-in back end is found as a version-1 table.
  const void *f = get_subplugin(NNS_SUBPLUGIN_FILTER, "custom-easy");
  ASSERT_NE(f, nullptr);
  gchar **filters = get_all_subplugins(NNS_SUBPLUGIN_FILTER);
  EXPECT_TRUE(g_strv_contains(filters, "custom-easy"));
  g_strfreev(filters);
}

// ---- tensor_common.h -----------------------------------------------------------------------

TEST(CompatCommon, PadFormatFromCurrentCaps) {
  GstPad *bare = GST_PAD(gst_object_ref_sink(gst_pad_new("src", GST_PAD_SRC)));
  EXPECT_EQ(gst_tensor_pad_get_format(bare), _NNS_TENSOR_FORMAT_END) << "no caps yet";
  gst_object_unref(bare);
  // Caps reach the pad through a harness (a caps event pushed on an unlinked pad is kept by
  // GStreamer 1.22 past the pad's end, which LeakSanitizer reports).
  nns::test::HarnessPtr h(gst_harness_new("identity"));
  gst_harness_set_src_caps_str(h.get(), "other/tensors,format=flexible,framerate=0/1");
  GstPad *pad = gst_element_get_static_pad(h->element, "src");
  EXPECT_EQ(gst_tensor_pad_get_format(pad), _NNS_TENSOR_FORMAT_FLEXIBLE);
  EXPECT_TRUE(gst_tensor_pad_caps_is_flexible(pad));
  EXPECT_FALSE(gst_tensor_pad_caps_is_static(pad));
  gst_object_unref(pad);
}

TEST(CompatCommon, AggregationAdaptersPerClient) {
  GHashTable *t = gst_tensor_aggregation_init();
  GstAdapter *def = gst_tensor_aggregation_get_adapter(t, 0);
  ASSERT_NE(def, nullptr);
  EXPECT_EQ(g_hash_table_size(t), 1u) << "the default adapter exists from the start";
  GstAdapter *five = gst_tensor_aggregation_get_adapter(t, 5);
  EXPECT_NE(five, def);
  EXPECT_EQ(gst_tensor_aggregation_get_adapter(t, 5), five);
  gst_adapter_push(five, gst_buffer_new_allocate(nullptr, 8, nullptr));
  gst_adapter_push(def, gst_buffer_new_allocate(nullptr, 4, nullptr));
  gst_tensor_aggregation_clear(t, 5);
  EXPECT_EQ(gst_adapter_available(five), 0u);
  EXPECT_EQ(gst_adapter_available(def), 4u);
  gst_tensor_aggregation_clear_all(t);
  EXPECT_EQ(gst_adapter_available(def), 0u);
  g_hash_table_destroy(t);
}

GstTensorsConfig static_config() {
  GstTensorsConfig c;
  gst_tensors_config_init(&c);
  c.info.num_tensors = 2;
  c.info.info[0].type = _NNS_UINT8;
  gst_tensor_parse_dimension("4:1", c.info.info[0].dimension);
  c.info.info[1].type = _NNS_UINT8;
  gst_tensor_parse_dimension("2:1", c.info.info[1].dimension);
  c.rate_n = 0;
  c.rate_d = 1;
  return c;
}

TEST(CompatCommon, BufferFromConfigSplitsStaticAndFlexible) {
  GstTensorsConfig c = static_config();
  const guint8 bytes[6] = {1, 2, 3, 4, 5, 6};
  GstBuffer *in = gst_buffer_new_memdup(bytes, 6);
  GST_BUFFER_PTS(in) = 42;
  GstBuffer *out = gst_tensor_buffer_from_config(in, &c);
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(gst_buffer_n_memory(out), 2u);
  EXPECT_EQ(gst_memory_get_sizes(gst_buffer_peek_memory(out, 0), nullptr, nullptr), 4u);
  EXPECT_EQ(gst_memory_get_sizes(gst_buffer_peek_memory(out, 1), nullptr, nullptr), 2u);
  EXPECT_EQ(GST_BUFFER_PTS(out), 42u);
  // Already split: the same buffer back.
  GstBuffer *again = gst_tensor_buffer_from_config(gst_buffer_ref(out), &c);
  EXPECT_EQ(again, out);
  gst_buffer_unref(again);
  gst_buffer_unref(out);
  // Too small for the config.
  EXPECT_EQ(gst_tensor_buffer_from_config(gst_buffer_new_memdup(bytes, 5), &c), nullptr);

  // Flexible: each tensor behind its 128-byte header, all in one memory.
  GstTensorMetaInfo m;
  gst_tensor_meta_info_init(&m);
  m.type = _NNS_UINT8;
  m.dimension[0] = 3;
  m.dimension[1] = 1;
  m.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
  std::vector<guint8> flex(2 * (128 + 3));
  ASSERT_TRUE(gst_tensor_meta_info_update_header(&m, flex.data()));
  ASSERT_TRUE(gst_tensor_meta_info_update_header(&m, flex.data() + 131));
  c.info.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
  GstBuffer *fout =
      gst_tensor_buffer_from_config(gst_buffer_new_memdup(flex.data(), flex.size()), &c);
  ASSERT_NE(fout, nullptr);
  EXPECT_EQ(gst_buffer_n_memory(fout), 2u);
  gst_buffer_unref(fout);
  // A header claiming more data than there is.
  m.dimension[0] = 1000;
  ASSERT_TRUE(gst_tensor_meta_info_update_header(&m, flex.data() + 131));
  EXPECT_EQ(gst_tensor_buffer_from_config(gst_buffer_new_memdup(flex.data(), flex.size()), &c),
            nullptr);
  gst_tensors_config_free(&c);
}

TEST(CompatCommon, ParseConfigFileSetsKnownProperties) {
  std::string path = nns::test::make_temp_dir() + "/fakesrc.conf";
  std::ofstream(path) << "num-buffers = 7\n  is-live=true\nno-such-property=3\njunk line\n";
  GstElement *src = gst_element_factory_make("fakesrc", nullptr);
  ASSERT_NE(src, nullptr);
  gst_tensor_parse_config_file(path.c_str(), G_OBJECT(src));
  gint n = 0;
  gboolean live = FALSE;
  g_object_get(src, "num-buffers", &n, "is-live", &live, nullptr);
  EXPECT_EQ(n, 7);
  EXPECT_TRUE(live);
  gst_tensor_parse_config_file("/nonexistent/x.conf", G_OBJECT(src));  // ignored
  gst_object_unref(src);
}

// ---- sparse --------------------------------------------------------------------------------

TEST(CompatSparse, DenseToSparseAndBack) {
  const float dense[4] = {0.f, 1.5f, 0.f, -2.f};
  GstMemory *mem = gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, const_cast<float *>(dense),
                                          sizeof dense, 0, sizeof dense, nullptr, nullptr);
  GstTensorMetaInfo meta;
  gst_tensor_meta_info_init(&meta);
  meta.type = _NNS_FLOAT32;
  meta.dimension[0] = 4;
  meta.dimension[1] = 1;
  meta.format = _NNS_TENSOR_FORMAT_STATIC;
  GstMemory *sparse = gst_tensor_sparse_from_dense(&meta, mem);
  ASSERT_NE(sparse, nullptr);
  EXPECT_EQ(meta.format, _NNS_TENSOR_FORMAT_SPARSE);
  EXPECT_EQ(meta.sparse_info.nnz, 2u);
  EXPECT_EQ(gst_memory_get_sizes(sparse, nullptr, nullptr), 128u + 2 * 4 + 2 * 4);
  GstTensorMetaInfo back;
  GstMemory *restored = gst_tensor_sparse_to_dense(&back, sparse);
  ASSERT_NE(restored, nullptr);
  EXPECT_EQ(back.format, _NNS_TENSOR_FORMAT_STATIC);
  GstMapInfo map;
  ASSERT_TRUE(gst_memory_map(restored, &map, GST_MAP_READ));
  ASSERT_EQ(map.size, sizeof dense);
  EXPECT_EQ(std::memcmp(map.data, dense, sizeof dense), 0);
  gst_memory_unmap(restored, &map);
  // A memory cut short is refused, not read past its end.
  GstMemory *cut = gst_memory_share(sparse, 0, 128 + 4);
  GstTensorMetaInfo m2;
  EXPECT_EQ(gst_tensor_sparse_to_dense(&m2, cut), nullptr);
  gst_memory_unref(cut);
  gst_memory_unref(restored);
  gst_memory_unref(sparse);
  gst_memory_unref(mem);
}

// ---- tensor_filter_single ------------------------------------------------------------------

namespace single {

// NNStreamer's class layout: GObjectClass, then the nine functions in this order.
static_assert(offsetof(GTensorFilterSingleClass, invoke) == sizeof(GObjectClass));
static_assert(offsetof(GTensorFilterSingleClass, set_invoke_async_callback) ==
              sizeof(GObjectClass) + 8 * sizeof(void *));
static_assert(sizeof(GTensorFilterSingle) == sizeof(GObject) + sizeof(void *));

std::string prop(GObject *o, const char *name) {
  gchar *v = nullptr;
  g_object_get(o, name, &v, nullptr);
  std::string r = v ? v : "";
  g_free(v);
  return r;
}

TEST(CompatFilterSingle, ModelInfoInvokeAndStop) {
  GObject *o = G_OBJECT(g_object_new(G_TYPE_TENSOR_FILTER_SINGLE, nullptr));
  ASSERT_NE(o, nullptr);
  auto *klass = G_TENSOR_FILTER_SINGLE_GET_CLASS_COMPAT(o);
  std::string lib = std::string(NNS_TEST_FILTER_DIR) + "/libcustom_passthrough.so";
  g_object_set(o, "framework", "custom", "model", lib.c_str(), nullptr);
  auto *self = G_TENSOR_FILTER_SINGLE(o);
  EXPECT_FALSE(klass->input_configured(self));
  ASSERT_TRUE(klass->start(self));
  EXPECT_TRUE(klass->input_configured(self));
  EXPECT_TRUE(klass->output_configured(self));
  EXPECT_EQ(prop(o, "input"), "10:1:1:1");
  EXPECT_EQ(prop(o, "inputtype"), "float32");
  EXPECT_EQ(prop(o, "outputtype"), "float32");
  float in[10], out[10] = {};
  for (int i = 0; i < 10; ++i) in[i] = static_cast<float>(i) * 1.5f;
  GstTensorMemory im = {in, sizeof in}, om = {out, sizeof out};
  ASSERT_TRUE(klass->invoke(self, &im, &om, FALSE));
  EXPECT_EQ(std::memcmp(in, out, sizeof in), 0);
  // allocate=TRUE: the output memory comes from here.
  GstTensorMemory am = {nullptr, sizeof out};
  ASSERT_TRUE(klass->invoke(self, &im, &am, TRUE));
  ASSERT_NE(am.data, nullptr);
  EXPECT_EQ(std::memcmp(in, am.data, sizeof in), 0);
  if (klass->allocate_in_invoke(self))
    klass->destroy_notify(self, &am);
  else
    g_free(am.data);
  EXPECT_TRUE(klass->stop(self));
  g_object_unref(o);
}

TEST(CompatFilterSingle, SetInputInfoAndBadModel) {
  GObject *o = G_OBJECT(g_object_new(G_TYPE_TENSOR_FILTER_SINGLE, nullptr));
  auto *klass = G_TENSOR_FILTER_SINGLE_GET_CLASS_COMPAT(o);
  auto *self = G_TENSOR_FILTER_SINGLE(o);
  std::string lib = std::string(NNS_TEST_FILTER_DIR) + "/libcustom_scaler.so";
  g_object_set(o, "framework", "custom", "model", lib.c_str(), "custom", "2x2", nullptr);
  ASSERT_TRUE(klass->start(self));
  GstTensorsInfo in, out;
  gst_tensors_info_init(&in);
  in.num_tensors = 1;
  in.info[0].type = _NNS_UINT8;
  gst_tensor_parse_dimension("1:4:4:1", in.info[0].dimension);
  ASSERT_EQ(klass->set_input_info(self, &in, &out), 0);
  EXPECT_EQ(out.num_tensors, 1u);
  EXPECT_EQ(out.info[0].dimension[1], 2u);
  EXPECT_EQ(out.info[0].dimension[2], 2u);
  EXPECT_EQ(prop(o, "output"), "1:2:2:1");
  uint8_t x[16], y[4] = {};
  for (int i = 0; i < 16; ++i) x[i] = static_cast<uint8_t>(i * 10);
  GstTensorMemory im = {x, 16}, om = {y, 4};
  ASSERT_TRUE(klass->invoke(self, &im, &om, FALSE));
  EXPECT_EQ(std::vector<int>(y, y + 4), (std::vector<int>{0, 20, 80, 100}));
  gst_tensors_info_free(&in);
  gst_tensors_info_free(&out);
  g_object_unref(o);

  GObject *bad = G_OBJECT(g_object_new(G_TYPE_TENSOR_FILTER_SINGLE, "framework", "custom", "model",
                                       "/nonexistent/libx.so", nullptr));
  auto *bk = G_TENSOR_FILTER_SINGLE_GET_CLASS_COMPAT(bad);
  EXPECT_FALSE(bk->start(G_TENSOR_FILTER_SINGLE(bad)));
  GstTensorMemory none = {nullptr, 0};
  EXPECT_FALSE(bk->invoke(G_TENSOR_FILTER_SINGLE(bad), &none, &none, FALSE));
  g_object_unref(bad);
}

// One property table for both (src/gst/filter_properties.h): the single has every property of
// tensor_filter's with its type, flags (but GStreamer's mutable-in-PLAYING), blurb and default,
// and reads back what was set.
TEST(CompatFilterSingle, PropertiesAreTensorFilters) {
  GstElement *f = gst_element_factory_make("tensor_filter", nullptr);
  ASSERT_NE(f, nullptr);
  auto *sk = static_cast<GObjectClass *>(g_type_class_ref(G_TYPE_TENSOR_FILTER_SINGLE));
  guint n = 0;
  GParamSpec **ps = g_object_class_list_properties(sk, &n);
  EXPECT_EQ(n, 27u);
  for (guint i = 0; i < n; ++i) {
    SCOPED_TRACE(ps[i]->name);
    GParamSpec *e = g_object_class_find_property(G_OBJECT_GET_CLASS(f), ps[i]->name);
    ASSERT_NE(e, nullptr);
    EXPECT_EQ(e->value_type, ps[i]->value_type);
    EXPECT_EQ(e->flags & ~GST_PARAM_MUTABLE_PLAYING, ps[i]->flags);
    EXPECT_STREQ(g_param_spec_get_blurb(e), g_param_spec_get_blurb(ps[i]));
    EXPECT_EQ(g_param_values_cmp(e, g_param_spec_get_default_value(e),
                                 g_param_spec_get_default_value(ps[i])),
              0);
  }
  g_free(ps);
  g_type_class_unref(sk);
  gst_object_unref(f);

  GObject *o =
      G_OBJECT(g_object_new(G_TYPE_TENSOR_FILTER_SINGLE, "silent", FALSE, "latency", 1, "suspend",
                            250u, "invoke-dynamic", TRUE, "invoke-async", TRUE,
                            "shared-tensor-filter-key", "k1", "inputlayout", "NCHW", nullptr));
  gboolean silent = TRUE, dynamic = FALSE, async = FALSE;
  gint latency = 0;
  guint suspend = 0;
  g_object_get(o, "silent", &silent, "latency", &latency, "suspend", &suspend, "invoke-dynamic",
               &dynamic, "invoke-async", &async, nullptr);
  EXPECT_FALSE(silent);
  EXPECT_EQ(latency, 1);
  EXPECT_EQ(suspend, 250u);
  EXPECT_TRUE(dynamic);
  EXPECT_TRUE(async);
  EXPECT_EQ(prop(o, "shared-tensor-filter-key"), "k1");
  EXPECT_EQ(prop(o, "inputlayout"), "NCHW");
  EXPECT_EQ(prop(o, "framework"), "auto");
  EXPECT_NE(prop(o, "sub-plugins").find("custom"), std::string::npos);
  g_object_unref(o);
}

}  // namespace single

}  // namespace

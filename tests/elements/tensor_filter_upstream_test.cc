// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter behaviours NNStreamer's own unit tests check: framework=auto reads back the
// framework chosen for the model (tests/nnstreamer_plugins, frameworkAuto*), and custom-easy
// filters with flexible tensors (tests/nnstreamer_filter_custom): flexible in and out, static in
// and flexible out, and the invalid combinations refused.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <mutex>
#include <string>
#include <vector>

#include "core/meta_header.h"
#include "elements/filter_test_util.h"
#include "support/harness.h"
#include "tensor_filter_custom_easy.h"

namespace nns::test {
namespace {

std::string framework_of(GstElement *pipeline, const char *name = "tfilter") {
  GstElement *f = gst_bin_get_by_name(GST_BIN(pipeline), name);
  EXPECT_TRUE(f);
  if (!f) return "";
  gchar *s = nullptr;
  g_object_get(f, "framework", &s, nullptr);
  gst_object_unref(f);
  std::string out = s ? s : "<NULL>";
  g_free(s);
  return out;
}

GstElement *parse(const std::string &desc) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &err);
  EXPECT_EQ(err, nullptr) << (err ? err->message : "");
  if (err) g_error_free(err);
  return p;
}

// --- framework=auto ------------------------------------------------------------------------

TEST(TensorFilterUpstream, FrameworkAutoReadsBackTheChosenFramework) {
  const std::string so = filter_dir() + "/libcustom_passthrough.so";
  // Either order of the properties, any case of "auto", or no framework at all.
  for (const std::string &props : {"framework=auto model=" + so, "model=" + so + " framework=auto",
                                   "model=" + so + " framework=AutO", "model=" + so}) {
    SCOPED_TRACE(props);
    GstElement *p = parse(fake_source(40, tensors_caps("float32", "10")) +
                          "tensor_filter name=tfilter " + props + " ! fakesink");
    ASSERT_TRUE(p);
    // Before any state change, as upstream's TEST_TENSOR_FILTER_AUTO_OPTION_P reads it.
    EXPECT_EQ(framework_of(p), "custom");
    auto r = run_pipeline(p);
    EXPECT_TRUE(r.eos) << r.error_text;
    // Once the model was opened: the framework that opened it.
    EXPECT_EQ(framework_of(p), "custom");
    gst_object_unref(p);
  }
}

TEST(TensorFilterUpstream, FrameworkAutoWithoutAFrameworkForTheModelFails) {
  // An extension no framework reads, and a model that does not exist: "auto" stays and the
  // start fails (upstream's frameworkAuto*NotSupportedExt_n / ModelNotFound_n).
  const std::string unknown = write_temp("model.unknownext", "x");
  for (const std::string &model : {unknown, std::string("/nonexistent/mirage.so")}) {
    SCOPED_TRACE(model);
    GstElement *p =
        parse(fake_source(40, tensors_caps("float32", "10")) +
              "tensor_filter name=tfilter framework=auto model=" + model + " ! fakesink");
    ASSERT_TRUE(p);
    if (model == unknown) {
      EXPECT_EQ(framework_of(p), "auto");
    }
    auto r = run_pipeline(p);
    EXPECT_TRUE(r.error);
    gst_object_unref(p);
  }
  // A framework name that does not exist (framework=auta) also fails at start.
  auto r = run_pipeline(fake_source(40, tensors_caps("float32", "10")) +
                        "tensor_filter framework=auta model=" + filter_dir() +
                        "/libcustom_passthrough.so ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("'auta'"), std::string::npos) << r.error_text;
}

// --- custom-easy with flexible tensors ------------------------------------------------------

struct CbData {
  std::mutex mu;
  guint filter_received = 0;
  guint sink_received = 0;
  bool bad = false;
};

// Output: one uint32 flexible tensor of N elements 0..N-1 at the N-th call.
int dynamic_filter(void *data, const GstTensorsInfo *, GstTensorsInfo *out_info,
                   const GstTensorMemory *, GstTensorMemory *output) {
  auto *cb = static_cast<CbData *>(data);
  if (!cb) return -EINVAL;
  std::lock_guard lk(cb->mu);
  std::memset(out_info, 0, sizeof *out_info);
  const guint n = ++cb->filter_received;
  out_info->num_tensors = 1;
  out_info->info[0].type = _NNS_UINT32;
  out_info->info[0].dimension[0] = n;
  out_info->info[0].dimension[1] = 1;
  out_info->info[0].dimension[2] = 1;
  out_info->info[0].dimension[3] = 1;
  out_info->format = _NNS_TENSOR_FORMAT_FLEXIBLE;
  output[0].size = sizeof(guint) * n;
  output[0].data = g_malloc0(output[0].size);
  for (guint i = 0; i < n; ++i) static_cast<guint *>(output[0].data)[i] = i;
  return 0;
}

void on_new_data(GstElement *, GstBuffer *buffer, gpointer user_data) {
  auto *cb = static_cast<CbData *>(user_data);
  std::lock_guard lk(cb->mu);
  const guint n = ++cb->sink_received;
  if (gst_buffer_n_memory(buffer) != 1) {
    cb->bad = true;
    return;
  }
  GstMemory *mem = gst_buffer_peek_memory(buffer, 0);
  GstMapInfo map;
  if (!gst_memory_map(mem, &map, GST_MAP_READ)) {
    cb->bad = true;
    return;
  }
  bool ok = nns::has_meta_header(map.data, map.size);
  if (ok) {
    nns::MetaHeader meta = nns::parse_meta_header(map.data, map.size);
    ok = meta.format == nns::TensorFormat::kFlexible && meta.dims[0] == n &&
         meta.type == nns::TensorType::kUInt32;
  }
  const gsize header = nns::kMetaHeaderSize;
  ok = ok && map.size - header == sizeof(guint) * n;
  for (guint i = 0; ok && i < n; ++i)
    ok = reinterpret_cast<const guint *>(map.data + header)[i] == i;
  gst_memory_unmap(mem, &map);
  if (!ok) cb->bad = true;
}

// Three video streams of different sizes joined into one stream (as upstream's tests), each
// source as flexible tensors or static ones converted to flexible by the capsfilter after join.
std::string joined_sources(bool flexible_each) {
  std::string out;
  const char *sizes[] = {"width=24,height=24", "width=32,height=24", "width=64,height=48"};
  for (int i = 0; i < 3; ++i)
    out += std::string("videotestsrc num-buffers=3 ! video/x-raw,format=RGB,") + sizes[i] +
           ",framerate=10/1 ! tensor_converter ! " +
           (flexible_each ? "other/tensors,format=flexible ! " : "") + "j.sink_" +
           std::to_string(i) + " ";
  return out + "join name=j ! other/tensors,format=flexible ! ";
}

struct EasyRun {
  RunResult r;
  guint filtered = 0, received = 0;
  bool bad = false;
};

EasyRun run_easy(const std::string &pipeline, CbData &data) {
  GstElement *p = parse(pipeline);
  EasyRun out;
  if (!p) return out;
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sinkx");
  g_signal_connect(sink, "new-data", G_CALLBACK(on_new_data), &data);
  out.r = run_pipeline(p);
  gst_object_unref(sink);
  gst_object_unref(p);
  std::lock_guard lk(data.mu);
  out.filtered = data.filter_received;
  out.received = data.sink_received;
  out.bad = data.bad;
  return out;
}

GstTensorsInfo flexible_info() {
  GstTensorsInfo info;
  std::memset(&info, 0, sizeof info);
  info.num_tensors = 1;
  info.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
  return info;
}

class CustomEasyFlexible : public ::testing::Test {
 protected:
  void TearDown() override { NNS_custom_easy_unregister("flexible_filter"); }
  CbData data;
};

TEST_F(CustomEasyFlexible, FlexibleInFlexibleOut) {
  GstTensorsInfo in = flexible_info();
  ASSERT_EQ(NNS_custom_easy_dynamic_register("flexible_filter", dynamic_filter, &data, &in), 0);
  auto e = run_easy(joined_sources(true) +
                        "tensor_filter framework=custom-easy invoke-dynamic=TRUE "
                        "model=flexible_filter ! other/tensors,format=flexible ! "
                        "tensor_sink name=sinkx",
                    data);
  EXPECT_TRUE(e.r.eos) << e.r.error_text;
  EXPECT_GE(e.received, 6u);  // join forwards what arrives: at least 6 of the 9 frames
  EXPECT_EQ(e.received, e.filtered);
  EXPECT_FALSE(e.bad);
}

TEST_F(CustomEasyFlexible, StaticInFlexibleOut) {
  GstTensorsInfo in = flexible_info();
  ASSERT_EQ(NNS_custom_easy_dynamic_register("flexible_filter", dynamic_filter, &data, &in), 0);
  auto e = run_easy(joined_sources(false) +
                        "tensor_filter framework=custom-easy invoke-dynamic=TRUE "
                        "model=flexible_filter ! other/tensors,format=flexible ! "
                        "tensor_sink name=sinkx",
                    data);
  EXPECT_TRUE(e.r.eos) << e.r.error_text;
  EXPECT_GE(e.received, 6u);
  EXPECT_EQ(e.received, e.filtered);
  EXPECT_FALSE(e.bad);
}

TEST_F(CustomEasyFlexible, StaticStreamIntoAFlexibleFilter) {
  // One static stream (no join) into the dynamic filter: flexible out, one call per frame.
  GstTensorsInfo in = flexible_info();
  ASSERT_EQ(NNS_custom_easy_dynamic_register("flexible_filter", dynamic_filter, &data, &in), 0);
  auto e = run_easy(
      "videotestsrc num-buffers=4 ! video/x-raw,format=RGB,width=8,height=8,framerate=10/1 ! "
      "tensor_converter ! tensor_filter framework=custom-easy invoke-dynamic=TRUE "
      "model=flexible_filter ! tensor_sink name=sinkx",
      data);
  EXPECT_TRUE(e.r.eos) << e.r.error_text;
  EXPECT_EQ(e.received, 4u);
  EXPECT_FALSE(e.bad);
}

TEST_F(CustomEasyFlexible, InvokeDynamicFalseIsRefused) {
  GstTensorsInfo in = flexible_info();
  ASSERT_EQ(NNS_custom_easy_dynamic_register("flexible_filter", dynamic_filter, &data, &in), 0);
  auto e = run_easy(joined_sources(true) +
                        "tensor_filter framework=custom-easy invoke-dynamic=FALSE "
                        "model=flexible_filter ! other/tensors,format=flexible ! "
                        "tensor_sink name=sinkx",
                    data);
  EXPECT_TRUE(e.r.error);
  EXPECT_FALSE(e.r.error_text.empty());
  EXPECT_EQ(e.received, 0u);
}

int static_filter(void *data, const GstTensorFilterProperties *, const GstTensorMemory *,
                  GstTensorMemory *output) {
  auto *cb = static_cast<CbData *>(data);
  std::lock_guard lk(cb->mu);
  output[0].size = sizeof(guint) * ++cb->filter_received;
  output[0].data = g_malloc0(output[0].size);
  return 0;
}

TEST(TensorFilterUpstreamCustom, StaticFilterWithFlexibleInfoIsRefused) {
  CbData data;
  GstTensorsInfo in = flexible_info(), out = flexible_info();
  ASSERT_EQ(NNS_custom_easy_register("normal_filter", static_filter, &data, &in, &out), 0);
  GstElement *p = parse(joined_sources(true) +
                        "tensor_filter framework=custom-easy model=normal_filter ! "
                        "other/tensors,format=flexible ! tensor_sink name=sinkx");
  ASSERT_TRUE(p);
  auto r = run_pipeline(p);
  gst_object_unref(p);
  EXPECT_TRUE(r.error);
  EXPECT_EQ(data.filter_received, 0u);
  EXPECT_EQ(NNS_custom_easy_unregister("normal_filter"), 0);
}

TEST(TensorFilterUpstreamCustom, InvokeDynamicOnAStaticCustomLibraryIsRefused) {
  auto r = run_pipeline(
      "videotestsrc num-buffers=3 ! video/x-raw,width=16,height=12,format=RGB,framerate=10/1 ! "
      "tensor_converter ! tensor_filter framework=custom invoke-dynamic=TRUE model=" +
      filter_dir() + "/libcustom_passthrough.so ! tensor_sink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("does not support dynamic invoke"), std::string::npos)
      << r.error_text;
}

TEST(TensorFilterUpstreamCustom, DynamicRegisterInvalidParameters) {
  CbData data;
  GstTensorsInfo in = flexible_info();
  EXPECT_NE(NNS_custom_easy_dynamic_register(nullptr, dynamic_filter, &data, &in), 0);
  EXPECT_NE(NNS_custom_easy_dynamic_register("temp_name", nullptr, nullptr, &in), 0);
  EXPECT_NE(NNS_custom_easy_dynamic_register("temp_name", dynamic_filter, nullptr, nullptr), 0);
  // Nothing was registered under that name.
  EXPECT_NE(NNS_custom_easy_unregister("temp_name"), 0);
}

}  // namespace
}  // namespace nns::test

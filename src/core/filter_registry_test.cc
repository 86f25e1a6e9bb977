// SPDX-License-Identifier: LGPL-2.1-only
// Filter registry (framework resolution), descriptor conversions and the NNStreamer-compatible
// GstTensorFilterProperties layout.
#include "core/filter_registry.h"

#include <gtest/gtest.h>

#include <cstddef>
#include <cstring>
#include <map>
#include <vector>

#include "core/error.h"
#include "core/filter_compat_props.h"
#include "core/c_tensor_info.h"
#include "core/filter_desc.h"
#include "nnstreamer_plugin_api_filter.h"

namespace {

class FakeConf : public nns::FilterConf {
 public:
  std::vector<std::string> dirs;
  std::map<std::string, std::string> values;  // "group/key"
  std::vector<std::string> filter_dirs() const override { return dirs; }
  std::vector<std::string> framework_priority(const std::string &ext) const override {
    return nns::split(value("filter", "framework_priority_" + ext), ",");
  }
  std::string value(const std::string &g, const std::string &k) const override {
    auto it = values.find(g + "/" + k);
    return it == values.end() ? "" : it->second;
  }
};

using V = std::vector<std::string>;

}  // namespace

TEST(FilterRegistry, AutoCandidatesFollowTableAndPriority) {
  FakeConf c;
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"/m/model.onnx"}, c),
            (V{"onnxruntime", "opencv"}));
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"/m/model.PT"}, c), (V{"pytorch"}));
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"/m/f.so"}, c), (V{"custom"}));
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"/m/s.py"}, c), (V{"python3"}));
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"/m/x.tflite"}, c),
            (V{"tensorflow-lite", "tensorflow2-lite", "armnn"}));
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"/m.d/noext"}, c), V{});
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"a.pb", "b.pb"}, c), (V{"caffe2"}));
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"a.so", "b.nb"}, c), (V{"vivante"}));
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"/tmp"}, c), (V{"nnfw"}));
  c.values["filter/framework_priority_onnx"] = "opencv,onnxruntime";
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"m.onnx"}, c), (V{"opencv", "onnxruntime"}));
  c.values["filter/framework_priority_tflite"] = "nnfw,armnn";
  EXPECT_EQ(nns::FilterRegistry::auto_candidates({"x.tflite"}, c),
            (V{"nnfw", "armnn", "tensorflow-lite", "tensorflow2-lite"}));
}

TEST(FilterRegistry, NameCandidatesExpandAliases) {
  FakeConf c;
  EXPECT_EQ(nns::FilterRegistry::name_candidates("pytorch", c), (V{"pytorch"}));
  EXPECT_EQ(nns::FilterRegistry::name_candidates("tensorflow2-lite", c),
            (V{"tensorflow2-lite", "armnn"}));
  EXPECT_EQ(nns::FilterRegistry::name_candidates("tflite", c),
            (V{"tflite", "tensorflow2-lite", "armnn"}));
  c.values["tensorflow-lite/subplugin_priority"] = "nnfw, armnn";
  EXPECT_EQ(nns::FilterRegistry::name_candidates("tensorflow-lite", c),
            (V{"tensorflow-lite", "nnfw", "armnn", "tensorflow2-lite"}));
  c.values["filter-aliases/ort"] = "onnxruntime";
  EXPECT_EQ(nns::FilterRegistry::name_candidates("ort", c), (V{"ort", "onnxruntime"}));
}

TEST(FilterRegistry, BuiltinsAndMissingFramework) {
  FakeConf c;
  c.dirs = {"/nonexistent/a", "/nonexistent/b"};
  auto &r = nns::FilterRegistry::get();
  EXPECT_STREQ(r.resolve("custom-easy", {}, c).iface->name, "custom-easy");
  EXPECT_STREQ(r.resolve("auto", {"/x/libf.so"}, c).iface->name, "custom");
  EXPECT_STREQ(r.resolve("cpp", {"name"}, c).iface->name, "cpp");
  try {
    r.resolve("onnxruntime", {"m.onnx"}, c);
    FAIL() << "no error";
  } catch (const nns::Error &e) {
    EXPECT_EQ(e.kind(), nns::ErrorKind::kNotFound);
    EXPECT_STREQ(e.what(),
                 "framework 'onnxruntime' is not available: no libnnstreamer_filter_onnxruntime.so "
                 "in /nonexistent/a, /nonexistent/b");
  }
  EXPECT_THROW(r.resolve("auto", {}, c), nns::Error);
}

TEST(FilterRegistry, RejectsIncompleteTables) {
  nns_filter_backend_i t{};
  t.api_version = NNS_FILTER_BACKEND_API_VERSION;
  t.name = "broken";
  EXPECT_THROW(nns::FilterRegistry::get().add_builtin(&t), nns::Error);
  t.api_version = NNS_FILTER_BACKEND_API_VERSION + 1;
  try {
    nns::validate_backend_table(&t, "x.so");
    FAIL();
  } catch (const nns::Error &e) {
    EXPECT_NE(std::string(e.what()).find("API version 3"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("needs version 1 to 2"), std::string::npos) << e.what();
  }
  t.api_version = 0;
  EXPECT_THROW(nns::validate_backend_table(&t, "x.so"), nns::Error);
}

namespace {
int v1_open(const nns_filter_props *, void **, char *, size_t) {
  return 0;
}
void v1_close(void *) {}
int v1_invoke(void *, const GstTensorMemory *, uint32_t, GstTensorMemory *, uint32_t, char *,
              size_t) {
  return 0;
}
}  // namespace

// A version 1 table ends at check_accelerator: it still loads, and the host sees the fields
// added later as NULL instead of reading past the table.
TEST(FilterRegistry, AcceptsVersion1TablesAsFullOnes) {
  constexpr std::size_t kV1Size = offsetof(nns_filter_backend_i, invoke_async);
  // The table sits at the end of a block filled with 0xAB, as if other data followed it.
  std::vector<unsigned char> block(kV1Size + sizeof(nns_filter_backend_i), 0xAB);
  auto *v1 = reinterpret_cast<nns_filter_backend_i *>(block.data());
  std::memset(v1, 0, kV1Size);
  v1->api_version = 1;
  v1->name = "v1table";
  v1->open = v1_open;
  v1->close = v1_close;
  v1->invoke = v1_invoke;
  auto &r = nns::FilterRegistry::get();
  r.add_builtin(v1);
  FakeConf conf;
  nns::BackendRef ref = r.find("v1table", conf);
  ASSERT_TRUE(ref);
  EXPECT_NE(ref.iface, v1);  // a full copy
  EXPECT_EQ(ref.iface->api_version, 1u);
  EXPECT_EQ(ref.iface->invoke, &v1_invoke);
  EXPECT_EQ(ref.iface->invoke_async, nullptr);
  r.remove_builtin("v1table");
}

TEST(FilterDesc, RoundTripsThroughGstTensorsInfo) {
  nns::TensorsInfo info;
  for (int i = 0; i < 20; ++i)
    info.tensors.push_back(nns::TensorInfo{i == 3 ? "name3" : "", nns::TensorType::kFloat32,
                                           nns::make_dims({static_cast<uint32_t>(i + 1), 2})});
  auto d = nns::make_desc(info);
  GstTensorsInfo g;
  nns::gst_info_from_desc(*d, &g);
  EXPECT_EQ(g.num_tensors, 20u);
  ASSERT_NE(g.extra, nullptr);
  EXPECT_EQ(g.extra[2].dimension[0], 19u);
  EXPECT_STREQ(g.info[3].name, "name3");
  auto d2 = nns::new_desc();
  nns::desc_from_gst_info(&g, *d2);
  nns::gst_info_clear(&g);
  EXPECT_TRUE(nns::info_from_desc(*d2).same_as(info));
  EXPECT_EQ(nns::info_from_desc(*d2)[3].name, "name3");
  d2->tensors[0].type = 77;
  EXPECT_THROW(nns::info_from_desc(*d2), nns::Error);
}

// The layout custom filters compiled against NNStreamer's headers rely on (LP64).
static_assert(sizeof(void *) != 8 || offsetof(GstTensorFilterProperties, model_files) == 16);
static_assert(sizeof(void *) != 8 || offsetof(GstTensorFilterProperties, input_meta) == 32);
static_assert(sizeof(void *) != 8 || sizeof(GstTensorsInfo) == 1304);
static_assert(sizeof(void *) != 8 || offsetof(GstTensorFilterProperties, input_layout) == 1336);
static_assert(sizeof(void *) != 8 || offsetof(GstTensorFilterProperties, output_meta) == 3392);
static_assert(sizeof(void *) != 8 ||
              offsetof(GstTensorFilterProperties, custom_properties) == 6744);
static_assert(sizeof(void *) != 8 || offsetof(GstTensorFilterProperties, accl_str) == 6768);
static_assert(sizeof(void *) != 8 || offsetof(GstTensorFilterProperties, latency) == 6784);

TEST(FilterCompatProps, FilledFromBackendProps) {
  const char *files[] = {"/a.so", "/b.bin", nullptr};
  nns::TensorsInfo in;
  in.tensors.push_back(nns::TensorInfo{"x", nns::TensorType::kUInt8, nns::make_dims({3, 4})});
  auto din = nns::make_desc(in);
  auto dout = nns::new_desc();
  nns_filter_props p{};
  p.framework = "custom";
  p.model_files = files;
  p.num_models = 2;
  p.input = din.get();
  p.output = dout.get();
  p.custom = "k:v";
  nns::CompatProps c(p);
  const GstTensorFilterProperties *g = c.get();
  EXPECT_STREQ(g->fwname, "custom");
  EXPECT_EQ(g->num_models, 2);
  EXPECT_STREQ(g->model_files[1], "/b.bin");
  EXPECT_STREQ(g->custom_properties, "k:v");
  EXPECT_EQ(g->input_configured, 1);
  EXPECT_EQ(g->output_configured, 0);
  EXPECT_EQ(g->input_meta.info[0].dimension[1], 4u);
  EXPECT_EQ(g->input_ranks[0], 2u);
  EXPECT_EQ(g->input_layout[0], _NNS_LAYOUT_ANY);
}

// Version 2 fields follow the version 1 table directly (back ends built against version 1
// headers end there).
static_assert(offsetof(nns_filter_backend_i, invoke_async) ==
              offsetof(nns_filter_backend_i, check_accelerator) + sizeof(void *));
static_assert(offsetof(nns_filter_props, invoke_async) ==
              offsetof(nns_filter_props, num_threads) + sizeof(int));

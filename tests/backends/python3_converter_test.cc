// SPDX-License-Identifier: LGPL-2.1-only
// tensor_converter mode=custom-script:<file.py> (converter sub-plugin python3): exact tensors and
// caps from JSON and raw payloads, zero-copy of input views, and the bus errors for broken
// scripts and ill-formed results. Scripts: tests/data/python/convdec/.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "backends/python3_convdec_util.h"
#include "gst/converter_registry.h"
#include "support/harness.h"

namespace {

using nns::test::HarnessPtr;
using nns::test::run_pipeline;
using nns::test::convdec::bytes_buffer;
using nns::test::convdec::current_caps;
using nns::test::convdec::expect_error_parts;
using nns::test::convdec::script;

std::vector<uint8_t> memory_bytes(GstBuffer *b, guint i) {
  GstMemory *m = gst_buffer_peek_memory(b, i);
  GstMapInfo map;
  EXPECT_TRUE(gst_memory_map(m, &map, GST_MAP_READ));
  std::vector<uint8_t> v(map.data, map.data + map.size);
  gst_memory_unmap(m, &map);
  return v;
}

HarnessPtr converter(const std::string &file, const std::string &in_caps) {
  HarnessPtr h(
      gst_harness_new_parse(("tensor_converter mode=custom-script:" + script(file)).c_str()));
  gst_harness_set_src_caps_str(h.get(), in_caps.c_str());
  return h;
}

std::vector<uint8_t> int32_bytes(const std::vector<int32_t> &v) {
  std::vector<uint8_t> b(v.size() * 4);
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

TEST(Python3Converter, JsonToTwoTensors) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  auto h = converter("conv_json.py", "application/octet-stream");
  std::string doc = R"({"name": "cat", "values": [1, -2, 300000, 4]})";
  ASSERT_EQ(gst_harness_push(h.get(), bytes_buffer({doc.begin(), doc.end()})), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(gst_buffer_n_memory(out), 2u);
  EXPECT_EQ(memory_bytes(out, 0), (std::vector<uint8_t>{'c', 'a', 't', 0}));
  EXPECT_EQ(memory_bytes(out, 1), int32_bytes({1, -2, 300000, 4}));
  gst_buffer_unref(out);
  EXPECT_EQ(current_caps(h.get()),
            "other/tensors, format=(string)static, num_tensors=(int)2, "
            "dimensions=(string)\"4:1:1:1\\,4:1:1:1\", types=(string)\"uint8\\,int32\", "
            "framerate=(fraction)10/1");
}

// The script returns its input views: the output memory is a share of the input memory.
TEST(Python3Converter, InputViewsAreSharedNotCopied) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  auto h = converter("conv_view.py", "application/octet-stream,framerate=5/1");
  std::vector<uint8_t> in = int32_bytes({7, 8, 9});
  GstBuffer *b = bytes_buffer(in);
  GstMapInfo map;
  ASSERT_TRUE(gst_buffer_map(b, &map, GST_MAP_READ));
  const guint8 *in_data = map.data;
  gst_buffer_unmap(b, &map);
  GST_BUFFER_PTS(b) = 42 * GST_MSECOND;
  ASSERT_EQ(gst_harness_push(h.get(), b), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(out, nullptr);
  ASSERT_EQ(gst_buffer_n_memory(out), 1u);
  ASSERT_TRUE(gst_buffer_map(out, &map, GST_MAP_READ));
  EXPECT_EQ(map.data, in_data);  // same bytes, no copy
  EXPECT_EQ(std::vector<uint8_t>(map.data, map.data + map.size), in);
  gst_buffer_unmap(out, &map);
  EXPECT_EQ(GST_BUFFER_PTS(out), 42 * GST_MSECOND);
  gst_buffer_unref(out);
  EXPECT_EQ(current_caps(h.get()),
            "other/tensors, format=(string)static, num_tensors=(int)1, "
            "dimensions=(string)3:1:1:1, types=(string)int32, framerate=(fraction)5/1");
}

// One tensor per input memory; the same script converts buffers of other sizes (new caps).
TEST(Python3Converter, EveryMemoryIsOneInputArray) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  auto h = converter("conv_view.py", "application/octet-stream");
  GstBuffer *b = bytes_buffer(int32_bytes({1, 2}));
  GstBuffer *b2 = bytes_buffer(int32_bytes({3, 4, 5, 6}));
  gst_buffer_append_memory(b, gst_buffer_get_memory(b2, 0));
  gst_buffer_unref(b2);
  ASSERT_EQ(gst_harness_push(h.get(), b), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_EQ(gst_buffer_n_memory(out), 2u);
  EXPECT_EQ(memory_bytes(out, 0), int32_bytes({1, 2}));
  EXPECT_EQ(memory_bytes(out, 1), int32_bytes({3, 4, 5, 6}));
  gst_buffer_unref(out);
  EXPECT_NE(current_caps(h.get()).find("dimensions=(string)\"2:1:1:1\\,4:1:1:1\""),
            std::string::npos)
      << current_caps(h.get());
  ASSERT_EQ(gst_harness_push(h.get(), bytes_buffer(int32_bytes({9}))), GST_FLOW_OK);
  out = gst_harness_pull(h.get());
  EXPECT_EQ(memory_bytes(out, 0), int32_bytes({9}));
  gst_buffer_unref(out);
  EXPECT_NE(current_caps(h.get()).find("dimensions=(string)1:1:1:1, types=(string)int32"),
            std::string::npos)
      << current_caps(h.get());
}

struct Case {
  uint8_t mode;
  std::vector<uint8_t> want;  // exact tensor bytes
  std::string caps_part;
};

TEST(Python3Converter, WellFormedResults) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  const std::vector<Case> cases = {
      {1, int32_bytes({0, 1, 2, 3}), "dimensions=(string)4, types=(string)int32"},
      {2, int32_bytes({3, 2, 1, 0}), "dimensions=(string)4, types=(string)int32"},  // copied once
      {10, int32_bytes({10, 11, 12, 13}), "types=(string)int32"},
      {12, int32_bytes({4, 5, 6, 7}),
       "dimensions=(string)16, types=(string)uint8, framerate=(fraction)10/1"},
  };
  for (const auto &c : cases) {
    SCOPED_TRACE("mode " + std::to_string(c.mode));
    auto h = converter("conv_cases.py", "application/octet-stream");
    ASSERT_EQ(gst_harness_push(h.get(), bytes_buffer({c.mode, 0, 0, 0})), GST_FLOW_OK);
    GstBuffer *out = gst_harness_pull(h.get());
    ASSERT_NE(out, nullptr);
    EXPECT_EQ(memory_bytes(out, 0), c.want);
    gst_buffer_unref(out);
    EXPECT_NE(current_caps(h.get()).find(c.caps_part), std::string::npos) << current_caps(h.get());
  }
}

// A slice inside the input buffer is shared at its offset.
TEST(Python3Converter, SliceOfInputIsSharedAtOffset) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  auto h = converter("conv_cases.py", "application/octet-stream");
  std::vector<uint8_t> in = {11, 0, 0, 0, 5, 0, 0, 0, 6, 0, 0, 0, 99};
  GstBuffer *b = bytes_buffer(in);
  GstMapInfo map;
  ASSERT_TRUE(gst_buffer_map(b, &map, GST_MAP_READ));
  const guint8 *in_data = map.data;
  gst_buffer_unmap(b, &map);
  ASSERT_EQ(gst_harness_push(h.get(), b), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(out, nullptr);
  ASSERT_TRUE(gst_buffer_map(out, &map, GST_MAP_READ));
  EXPECT_EQ(map.data, in_data + 4);
  gst_buffer_unmap(out, &map);
  EXPECT_EQ(memory_bytes(out, 0), int32_bytes({5, 6}));
  gst_buffer_unref(out);
}

// A whole pipeline: filesrc of a JSON file -> tensors -> filesink, exact bytes.
TEST(Python3Converter, PipelineFromFile) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  std::string dir = nns::test::make_temp_dir();
  std::ofstream(dir + "/in.json") << R"({"name": "dog", "values": [5, 6]})";
  auto r = run_pipeline("filesrc location=" + dir +
                        "/in.json blocksize=-1 ! "
                        "application/octet-stream ! tensor_converter mode=custom-script:" +
                        script("conv_json.py") + " ! filesink location=" + dir + "/out.raw");
  ASSERT_TRUE(r.eos) << r.error_text;
  std::vector<uint8_t> want = {'d', 'o', 'g', 0};
  auto v = int32_bytes({5, 6});
  want.insert(want.end(), v.begin(), v.end());
  EXPECT_EQ(nns::test::read_file(dir + "/out.raw"), want);
}

// ---- Errors: the bus error names the script and carries the Python exception. ----

nns::test::RunResult run_with(const std::string &script_path, uint8_t first_byte = 1) {
  std::string dir = nns::test::make_temp_dir();
  std::ofstream(dir + "/in.bin", std::ios::binary)
      << std::string(1, static_cast<char>(first_byte)) << std::string(15, '\0');
  return run_pipeline("filesrc location=" + dir +
                      "/in.bin blocksize=-1 ! "
                      "application/octet-stream ! tensor_converter mode=custom-script:" +
                      script_path + " ! fakesink");
}

TEST(Python3ConverterErrors, MissingScript) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  auto r = run_with(script("no_such_script.py"));
  expect_error_parts(r, {"tensorconverter", "mode=custom-script:", "no_such_script.py"});
}

TEST(Python3ConverterErrors, SyntaxError) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  auto r = run_with(script("bad_syntax_conv.py"));
  expect_error_parts(r, {"mode=custom-script:", "bad_syntax_conv.py", "SyntaxError", "line 5"});
}

TEST(Python3ConverterErrors, ClassMissing) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  expect_error_parts(run_with(script("conv_no_class.py")),
                     {"conv_no_class.py", "defines no class CustomConverter"});
}

TEST(Python3ConverterErrors, MethodMissing) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  expect_error_parts(run_with(script("conv_no_method.py")),
                     {"conv_no_method.py", "has no convert(self, input_array) method"});
}

TEST(Python3ConverterErrors, ConstructorRaises) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  expect_error_parts(run_with(script("conv_raise_init.py")),
                     {"CustomConverter() raised", "RuntimeError: converter constructor refuses"});
}

TEST(Python3ConverterErrors, IllFormedResults) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  const std::vector<std::pair<uint8_t, std::vector<std::string>>> cases = {
      {3, {"convert() raised", "ValueError: mode 3 raises", "conv_cases.py\", line"}},
      {4, {"raw_data[0] is a bytes, not a numpy array"}},
      {5, {"raw_data[0] has 8 bytes; tensors_info[0] (4 int32) needs 16"}},
      {6, {"raw_data has 1 arrays but tensors_info describes 2 tensors"}},
      {7, {"convert() returned list; expected a tuple (tensors_info, raw_data, rate_n, rate_d)"}},
      {8, {"rate_n is str ten; expected an int"}},
      {9, {"tensors_info, tensor 0 is a int, not a nnstreamer_python.TensorShape"}},
      {77, {"KeyError", "no case 77"}},
  };
  for (const auto &[mode, parts] : cases) {
    SCOPED_TRACE("mode " + std::to_string(mode));
    auto r = run_with(script("conv_cases.py"), mode);
    auto all = parts;
    all.push_back("tensorconverter");
    all.push_back("conv_cases.py");
    expect_error_parts(r, all);
  }
}

}  // namespace

// --- the sub-plugin table directly, as NNStreamer's tensorConverterPython tests use it -----

namespace {

const NNStreamerExternalConverter *python3_converter() {
  return nns::gst::ConverterRegistry::instance().find("python3");
}

// openTwice: the same script again keeps the open one (1); another script replaces it (0).
TEST(Python3ConverterUpstream, OpenTwice) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  const NNStreamerExternalConverter *ex = python3_converter();
  ASSERT_TRUE(ex);
  void *core = nullptr;
  const std::string a = script("conv_json.py"), b = script("conv_view.py");
  EXPECT_EQ(ex->open(a.c_str(), &core), 0);
  void *first = core;
  EXPECT_EQ(ex->open(a.c_str(), &core), 1);
  EXPECT_EQ(core, first);
  EXPECT_EQ(ex->open(b.c_str(), &core), 0);
  // The replacement converts: conv_view.py gives a view of the input.
  GstTensorsConfig config;
  std::memset(&config, 0, sizeof config);
  GstBuffer *in = bytes_buffer({1, 2, 3, 4});
  GstBuffer *out = ex->convert(in, &config, core);
  EXPECT_TRUE(out);
  if (out) gst_buffer_unref(out);
  gst_buffer_unref(in);
  ex->close(&core);
  EXPECT_EQ(core, nullptr);
}

TEST(Python3ConverterUpstream, InvalidParameters) {
  REQUIRE_PYTHON3_SUBPLUGIN("tensor_converter", "converter");
  const NNStreamerExternalConverter *ex = python3_converter();
  ASSERT_TRUE(ex);
  GstTensorsConfig config;
  std::memset(&config, 0, sizeof config);
  // invalidParam2_n / 3_n: get_out_config without caps or without config.
  EXPECT_FALSE(ex->get_out_config(nullptr, &config));
  GstCaps *caps = gst_caps_from_string("application/octet-stream");
  EXPECT_FALSE(ex->get_out_config(caps, nullptr));
  EXPECT_TRUE(ex->get_out_config(caps, &config));
  gst_caps_unref(caps);
  // invalidParam4_n / 5_n: convert without a buffer or without a config.
  void *core = nullptr;
  ASSERT_EQ(ex->open(script("conv_json.py").c_str(), &core), 0);
  EXPECT_EQ(ex->convert(nullptr, &config, core), nullptr);
  GstBuffer *buf = gst_buffer_new();
  EXPECT_EQ(ex->convert(buf, nullptr, core), nullptr);
  gst_buffer_unref(buf);
  ex->close(&core);
  // invalidParam6_n: a script without the CustomConverter class does not open.
  EXPECT_NE(ex->open(script("conv_no_class.py").c_str(), &core), 0);
  ex->close(&core);
  // invalidParam_n: a script that does not exist fails the pipeline (see MissingScript).
}

}  // namespace

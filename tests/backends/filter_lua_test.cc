// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter framework=lua (backends/filter/lua): NNStreamer's script convention, as file
// and as inline text, exact outputs, and bus errors naming the script line.
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "elements/flow_harness.h"
#include "support/harness.h"

namespace nns::test {
namespace {

#define REQUIRE_LUA()                                                                             \
  do {                                                                                            \
    if (!std::filesystem::exists(std::string(NNS_BUILD_DIR) +                                     \
                                 "/subplugins/filters/libnnstreamer_filter_lua.so"))              \
      NNS_SKIP_UNLESS_CI("the lua back end was not built (liblua5.4-dev, scripts/deps/lua.apt)"); \
  } while (0)

std::string caps(const std::string &type, const std::string &dims) {
  return "other/tensors,format=static,num_tensors=1,types=(string)" + type +
         ",dimensions=(string)" + dims + ",framerate=0/1";
}

std::string write_script(const std::string &name, const std::string &text) {
  std::string p = make_temp_dir() + "/" + name;
  FILE *f = std::fopen(p.c_str(), "w");
  std::fputs(text.c_str(), f);
  std::fclose(f);
  return p;
}

// Runs appsrc ! tensor_filter framework=lua model=<model> ! appsink on `frames`.
struct LuaRun {
  RunResult r;
  std::vector<Frame> out;
};
LuaRun run_lua(const std::string &model, const std::string &in_caps,
               const std::vector<Frame> &frames) {
  AppPipeline p("appsrc name=src ! tensor_filter name=f framework=lua ! appsink name=out");
  GstElement *f = gst_bin_get_by_name(GST_BIN(p.pipeline()), "f");
  g_object_set(f, "model", model.c_str(), nullptr);
  gst_object_unref(f);
  p.set_caps("src", in_caps);
  for (const auto &fr : frames) p.push("src", fr);
  p.eos("src");
  LuaRun lr;
  lr.r = p.run();
  lr.out = p.frames("out");
  return lr;
}

// The passthrough script of NNStreamer's documentation, as inline text (single quotes, no '--').
const char *kPassthrough =
    "inputTensorsInfo = { num = 1, dim = {{3, 2, 1, 1},}, type = {'uint8',} } "
    "outputTensorsInfo = { num = 1, dim = {{3, 2, 1, 1},}, type = {'uint8',} } "
    "function nnstreamer_invoke() "
    "  input = input_tensor(1) output = output_tensor(1) "
    "  for i=1,3*2 do output[i] = input[i] end "
    "end";

TEST(FilterLua, InlinePassthroughIsExact) {
  REQUIRE_LUA();
  auto lr = run_lua(kPassthrough, caps("uint8", "3:2:1:1"),
                    {Frame({Bytes{1, 2, 3, 4, 5, 255}}), Frame({Bytes{9, 8, 7, 6, 5, 4}})});
  ASSERT_TRUE(lr.r.eos) << lr.r.error_text;
  ASSERT_EQ(lr.out.size(), 2u);
  EXPECT_EQ(lr.out[0].mems[0], (Bytes{1, 2, 3, 4, 5, 255}));
  EXPECT_EQ(lr.out[1].mems[0], (Bytes{9, 8, 7, 6, 5, 4}));
}

TEST(FilterLua, ScalerFileFloatToUint8Saturates) {
  REQUIRE_LUA();
  std::string path = write_script("scaler.lua", R"(-- y = 2 x + 1, saturated into uint8
inputTensorsInfo = { num = 1, dim = {{4, 1}}, type = {'float32'} }
outputTensorsInfo = { num = 1, dim = {{4, 1}}, type = {'uint8'} }
function nnstreamer_invoke()
  local x, y = input_tensor(1), output_tensor(1)
  for i = 1, #x do y[i] = 2 * x[i] + 1 end
end
)");
  auto lr = run_lua(path, caps("float32", "4:1"),
                    {Frame({bytes_of(std::vector<float>{0.f, 1.75f, -3.f, 500.f})})});
  ASSERT_TRUE(lr.r.eos) << lr.r.error_text;
  ASSERT_EQ(lr.out.size(), 1u);
  EXPECT_EQ(lr.out[0].mems[0], (Bytes{1, 4, 0, 255}));
  EXPECT_NE(lr.out[0].caps.find("uint8"), std::string::npos) << lr.out[0].caps;
}

// A generator as NNStreamer's tensor_sparse tests use one: the input only clocks it.
TEST(FilterLua, GeneratorTwoOutputs) {
  REQUIRE_LUA();
  std::string path = write_script("gen.lua", R"(
inputTensorsInfo = { num = 1, dim = {{1}}, type = {'uint8'} }
outputTensorsInfo = { num = 2, dim = {{3, 2}, {2}}, type = {'float32', 'int16'} }
calls = 0
function nnstreamer_invoke()
  calls = calls + 1
  local a, b = output_tensor(1), output_tensor(2)
  for i = 1, 6 do a[i] = (i % 2 == 0) and 0 or i * calls end
  b[1] = -calls
  b[2] = 40000
end
)");
  auto lr = run_lua(path, caps("uint8", "1"), {Frame({Bytes{0}}), Frame({Bytes{0}})});
  ASSERT_TRUE(lr.r.eos) << lr.r.error_text;
  ASSERT_EQ(lr.out.size(), 2u);
  ASSERT_EQ(lr.out[1].mems.size(), 2u);
  EXPECT_EQ(values_of<float>(lr.out[0].mems[0]), (std::vector<float>{1, 0, 3, 0, 5, 0}));
  EXPECT_EQ(values_of<float>(lr.out[1].mems[0]), (std::vector<float>{2, 0, 6, 0, 10, 0}));
  EXPECT_EQ(values_of<int16_t>(lr.out[1].mems[1]), (std::vector<int16_t>{-2, 32767}));
}

TEST(FilterLua, SyntaxErrorNamesTheLine) {
  REQUIRE_LUA();
  auto lr = run_lua("inputTensorsInfo = {num = 1}\noutputTensorsInfo = = 3\n", caps("uint8", "1"),
                    {Frame({Bytes{0}})});
  ASSERT_TRUE(lr.r.error);
  EXPECT_NE(lr.r.error_text.find("inline script:2:"), std::string::npos) << lr.r.error_text;
  EXPECT_NE(lr.r.error_text.find("framework 'lua'"), std::string::npos) << lr.r.error_text;
}

TEST(FilterLua, RuntimeErrorNamesFileAndLine) {
  REQUIRE_LUA();
  std::string path =
      write_script("bad.lua", R"(inputTensorsInfo = { num = 1, dim = {{4}}, type = {'uint8'} }
outputTensorsInfo = { num = 1, dim = {{4}}, type = {'uint8'} }
function nnstreamer_invoke()
  output_tensor(1)[5] = 1
end
)");
  auto lr = run_lua(path, caps("uint8", "4"), {Frame({Bytes{0, 0, 0, 0}})});
  ASSERT_TRUE(lr.r.error);
  EXPECT_NE(lr.r.error_text.find("bad.lua:4: output_tensor(1)[5]: index out of range (1..4)"),
            std::string::npos)
      << lr.r.error_text;
}

TEST(FilterLua, MissingInfoAndFunctionAreNamed) {
  REQUIRE_LUA();
  auto lr = run_lua("inputTensorsInfo = { num = 1, dim = {{4}}, type = {'uint8'} }",
                    caps("uint8", "4"), {Frame({Bytes{0, 0, 0, 0}})});
  ASSERT_TRUE(lr.r.error);
  EXPECT_NE(lr.r.error_text.find("outputTensorsInfo: the script does not define this table"),
            std::string::npos)
      << lr.r.error_text;
  lr = run_lua(
      "inputTensorsInfo = { num = 1, dim = {{4}}, type = {'uint8'} } "
      "outputTensorsInfo = { num = 1, dim = {{4}}, type = {'uint7'} }",
      caps("uint8", "4"), {Frame({Bytes{0, 0, 0, 0}})});
  ASSERT_TRUE(lr.r.error);
  EXPECT_NE(lr.r.error_text.find("type[1] 'uint7' is not a tensor type"), std::string::npos)
      << lr.r.error_text;
  lr = run_lua(
      "inputTensorsInfo = { num = 1, dim = {{4}}, type = {'uint8'} } "
      "outputTensorsInfo = { num = 1, dim = {{4}}, type = {'uint8'} }",
      caps("uint8", "4"), {Frame({Bytes{0, 0, 0, 0}})});
  ASSERT_TRUE(lr.r.error);
  EXPECT_NE(lr.r.error_text.find("defines no function nnstreamer_invoke()"), std::string::npos)
      << lr.r.error_text;
}

}  // namespace
}  // namespace nns::test

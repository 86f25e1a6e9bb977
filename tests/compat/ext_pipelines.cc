// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer-style custom filters compiled by tests/compat/build_ext.sh from the INSTALLED headers
// only, linked to the installed libnnstreamer-single.so, run in pipelines
// (tensor_filter framework=custom model=<.so>) with exact output values.
#include <gtest/gtest.h>

#include <string>
#include <vector>

#include "elements/flow_harness.h"

namespace {

using nns::test::AppPipeline;
using nns::test::bytes_of;
using nns::test::Frame;
using nns::test::values_of;

std::string ext(const std::string &name) {
  return std::string(NNS_COMPAT_EXT_DIR) + "/lib" + name + ".so";
}

std::string static_caps(const std::string &dims, const std::string &types) {
  int n = 1;
  for (char c : dims) n += c == ',';
  return "other/tensors,format=static,num_tensors=" + std::to_string(n) + ",dimensions=(string)\"" +
         dims + "\",types=(string)\"" + types + "\",framerate=(fraction)0/1";
}

TEST(CompatExt, FixedPassthrough) {
  AppPipeline p("appsrc name=in ! tensor_filter framework=custom model=" + ext("ext_passthrough") +
                " ! appsink name=out");
  p.set_caps("in", static_caps("3:4:2:1", "uint8"));
  std::vector<uint8_t> a(24), b(24);
  for (int i = 0; i < 24; ++i) {
    a[i] = static_cast<uint8_t>(i);
    b[i] = static_cast<uint8_t>(200 - i);
  }
  p.push("in", Frame({a}));
  p.push("in", Frame({b}));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].mems.at(0), a);
  EXPECT_EQ(out[1].mems.at(0), b);
  EXPECT_NE(out[0].caps.find("3:4:2:1"), std::string::npos) << out[0].caps;
}

TEST(CompatExt, VariablePassthroughTwoTensors) {
  AppPipeline p("appsrc name=in ! tensor_filter framework=custom model=" +
                ext("ext_passthrough_variable") + " ! appsink name=out");
  p.set_caps("in", static_caps("2:2,3", "uint8,float32"));
  std::vector<uint8_t> a = {1, 2, 3, 4};
  std::vector<float> f = {0.5f, -1.25f, 3.0f};
  p.push("in", Frame({a, bytes_of(f)}));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 1u);
  ASSERT_EQ(out[0].mems.size(), 2u);
  EXPECT_EQ(out[0].mems[0], a);
  EXPECT_EQ(values_of<float>(out[0].mems[1]), f);
}

TEST(CompatExt, ScalerAllocatesItsOutput) {
  AppPipeline p("appsrc name=in ! tensor_filter framework=custom custom=2:2 model=" +
                ext("ext_scaler") + " ! appsink name=out");
  p.set_caps("in", static_caps("1:4:4:1", "uint8"));
  std::vector<uint8_t> img(16);
  for (int i = 0; i < 16; ++i) img[i] = static_cast<uint8_t>(i);
  p.push("in", Frame({img}));
  p.push("in", Frame({img}));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 2u);
  // Nearest neighbour 4x4 -> 2x2: source pixels (0,0) (2,0) (0,2) (2,2).
  EXPECT_EQ(out[1].mems.at(0), (std::vector<uint8_t>{0, 2, 8, 10}));
  EXPECT_NE(out[0].caps.find("1:2:2:1"), std::string::npos) << out[0].caps;
}

TEST(CompatExt, StatefulFilterInRepositoryLoop) {
  const int steps = 5;
  AppPipeline p("tensor_reposrc slot-index=71 num-buffers=" + std::to_string(steps) + " caps=\"" +
                static_caps("4:1", "float32") +
                "\" ! tensor_filter framework=custom model=" + ext("ext_rnn") +
                " ! tee name=t t. ! queue ! tensor_reposink slot-index=71 t. ! queue ! "
                "appsink name=out");
  auto r = p.run(20);
  ASSERT_TRUE(r.eos) << r.error_text << (r.timed_out ? " (timed out)" : "");
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), static_cast<std::size_t>(steps));
  std::vector<float> h(4, 0.0f);  // h(0) from tensor_reposrc: zeros
  for (int t = 1; t <= steps; ++t) {
    for (int j = 0; j < 4; ++j) h[j] = 0.5f * h[j] + static_cast<float>(t + j);
    EXPECT_EQ(values_of<float>(out[t - 1].mems.at(0)), h) << "step " << t;
  }
  EXPECT_EQ(h[0], 1.0f / 16 + 2.0f / 8 + 3.0f / 4 + 4.0f / 2 + 5.0f);  // sanity of the reference
}

TEST(CompatExt, RefusedInputIsABusError) {
  // ext_rnn accepts float32 4:1 only: its setInputDim refuses 3:1 and the filter reports it.
  auto r = nns::test::run_pipeline(
      "tensor_reposrc slot-index=72 num-buffers=1 caps=\"" + static_caps("3:1", "float32") +
      "\" ! tensor_filter framework=custom model=" + ext("ext_rnn") + " ! fakesink");
  EXPECT_TRUE(r.error) << "expected an error, eos=" << r.eos;
  EXPECT_FALSE(r.error_text.empty());
  RecordProperty("error_text", r.error_text);
}

}  // namespace

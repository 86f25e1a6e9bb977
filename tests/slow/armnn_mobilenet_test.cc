// SPDX-License-Identifier: LGPL-2.1-only
// The suite's single real MobileNet v2 (quantized .tflite) inference through the armnn back end.
// On x86 Arm NN only has the CpuRef reference device: one inference takes several seconds, so
// this file sits in tests/slow/ (ctest label "slow"; skip with `ctest -LE slow`).
#include <gtest/gtest.h>

#include <algorithm>
#include <fstream>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace {

TEST(ArmnnMobilenet, OrangeIsClass951) {
  const nns::test::BackendLib &lib = nns::test::backend_lib("armnn");
  if (!lib.ok()) GTEST_SKIP() << "armnn back end: " << lib.error();
  NNS_REQUIRE_SHARED_MODELS();
  const std::string dir = nns::test::shared_models_dir();
  nns::test::Props p;
  p.models = {dir + "/models/mobilenet_v2_1.0_224_quant.tflite"};
  nns::test::Instance inst(lib.api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  std::vector<uint8_t> image = nns::test::read_file(dir + "/data/orange.raw");
  ASSERT_EQ(image.size(), 224u * 224u * 3u);
  std::vector<uint8_t> scores(1001, 0);
  std::vector<GstTensorMemory> ins{{image.data(), image.size()}};
  std::vector<GstTensorMemory> outs{{scores.data(), scores.size()}};
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  auto best = std::max_element(scores.begin(), scores.end()) - scores.begin();
  EXPECT_EQ(best, 951);
  EXPECT_EQ(scores[951], 209);  // CpuRef is exact: lemon (952) 174 is next
  std::ifstream labels(dir + "/labels/labels.txt");
  std::string line;
  for (int i = 0; i <= 951 && std::getline(labels, line); ++i) {
  }
  EXPECT_EQ(line, "orange");
}

}  // namespace

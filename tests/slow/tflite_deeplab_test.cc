// SPDX-License-Identifier: LGPL-2.1-only
// DeepLab v3 (deeplabv3_257_mv_gpu.tflite, float) on orange.png through the tflite back end
// against Arm NN CpuRef (exact reference, ~9 s per frame here, hence tests/slow/, ctest label
// "slow"): the per-pixel class maps agree on >= 99.5 % of the 257x257 pixels.
#include <gtest/gtest.h>

#include <cstring>
#include <filesystem>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace {

std::vector<int> class_map(const std::string &framework, const std::string &dir) {
  const std::string shared = nns::test::shared_models_dir();
  std::string out = dir + "/" + framework + ".bin";
  nns::test::RunResult r = nns::test::run_pipeline(
      "filesrc location=" + shared +
          "/data/orange.png ! pngdec ! videoconvert ! videoscale ! "
          "video/x-raw,format=RGB,width=257,height=257 ! tensor_converter ! "
          "tensor_transform mode=arithmetic option=typecast:float32,add:-127.5,div:127.5 ! "
          "tensor_filter framework=" +
          framework + " model=" + shared +
          "/models/deeplabv3_257_mv_gpu.tflite ! filesink location=" + out,
      120.0);
  EXPECT_TRUE(r.eos) << framework << ": " << r.error_text;
  auto bytes = nns::test::read_file(out);
  const std::size_t pixels = 257 * 257, classes = 21;
  if (bytes.size() != pixels * classes * 4) {
    ADD_FAILURE() << framework << ": output is " << bytes.size() << " bytes";
    return {};
  }
  std::vector<float> f(pixels * classes);
  std::memcpy(f.data(), bytes.data(), bytes.size());
  std::vector<int> map(pixels);
  for (std::size_t p = 0; p < pixels; ++p) {
    int best = 0;
    for (std::size_t c = 1; c < classes; ++c)
      if (f[p * classes + c] > f[p * classes + best]) best = static_cast<int>(c);
    map[p] = best;
  }
  return map;
}

TEST(TfliteDeeplab, ClassMapMatchesArmnnCpuRef) {
  NNS_REQUIRE_SHARED_MODELS();
  if (!std::filesystem::exists(nns::test::backend_path("tensorflow2-lite")) ||
      !std::filesystem::exists(nns::test::backend_path("armnn")))
    GTEST_SKIP() << "needs both the tensorflow2-lite and the armnn back ends";
  std::string dir = nns::test::make_temp_dir();
  auto ours = class_map("tensorflow2-lite", dir), ref = class_map("armnn", dir);
  ASSERT_EQ(ours.size(), ref.size());
  ASSERT_FALSE(ours.empty());
  std::size_t same = 0;
  for (std::size_t i = 0; i < ours.size(); ++i) same += ours[i] == ref[i];
  double share = static_cast<double>(same) / static_cast<double>(ours.size());
  std::printf("class maps agree on %.4f of the pixels\n", share);
  EXPECT_GE(share, 0.995);
  std::filesystem::remove_all(dir);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer's accelerator names and accelerator= reading (filter_accl.h), value by value.
#include "core/filter_accl.h"

#include <gtest/gtest.h>

using namespace nns::accl;

namespace {

const char *const kNpuGpuCpu[] = {"npu", "gpu", "cpu", nullptr};

}  // namespace

TEST(AcclNames, EveryNameAndValue) {
  struct Case {
    const char *name;
    accl_hw hw;
  };
  const Case cases[] = {
      {"none", ACCL_NONE},
      {"default", ACCL_DEFAULT},
      {"auto", ACCL_AUTO},
      {"cpu", ACCL_CPU},
      {"cpu.simd", ACCL_CPU_SIMD},
      {"gpu", ACCL_GPU},
      {"npu", ACCL_NPU},
      {"npu.movidius", ACCL_NPU_MOVIDIUS},
      {"npu.edgetpu", ACCL_NPU_EDGE_TPU},
      {"npu.vivante", ACCL_NPU_VIVANTE},
      {"npu.srcn", ACCL_NPU_SRCN},
      {"npu.slsi", ACCL_NPU_SLSI},
      {"npu.sr", ACCL_NPU_SR},
  };
  for (const Case &c : cases) {
    EXPECT_EQ(type_of(c.name), c.hw) << c.name;
    EXPECT_STREQ(name_of(c.hw), c.name) << std::hex << c.hw;
  }
  EXPECT_EQ(static_cast<int>(ACCL_CPU_SIMD), 0x1100);
  EXPECT_EQ(static_cast<int>(ACCL_NPU_SR), 0x4100);
  EXPECT_EQ(static_cast<int>(ACCL_NPU_EDGE_TPU), 0x4002);
}

TEST(AcclNames, UnknownCaseAndNull) {
  EXPECT_EQ(type_of("GPU"), ACCL_NONE);  // exact spelling only
  EXPECT_EQ(type_of("npu.edge_tpu"), ACCL_NONE);
  EXPECT_EQ(type_of(""), ACCL_NONE);
  EXPECT_EQ(type_of(nullptr), ACCL_NONE);
  EXPECT_STREQ(name_of(static_cast<accl_hw>(0x3000)), "none");
  EXPECT_STREQ(name_of(static_cast<accl_hw>(-1)), "none");
}

TEST(AcclNames, NeonIsAnArmAccelerator) {
#if defined(__aarch64__) || defined(__arm__)
  EXPECT_EQ(type_of("cpu.neon"), ACCL_CPU_NEON);
  EXPECT_STREQ(name_of(ACCL_CPU_SIMD), "cpu.neon");
#else
  EXPECT_EQ(type_of("cpu.neon"), ACCL_NONE);
  EXPECT_STREQ(name_of(ACCL_CPU_NEON), "cpu.simd");
  EXPECT_TRUE(usable_here("cpu.neon"));  // NNStreamer filters it out on Arm only
#endif
  EXPECT_TRUE(usable_here("gpu"));
  EXPECT_TRUE(usable_here(nullptr));
}

TEST(AcclMatch, OrderNegationAndFallbacks) {
  const std::vector<std::string> sup = {"npu", "gpu", "cpu", "auto", "default"};
  using V = std::vector<accl_hw>;
  EXPECT_EQ(match_all(nullptr, sup), V{ACCL_DEFAULT});
  EXPECT_EQ(match_all("", sup), V{ACCL_NONE});
  EXPECT_EQ(match_all("false:gpu", sup), V{ACCL_NONE});
  EXPECT_EQ(match_all("gpu", sup), V{ACCL_NONE});
  EXPECT_EQ(match_all("true", sup), V{ACCL_AUTO});
  EXPECT_EQ(match_all("TRUE:gpu", sup), V{ACCL_GPU});
  EXPECT_EQ(match_all("true:cpu,gpu", sup), (V{ACCL_CPU, ACCL_GPU}));
  EXPECT_EQ(match_all("true:gpu,cpu", sup), (V{ACCL_GPU, ACCL_CPU}));
  EXPECT_EQ(match_all("true:npu,gpu,!cpu", sup), (V{ACCL_NPU, ACCL_GPU}));
  EXPECT_EQ(match_all("true:!npu", sup), V{ACCL_AUTO});
  EXPECT_EQ(match_all("true:(gpu)", sup), V{ACCL_GPU});
  EXPECT_EQ(match_all("true:vpu", sup), V{ACCL_AUTO});  // not supported: auto
  EXPECT_EQ(match_all("true:GPU", sup), V{ACCL_AUTO});  // found, but not an exact name
  EXPECT_EQ(match_all("true:default,auto", sup), (V{ACCL_DEFAULT, ACCL_AUTO}));
  EXPECT_EQ(match_all("true:gpucpu", sup), (V{ACCL_GPU, ACCL_CPU}));  // no separator needed
  EXPECT_EQ(match_all("true:gpu", {}), V{ACCL_NONE});
}

// At one position the first supported name that fits wins: "npu" before "npu.srcn" in the list
// takes "npu.srcn" as npu.
TEST(AcclMatch, ListOrderDecidesAtOnePosition) {
  using V = std::vector<accl_hw>;
  EXPECT_EQ(match_all("true:npu.srcn", {"npu", "npu.srcn"}), V{ACCL_NPU});
  EXPECT_EQ(match_all("true:npu.srcn", {"npu.srcn", "npu"}), V{ACCL_NPU_SRCN});
  EXPECT_EQ(match_all("true:npu.sr", {"npu.srcn", "npu.sr"}), V{ACCL_NPU_SR});
}

TEST(AcclParse, AsParseAcclHw) {
  EXPECT_EQ(parse("true:cpu,gpu", kNpuGpuCpu, nullptr, nullptr), ACCL_CPU);
  EXPECT_EQ(parse("true:gpu,cpu", kNpuGpuCpu, nullptr, nullptr), ACCL_GPU);
  EXPECT_EQ(parse("true:!npu,gpu", kNpuGpuCpu, nullptr, nullptr), ACCL_GPU);
  EXPECT_EQ(parse("false:gpu", kNpuGpuCpu, "gpu", "cpu"), ACCL_NONE);
  // auto: the given one, else the first supported.
  EXPECT_EQ(parse("true", kNpuGpuCpu, "gpu", "cpu"), ACCL_GPU);
  EXPECT_EQ(parse("true", kNpuGpuCpu, nullptr, "cpu"), ACCL_NPU);
  EXPECT_EQ(parse("true:auto", kNpuGpuCpu, "cpu", nullptr), ACCL_CPU);
  EXPECT_EQ(parse("true:tpu", kNpuGpuCpu, "cpu", nullptr), ACCL_CPU);
  // default (unset accelerator= too): the given one, else the first supported.
  EXPECT_EQ(parse(nullptr, kNpuGpuCpu, "gpu", "cpu"), ACCL_CPU);
  EXPECT_EQ(parse(nullptr, kNpuGpuCpu, "gpu", nullptr), ACCL_NPU);
  EXPECT_EQ(parse("true:default", kNpuGpuCpu, "gpu", "cpu"), ACCL_CPU);
  // auto / default need not be supported ones; an unknown name is ACCL_NONE.
  EXPECT_EQ(parse(nullptr, kNpuGpuCpu, nullptr, "npu.edgetpu"), ACCL_NPU_EDGE_TPU);
  EXPECT_EQ(parse(nullptr, kNpuGpuCpu, nullptr, "tpu"), ACCL_NONE);
  // No supported list.
  const char *const none[] = {nullptr};
  EXPECT_EQ(parse("true:cpu", none, "cpu", "cpu"), ACCL_NONE);
  EXPECT_EQ(parse("true:cpu", nullptr, "cpu", "cpu"), ACCL_NONE);
}

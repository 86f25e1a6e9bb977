// SPDX-License-Identifier: LGPL-2.1-only
// The armnn filter back end through its C ABI (dlopen of the built .so) on the tiny .tflite
// models: model-derived tensor info, 32 inputs/outputs matched by name, device choice, and the
// error messages. The one real MobileNet inference lives in tests/slow/ (ctest label "slow").
#include <gtest/gtest.h>

#include <cerrno>
#include <fstream>
#include <string>

#include "backends/backend_loader.h"
#include "backends/tflite_sample_checks.h"
#include "support/harness.h"

namespace {

using nns::test::BackendLib;
using nns::test::Instance;
using nns::test::Props;
using nns::test::tensor_desc;
using nns::test::tensors_desc;

const BackendLib &lib() {
  return nns::test::backend_lib("armnn");
}

#define REQUIRE_BACKEND()                                                 \
  do {                                                                    \
    if (!lib().ok()) GTEST_SKIP() << "armnn back end: " << lib().error(); \
  } while (0)

std::string model(const char *name) {
  return nns::test::shared_models_dir() + "/models/" + name;
}

Props add_props() {
  Props p;
  p.framework = "armnn";
  p.models = {model("add.tflite")};
  return p;
}

TEST(ArmnnBackend, Table) {
  REQUIRE_BACKEND();
  const nns_filter_backend_i *api = lib().api();
  EXPECT_EQ(api->api_version, NNS_FILTER_BACKEND_API_VERSION);
  EXPECT_STREQ(api->name, "armnn");
  ASSERT_NE(api->extensions, nullptr);
  EXPECT_STREQ(api->extensions[0], ".tflite");
  EXPECT_EQ(api->extensions[1], nullptr);
  ASSERT_NE(api->check_accelerator, nullptr);
  EXPECT_EQ(api->check_accelerator("cpu"), 0);  // CpuRef is always packaged
  EXPECT_EQ(api->check_accelerator("auto"), 0);
  EXPECT_NE(api->check_accelerator("npu"), 0);
}

TEST(ArmnnBackend, AddModelInfoAndInvoke) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = add_props();
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns::test::expect_add_sample(inst);
}

TEST(ArmnnBackend, ThirtyTwoInputsAndOutputsByName) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {model("simple_32_in_32_out.tflite")};
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns::test::expect_thirty_two_sample(inst);
}

TEST(ArmnnBackend, QuantizedMobilenetInfo) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {model("mobilenet_v2_1.0_224_quant.tflite")};
  // input=/inputtype= equal to the model (trailing 1s do not matter) are accepted.
  p.input = tensors_desc({tensor_desc(_NNS_UINT8, {3, 224, 224})});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc in, out;
  ASSERT_EQ(inst.model_info(in, out), 0) << inst.error();
  EXPECT_EQ(in.tensors[0].type, static_cast<uint32_t>(_NNS_UINT8));
  EXPECT_EQ(in.tensors[0].dims[0], 3u);
  EXPECT_EQ(in.tensors[0].dims[1], 224u);
  EXPECT_EQ(in.tensors[0].dims[2], 224u);
  EXPECT_EQ(in.tensors[0].dims[3], 1u);
  EXPECT_EQ(out.tensors[0].type, static_cast<uint32_t>(_NNS_UINT8));
  EXPECT_EQ(out.tensors[0].dims[0], 1001u);
  EXPECT_EQ(out.tensors[0].dims[1], 1u);
}

TEST(ArmnnBackend, SetInputInfoOnlyAcceptsTheModelShape) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = add_props();
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc out{};
  EXPECT_EQ(inst.set_input_info(tensors_desc({tensor_desc(_NNS_FLOAT32, {1, 1})}), out), 0);
  EXPECT_EQ(out.tensors[0].type, static_cast<uint32_t>(_NNS_FLOAT32));
  EXPECT_EQ(inst.set_input_info(tensors_desc({tensor_desc(_NNS_FLOAT32, {4})}), out), -ENOTSUP);
  EXPECT_EQ(inst.set_input_info(tensors_desc({tensor_desc(_NNS_INT32, {1})}), out), -ENOTSUP);
}

TEST(ArmnnBackend, DeviceChoice) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  for (const char *custom : {"Backend:CpuRef", "backend:cpuref", " Backend : CpuRef "}) {
    Props p = add_props();
    p.custom = custom;
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), 0) << custom << ": " << inst.error();
  }
  for (const char *accl : {"true:cpu", "true:gpu,cpu", "true:npu", "false:gpu", "true:auto"}) {
    Props p = add_props();
    p.accelerator = accl;
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), 0) << accl << ": " << inst.error();
    if (inst.rc() == 0) {
      float x = 1, o = 0;
      std::vector<GstTensorMemory> ins{{&x, 4}};
      std::vector<GstTensorMemory> outs{{&o, 4}};
      EXPECT_EQ(inst.invoke(ins, outs), 0) << inst.error();
      EXPECT_FLOAT_EQ(o, 3.f);
    }
  }
}

// ---- errors ----

TEST(ArmnnBackendErrors, MissingModel) {
  REQUIRE_BACKEND();
  Props p;
  p.models = {"/nonexistent/m.tflite"};
  Instance inst(lib().api(), p);
  EXPECT_EQ(inst.rc(), -ENOENT);
  EXPECT_NE(inst.error().find("'/nonexistent/m.tflite' does not exist"), std::string::npos)
      << inst.error();
}

TEST(ArmnnBackendErrors, CorruptModel) {
  REQUIRE_BACKEND();
  std::string dir = nns::test::make_temp_dir();
  std::string path = dir + "/corrupt.tflite";
  std::ofstream(path) << "not a flatbuffer at all, just some text\n";
  Props p;
  p.models = {path};
  Instance inst(lib().api(), p);
  EXPECT_EQ(inst.rc(), -EINVAL);
  EXPECT_NE(inst.error().find("cannot parse TensorFlow Lite model '" + path + "'"),
            std::string::npos)
      << inst.error();
  EXPECT_NE(inst.error().find("flatbuffers"), std::string::npos) << inst.error();  // Arm NN's
  std::filesystem::remove_all(dir);
}

TEST(ArmnnBackendErrors, UnsupportedOperator) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {model("sample_4x4x4x4x4_two_input_one_output.tflite")};
  Instance inst(lib().api(), p);
  EXPECT_EQ(inst.rc(), -EINVAL);
  EXPECT_NE(inst.error().find("sample_4x4x4x4x4_two_input_one_output.tflite"), std::string::npos)
      << inst.error();
  EXPECT_NE(inst.error().find("Operator not supported"), std::string::npos) << inst.error();
}

TEST(ArmnnBackendErrors, PropertiesDisagreeWithModel) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  {
    Props p = add_props();
    p.input = tensors_desc({tensor_desc(_NNS_FLOAT32, {2})});
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find("input tensor #0 is float32 1, but input=/inputtype= say "
                                "float32 2"),
              std::string::npos)
        << inst.error();
  }
  {
    Props p = add_props();
    p.output = tensors_desc({tensor_desc(_NNS_UINT8, {1})});
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find("output tensor #0 is float32 1, but output=/outputtype= say "
                                "uint8 1"),
              std::string::npos)
        << inst.error();
  }
  {
    Props p = add_props();
    auto t = tensor_desc(_NNS_FLOAT32, {1});
    p.input = tensors_desc({t, t});
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find("has 1 input tensor(s), but input=/inputtype= give 2"),
              std::string::npos)
        << inst.error();
  }
}

TEST(ArmnnBackendErrors, InvokeSizesChecked) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = add_props();
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  double x = 1, o = 0;
  std::vector<GstTensorMemory> ins{{&x, 8}};
  std::vector<GstTensorMemory> outs{{&o, 4}};
  EXPECT_EQ(inst.invoke(ins, outs), -EINVAL);
  EXPECT_NE(inst.error().find("input tensor #0 has 8 bytes, but float32 1 needs 4"),
            std::string::npos)
      << inst.error();
  std::vector<GstTensorMemory> two{{&x, 4}, {&x, 4}};
  EXPECT_EQ(inst.invoke(two, outs), -EINVAL);
  EXPECT_NE(inst.error().find("has 1 input(s) and 1 output(s), got 2 and 1"), std::string::npos)
      << inst.error();
}

TEST(ArmnnBackendErrors, CustomAndAccelerator) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  {
    Props p = add_props();
    p.custom = "Backend:CpuRef,NumThreads:2";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find("unknown custom option 'NumThreads'"), std::string::npos)
        << inst.error();
  }
  if (lib().api()->check_accelerator("gpu") == 0) GTEST_SKIP() << "Arm NN has a GPU here";
  {
    Props p = add_props();
    p.custom = "Backend:GpuAcc";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -ENODEV);
    EXPECT_NE(inst.error().find("Backend:GpuAcc: no such Arm NN device here (registered: "),
              std::string::npos)
        << inst.error();
    EXPECT_NE(inst.error().find("CpuRef"), std::string::npos) << inst.error();
  }
  {
    Props p = add_props();
    p.accelerator = "true:gpu";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -ENODEV);
    EXPECT_NE(inst.error().find("accelerator=true:gpu: none of these devices"), std::string::npos)
        << inst.error();
  }
}

}  // namespace

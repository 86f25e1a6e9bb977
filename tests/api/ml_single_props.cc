// SPDX-License-Identifier: LGPL-2.1-only
// Single-shot API: ml_single_set_property / ml_single_get_property (tensor_filter's names):
// values read back, tensor properties through the back end's set-input, custom reopening the
// model, model reloading with is-updatable, and the errors for what cannot change.
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <string>

#include "ml_single_test_util.h"
#include "nnstreamer-single.h"
#include "nnstreamer-single.hh"
#include "tensor_filter_custom_easy.h"

namespace {

using namespace nns::test::ml;
using nns::ml::Single;
using nns::ml::TensorsData;
using nns::ml::TensorsInfo;

int add_k(void *data, const GstTensorFilterProperties *, const GstTensorMemory *in,
          GstTensorMemory *out) {
  int k = *static_cast<int *>(data);
  for (size_t i = 0; i < in[0].size; ++i)
    static_cast<uint8_t *>(out[0].data)[i] =
        static_cast<uint8_t>(static_cast<uint8_t *>(in[0].data)[i] + k);
  return 0;
}

int kOne = 1, kTen = 10;

class MlSingleProps : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    GstTensorsInfo info{};
    info.num_tensors = 1;
    info.info[0].type = _NNS_UINT8;
    info.info[0].dimension[0] = 4;
    ASSERT_EQ(NNS_custom_easy_register("mlp_add_one", add_k, &kOne, &info, &info), 0);
    ASSERT_EQ(NNS_custom_easy_register("mlp_add_ten", add_k, &kTen, &info, &info), 0);
  }
  static int set(Single &s, const char *name, const char *value) {
    return ml_single_set_property(s.get(), name, value);
  }
  static uint8_t first_out(Single &s, uint8_t v) {
    TensorsData in(s.input_info());
    std::memset(in.data(0), v, in.size(0));
    return s.invoke(in).as<uint8_t>(0)[0];
  }
};

TEST_F(MlSingleProps, GetReportsEveryValue) {
  Single s("mlp_add_one", "custom-easy");
  const std::pair<const char *, const char *> want[] = {
      {"input", "4"},
      {"inputtype", "uint8"},
      {"inputname", ""},
      {"inputlayout", "ANY"},
      {"inputranks", "1"},
      {"output", "4"},
      {"outputtype", "uint8"},
      {"outputname", ""},
      {"outputlayout", "ANY"},
      {"outputranks", "1"},
      {"custom", ""},
      {"accelerator", ""},
      {"is-updatable", "false"},
      {"framework", "custom-easy"},
      {"model", "mlp_add_one"},
  };
  for (auto &[name, value] : want) EXPECT_EQ(s.property(name), value) << name;
  char *v = reinterpret_cast<char *>(1);
  EXPECT_EQ(ml_single_get_property(s.get(), "silent", &v), ML_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(v, nullptr);
  EXPECT_NE(s.last_error().find("unknown property 'silent'"), std::string::npos) << s.last_error();
  EXPECT_EQ(ml_single_get_property(s.get(), nullptr, &v), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_single_get_property(s.get(), "input", nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_single_get_property(nullptr, "input", &v), ML_ERROR_INVALID_PARAMETER);
}

TEST_F(MlSingleProps, ReadOnlyUnknownAndBadValues) {
  Single s("mlp_add_one", "custom-easy");
  EXPECT_EQ(set(s, "framework", "onnxruntime"), ML_ERROR_NOT_SUPPORTED);
  EXPECT_NE(s.last_error().find("read-only"), std::string::npos) << s.last_error();
  EXPECT_EQ(set(s, "inputranks", "2"), ML_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(set(s, "silent", "false"), ML_ERROR_NOT_SUPPORTED);
  EXPECT_NE(s.last_error().find("known: input"), std::string::npos) << s.last_error();
  EXPECT_EQ(set(s, "input", nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(set(s, nullptr, "x"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(set(s, "is-updatable", "maybe"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(set(s, "input", "4:x"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(set(s, "inputtype", "uint8,uint8"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(s.last_error().find("gives 2 tensor(s); the model has 1"), std::string::npos)
      << s.last_error();
  // A fixed model cannot change its input; its output follows from the model.
  EXPECT_EQ(set(s, "input", "8"), ML_ERROR_NOT_SUPPORTED);
  EXPECT_EQ(set(s, "output", "8"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(s.last_error().find("follows from the model"), std::string::npos) << s.last_error();
  // The C++ wrapper throws with the code and the message.
  try {
    s.set_property("model", "mlp_add_ten");
    ADD_FAILURE() << "no exception";
  } catch (const nns::ml::Error &e) {
    EXPECT_EQ(e.code(), ML_ERROR_NOT_SUPPORTED);
    EXPECT_NE(std::string(e.what()).find("is-updatable"), std::string::npos) << e.what();
  }
  // The current value is accepted as it is.
  EXPECT_EQ(set(s, "input", "4"), ML_ERROR_NONE);
  EXPECT_EQ(first_out(s, 1), 2);
}

TEST_F(MlSingleProps, NamesLayoutsAndAccelerator) {
  Single s("mlp_add_one", "custom-easy");
  s.set_property("inputname", "pixels");
  s.set_property("outputname", "scores");
  s.set_property("inputlayout", "NHWC");
  s.set_property("outputlayout", "nchw");
  s.set_property("accelerator", "true:cpu");
  EXPECT_EQ(s.property("inputname"), "pixels");
  EXPECT_EQ(s.input_info().name(0), "pixels");
  EXPECT_EQ(s.property("outputname"), "scores");
  EXPECT_EQ(s.output_info().name(0), "scores");
  EXPECT_EQ(s.property("inputlayout"), "NHWC");
  EXPECT_EQ(s.property("outputlayout"), "NCHW");
  EXPECT_EQ(s.property("accelerator"), "true:cpu");
  EXPECT_EQ(first_out(s, 41), 42);  // still the same model after reopening
}

TEST_F(MlSingleProps, ModelReloadNeedsIsUpdatable) {
  Single s("mlp_add_one", "custom-easy");
  EXPECT_EQ(set(s, "model", "mlp_add_ten"), ML_ERROR_NOT_SUPPORTED);
  EXPECT_NE(s.last_error().find("is-updatable"), std::string::npos) << s.last_error();
  EXPECT_EQ(first_out(s, 5), 6);
  s.set_property("is-updatable", "TRUE");
  EXPECT_EQ(s.property("is-updatable"), "true");
  s.set_property("model", "mlp_add_ten");
  EXPECT_EQ(s.property("model"), "mlp_add_ten");
  EXPECT_EQ(first_out(s, 5), 15);
  // A model that cannot be opened keeps the current one.
  EXPECT_EQ(set(s, "model", "mlp_not_registered"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(s.last_error().find("mlp_not_registered"), std::string::npos) << s.last_error();
  EXPECT_EQ(s.property("model"), "mlp_add_ten");
  EXPECT_EQ(first_out(s, 5), 15);
}

// tests/data/python/identity.py returns its inputs; add.py the sum and product of two 2:2.
TEST_F(MlSingleProps, Python3ReloadGivesTheNewModelsOutput) {
  REQUIRE_BACKEND("python3");
  TensorsInfo in = info_of(ML_TENSOR_TYPE_FLOAT32, {{2, 2}, {2, 2}});
  Single s(python_script("identity.py"), "python3", &in);
  TensorsData x(in);
  const float a[4] = {1, 2, 3, 4}, b[4] = {0.5f, -1, 2, 10};
  std::memcpy(x.data(0), a, sizeof a);
  std::memcpy(x.data(1), b, sizeof b);
  TensorsData same = s.invoke(x);
  EXPECT_EQ(std::memcmp(same.data(1), b, sizeof b), 0);

  s.set_property("is-updatable", "true");
  s.set_property("model", python_script("add.py"));
  EXPECT_EQ(s.property("model"), python_script("add.py"));
  EXPECT_EQ(s.property("output"), "2:2,2:2");
  TensorsData r = s.invoke(x);
  const float sum[4] = {1.5f, 1, 5, 14}, prod[4] = {0.5f, -2, 6, 40};
  EXPECT_EQ(std::memcmp(r.data(0), sum, sizeof sum), 0);
  EXPECT_EQ(std::memcmp(r.data(1), prod, sizeof prod), 0);

  EXPECT_EQ(set(s, "model", "/nonexistent/script.py"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(s.last_error().find("/nonexistent/script.py"), std::string::npos) << s.last_error();
  EXPECT_EQ(std::memcmp(s.invoke(x).data(1), prod, sizeof prod), 0);
}

// custom= changes what the script does: identity.py doubles with 'double'; args.py has one
// output element per argument.
TEST_F(MlSingleProps, Python3CustomReopensTheModel) {
  REQUIRE_BACKEND("python3");
  TensorsInfo in = info_of(ML_TENSOR_TYPE_FLOAT32, {{3}});
  Single s(python_script("identity.py"), "python3", &in);
  TensorsData x(in);
  x.as<float>(0)[0] = 1.5f;
  x.as<float>(0)[2] = -4;
  EXPECT_EQ(s.invoke(x).as<float>(0)[2], -4);
  s.set_property("custom", "double");
  EXPECT_EQ(s.property("custom"), "double");
  TensorsData d = s.invoke(x);
  EXPECT_EQ(d.as<float>(0)[0], 3);
  EXPECT_EQ(d.as<float>(0)[2], -8);

  Single args(python_script("args.py"), ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY, nullptr, nullptr,
              "ab cde");
  EXPECT_EQ(args.property("framework"), "python3");
  EXPECT_EQ(args.property("output"), "2");
  args.set_property("custom", "a bb ccc");
  EXPECT_EQ(args.property("output"), "3");
  TensorsData one(args.input_info());
  TensorsData lens = args.invoke(one);
  ASSERT_EQ(lens.size(0), 3u);
  EXPECT_EQ(lens.as<uint8_t>(0)[2], 3);
}

// add_mul_dynamic.onnx (free batch axis): tensor properties go through ONNX Runtime; a custom
// key it does not know leaves the model as it was.
TEST_F(MlSingleProps, OnnxTensorPropertiesAndCustom) {
  REQUIRE_BACKEND("onnxruntime");
  REQUIRE_FILE(generated("add_mul_dynamic.onnx"));
  TensorsInfo in = info_of(ML_TENSOR_TYPE_FLOAT32, {{4, 3, 1}, {4, 3, 1}});
  Single s(generated("add_mul_dynamic.onnx"), "onnxruntime", &in);
  EXPECT_EQ(s.property("inputname"), "a,b");
  EXPECT_EQ(s.property("outputname"), "sum,product");
  s.set_property("input", "4:3:2,4:3:2");
  EXPECT_EQ(s.property("output"), "4:3:2,4:3:2");
  TensorsInfo in2 = s.input_info();
  TensorsData x(in2);
  for (int i = 0; i < 24; ++i) {
    x.as<float>(0)[i] = static_cast<float>(i);
    x.as<float>(1)[i] = 2;
  }
  TensorsData r = s.invoke(x);
  EXPECT_FLOAT_EQ(r.as<float>(0)[23], 25);
  EXPECT_FLOAT_EQ(r.as<float>(1)[23], 46);
  EXPECT_EQ(set(s, "inputtype", "int32,int32"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(s.property("inputtype"), "float32,float32");
  EXPECT_EQ(set(s, "output", "4:3:5,4:3:5"), ML_ERROR_INVALID_PARAMETER);

  EXPECT_EQ(set(s, "custom", "Bogus:1"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(s.last_error().find("Bogus"), std::string::npos) << s.last_error();
  EXPECT_EQ(s.property("custom"), "");
  s.set_property("custom", "NumThreads:1");
  EXPECT_EQ(s.property("custom"), "NumThreads:1");
  EXPECT_EQ(s.property("input"), "4:3:2,4:3:2");  // the reopened model keeps the input
  EXPECT_FLOAT_EQ(s.invoke(x).as<float>(1)[5], 10);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// Single-shot API: ml_single_invoke_dynamic, ml_single_set_input_info, ml_single_open_full and
// ml_single_open_with_option's keys, with custom-easy models, a python3 script whose output
// shape follows its input, ONNX Runtime with a free batch axis and LeNet on PyTorch.
#include <gtest/gtest.h>

#include <cerrno>
#include <cstdlib>
#include <cstring>
#include <vector>

#include "ml_single_test_util.h"
#include "nnstreamer-single.h"
#include "nnstreamer-single.hh"
#include "tensor_filter_custom_easy.h"

namespace {

using namespace nns::test::ml;
using nns::ml::Single;
using nns::ml::TensorsData;
using nns::ml::TensorsInfo;

// Dynamic: out0 = the uint8 input twice (2n elements), out1 = int32 {n}.
int repeat(void *, const GstTensorsInfo *in_info, GstTensorsInfo *out_info,
           const GstTensorMemory *in, GstTensorMemory *out) {
  size_t n = in[0].size;
  out_info->num_tensors = 2;
  out_info->info[0].type = _NNS_UINT8;
  out_info->info[0].dimension[0] = static_cast<uint32_t>(2 * n);
  out_info->info[1].type = _NNS_INT32;
  out_info->info[1].dimension[0] = 1;
  if (in_info->info[0].dimension[0] != n) return -22;
  out[0].size = 2 * n;
  out[0].data = std::malloc(2 * n);
  std::memcpy(out[0].data, in[0].data, n);
  std::memcpy(static_cast<uint8_t *>(out[0].data) + n, in[0].data, n);
  out[1].size = sizeof(int32_t);
  out[1].data = std::malloc(sizeof(int32_t));
  *static_cast<int32_t *>(out[1].data) = static_cast<int32_t>(n);
  return 0;
}

int add_one(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
            GstTensorMemory *out) {
  for (size_t k = 0; k < in[0].size; ++k)
    static_cast<uint8_t *>(out[0].data)[k] =
        static_cast<uint8_t>(static_cast<uint8_t *>(in[0].data)[k] + 1);
  return 0;
}

class MlSingleDynamic : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    GstTensorsInfo in{};
    in.num_tensors = 1;
    in.info[0].type = _NNS_UINT8;
    in.info[0].dimension[0] = 4;
    // Derived fixtures run this again: the names are then taken already.
    int rc = NNS_custom_easy_dynamic_register("mld_repeat", repeat, nullptr, &in);
    ASSERT_TRUE(rc == 0 || rc == -EEXIST) << rc;
    rc = NNS_custom_easy_register("mld_add_one", add_one, nullptr, &in, &in);
    ASSERT_TRUE(rc == 0 || rc == -EEXIST) << rc;
  }
};

TensorsData u8_data(const TensorsInfo &info, std::initializer_list<uint8_t> v) {
  TensorsData d(info);
  EXPECT_EQ(d.size(0), v.size());
  std::memcpy(d.data(0), std::data(v), v.size());
  return d;
}

TEST_F(MlSingleDynamic, CustomEasyOutputFollowsEachInput) {
  Single model("mld_repeat", "custom-easy");
  EXPECT_EQ(model.output_info().count(), 0u);  // decided per call
  TensorsInfo in3 = info_of(ML_TENSOR_TYPE_UINT8, {{3}});
  auto r = model.invoke_dynamic(u8_data(in3, {7, 8, 9}), in3);
  ASSERT_EQ(r.info.count(), 2u);
  EXPECT_EQ(r.info.dims(0), std::vector<unsigned>{6});
  EXPECT_EQ(r.info.type(1), ML_TENSOR_TYPE_INT32);
  ASSERT_EQ(r.data.size(0), 6u);
  const uint8_t want[] = {7, 8, 9, 7, 8, 9};
  EXPECT_EQ(std::memcmp(r.data.data(0), want, 6), 0);
  EXPECT_EQ(r.data.as<int32_t>(1)[0], 3);

  TensorsInfo in5 = info_of(ML_TENSOR_TYPE_UINT8, {{5}});
  auto r5 = model.invoke_dynamic(u8_data(in5, {1, 2, 3, 4, 5}), in5);
  EXPECT_EQ(r5.info.dims(0), std::vector<unsigned>{10});
  EXPECT_EQ(r5.data.as<uint8_t>(0)[9], 5);
  EXPECT_EQ(r5.data.as<int32_t>(1)[0], 5);

  // The handle follows the last call: plain invokes take 5 elements now.
  EXPECT_EQ(model.input_info().dims(0), std::vector<unsigned>{5});
  EXPECT_EQ(model.output_info().dims(0), std::vector<unsigned>{10});
  TensorsData out = model.invoke(u8_data(in5, {9, 9, 9, 9, 1}));
  EXPECT_EQ(out.as<uint8_t>(0)[4], 1);
  EXPECT_EQ(out.as<uint8_t>(0)[9], 1);
  TensorsData fast(model.output_info());
  model.invoke(u8_data(in5, {2, 2, 2, 2, 2}), fast);
  EXPECT_EQ(fast.as<uint8_t>(0)[7], 2);
  EXPECT_EQ(fast.as<int32_t>(1)[0], 5);
  TensorsData wrong_out(info_of(ML_TENSOR_TYPE_UINT8, {{4}, {1}}));
  EXPECT_EQ(
      ml_single_invoke_fast(model.get(), u8_data(in5, {1, 1, 1, 1, 1}).get(), wrong_out.get()),
      ML_ERROR_INVALID_PARAMETER);
  ml_tensors_data_h o = nullptr;
  EXPECT_EQ(ml_single_invoke(model.get(), u8_data(in3, {1, 1, 1}).get(), &o),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(model.last_error().find("takes 5"), std::string::npos) << model.last_error();
}

TEST_F(MlSingleDynamic, FixedModelSameShapeWorksOtherShapeFailsClearly) {
  Single model("mld_add_one", "custom-easy");
  TensorsInfo in4 = model.input_info();
  auto r = model.invoke_dynamic(u8_data(in4, {1, 2, 3, 250}), in4);
  ASSERT_EQ(r.info.count(), 1u);
  EXPECT_EQ(r.info.dims(0), std::vector<unsigned>{4});
  const uint8_t want[] = {2, 3, 4, 251};
  EXPECT_EQ(std::memcmp(r.data.data(0), want, 4), 0);

  TensorsInfo in8 = info_of(ML_TENSOR_TYPE_UINT8, {{8}});
  ml_tensors_data_h out = nullptr;
  ml_tensors_info_h out_info = nullptr;
  TensorsData d8(in8);
  EXPECT_EQ(ml_single_invoke_dynamic(model.get(), d8.get(), in8.get(), &out, &out_info),
            ML_ERROR_STREAMS_PIPE);
  EXPECT_EQ(out, nullptr);
  EXPECT_EQ(out_info, nullptr);
  EXPECT_NE(model.last_error().find("NNS_custom_easy_dynamic_register"), std::string::npos)
      << model.last_error();
  EXPECT_EQ(model.input_info().dims(0), std::vector<unsigned>{4});  // unchanged
  EXPECT_EQ(model.invoke(u8_data(in4, {0, 0, 0, 9})).as<uint8_t>(0)[3], 10);

  // Data that does not match in_info; NULL arguments.
  EXPECT_EQ(ml_single_invoke_dynamic(model.get(), u8_data(in4, {0, 0, 0, 0}).get(), in8.get(), &out,
                                     &out_info),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(model.last_error().find("has 4 bytes, the model takes 8"), std::string::npos)
      << model.last_error();
  EXPECT_EQ(ml_single_invoke_dynamic(model.get(), d8.get(), nullptr, &out, &out_info),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_single_invoke_dynamic(model.get(), d8.get(), in8.get(), nullptr, &out_info),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_single_invoke_dynamic(nullptr, d8.get(), in8.get(), &out, &out_info),
            ML_ERROR_INVALID_PARAMETER);
}

// tests/data/python/dynamic.py: out0 = (x * 2).T, out1 = int32 numpy shape of x.
TEST_F(MlSingleDynamic, Python3ScriptTransposes) {
  REQUIRE_BACKEND("python3");
  TensorsInfo in = info_of(ML_TENSOR_TYPE_FLOAT32, {{3, 2}});
  Single model(python_script("dynamic.py"), "python3", &in);
  TensorsData x(in);
  for (int i = 0; i < 6; ++i) x.as<float>(0)[i] = static_cast<float>(i);  // [[0,1,2],[3,4,5]]
  auto r = model.invoke_dynamic(x, in);
  ASSERT_EQ(r.info.count(), 2u);
  EXPECT_EQ(r.info.dims(0), (std::vector<unsigned>{2, 3}));  // numpy (3, 2)
  EXPECT_EQ(r.info.type(0), ML_TENSOR_TYPE_FLOAT32);
  const float want[] = {0, 6, 2, 8, 4, 10};
  ASSERT_EQ(r.data.size(0), sizeof want);
  EXPECT_EQ(std::memcmp(r.data.data(0), want, sizeof want), 0);
  EXPECT_EQ(r.info.type(1), ML_TENSOR_TYPE_INT32);
  EXPECT_EQ(r.data.as<int32_t>(1)[0], 2);
  EXPECT_EQ(r.data.as<int32_t>(1)[1], 3);

  TensorsInfo in2 = info_of(ML_TENSOR_TYPE_FLOAT32, {{5, 4}});
  TensorsData y(in2);
  for (int i = 0; i < 20; ++i) y.as<float>(0)[i] = 0.5f * static_cast<float>(i);
  auto r2 = model.invoke_dynamic(y, in2);
  EXPECT_EQ(r2.info.dims(0), (std::vector<unsigned>{4, 5}));
  // Transposed: element (col c, row k) of the output is 2 * x[k][c].
  EXPECT_FLOAT_EQ(r2.data.as<float>(0)[1], 2 * 0.5f * 5);  // out[0][1] = 2 * x[1][0]
  EXPECT_FLOAT_EQ(r2.data.as<float>(0)[4 * 2 + 3], 2 * 0.5f * (3 * 5 + 2));
  EXPECT_EQ(r2.data.as<int32_t>(1)[0], 4);
  EXPECT_EQ(r2.data.as<int32_t>(1)[1], 5);
}

// add_mul_dynamic.onnx: sum and product of a, b float32 [batch, 3, 4].
class OnnxBatch : public MlSingleDynamic {
 protected:
  void SetUp() override {
    if (!backend_built("onnxruntime")) GTEST_SKIP() << "the onnxruntime back end is not built";
    if (!std::filesystem::exists(generated("add_mul_dynamic.onnx")))
      GTEST_SKIP() << "generated test models missing (target nns_test_models)";
    a1 = read_floats(generated("add_mul_dynamic.in0.raw"));
    b1 = read_floats(generated("add_mul_dynamic.in1.raw"));
    ASSERT_EQ(a1.size(), 12u);
    ASSERT_EQ(b1.size(), 12u);
  }
  // Batch n: sample k is the reference input plus k.
  TensorsData batch(const TensorsInfo &info, unsigned n) const {
    TensorsData d(info);
    for (unsigned k = 0; k < n; ++k)
      for (unsigned i = 0; i < 12; ++i) {
        d.as<float>(0)[k * 12 + i] = a1[i] + static_cast<float>(k);
        d.as<float>(1)[k * 12 + i] = b1[i] - static_cast<float>(k);
      }
    return d;
  }
  void expect_sums(const TensorsData &out, unsigned n) const {
    std::vector<float> sum, prod;
    for (unsigned k = 0; k < n; ++k)
      for (unsigned i = 0; i < 12; ++i) {
        float a = a1[i] + static_cast<float>(k), b = b1[i] - static_cast<float>(k);
        sum.push_back(a + b);
        prod.push_back(a * b);
      }
    ASSERT_EQ(out.size(0), n * 48u);
    expect_near_all(out.as<float>(0), sum);
    expect_near_all(out.as<float>(1), prod);
  }
  std::vector<float> a1, b1;
};

TEST_F(OnnxBatch, InvokeDynamicChangesTheBatch) {
  TensorsInfo in1 = info_of(ML_TENSOR_TYPE_FLOAT32, {{4, 3, 1}, {4, 3, 1}});
  Single model(generated("add_mul_dynamic.onnx"), "onnxruntime", &in1);
  TensorsInfo in2 = info_of(ML_TENSOR_TYPE_FLOAT32, {{4, 3, 2}, {4, 3, 2}});
  auto r = model.invoke_dynamic(batch(in2, 2), in2);
  ASSERT_EQ(r.info.count(), 2u);
  EXPECT_EQ(r.info.dims(1), (std::vector<unsigned>{4, 3, 2}));
  expect_sums(r.data, 2);
  // The handle now takes batch 2 through plain invoke too.
  EXPECT_EQ(model.input_info().dims(0), (std::vector<unsigned>{4, 3, 2}));
  expect_sums(model.invoke(batch(in2, 2)), 2);
  // Back to batch 1: torch's reference output.
  auto r1 = model.invoke_dynamic(batch(in1, 1), in1);
  expect_near_all(r1.data.as<float>(0), read_floats(generated("add_mul_dynamic.out0.raw")));
  expect_near_all(r1.data.as<float>(1), read_floats(generated("add_mul_dynamic.out1.raw")));
}

TEST_F(OnnxBatch, SetInputInfoResizesTheOutput) {
  TensorsInfo in1 = info_of(ML_TENSOR_TYPE_FLOAT32, {{4, 3, 1}, {4, 3, 1}});
  Single model(generated("add_mul_dynamic.onnx"), "onnxruntime", &in1);
  TensorsInfo in3 = info_of(ML_TENSOR_TYPE_FLOAT32, {{4, 3, 3}, {4, 3, 3}});
  model.set_input_info(in3);
  TensorsInfo out = model.output_info();
  ASSERT_EQ(out.count(), 2u);
  EXPECT_EQ(out.dims(0), (std::vector<unsigned>{4, 3, 3}));
  EXPECT_EQ(out.size(), 2u * 36 * 4);
  expect_sums(model.invoke(batch(in3, 3)), 3);
  // The model takes float32 only.
  TensorsInfo ints = info_of(ML_TENSOR_TYPE_INT32, {{4, 3, 1}, {4, 3, 1}});
  EXPECT_EQ(ml_single_set_input_info(model.get(), ints.get()), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(model.last_error().find("int32"), std::string::npos) << model.last_error();
  EXPECT_EQ(model.input_info().dims(0), (std::vector<unsigned>{4, 3, 3}));  // kept
  TensorsInfo empty;
  EXPECT_EQ(ml_single_set_input_info(model.get(), empty.get()), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_single_set_input_info(model.get(), nullptr), ML_ERROR_INVALID_PARAMETER);
}

TEST_F(MlSingleDynamic, SetInputInfoNotSupportedByAFixedModel) {
  Single model("mld_add_one", "custom-easy");
  model.set_input_info(model.input_info());  // the same shapes: nothing to change
  TensorsInfo in8 = info_of(ML_TENSOR_TYPE_UINT8, {{8}});
  EXPECT_EQ(ml_single_set_input_info(model.get(), in8.get()), ML_ERROR_NOT_SUPPORTED);
  std::string err = model.last_error();
  EXPECT_NE(err.find("mld_add_one"), std::string::npos) << err;
  EXPECT_NE(err.find("uint8 8"), std::string::npos) << err;
}

// LeNet on PyTorch: 9.raw is a 9.
class Lenet : public MlSingleDynamic {
 protected:
  void SetUp() override {
    if (!backend_built("pytorch")) GTEST_SKIP() << "the pytorch back end is not built";
    std::string shared = shared_models();
    if (shared.empty()) GTEST_SKIP() << "../shared/models is not beside the project";
    model = shared + "/models/pytorch_lenet5.pt";
    digit = read_all(shared + "/data/9.raw");
    ASSERT_EQ(digit.size(), 28u * 28);
  }
  static unsigned best(const TensorsData &out) {
    const uint8_t *s = out.as<uint8_t>(0);
    unsigned b = 0;
    for (unsigned i = 1; i < 10; ++i)
      if (s[i] > s[b]) b = i;
    return b;
  }
  unsigned classify(Single &s) const {
    TensorsData in(s.input_info());
    std::memcpy(in.data(0), digit.data(), digit.size());
    return best(s.invoke(in));
  }
  TensorsInfo in = info_of(ML_TENSOR_TYPE_UINT8, {{1, 28, 28, 1}});
  TensorsInfo out = info_of(ML_TENSOR_TYPE_UINT8, {{10, 1}});
  std::string model;
  std::vector<uint8_t> digit;
};

TEST_F(Lenet, OpenFullPassesTheCustomOption) {
  Single s(model, ML_NNFW_TYPE_PYTORCH, ML_NNFW_HW_CPU, &in, &out, "NumThreads:1");
  EXPECT_EQ(classify(s), 9u);
  EXPECT_EQ(s.property("custom"), "NumThreads:1");
  EXPECT_EQ(s.property("accelerator"), "true:cpu");
  ml_single_h h = nullptr;
  EXPECT_EQ(ml_single_open_full(&h, model.c_str(), in.get(), out.get(), ML_NNFW_TYPE_PYTORCH,
                                ML_NNFW_HW_ANY, "Bogus_Key:1"),
            ML_ERROR_STREAMS_PIPE);
  EXPECT_EQ(h, nullptr);
  EXPECT_NE(std::string(ml_error()).find("Bogus_Key"), std::string::npos) << ml_error();
  // The given output must match the model's (PyTorch checks it while opening: a failed open
  // is ML_ERROR_STREAMS_PIPE, as NNStreamer's failed start).
  TensorsInfo out11 = info_of(ML_TENSOR_TYPE_UINT8, {{11, 1}});
  EXPECT_EQ(ml_single_open_full(&h, model.c_str(), in.get(), out11.get(), ML_NNFW_TYPE_PYTORCH,
                                ML_NNFW_HW_ANY, nullptr),
            ML_ERROR_STREAMS_PIPE);
  EXPECT_NE(std::string(ml_error()).find("11:1"), std::string::npos) << ml_error();
}

TEST_F(Lenet, OpenWithOptionKeys) {
  ml_option_h opt = nullptr;
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  ml_nnfw_type_e nnfw = ML_NNFW_TYPE_PYTORCH;
  ml_nnfw_hw_e hw = ML_NNFW_HW_CPU;
  char custom[] = "NumThreads:1";
  ml_option_set(opt, "models", model.data(), nullptr);
  ml_option_set(opt, "nnfw", &nnfw, nullptr);
  ml_option_set(opt, "hw", &hw, nullptr);
  ml_option_set(opt, "input_info", in.get(), nullptr);
  ml_option_set(opt, "output_info", out.get(), nullptr);
  ml_option_set(opt, "custom", custom, nullptr);
  ml_single_h h = nullptr;
  ASSERT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_NONE) << ml_error();
  Single s = Single::adopt(h);
  EXPECT_EQ(classify(s), 9u);
  EXPECT_EQ(s.property("framework"), "pytorch");
  EXPECT_EQ(s.property("accelerator"), "true:cpu");
  EXPECT_EQ(s.property("custom"), "NumThreads:1");

  // "framework" (NNStreamer's other key) wins over "nnfw".
  char fw[] = "no-such-framework";
  ml_option_set(opt, "framework", fw, nullptr);
  EXPECT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_NOT_SUPPORTED);
  EXPECT_NE(std::string(ml_error()).find("no-such-framework"), std::string::npos) << ml_error();
  ml_option_destroy(opt);

  // Option values of the wrong kind.
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  ml_option_set(opt, "models", model.data(), nullptr);
  uint32_t not_info[4] = {0, 0, 0, 0};
  ml_option_set(opt, "input_info", not_info, nullptr);
  EXPECT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("input_info"), std::string::npos) << ml_error();
  TensorsInfo incomplete;
  incomplete.set_count(1);
  ml_option_set(opt, "input_info", incomplete.get(), nullptr);
  EXPECT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("incomplete"), std::string::npos) << ml_error();
  ml_nnfw_type_e bad = static_cast<ml_nnfw_type_e>(999);
  ml_option_set(opt, "input_info", in.get(), nullptr);
  ml_option_set(opt, "nnfw", &bad, nullptr);
  EXPECT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("999"), std::string::npos) << ml_error();
  ml_option_destroy(opt);
  EXPECT_EQ(ml_single_open_with_option(&h, nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_single_open_with_option(&h, not_info), ML_ERROR_INVALID_PARAMETER);
}

}  // namespace

namespace {

// add.tflite (x + 2, float32 [1]) on the tflite back end: opening with other input info,
// ml_single_set_input_info and ml_single_invoke_dynamic resize the graph.
TEST_F(MlSingleDynamic, TfliteShapesFollowTheInput) {
  REQUIRE_BACKEND("tensorflow2-lite");
  std::string path = shared_models() + "/models/add.tflite";
  if (shared_models().empty()) GTEST_SKIP() << "../shared/models missing";
  TensorsInfo in4 = info_of(ML_TENSOR_TYPE_FLOAT32, {{4}});
  Single opened(path, ML_NNFW_TYPE_TENSORFLOW_LITE, ML_NNFW_HW_ANY, &in4);
  EXPECT_EQ(opened.output_info().dims(0), std::vector<unsigned>{4});
  Single model(path, "tensorflow-lite");
  model.set_input_info(in4);
  EXPECT_EQ(model.output_info().dims(0), std::vector<unsigned>{4});
  TensorsData d(in4);
  for (int i = 0; i < 4; ++i) d.as<float>(0)[i] = static_cast<float>(i);
  TensorsData o = model.invoke(d);
  expect_near_all(o.as<float>(0), {2, 3, 4, 5});
  TensorsInfo in3 = info_of(ML_TENSOR_TYPE_FLOAT32, {{3}});
  TensorsData d3(in3);
  for (int i = 0; i < 3; ++i) d3.as<float>(0)[i] = 10.f * static_cast<float>(i);
  auto r = model.invoke_dynamic(d3, in3);
  EXPECT_EQ(r.info.dims(0), std::vector<unsigned>{3});
  expect_near_all(r.data.as<float>(0), {2, 12, 22});
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// The single-shot API, used the way an application does: linked only against
// libnnstreamer-single (not the GStreamer plugin), through the C API and the C++ wrapper.
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <thread>
#include <vector>

#include "nnstreamer-single.h"
#include "nnstreamer-single.hh"
#include "tensor_filter_custom_easy.h"

namespace {

GstTensorsInfo u8_info(unsigned n) {
  GstTensorsInfo info{};
  info.num_tensors = 1;
  info.info[0].type = _NNS_UINT8;
  info.info[0].dimension[0] = n;
  return info;
}

// out = in + 1 (uint8, 4 elements)
int add_one(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
            GstTensorMemory *out) {
  auto *i = static_cast<const uint8_t *>(in[0].data);
  auto *o = static_cast<uint8_t *>(out[0].data);
  for (size_t k = 0; k < in[0].size; ++k) o[k] = static_cast<uint8_t>(i[k] + 1);
  return 0;
}

int slow_copy(void *, const GstTensorFilterProperties *, const GstTensorMemory *in,
              GstTensorMemory *out) {
  std::this_thread::sleep_for(std::chrono::milliseconds(300));
  std::memcpy(out[0].data, in[0].data, in[0].size);
  return 0;
}

int failing(void *, const GstTensorFilterProperties *, const GstTensorMemory *, GstTensorMemory *) {
  return -5;
}

class MlSingle : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    GstTensorsInfo in = u8_info(4), out = u8_info(4);
    ASSERT_EQ(NNS_custom_easy_register("ml_add_one", add_one, nullptr, &in, &out), 0);
    ASSERT_EQ(NNS_custom_easy_register("ml_slow", slow_copy, nullptr, &in, &out), 0);
    ASSERT_EQ(NNS_custom_easy_register("ml_fail", failing, nullptr, &in, &out), 0);
  }
};

std::string shared_models() {
  std::filesystem::path p =
      std::filesystem::path(NNS_SOURCE_DIR) / ".." / "shared" / "models" / "upstream";
  return std::filesystem::exists(p) ? std::filesystem::canonical(p).string() : "";
}

std::vector<uint8_t> read_all(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  return {std::istreambuf_iterator<char>(f), std::istreambuf_iterator<char>()};
}

TEST_F(MlSingle, CustomEasyOpenQueryInvokeClose) {
  ml_single_h h = nullptr;
  ml_option_h opt = nullptr;
  ASSERT_EQ(ml_option_create(&opt), ML_ERROR_NONE);
  char models[] = "ml_add_one", fw[] = "custom-easy";
  ml_option_set(opt, "models", models, nullptr);
  ml_option_set(opt, "framework_name", fw, nullptr);
  ASSERT_EQ(ml_single_open_with_option(&h, opt), ML_ERROR_NONE) << ml_error();
  ml_option_destroy(opt);

  ml_tensors_info_h in_info = nullptr, out_info = nullptr;
  ASSERT_EQ(ml_single_get_input_info(h, &in_info), ML_ERROR_NONE);
  ASSERT_EQ(ml_single_get_output_info(h, &out_info), ML_ERROR_NONE);
  unsigned count = 0;
  ml_tensors_info_get_count(in_info, &count);
  EXPECT_EQ(count, 1u);
  ml_tensor_type_e type;
  ml_tensors_info_get_tensor_type(out_info, 0, &type);
  EXPECT_EQ(type, ML_TENSOR_TYPE_UINT8);
  ml_tensor_dimension dim;
  ml_tensors_info_get_tensor_dimension(in_info, 0, dim);
  EXPECT_EQ(dim[0], 4u);
  size_t size = 0;
  ml_tensors_info_get_tensor_size(in_info, -1, &size);
  EXPECT_EQ(size, 4u);

  ml_tensors_data_h in = nullptr, out = nullptr;
  ASSERT_EQ(ml_tensors_data_create(in_info, &in), ML_ERROR_NONE);
  uint8_t v[4] = {1, 2, 3, 255};
  ASSERT_EQ(ml_tensors_data_set_tensor_data(in, 0, v, 4), ML_ERROR_NONE);
  ASSERT_EQ(ml_single_invoke(h, in, &out), ML_ERROR_NONE) << ml_error();
  void *raw = nullptr;
  ASSERT_EQ(ml_tensors_data_get_tensor_data(out, 0, &raw, &size), ML_ERROR_NONE);
  ASSERT_EQ(size, 4u);
  const uint8_t want[4] = {2, 3, 4, 0};
  EXPECT_EQ(std::memcmp(raw, want, 4), 0);

  // invoke_fast into caller-created output
  ml_tensors_data_h out2 = nullptr;
  ASSERT_EQ(ml_tensors_data_create(out_info, &out2), ML_ERROR_NONE);
  ASSERT_EQ(ml_single_invoke_fast(h, in, out2), ML_ERROR_NONE);
  ml_tensors_data_get_tensor_data(out2, 0, &raw, &size);
  EXPECT_EQ(std::memcmp(raw, want, 4), 0);

  char *prop = nullptr;
  ASSERT_EQ(ml_single_get_property(h, "input", &prop), ML_ERROR_NONE);
  EXPECT_STREQ(prop, "4");
  free(prop);
  ASSERT_EQ(ml_single_get_property(h, "outputtype", &prop), ML_ERROR_NONE);
  EXPECT_STREQ(prop, "uint8");
  free(prop);

  ml_tensors_data_destroy(out2);
  ml_tensors_data_destroy(out);
  ml_tensors_data_destroy(in);
  ml_tensors_info_destroy(in_info);
  ml_tensors_info_destroy(out_info);
  EXPECT_EQ(ml_single_close(h), ML_ERROR_NONE);
}

TEST_F(MlSingle, CppWrapper) {
  nns::ml::Single model("ml_add_one", "custom-easy");
  nns::ml::TensorsData in(model.input_info());
  auto *p = in.as<uint8_t>(0);
  for (int i = 0; i < 4; ++i) p[i] = static_cast<uint8_t>(10 * i);
  nns::ml::TensorsData out = model.invoke(in);
  ASSERT_EQ(out.size(0), 4u);
  EXPECT_EQ(out.as<uint8_t>(0)[3], 31);
  try {
    nns::ml::Single bad("/nonexistent/model.so", "custom");
    FAIL() << "no exception";
  } catch (const nns::ml::Error &e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/model.so"), std::string::npos) << e.what();
  }
}

TEST_F(MlSingle, ErrorsNameTheCause) {
  ml_single_h h = nullptr;
  // Unknown framework name through the option path
  nns::ml::TensorsInfo info;
  EXPECT_THROW(nns::ml::Single("ml_add_one", "no-such-framework"), nns::ml::Error);
  // Missing model file
  EXPECT_EQ(ml_single_open(&h, "/nonexistent/filter.so", nullptr, nullptr,
                           ML_NNFW_TYPE_CUSTOM_FILTER, ML_NNFW_HW_ANY),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(h, nullptr);
  EXPECT_NE(std::string(ml_error()).find("/nonexistent/filter.so"), std::string::npos)
      << ml_error();
  // Bad arguments
  EXPECT_EQ(ml_single_open(nullptr, "x", nullptr, nullptr, ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(
      ml_single_open(&h, "x", nullptr, nullptr, static_cast<ml_nnfw_type_e>(999), ML_NNFW_HW_ANY),
      ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_single_invoke(nullptr, nullptr, nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_tensors_info_set_count(info.get(), 0), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_tensors_info_set_tensor_type(info.get(), 3, ML_TENSOR_TYPE_UINT8),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("index 3"), std::string::npos) << ml_error();

  // Input that does not match the model
  nns::ml::Single model("ml_add_one", "custom-easy");
  nns::ml::TensorsInfo wrong;
  wrong.set_count(1).set(0, ML_TENSOR_TYPE_UINT8, {8});
  nns::ml::TensorsData in(wrong);
  ml_tensors_data_h out = nullptr;
  EXPECT_EQ(ml_single_invoke(model.get(), in.get(), &out), ML_ERROR_INVALID_PARAMETER);
  std::string err = ml_single_get_last_error(model.get());
  EXPECT_NE(err.find("8 bytes"), std::string::npos) << err;
  EXPECT_NE(err.find("takes 4"), std::string::npos) << err;

  // A back end whose invoke fails
  nns::ml::Single f("ml_fail", "custom-easy");
  nns::ml::TensorsData fin(f.input_info());
  EXPECT_EQ(ml_single_invoke(f.get(), fin.get(), &out), ML_ERROR_STREAMS_PIPE);
  EXPECT_NE(std::string(ml_single_get_last_error(f.get())).find("ml_fail"), std::string::npos)
      << ml_single_get_last_error(f.get());
}

TEST_F(MlSingle, TimeoutThenRecovers) {
  nns::ml::Single model("ml_slow", "custom-easy");
  model.set_timeout(50);
  nns::ml::TensorsData in(model.input_info());
  in.as<uint8_t>(0)[0] = 7;
  ml_tensors_data_h out = nullptr;
  EXPECT_EQ(ml_single_invoke(model.get(), in.get(), &out), ML_ERROR_TIMED_OUT);
  // Still busy with the timed-out call (300 ms): the time-out did cut the wait.
  EXPECT_EQ(ml_single_invoke(model.get(), in.get(), &out), ML_ERROR_TRY_AGAIN);
  // Once the late call has ended the handle works again (polled: no wall-clock assumption).
  model.set_timeout(10000);
  int rc = ML_ERROR_TRY_AGAIN;
  for (int i = 0; i < 200 && rc == ML_ERROR_TRY_AGAIN; ++i) {
    rc = ml_single_invoke(model.get(), in.get(), &out);
    if (rc == ML_ERROR_TRY_AGAIN) std::this_thread::sleep_for(std::chrono::milliseconds(50));
  }
  ASSERT_EQ(rc, ML_ERROR_NONE) << ml_error();
  nns::ml::TensorsData o(out);
  EXPECT_EQ(o.as<uint8_t>(0)[0], 7);
}

TEST_F(MlSingle, MobilenetOnnxruntimeOrange) {
  std::string shared = shared_models();
  if (shared.empty()) GTEST_SKIP() << "../shared/models is not beside the project";
  std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_onnxruntime.so";
  if (!std::filesystem::exists(so)) GTEST_SKIP() << so << " is not built";
  ml_single_h h = nullptr;
  ASSERT_EQ(ml_single_open(&h, (shared + "/models/mobilenet_v2_quant.onnx").c_str(), nullptr,
                           nullptr, ML_NNFW_TYPE_ONNX_RUNTIME, ML_NNFW_HW_ANY),
            ML_ERROR_NONE)
      << ml_error();
  nns::ml::TensorsInfo in_info = [&] {
    ml_tensors_info_h i;
    ml_single_get_input_info(h, &i);
    return nns::ml::TensorsInfo(i);
  }();
  // The model (a PyTorch export) takes float32 CHW with torchvision's ImageNet normalisation;
  // orange.raw is HWC uint8.
  EXPECT_EQ(in_info.size(), 224u * 224 * 3 * 4);
  nns::ml::TensorsData in(in_info);
  auto raw = read_all(shared + "/data/orange.raw");
  ASSERT_EQ(raw.size(), 224u * 224 * 3);
  float *chw = in.as<float>(0);
  const float mean[3] = {123.675f, 116.28f, 103.53f}, stdev[3] = {58.395f, 57.12f, 57.375f};
  for (size_t y = 0; y < 224; ++y)
    for (size_t x = 0; x < 224; ++x)
      for (size_t c = 0; c < 3; ++c)
        chw[c * 224 * 224 + y * 224 + x] = (raw[(y * 224 + x) * 3 + c] - mean[c]) / stdev[c];
  ml_tensors_data_h out = nullptr;
  ASSERT_EQ(ml_single_invoke(h, in.get(), &out), ML_ERROR_NONE) << ml_error();
  nns::ml::TensorsData o(out);
  ASSERT_EQ(o.size(0), 4000u);
  const float *s = o.as<float>(0);
  size_t best = 0;
  for (size_t i = 1; i < 1000; ++i)
    if (s[i] > s[best]) best = i;
  // "orange" in the 1000-class ImageNet order (the index tensor_filter's pipeline test expects)
  EXPECT_EQ(best, 950u);
  ml_single_close(h);
}

TEST_F(MlSingle, LenetPytorchNine) {
  std::string shared = shared_models();
  if (shared.empty()) GTEST_SKIP() << "../shared/models is not beside the project";
  std::string so =
      std::string(NNS_BUILD_DIR) + "/subplugins/filters/libnnstreamer_filter_pytorch.so";
  if (!std::filesystem::exists(so)) GTEST_SKIP() << so << " is not built";
  nns::ml::TensorsInfo in_info, out_info;
  in_info.set_count(1).set(0, ML_TENSOR_TYPE_UINT8, {1, 28, 28, 1});
  out_info.set_count(1).set(0, ML_TENSOR_TYPE_UINT8, {10, 1});
  nns::ml::Single model(shared + "/models/pytorch_lenet5.pt", "pytorch", &in_info, &out_info);
  nns::ml::TensorsData in(model.input_info());
  auto raw = read_all(shared + "/data/9.raw");
  ASSERT_EQ(raw.size(), in.size(0));
  std::memcpy(in.data(0), raw.data(), raw.size());
  nns::ml::TensorsData out = model.invoke(in);
  const uint8_t *s = out.as<uint8_t>(0);
  size_t best = 0;
  for (size_t i = 1; i < 10; ++i)
    if (s[i] > s[best]) best = i;
  EXPECT_EQ(best, 9u);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// The opencv filter back end through its C ABI: Caffe LeNet (two model files), Darknet
// .cfg + .weights (generated, numpy reference), TensorFlow graph with input=, ONNX info read from
// the file, custom= keys and error texts.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace nns::test {
namespace {

class OpenCv : public ::testing::Test {
 protected:
  void SetUp() override {
    const BackendLib &b = backend_lib("opencv");
    if (!b.ok()) GTEST_SKIP() << "opencv back end unavailable: " << b.error();
    api_ = b.api();
  }
  std::unique_ptr<Instance> open(Props &p, std::string *err = nullptr, int *rc = nullptr) {
    return Instance::open(api_, p, rc, err);
  }
  std::string open_error(Props &p, int *rc = nullptr) {
    std::string err;
    auto inst = open(p, &err, rc);
    EXPECT_EQ(inst, nullptr) << "open unexpectedly succeeded";
    return err;
  }
  static std::string prototxt() {
    return std::string(NNS_SOURCE_DIR) + "/tests/data/lenet_deploy.prototxt";
  }
  const nns_filter_backend_i *api_ = nullptr;
};

// 9.raw (28x28 gray) as float32 (x - 127.5) / 127.5.
std::vector<float> nine() {
  std::vector<uint8_t> raw = read_file(shared_models_dir() + "/data/9.raw");
  std::vector<float> f(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) f[i] = (raw[i] - 127.5f) / 127.5f;
  return f;
}

TEST_F(OpenCv, TableDescribesBackEnd) {
  EXPECT_STREQ(api_->name, "opencv");
  EXPECT_FALSE(api_->flags & NNS_FILTER_FLAG_THREAD_SAFE);
  ASSERT_NE(api_->extensions, nullptr);
}

TEST_F(OpenCv, CaffeLenetClassifiesNine) {
  NNS_REQUIRE_SHARED_MODELS();
  std::string caffemodel = shared_models_dir() + "/models/lenet_iter_9000.caffemodel";
  // Either order of the two files works.
  for (auto files : {std::vector<std::string>{prototxt(), caffemodel},
                     std::vector<std::string>{caffemodel, prototxt()}}) {
    Props p;
    p.models = files;
    std::string err;
    auto inst = open(p, &err);
    ASSERT_TRUE(inst) << err;
    nns_tensors_desc in{}, out{};
    ASSERT_EQ(inst->model_info(in, out, &err), 0) << err;
    ASSERT_EQ(in.num_tensors, 1u);
    EXPECT_EQ(desc_string(in.tensors[0]), "float32 28:28:1:1");
    ASSERT_EQ(out.num_tensors, 1u);
    EXPECT_EQ(desc_string(out.tensors[0]), "'prob' float32 10:1");
    std::vector<float> x = nine(), prob(10);
    ASSERT_EQ(x.size(), 784u);
    std::vector<GstTensorMemory> i = {{x.data(), 784 * 4}}, o = {{prob.data(), 40}};
    ASSERT_EQ(inst->invoke(i, o, &err), 0) << err;
    EXPECT_EQ(std::max_element(prob.begin(), prob.end()) - prob.begin(), 9);
    EXPECT_GT(prob[9], 0.99f);
  }
}

TEST_F(OpenCv, OnnxInfoIsReadFromTheFile) {
  auto m = load_ref("add_mul");
  ASSERT_TRUE(m) << "generated models missing in " << models_dir();
  Props p;
  p.models = {m->file("onnx")};
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  ASSERT_EQ(in.num_tensors, 2u);
  EXPECT_EQ(desc_string(in.tensors[0]), "'a' float32 4:3:1");
  EXPECT_EQ(desc_string(in.tensors[1]), "'b' float32 4:3:1");
  ASSERT_EQ(out.num_tensors, 2u);  // in the graph's order, not OpenCV's
  EXPECT_EQ(desc_string(out.tensors[0]), "'sum' float32 4:3:1");
  EXPECT_EQ(desc_string(out.tensors[1]), "'product' float32 4:3:1");

  auto u = load_ref("uint8_scale");
  ASSERT_TRUE(u);
  p.models = {u->file("onnx")};
  inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  ASSERT_EQ(inst->model_info(in, out), 0);
  EXPECT_EQ(desc_string(in.tensors[0]), "'pixels' uint8 3:8:8:1");
}

// tests/data/generate_models.py's tiny_darknet: conv3x3 (leaky) -> maxpool -> connected, with
// known weights; OpenCV's output must match the generator's numpy reference within 1e-5.
TEST_F(OpenCv, DarknetMatchesNumpyReference) {
  auto m = load_ref("tiny_darknet");
  ASSERT_TRUE(m) << "generated models missing in " << models_dir();
  std::string cfg = m->file("darknet_cfg"), weights = m->file("darknet_weights");
  ASSERT_EQ(m->inputs.size(), 1u);
  ASSERT_EQ(m->outputs.size(), 1u);
  // Either order of the two files works (classified by extension).
  for (auto files :
       {std::vector<std::string>{cfg, weights}, std::vector<std::string>{weights, cfg}}) {
    Props p;
    p.models = files;
    std::string err;
    auto inst = open(p, &err);
    ASSERT_TRUE(inst) << files[0] << "," << files[1] << ": " << err;
    nns_tensors_desc in{}, out{};
    ASSERT_EQ(inst->model_info(in, out, &err), 0) << err;
    ASSERT_EQ(in.num_tensors, 1u);
    EXPECT_EQ(desc_string(in.tensors[0]), "float32 8:6:3:1");  // [net] channels, height, width
    ASSERT_EQ(out.num_tensors, 1u);
    EXPECT_EQ(desc_string(out.tensors[0]), "'fullyConnected_2' float32 5:1");

    std::vector<uint8_t> x = m->inputs[0].bytes;
    std::vector<float> y(5, -999.f);
    std::vector<GstTensorMemory> i = {{x.data(), x.size()}}, o = {{y.data(), y.size() * 4}};
    ASSERT_EQ(inst->invoke(i, o, &err), 0) << err;
    EXPECT_EQ(compare(m->outputs[0], reinterpret_cast<const uint8_t *>(y.data()), y.size() * 4,
                      1e-5, 0.0),
              "");
  }
}

TEST_F(OpenCv, DarknetFileErrors) {
  auto m = load_ref("tiny_darknet");
  ASSERT_TRUE(m) << "generated models missing in " << models_dir();
  std::string cfg = m->file("darknet_cfg"), weights = m->file("darknet_weights");
  Props p;
  p.models = {cfg};
  std::string err = open_error(p);
  EXPECT_NE(err.find("only the configuration file " + cfg), std::string::npos) << err;
  EXPECT_NE(err.find(".weights"), std::string::npos) << err;

  p.models = {weights};
  err = open_error(p);
  EXPECT_NE(err.find(weights + " needs its network description (.cfg)"), std::string::npos) << err;

  int rc = 0;
  std::string missing = models_dir() + "/no_such_net.weights";
  p.models = {cfg, missing};
  err = open_error(p, &rc);
  EXPECT_EQ(rc, -ENOENT);
  EXPECT_NE(err.find(missing + ": model file not found"), std::string::npos) << err;

  // OpenCV itself loads a short .weights file as a network of garbage: the back end refuses it.
  std::string dir = make_temp_dir();
  std::vector<uint8_t> bytes = read_file(weights);
  ASSERT_EQ(bytes.size(), 20u + 4u * (4 + 4 * 3 * 3 * 3 + 5 + 5 * 4 * 3 * 4));
  std::string cut = dir + "/cut.weights";
  {
    std::ofstream f(cut, std::ios::binary);
    f.write(reinterpret_cast<const char *>(bytes.data()), 100);
  }
  p.models = {cut, cfg};
  err = open_error(p);
  EXPECT_NE(err.find(cut + ": Darknet weights file has 100 bytes, but its .cfg needs 1448"),
            std::string::npos)
      << err;
  std::filesystem::remove_all(dir);
}

TEST_F(OpenCv, TensorflowGraphNeedsInputProperty) {
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {shared_models_dir() + "/models/mnist.pb"};
  std::string err = open_error(p);
  EXPECT_NE(err.find("mnist.pb"), std::string::npos) << err;
  EXPECT_NE(err.find("not known from the model"), std::string::npos) << err;
  EXPECT_NE(err.find("input="), std::string::npos) << err;

  p.input.num_tensors = 1;
  p.input.tensors[0] = make_desc("", _NNS_FLOAT32, "784:1");
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  EXPECT_EQ(desc_string(out.tensors[0]), "'softmax' float32 10:1");
  std::vector<uint8_t> raw = read_file(shared_models_dir() + "/data/9.raw");
  std::vector<float> x(784), prob(10);
  for (int k = 0; k < 784; ++k) x[k] = raw[k] / 255.f;
  std::vector<GstTensorMemory> i = {{x.data(), 784 * 4}}, o = {{prob.data(), 40}};
  ASSERT_EQ(inst->invoke(i, o, &err), 0) << err;
  EXPECT_EQ(std::max_element(prob.begin(), prob.end()) - prob.begin(), 9);
}

TEST_F(OpenCv, ModelFileErrors) {
  NNS_REQUIRE_SHARED_MODELS();
  std::string caffemodel = shared_models_dir() + "/models/lenet_iter_9000.caffemodel";
  Props p;
  p.models = {caffemodel};
  std::string err = open_error(p);
  EXPECT_NE(err.find(".prototxt"), std::string::npos) << err;

  p.models = {prototxt()};
  err = open_error(p);
  EXPECT_NE(err.find("weights"), std::string::npos) << err;

  p.models = {prototxt(), prototxt()};
  err = open_error(p);
  EXPECT_NE(err.find("two configuration files"), std::string::npos) << err;

  p.models = {std::string(NNS_SOURCE_DIR) + "/tests/data/generate_models.py"};
  err = open_error(p);
  EXPECT_NE(err.find("unknown model file type '.py'"), std::string::npos) << err;

  int rc = 0;
  p.models = {"/nonexistent.onnx"};
  err = open_error(p, &rc);
  EXPECT_EQ(rc, -ENOENT);
  EXPECT_NE(err.find("/nonexistent.onnx: model file not found"), std::string::npos) << err;
}

TEST_F(OpenCv, CustomOptions) {
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {prototxt(), shared_models_dir() + "/models/lenet_iter_9000.caffemodel"};
  p.custom = "Backend:opencv,Target:cpu,NumThreads:1";
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  p.custom = "Device:gpu";
  err = open_error(p);
  EXPECT_NE(err.find("'Device'"), std::string::npos) << err;
  EXPECT_NE(err.find("Backend, Target, NumThreads"), std::string::npos) << err;
  p.custom = "Backend:cuda";
  err = open_error(p);
  EXPECT_NE(err.find("Backend:cuda"), std::string::npos) << err;
  EXPECT_NE(err.find("default, opencv"), std::string::npos) << err;
}

TEST_F(OpenCv, WrongSizesAndInputTypes) {
  auto m = load_ref("add_mul");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  auto inst = open(p);
  ASSERT_TRUE(inst);
  std::vector<float> a(12), b(12), s(12), q(12);
  std::vector<GstTensorMemory> i = {{a.data(), 48}, {b.data(), 44}};
  std::vector<GstTensorMemory> o = {{s.data(), 48}, {q.data(), 48}};
  std::string err;
  EXPECT_EQ(inst->invoke(i, o, &err), -EINVAL);
  EXPECT_NE(err.find("input 1 ('b'"), std::string::npos) << err;
  EXPECT_NE(err.find("44 bytes, expected 48"), std::string::npos) << err;

  p.input.num_tensors = 2;
  p.input.tensors[0] = make_desc("", _NNS_INT32, "4:3:1");
  p.input.tensors[1] = make_desc("", _NNS_FLOAT32, "4:3:1");
  err = open_error(p);
  EXPECT_NE(err.find("int32 4:3:1"), std::string::npos) << err;
  EXPECT_NE(err.find("float32 or uint8"), std::string::npos) << err;
}

TEST_F(OpenCv, InvokeDynamicFollowsInputShape) {
  auto m = load_ref("add_mul");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  p.invoke_dynamic = true;
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  std::vector<float> a(24), b(24);
  for (int k = 0; k < 24; ++k) a[k] = float(k), b[k] = 0.5f;
  nns_tensors_desc in_info{}, out_info{};
  in_info.num_tensors = 2;
  in_info.tensors[0] = make_desc("a", _NNS_FLOAT32, "4:3:2");
  in_info.tensors[1] = make_desc("b", _NNS_FLOAT32, "4:3:2");
  GstTensorMemory i[2] = {{a.data(), 96}, {b.data(), 96}};
  GstTensorMemory o[NNS_TENSOR_SIZE_LIMIT] = {};
  char buf[512] = {0};
  ASSERT_EQ(api_->invoke_dynamic(inst->priv(), &in_info, i, &out_info, o, buf, sizeof(buf)), 0)
      << buf;
  ASSERT_EQ(out_info.num_tensors, 2u);
  EXPECT_EQ(desc_string(out_info.tensors[0]), "'sum' float32 4:3:2");
  ASSERT_EQ(o[0].size, 96u);
  for (int k = 0; k < 24; ++k) EXPECT_FLOAT_EQ(static_cast<float *>(o[0].data)[k], k + 0.5f);
  api_->free_output(inst->priv(), o[0].data);
  api_->free_output(inst->priv(), o[1].data);
}

}  // namespace
}  // namespace nns::test

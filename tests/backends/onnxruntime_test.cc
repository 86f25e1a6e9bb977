// SPDX-License-Identifier: LGPL-2.1-only
// The onnxruntime filter back end, driven directly through its C ABI (dlopen): model info,
// invoke on generated and real models, zero copy, dynamic shapes, custom= and error texts.
#include <gtest/gtest.h>

#include <algorithm>
#include <thread>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace nns::test {
namespace {

class OnnxRuntime : public ::testing::Test {
 protected:
  void SetUp() override {
    const BackendLib &b = backend_lib("onnxruntime");
    if (!b.ok()) GTEST_SKIP() << "onnxruntime back end unavailable: " << b.error();
    api_ = b.api();
  }
  std::optional<RefModel> ref(const std::string &name) {
    auto m = load_ref(name);
    if (!m) ADD_FAILURE() << "generated model " << name << " missing in " << models_dir();
    return m;
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
  const nns_filter_backend_i *api_ = nullptr;
};

// Runs `inst` on the reference inputs and checks every output against the reference.
void expect_reference(Instance &inst, const RefModel &m) {
  std::vector<std::vector<uint8_t>> ins, outs;
  std::vector<GstTensorMemory> in, out;
  for (auto &t : m.inputs) ins.push_back(t.bytes);
  for (auto &t : m.outputs) outs.emplace_back(t.bytes.size(), 0xAB);
  for (auto &b : ins) in.push_back({b.data(), b.size()});
  for (auto &b : outs) out.push_back({b.data(), b.size()});
  std::string err;
  ASSERT_EQ(inst.invoke(in, out, &err), 0) << err;
  for (std::size_t i = 0; i < m.outputs.size(); ++i)
    EXPECT_EQ(compare(m.outputs[i], outs[i].data(), outs[i].size(), m.abs_tol, m.rel_tol), "")
        << m.name << " output " << i;
}

TEST_F(OnnxRuntime, TableDescribesBackEnd) {
  EXPECT_STREQ(api_->name, "onnxruntime");
  EXPECT_TRUE(api_->flags & NNS_FILTER_FLAG_THREAD_SAFE);
  EXPECT_TRUE(api_->flags & NNS_FILTER_FLAG_DYNAMIC);
  EXPECT_FALSE(api_->flags & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE);
  ASSERT_NE(api_->extensions, nullptr);
  EXPECT_STREQ(api_->extensions[0], ".onnx");
}

TEST_F(OnnxRuntime, ModelInfoComesFromTheModel) {
  auto m = ref("add_mul");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out, &err), 0) << err;
  ASSERT_EQ(in.num_tensors, 2u);
  ASSERT_EQ(out.num_tensors, 2u);
  EXPECT_EQ(in.format, _NNS_TENSOR_FORMAT_STATIC);
  EXPECT_EQ(desc_string(in.tensors[0]), "'a' float32 4:3:1");
  EXPECT_EQ(desc_string(in.tensors[1]), "'b' float32 4:3:1");
  EXPECT_EQ(desc_string(out.tensors[0]), "'sum' float32 4:3:1");
  EXPECT_EQ(desc_string(out.tensors[1]), "'product' float32 4:3:1");
  expect_reference(*inst, *m);
}

TEST_F(OnnxRuntime, Uint8ModelAndConvNet) {
  for (const char *name : {"uint8_scale", "conv_net"}) {
    auto m = ref(name);
    ASSERT_TRUE(m);
    Props p;
    p.models = {m->file("onnx")};
    std::string err;
    auto inst = open(p, &err);
    ASSERT_TRUE(inst) << err;
    nns_tensors_desc in{}, out{};
    ASSERT_EQ(inst->model_info(in, out), 0);
    for (std::size_t i = 0; i < m->inputs.size(); ++i)
      EXPECT_EQ(desc_string(in.tensors[i]), desc_string(m->inputs[i].desc));
    for (std::size_t i = 0; i < m->outputs.size(); ++i)
      EXPECT_EQ(desc_string(out.tensors[i]), desc_string(m->outputs[i].desc));
    expect_reference(*inst, *m);
  }
}

TEST_F(OnnxRuntime, ZeroCopyInputsAndOutputs) {
  auto m = ref("add_mul");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  auto inst = open(p);
  ASSERT_TRUE(inst);
  auto counter = reinterpret_cast<uint64_t (*)(void *)>(
      dlsym(RTLD_DEFAULT, "nns_filter_onnxruntime_copied_bytes"));
  if (!counter) {
    void *h = dlopen(backend_path("onnxruntime").c_str(), RTLD_NOW | RTLD_NOLOAD);
    ASSERT_NE(h, nullptr);
    counter =
        reinterpret_cast<uint64_t (*)(void *)>(dlsym(h, "nns_filter_onnxruntime_copied_bytes"));
  }
  ASSERT_NE(counter, nullptr);
  // Inputs in read-only pages: ORT reads them where they are. Outputs are written in place.
  std::vector<uint8_t> a = m->inputs[0].bytes, b = m->inputs[1].bytes;
  std::vector<float> sum(12, -1.f), prod(12, -1.f);
  std::vector<GstTensorMemory> in = {{a.data(), a.size()}, {b.data(), b.size()}};
  std::vector<GstTensorMemory> out = {{sum.data(), 48}, {prod.data(), 48}};
  for (int iter = 0; iter < 3; ++iter) {
    std::string err;
    ASSERT_EQ(inst->invoke(in, out, &err), 0) << err;
  }
  EXPECT_EQ(compare(m->outputs[0], reinterpret_cast<uint8_t *>(sum.data()), 48, 1e-6, 0), "");
  EXPECT_EQ(compare(m->outputs[1], reinterpret_cast<uint8_t *>(prod.data()), 48, 1e-6, 0), "");
  EXPECT_EQ(counter(inst->priv()), 0u) << "the back end copied output bytes";
  EXPECT_EQ(a, m->inputs[0].bytes) << "input modified";
}

// mobilenet_v2_quant.onnx is a PyTorch (torchvision) export quantized with onnx.quantize: float32
// NCHW [1,3,224,224] with torchvision's ImageNet normalisation ((x / 255 - mean) / std per RGB
// channel), 1000 scores in the 1000-class ImageNet order (no background class), read through
// build/data/imagenet_labels_1000.txt. The output is quantized (uint8, step 0.10035, zero point
// 94): on the orange "orange" (950) and "lemon" (951) both saturate the last MatMul and land on
// the same level, 160 steps = 16.0566; argmax takes the first, as image_labeling does.
TEST_F(OnnxRuntime, MobilenetOnOrangeGives950) {
  NNS_REQUIRE_SHARED_MODELS();
  std::string dir = shared_models_dir();
  Props p;
  p.models = {dir + "/models/mobilenet_v2_quant.onnx"};
  p.custom = "NumThreads:1";
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  ASSERT_EQ(in.num_tensors, 1u);
  EXPECT_EQ(desc_string(in.tensors[0]), "'input' float32 224:224:3:1");
  ASSERT_EQ(out.num_tensors, 1u);
  EXPECT_EQ(desc_string(out.tensors[0]), "'output' float32 1000:1");

  std::vector<uint8_t> img = read_file(dir + "/data/orange.raw");
  ASSERT_EQ(img.size(), 224u * 224u * 3u);
  // (x - 255 mean) / (255 std): torchvision's normalisation of x / 255, within 5e-7.
  const float mean[3] = {123.675f, 116.28f, 103.53f}, stdev[3] = {58.395f, 57.12f, 57.375f};
  std::vector<float> chw(3 * 224 * 224), scores(1000);
  for (std::size_t y = 0; y < 224; ++y)
    for (std::size_t x = 0; x < 224; ++x)
      for (std::size_t c = 0; c < 3; ++c)
        chw[c * 224 * 224 + y * 224 + x] = (img[(y * 224 + x) * 3 + c] - mean[c]) / stdev[c];
  std::vector<GstTensorMemory> i = {{chw.data(), chw.size() * 4}};
  std::vector<GstTensorMemory> o = {{scores.data(), scores.size() * 4}};
  ASSERT_EQ(inst->invoke(i, o, &err), 0) << err;
  std::size_t best = std::max_element(scores.begin(), scores.end()) - scores.begin();
  EXPECT_EQ(best, 950u);
  // The tie with 951 at the output's level 94 + 160, and the rest far below: 949 "strawberry"
  // 11.74 (117 steps), 954 "banana" 11.34.
  const float step = 0.10035347f;
  EXPECT_NEAR(scores[950], 160 * step, 1e-4);
  EXPECT_EQ(scores[951], scores[950]);
  std::vector<float> rest = scores;
  rest[950] = rest[951] = -1e9f;
  std::size_t third = std::max_element(rest.begin(), rest.end()) - rest.begin();
  EXPECT_EQ(third, 949u);
  EXPECT_NEAR(scores[949], 117 * step, 1e-4);

  std::string labels_path = imagenet_labels_1000();
  ASSERT_FALSE(labels_path.empty()) << "build/data/imagenet_labels_1000.txt was not generated "
                                       "from ../shared's labels.txt; re-run cmake";
  std::vector<uint8_t> labels = read_file(labels_path);
  std::string text(labels.begin(), labels.end());
  std::vector<std::string> lines;
  for (std::size_t pos = 0; pos < text.size();) {
    std::size_t nl = text.find('\n', pos);
    if (nl == std::string::npos) nl = text.size();
    lines.push_back(text.substr(pos, nl - pos));
    pos = nl + 1;
  }
  ASSERT_EQ(lines.size(), 1000u);
  EXPECT_EQ(lines[0], "tench");
  EXPECT_EQ(lines[949], "strawberry");
  EXPECT_EQ(lines[950], "orange");
  EXPECT_EQ(lines[951], "lemon");
}

TEST_F(OnnxRuntime, FreeDimensionNeedsInputOrInvokeDynamic) {
  auto m = ref("add_mul_dynamic");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  int rc = 0;
  std::string err = open_error(p, &rc);
  EXPECT_EQ(rc, -EINVAL);
  EXPECT_NE(err.find("onnxruntime"), std::string::npos) << err;
  EXPECT_NE(err.find("'a'"), std::string::npos) << err;
  EXPECT_NE(err.find("free dimensions"), std::string::npos) << err;
  EXPECT_NE(err.find("[?,3,4]"), std::string::npos) << err;
  EXPECT_NE(err.find("input="), std::string::npos) << err;
  EXPECT_NE(err.find("invoke-dynamic"), std::string::npos) << err;
}

TEST_F(OnnxRuntime, FreeDimensionResolvedByInput) {
  auto m = ref("add_mul_dynamic");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  p.input.num_tensors = 2;
  p.input.tensors[0] = make_desc("", _NNS_FLOAT32, "4:3:2");
  p.input.tensors[1] = make_desc("", _NNS_FLOAT32, "4:3:2");
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  EXPECT_EQ(desc_string(in.tensors[0]), "'a' float32 4:3:2");
  EXPECT_EQ(desc_string(out.tensors[1]), "'product' float32 4:3:2");
  std::vector<float> a(24), b(24), s(24), q(24);
  for (int k = 0; k < 24; ++k) a[k] = k * 0.5f, b[k] = 3.f - k;
  std::vector<GstTensorMemory> i = {{a.data(), 96}, {b.data(), 96}};
  std::vector<GstTensorMemory> o = {{s.data(), 96}, {q.data(), 96}};
  ASSERT_EQ(inst->invoke(i, o, &err), 0) << err;
  for (int k = 0; k < 24; ++k) {
    EXPECT_FLOAT_EQ(s[k], a[k] + b[k]);
    EXPECT_FLOAT_EQ(q[k], a[k] * b[k]);
  }
}

TEST_F(OnnxRuntime, InvokeDynamicAllocatesOutputs) {
  auto m = ref("add_mul_dynamic");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  p.invoke_dynamic = true;
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  EXPECT_EQ(in.format, _NNS_TENSOR_FORMAT_FLEXIBLE);
  for (uint32_t batch : {3u, 1u}) {
    std::string dims = "4:3:" + std::to_string(batch);
    std::vector<float> a(12 * batch), b(12 * batch);
    for (std::size_t k = 0; k < a.size(); ++k) a[k] = float(k), b[k] = 2.f;
    nns_tensors_desc in_info{}, out_info{};
    in_info.num_tensors = 2;
    in_info.tensors[0] = make_desc("a", _NNS_FLOAT32, dims);
    in_info.tensors[1] = make_desc("b", _NNS_FLOAT32, dims);
    GstTensorMemory i[2] = {{a.data(), a.size() * 4}, {b.data(), b.size() * 4}};
    GstTensorMemory o[NNS_TENSOR_SIZE_LIMIT] = {};
    char buf[512] = {0};
    ASSERT_EQ(api_->invoke_dynamic(inst->priv(), &in_info, i, &out_info, o, buf, sizeof(buf)), 0)
        << buf;
    ASSERT_EQ(out_info.num_tensors, 2u);
    EXPECT_EQ(desc_string(out_info.tensors[0]), "'sum' float32 " + dims);
    ASSERT_EQ(o[1].size, a.size() * 4);
    auto *prod = static_cast<const float *>(o[1].data);
    for (std::size_t k = 0; k < a.size(); ++k) EXPECT_FLOAT_EQ(prod[k], 2.f * k);
    api_->free_output(inst->priv(), o[0].data);
    api_->free_output(inst->priv(), o[1].data);
  }
}

TEST_F(OnnxRuntime, CustomOptions) {
  auto m = ref("conv_net");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  p.custom =
      "NumThreads:1,InterOpNumThreads:1,GraphOptimizationLevel:basic,ExecutionMode:sequential,"
      "AllowSpinning:false";
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  expect_reference(*inst, *m);

  p.custom = "NumThreads:2,Delegate:XNNPACK";
  err = open_error(p);
  EXPECT_NE(err.find("'Delegate'"), std::string::npos) << err;
  EXPECT_NE(err.find("NumThreads, InterOpNumThreads, GraphOptimizationLevel, ExecutionMode, "
                     "AllowSpinning"),
            std::string::npos)
      << err;
  p.custom = "NumThreads:many";
  err = open_error(p);
  EXPECT_NE(err.find("NumThreads:many"), std::string::npos) << err;
  p.custom = "GraphOptimizationLevel:max";
  err = open_error(p);
  EXPECT_NE(err.find("disable, basic, extended, all"), std::string::npos) << err;
}

TEST_F(OnnxRuntime, MissingOrCorruptModel) {
  Props p;
  p.models = {"/nonexistent/model.onnx"};
  int rc = 0;
  std::string err = open_error(p, &rc);
  EXPECT_EQ(rc, -ENOENT);
  EXPECT_NE(err.find("/nonexistent/model.onnx"), std::string::npos) << err;
  EXPECT_NE(err.find("not found"), std::string::npos) << err;

  std::string dir = make_temp_dir();
  std::string bad = dir + "/bad.onnx";
  {
    std::ofstream f(bad);
    f << "this is not a protobuf";
  }
  p.models = {bad};
  err = open_error(p);
  EXPECT_NE(err.find("cannot load the model"), std::string::npos) << err;
  std::filesystem::remove_all(dir);

  p.models = {};
  err = open_error(p);
  EXPECT_NE(err.find("exactly one"), std::string::npos) << err;
}

TEST_F(OnnxRuntime, InputPropertyMustMatchModel) {
  auto m = ref("add_mul");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  p.input.num_tensors = 2;
  p.input.tensors[0] = make_desc("", _NNS_UINT8, "4:3:1");
  p.input.tensors[1] = make_desc("", _NNS_FLOAT32, "4:3:1");
  std::string err = open_error(p);
  EXPECT_NE(err.find("uint8 4:3:1"), std::string::npos) << err;
  EXPECT_NE(err.find("model input 'a' is float32 4:3:1"), std::string::npos) << err;

  p.input.tensors[0] = make_desc("", _NNS_FLOAT32, "3:4:1");
  err = open_error(p);
  EXPECT_NE(err.find("[1,4,3]"), std::string::npos) << err;
  EXPECT_NE(err.find("[1,3,4]"), std::string::npos) << err;

  p.input.num_tensors = 1;
  err = open_error(p);
  EXPECT_NE(err.find("got 1 input= tensors, the model has 2"), std::string::npos) << err;

  // Named inputs are matched by name, in the order given.
  p.input.num_tensors = 2;
  p.input.tensors[0] = make_desc("b", _NNS_FLOAT32, "4:3:1");
  p.input.tensors[1] = make_desc("a", _NNS_FLOAT32, "4:3:1");
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  EXPECT_STREQ(in.tensors[0].name, "b");
  p.input.tensors[0] = make_desc("c", _NNS_FLOAT32, "4:3:1");
  err = open_error(p);
  EXPECT_NE(err.find("'c'"), std::string::npos) << err;
}

TEST_F(OnnxRuntime, OutputNamesSelectOutputs) {
  auto m = ref("add_mul");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  p.output.num_tensors = 1;
  p.output.tensors[0] = make_desc("product", _NNS_END, "");
  std::string err;
  auto inst = open(p, &err);
  ASSERT_TRUE(inst) << err;
  nns_tensors_desc in{}, out{};
  ASSERT_EQ(inst->model_info(in, out), 0);
  ASSERT_EQ(out.num_tensors, 1u);
  EXPECT_STREQ(out.tensors[0].name, "product");
  std::vector<uint8_t> a = m->inputs[0].bytes, b = m->inputs[1].bytes, q(48);
  std::vector<GstTensorMemory> i = {{a.data(), 48}, {b.data(), 48}}, o = {{q.data(), 48}};
  ASSERT_EQ(inst->invoke(i, o, &err), 0) << err;
  EXPECT_EQ(compare(m->outputs[1], q.data(), 48, 1e-6, 0), "");

  p.output.tensors[0] = make_desc("quotient", _NNS_END, "");
  err = open_error(p);
  EXPECT_NE(err.find("'quotient'"), std::string::npos) << err;
  EXPECT_NE(err.find("'sum', 'product'"), std::string::npos) << err;

  p.output.num_tensors = 2;
  p.output.tensors[0] = make_desc("", _NNS_FLOAT32, "4:3:1");
  p.output.tensors[1] = make_desc("", _NNS_FLOAT32, "5:3:1");
  err = open_error(p);
  EXPECT_NE(err.find("float32 5:3:1"), std::string::npos) << err;
}

TEST_F(OnnxRuntime, WrongBufferSizesAreRejected) {
  auto m = ref("add_mul");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  auto inst = open(p);
  ASSERT_TRUE(inst);
  std::vector<uint8_t> a(40), b(48), s(48), q(48);
  std::vector<GstTensorMemory> i = {{a.data(), 40}, {b.data(), 48}};
  std::vector<GstTensorMemory> o = {{s.data(), 48}, {q.data(), 48}};
  std::string err;
  EXPECT_EQ(inst->invoke(i, o, &err), -EINVAL);
  EXPECT_NE(err.find("input 0 ('a'"), std::string::npos) << err;
  EXPECT_NE(err.find("40 bytes, expected 48"), std::string::npos) << err;
  i.pop_back();
  EXPECT_EQ(inst->invoke(i, o, &err), -EINVAL);
  EXPECT_NE(err.find("got 1 input tensors, the model has 2"), std::string::npos) << err;
}

TEST_F(OnnxRuntime, ConcurrentInvokesOnOneInstance) {
  auto m = ref("conv_net");
  ASSERT_TRUE(m);
  Props p;
  p.models = {m->file("onnx")};
  p.custom = "NumThreads:1";
  auto inst = open(p);
  ASSERT_TRUE(inst);
  std::atomic<int> bad{0};
  auto worker = [&] {
    for (int k = 0; k < 200; ++k) {
      std::vector<uint8_t> x = m->inputs[0].bytes, l(20), pr(20);
      std::vector<GstTensorMemory> i = {{x.data(), x.size()}},
                                   o = {{l.data(), 20}, {pr.data(), 20}};
      if (inst->invoke(i, o) != 0 || !compare(m->outputs[1], pr.data(), 20, 1e-5, 1e-4).empty())
        ++bad;
    }
  };
  std::thread t1(worker), t2(worker);
  t1.join();
  t2.join();
  EXPECT_EQ(bad.load(), 0);
}

TEST_F(OnnxRuntime, ReloadKeepsTensorsOrFails) {
  auto m = ref("add_mul");
  auto c = ref("conv_net");
  ASSERT_TRUE(m && c);
  Props p;
  p.models = {m->file("onnx")};
  auto inst = open(p);
  ASSERT_TRUE(inst);
  char buf[512] = {0};
  EXPECT_EQ(api_->reload(inst->priv(), p.get("onnxruntime"), buf, sizeof(buf)), 0) << buf;
  expect_reference(*inst, *m);
  p.models = {c->file("onnx")};
  EXPECT_EQ(api_->reload(inst->priv(), p.get("onnxruntime"), buf, sizeof(buf)), -EINVAL);
  EXPECT_NE(std::string(buf).find("differ"), std::string::npos) << buf;
  expect_reference(*inst, *m);  // still the old model
}

}  // namespace
}  // namespace nns::test

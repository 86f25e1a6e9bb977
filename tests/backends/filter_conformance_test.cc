// SPDX-License-Identifier: LGPL-2.1-only
// Cross-back-end conformance: every filter back end that is built runs the same generated
// models (tests/data/generate_models.py: ONNX, TorchScript, python3 and TensorFlow Lite twins of
// one torch module) and must reproduce torch's reference outputs within the sidecar's tolerance.
// A flavour the generator could not write (the sidecar's "not_written", e.g. .tflite without
// python3-flatbuffers) skips with the generator's reason, and fails when CI=true.
//
// To add a back end: one line in kBackends (its framework name and the sidecar "files" key of
// the model flavour it reads). To add a model: generate it and add its name to kModels.
#include <gtest/gtest.h>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace nns::test {
namespace {

struct BackendKind {
  const char *framework;  // libnnstreamer_filter_<framework>.so
  const char *file_kind;  // key in the sidecar's "files": onnx, pytorch, python3, tflite
};

// Readable ctest names: "(onnxruntime, add_mul)".
void PrintTo(const BackendKind &k, std::ostream *os) {
  *os << k.framework;
}

const BackendKind kBackends[] = {
    {"onnxruntime", "onnx"}, {"opencv", "onnx"},  {"pytorch", "pytorch"},
    {"python3", "python3"},  {"armnn", "tflite"}, {"tensorflow2-lite", "tflite"},
};

const std::string kModels[] = {"add_mul", "conv_net", "uint8_scale"};

using Param = std::tuple<BackendKind, std::string>;

class FilterConformance : public ::testing::TestWithParam<Param> {
 protected:
  void SetUp() override {
    const auto &[kind, model] = GetParam();
    const BackendLib &b = backend_lib(kind.framework);
    if (!b.ok()) GTEST_SKIP() << "back end '" << kind.framework << "' not available: " << b.error();
    api_ = b.api();
    ref_ = load_ref(model);
    ASSERT_TRUE(ref_) << "generated model " << model << " missing in " << models_dir()
                      << " (is /usr/bin/python3 with torch+onnx installed?)";
    file_ = ref_->file(kind.file_kind);
    if (file_.empty()) {
      std::string why = ref_->why_not_written(kind.file_kind);
      if (why.empty())
        GTEST_SKIP() << "no '" << kind.file_kind << "' flavour of " << model << " by design";
      NNS_SKIP_UNLESS_CI("the '" << kind.file_kind << "' flavour of " << model << " for back end '"
                                 << kind.framework << "' was " << why);
    }
  }

  const nns_filter_backend_i *api_ = nullptr;
  std::optional<RefModel> ref_;
  std::string file_;
};

// Drops names: input=/output= as a user writes them (dims and types only).
nns_tensors_desc unnamed(const std::vector<RefTensor> &v) {
  nns_tensors_desc d = descs_of(v);
  for (uint32_t i = 0; i < d.num_tensors; ++i) set_name(d.tensors[i], "");
  return d;
}

// Open with input=/output= given, invoke on the reference input, compare every output.
TEST_P(FilterConformance, ReproducesReferenceOutputs) {
  Props p;
  p.models = {file_};
  p.input = unnamed(ref_->inputs);
  p.output = unnamed(ref_->outputs);
  std::string err;
  auto inst = Instance::open(api_, p, nullptr, &err);
  ASSERT_TRUE(inst) << "open " << file_ << ": " << err;

  std::vector<std::vector<uint8_t>> ins, outs;
  std::vector<GstTensorMemory> in, out;
  for (auto &t : ref_->inputs) ins.push_back(t.bytes);
  for (auto &t : ref_->outputs) outs.emplace_back(t.bytes.size(), 0xCD);
  for (auto &b : ins) in.push_back({b.data(), b.size()});
  for (auto &b : outs) out.push_back({b.data(), b.size()});
  bool allocates = api_->flags & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE;
  ASSERT_EQ(inst->invoke(in, out, &err), 0) << err;
  for (std::size_t i = 0; i < ref_->outputs.size(); ++i) {
    EXPECT_EQ(compare(ref_->outputs[i], static_cast<const uint8_t *>(out[i].data), out[i].size,
                      ref_->abs_tol, ref_->rel_tol),
              "")
        << ref_->name << " output " << i;
    if (allocates && api_->free_output) api_->free_output(inst->priv(), out[i].data);
  }
  // Inputs are never written.
  for (std::size_t i = 0; i < ins.size(); ++i) EXPECT_EQ(ins[i], ref_->inputs[i].bytes);
}

// Back ends that know their model's tensors report the reference types and dims.
TEST_P(FilterConformance, ModelInfoMatchesReference) {
  Props p;
  p.models = {file_};
  std::string err;
  int rc = 0;
  auto inst = Instance::open(api_, p, &rc, &err);
  if (!inst) GTEST_SKIP() << "back end needs input=/output= for this model: " << err;
  nns_tensors_desc in{}, out{};
  rc = inst->model_info(in, out, &err);
  if (rc == -ENOTSUP) GTEST_SKIP() << "back end does not report model info";
  ASSERT_EQ(rc, 0) << err;
  ASSERT_EQ(in.num_tensors, ref_->inputs.size());
  ASSERT_EQ(out.num_tensors, ref_->outputs.size());
  for (std::size_t i = 0; i < ref_->inputs.size(); ++i) {
    EXPECT_EQ(in.tensors[i].type, ref_->inputs[i].desc.type) << "input " << i;
    EXPECT_TRUE(desc_dims_equal(in.tensors[i], ref_->inputs[i].desc))
        << desc_string(in.tensors[i]) << " vs " << desc_string(ref_->inputs[i].desc);
  }
  for (std::size_t i = 0; i < ref_->outputs.size(); ++i) {
    EXPECT_EQ(out.tensors[i].type, ref_->outputs[i].desc.type) << "output " << i;
    EXPECT_TRUE(desc_dims_equal(out.tensors[i], ref_->outputs[i].desc))
        << desc_string(out.tensors[i]) << " vs " << desc_string(ref_->outputs[i].desc);
  }
}

std::string param_name(const ::testing::TestParamInfo<Param> &info) {
  std::string s = std::string(std::get<0>(info.param).framework) + "_" + std::get<1>(info.param);
  for (auto &c : s)
    if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  return s;
}

INSTANTIATE_TEST_SUITE_P(AllBackends, FilterConformance,
                         ::testing::Combine(::testing::ValuesIn(kBackends),
                                            ::testing::ValuesIn(kModels)),
                         param_name);

}  // namespace
}  // namespace nns::test

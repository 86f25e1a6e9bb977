// SPDX-License-Identifier: LGPL-2.1-only
// The pytorch filter back end through its C ABI (dlopen of the built .so): LeNet on a real
// digit, several inputs/outputs, rank 5 and 16, every dtype, zero-copy counters, and the error
// messages a user sees.
#include <gtest/gtest.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <numeric>

#include "../../backends/filter/pytorch/pytorch_stats.h"
#include "backends/backend_loader.h"
#include "support/harness.h"

namespace {

using nns::test::BackendLib;
using nns::test::Instance;
using nns::test::Props;
using nns::test::tensor_desc;
using nns::test::tensors_desc;

const BackendLib &lib() {
  return nns::test::backend_lib("pytorch");
}

#define REQUIRE_BACKEND()                                                   \
  do {                                                                      \
    if (!lib().ok()) GTEST_SKIP() << "pytorch back end: " << lib().error(); \
  } while (0)

std::string gen_model(const char *name) {
  return std::string(NNS_BUILD_DIR) + "/tests/models/pytorch/" + name + ".pt";
}

std::string shared_model(const char *name) {
  return nns::test::shared_models_dir() + "/models/" + name;
}

nns_pytorch_stats stats_of(const Instance &inst) {
  auto fn =
      reinterpret_cast<nns_filter_pytorch_get_stats_fn>(lib().sym(NNS_FILTER_PYTORCH_GET_STATS));
  nns_pytorch_stats s{};
  EXPECT_NE(fn, nullptr);
  if (fn) {
    EXPECT_EQ(fn(inst.priv(), &s), 0);
  }
  return s;
}

Props lenet_props() {
  Props p;
  p.framework = "pytorch";
  p.models = {shared_model("pytorch_lenet5.pt")};
  p.input = tensors_desc({tensor_desc(_NNS_UINT8, {1, 28, 28, 1})});
  p.output = tensors_desc({tensor_desc(_NNS_UINT8, {10, 1})});
  return p;
}

TEST(PytorchBackend, Table) {
  REQUIRE_BACKEND();
  const nns_filter_backend_i *api = lib().api();
  EXPECT_EQ(api->api_version, NNS_FILTER_BACKEND_API_VERSION);
  EXPECT_STREQ(api->name, "pytorch");
  ASSERT_NE(api->extensions, nullptr);
  EXPECT_STREQ(api->extensions[0], ".pt");
  EXPECT_TRUE(api->flags & NNS_FILTER_FLAG_DYNAMIC);
  EXPECT_FALSE(api->flags & NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE);
  ASSERT_NE(api->check_accelerator, nullptr);
  EXPECT_EQ(api->check_accelerator("cpu"), 0);
  EXPECT_NE(api->check_accelerator("gpu"), 0);  // CPU-only libtorch here
  EXPECT_NE(api->check_accelerator("npu"), 0);
}

TEST(PytorchBackend, LenetClassifiesNine) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = lenet_props();
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();

  nns_tensors_desc in, out;
  ASSERT_EQ(inst.model_info(in, out), 0) << inst.error();
  ASSERT_EQ(in.num_tensors, 1u);
  EXPECT_EQ(in.tensors[0].type, static_cast<uint32_t>(_NNS_UINT8));
  ASSERT_EQ(out.num_tensors, 1u);
  EXPECT_EQ(out.tensors[0].dims[0], 10u);

  std::vector<uint8_t> digit = nns::test::read_file(nns::test::shared_models_dir() + "/data/9.raw");
  ASSERT_EQ(digit.size(), 784u);
  std::vector<uint8_t> scores(10, 0xAA);
  std::vector<GstTensorMemory> ins{{digit.data(), digit.size()}};
  std::vector<GstTensorMemory> outs{{scores.data(), scores.size()}};
  for (int round = 0; round < 3; ++round) {  // the profiling executor re-plans on early runs
    ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
    auto best = std::max_element(scores.begin(), scores.end()) - scores.begin();
    EXPECT_EQ(best, 9);
    EXPECT_EQ(scores[9], 254);
    for (int k = 0; k < 9; ++k) EXPECT_EQ(scores[k], 0) << k;
  }
  nns_pytorch_stats s = stats_of(inst);
  EXPECT_EQ(s.invokes, 3u);
  EXPECT_EQ(s.input_copies, 0u);
  EXPECT_EQ(s.output_copies, 3u);  // result tensors are torch's; copied into our buffer
}

TEST(PytorchBackend, OutputFoundFromInputOnly) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = lenet_props();
  p.output = nns_tensors_desc{};
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc in, out;
  ASSERT_EQ(inst.model_info(in, out), 0) << inst.error();
  ASSERT_EQ(out.num_tensors, 1u);
  EXPECT_EQ(out.tensors[0].type, static_cast<uint32_t>(_NNS_UINT8));
  EXPECT_EQ(out.tensors[0].dims[0], 10u);  // torch [1,10] -> 10:1
  EXPECT_EQ(out.tensors[0].dims[1], 1u);
  EXPECT_EQ(out.tensors[0].dims[2], 0u);
}

TEST(PytorchBackend, NoShapesUntilSetInputInfo) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = lenet_props();
  p.input = nns_tensors_desc{};
  p.output = nns_tensors_desc{};
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc in, out;
  EXPECT_EQ(inst.model_info(in, out), -ENOTSUP);
  nns_tensors_desc want = tensors_desc({tensor_desc(_NNS_UINT8, {1, 28, 28, 1})});
  ASSERT_EQ(inst.set_input_info(want, out), 0) << inst.error();
  ASSERT_EQ(out.num_tensors, 1u);
  EXPECT_EQ(out.tensors[0].dims[0], 10u);
  // A different batch size is fine for TorchScript: [2,28,28,1] -> [2,10].
  nns_tensors_desc batch = tensors_desc({tensor_desc(_NNS_UINT8, {1, 28, 28, 2})});
  ASSERT_EQ(inst.set_input_info(batch, out), 0) << inst.error();
  EXPECT_EQ(out.tensors[0].dims[0], 10u);
  EXPECT_EQ(out.tensors[0].dims[1], 2u);
}

TEST(PytorchBackend, TwoInputsTwoOutputs) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {shared_model("sample_3x4_two_input_two_output.pt")};
  p.input = tensors_desc({tensor_desc(_NNS_FLOAT32, {4, 3}), tensor_desc(_NNS_FLOAT32, {4, 3})});
  p.output = tensors_desc({tensor_desc(_NNS_FLOAT32, {4, 3}), tensor_desc(_NNS_FLOAT32, {4, 3})});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  std::vector<float> x(12), h(12), o1(12), o2(12);
  std::iota(x.begin(), x.end(), 0.f);
  std::iota(h.begin(), h.end(), 100.f);
  std::vector<GstTensorMemory> ins{{x.data(), 48}, {h.data(), 48}};
  std::vector<GstTensorMemory> outs{{o1.data(), 48}, {o2.data(), 48}};
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  for (int i = 0; i < 12; ++i) {
    EXPECT_FLOAT_EQ(o1[i], x[i] + 1.f);  // the model adds constants 1 and 2
    EXPECT_FLOAT_EQ(o2[i], h[i] + 2.f);
  }
}

TEST(PytorchBackend, RankFive) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {shared_model("sample_4x4x4x4x4_two_input_one_output.pt")};
  auto t = tensor_desc(_NNS_FLOAT32, {4, 4, 4, 4, 4});
  p.input = tensors_desc({t, t});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc in, out;
  ASSERT_EQ(inst.model_info(in, out), 0) << inst.error();
  ASSERT_EQ(out.num_tensors, 1u);
  for (int k = 0; k < 5; ++k) EXPECT_EQ(out.tensors[0].dims[k], 4u);
  EXPECT_EQ(out.tensors[0].dims[5], 0u);
  std::vector<float> a(1024), b(1024), o(1024);
  for (int i = 0; i < 1024; ++i) a[i] = i * 0.5f, b[i] = 3.f - i;
  std::vector<GstTensorMemory> ins{{a.data(), 4096}, {b.data(), 4096}};
  std::vector<GstTensorMemory> outs{{o.data(), 4096}};
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  for (int i = 0; i < 1024; ++i) ASSERT_FLOAT_EQ(o[i], a[i] + b[i]) << i;
}

// Rank 16 (the NNStreamer limit) through the element-wise add model, with invoke-dynamic
// reporting the output shape from the result.
TEST(PytorchBackend, RankSixteenDynamic) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p;
  p.models = {shared_model("sample_4x4x4x4x4_two_input_one_output.pt")};
  p.invoke_dynamic = 1;
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensor_desc t = tensor_desc(_NNS_INT32, {});
  for (int k = 0; k < 16; ++k) t.dims[k] = (k == 0 || k == 15) ? 3 : (k % 5 == 0 ? 2 : 1);
  std::size_t n = nns::test::desc_bytes(t) / 4;
  ASSERT_EQ(n, 36u);
  nns_tensors_desc info = tensors_desc({t, t});
  std::vector<int32_t> a(n), b(n);
  for (std::size_t i = 0; i < n; ++i) a[i] = static_cast<int32_t>(i), b[i] = 1000;
  std::vector<GstTensorMemory> ins{{a.data(), n * 4}, {b.data(), n * 4}};
  nns_tensors_desc oinfo{};
  std::vector<GstTensorMemory> outs;
  ASSERT_EQ(inst.invoke_dynamic(info, ins, oinfo, outs), 0);
  ASSERT_EQ(oinfo.num_tensors, 1u);
  EXPECT_EQ(oinfo.tensors[0].type, static_cast<uint32_t>(_NNS_INT32));
  for (int k = 0; k < 16; ++k) EXPECT_EQ(oinfo.tensors[0].dims[k], t.dims[k]) << k;
  ASSERT_EQ(outs[0].size, n * 4);
  auto *o = static_cast<const int32_t *>(outs[0].data);
  for (std::size_t i = 0; i < n; ++i) EXPECT_EQ(o[i], a[i] + 1000);
  inst.free_output(outs[0].data);
  nns_pytorch_stats s = stats_of(inst);
  EXPECT_EQ(s.output_zero_copy, 1u);  // the result tensor itself was handed out
  EXPECT_EQ(s.output_copies, 0u);
}

template <typename T>
void check_add(uint32_t type, T x, T y, T want) {
  Props p;
  p.models = {shared_model("sample_4x4x4x4x4_two_input_one_output.pt")};
  auto d = tensor_desc(type, {3, 2});
  p.input = tensors_desc({d, d});
  p.output = tensors_desc({d});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << "type " << type << ": " << inst.error();
  std::vector<T> a(6, x), b(6, y), o(6);
  std::vector<GstTensorMemory> ins{{a.data(), 6 * sizeof(T)}, {b.data(), 6 * sizeof(T)}};
  std::vector<GstTensorMemory> outs{{o.data(), 6 * sizeof(T)}};
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  for (const T &v : o) EXPECT_EQ(v, want) << "type " << type;
}

TEST(PytorchBackend, AllTorchDtypes) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  check_add<uint8_t>(_NNS_UINT8, 200, 50, 250);
  check_add<int8_t>(_NNS_INT8, -100, 27, -73);
  check_add<int16_t>(_NNS_INT16, -30000, 1000, -29000);
  check_add<int32_t>(_NNS_INT32, 1 << 30, 5, (1 << 30) + 5);
  check_add<int64_t>(_NNS_INT64, int64_t{1} << 40, 7, (int64_t{1} << 40) + 7);
  check_add<float>(_NNS_FLOAT32, 1.25f, 2.5f, 3.75f);
  check_add<double>(_NNS_FLOAT64, 1e100, 1e100, 2e100);
  check_add<uint16_t>(_NNS_FLOAT16, 0x3C00, 0x4000, 0x4200);  // half 1 + 2 = 3
}

TEST(PytorchBackend, UnsignedWideTypesRejected) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  for (uint32_t type : {_NNS_UINT16, _NNS_UINT32, _NNS_UINT64}) {
    Props p;
    p.models = {shared_model("sample_4x4x4x4x4_two_input_one_output.pt")};
    auto d = tensor_desc(type, {3});
    p.input = tensors_desc({d, d});
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find(type == _NNS_UINT16   ? "uint16"
                                : type == _NNS_UINT32 ? "uint32"
                                                      : "uint64"),
              std::string::npos)
        << inst.error();
    EXPECT_NE(inst.error().find("does not support"), std::string::npos) << inst.error();
  }
}

// The model adds 1 to its input in place: the caller's buffer changes, so torch worked on the
// caller's memory (no input copy).
TEST(PytorchBackend, InputsAreNotCopied) {
  REQUIRE_BACKEND();
  Props p;
  p.models = {gen_model("inplace_add1")};
  p.input = tensors_desc({tensor_desc(_NNS_UINT8, {4})});
  p.output = tensors_desc({tensor_desc(_NNS_UINT8, {4})});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  std::vector<uint8_t> buf{1, 2, 3, 4}, out(4);
  std::vector<GstTensorMemory> ins{{buf.data(), 4}};
  std::vector<GstTensorMemory> outs{{out.data(), 4}};
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  EXPECT_EQ(buf, (std::vector<uint8_t>{2, 3, 4, 5}));
  EXPECT_EQ(out, (std::vector<uint8_t>{2, 3, 4, 5}));
  nns_pytorch_stats s = stats_of(inst);
  EXPECT_EQ(s.output_copies, 1u);
  EXPECT_EQ(s.output_zero_copy, 0u);

  // In-place host (output buffer == input buffer): the result already lives there, no copy.
  std::vector<GstTensorMemory> same{{buf.data(), 4}};
  ASSERT_EQ(inst.invoke(ins, same), 0) << inst.error();
  EXPECT_EQ(buf, (std::vector<uint8_t>{3, 4, 5, 6}));
  s = stats_of(inst);
  EXPECT_EQ(s.output_copies, 1u);
  EXPECT_EQ(s.output_zero_copy, 1u);
  EXPECT_EQ(s.input_copies, 0u);

  // invoke-dynamic must not hand the caller's input memory back as an output: cloned.
  nns_tensors_desc oinfo{};
  std::vector<GstTensorMemory> douts;
  ASSERT_EQ(inst.invoke_dynamic(p.input, ins, oinfo, douts), 0) << inst.error();
  ASSERT_EQ(douts.size(), 1u);
  EXPECT_NE(douts[0].data, static_cast<void *>(buf.data()));
  EXPECT_EQ(std::memcmp(douts[0].data, buf.data(), 4), 0);
  EXPECT_EQ(buf, (std::vector<uint8_t>{4, 5, 6, 7}));
  inst.free_output(douts[0].data);
  s = stats_of(inst);
  EXPECT_EQ(s.output_copies, 2u);
}

TEST(PytorchBackend, NestedTupleListOutputsDynamicZeroCopy) {
  REQUIRE_BACKEND();
  Props p;
  p.models = {gen_model("nested_out")};
  p.invoke_dynamic = 1;
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  std::vector<float> x{1, 2, 3, 4, 5, 6};
  nns_tensors_desc info = tensors_desc({tensor_desc(_NNS_FLOAT32, {3, 2})});
  std::vector<GstTensorMemory> ins{{x.data(), 24}};
  nns_tensors_desc oinfo{};
  std::vector<GstTensorMemory> outs;
  ASSERT_EQ(inst.invoke_dynamic(info, ins, oinfo, outs), 0) << inst.error();
  ASSERT_EQ(oinfo.num_tensors, 3u);
  EXPECT_EQ(oinfo.format, static_cast<uint32_t>(_NNS_TENSOR_FORMAT_FLEXIBLE));
  EXPECT_EQ(oinfo.tensors[0].dims[0], 3u);
  EXPECT_EQ(oinfo.tensors[0].dims[1], 2u);
  EXPECT_EQ(oinfo.tensors[1].dims[0], 1u);  // 0-dim sum -> one element
  EXPECT_EQ(oinfo.tensors[1].dims[1], 0u);
  auto *o0 = static_cast<const float *>(outs[0].data);
  auto *o1 = static_cast<const float *>(outs[1].data);
  auto *o2 = static_cast<const float *>(outs[2].data);
  for (int i = 0; i < 6; ++i) {
    EXPECT_FLOAT_EQ(o0[i], 2 * x[i]);
    EXPECT_FLOAT_EQ(o2[i], x[i] + 1);
  }
  EXPECT_FLOAT_EQ(o1[0], 21.f);
  for (auto &m : outs) inst.free_output(m.data);
  nns_pytorch_stats s = stats_of(inst);
  EXPECT_EQ(s.output_zero_copy, 3u);
  EXPECT_EQ(s.output_copies, 0u);

  // The same model with static outputs: three caller buffers.
  Props q;
  q.models = {gen_model("nested_out")};
  q.input = info;
  Instance st(lib().api(), q);
  ASSERT_EQ(st.rc(), 0) << st.error();
  nns_tensors_desc in, out;
  ASSERT_EQ(st.model_info(in, out), 0) << st.error();
  ASSERT_EQ(out.num_tensors, 3u);
  std::vector<float> a(6), b(1), c(6);
  std::vector<GstTensorMemory> souts{{a.data(), 24}, {b.data(), 4}, {c.data(), 24}};
  ASSERT_EQ(st.invoke(ins, souts), 0) << st.error();
  EXPECT_FLOAT_EQ(b[0], 21.f);
  EXPECT_FLOAT_EQ(c[5], 7.f);
}

TEST(PytorchBackend, DynamicNeverHandsOutSharedStorage) {
  REQUIRE_BACKEND();
  std::vector<float> x{1, 2, 3, 4};
  nns_tensors_desc info = tensors_desc({tensor_desc(_NNS_FLOAT32, {4})});
  std::vector<GstTensorMemory> ins{{x.data(), 16}};
  {
    Props p;
    p.models = {gen_model("param_out")};
    Instance inst(lib().api(), p);
    ASSERT_EQ(inst.rc(), 0) << inst.error();
    for (int round = 0; round < 2; ++round) {
      nns_tensors_desc oinfo{};
      std::vector<GstTensorMemory> outs;
      ASSERT_EQ(inst.invoke_dynamic(info, ins, oinfo, outs), 0) << inst.error();
      auto *o = static_cast<float *>(outs[0].data);
      for (int i = 0; i < 4; ++i) EXPECT_FLOAT_EQ(o[i], static_cast<float>(i));
      o[0] = 99.f;  // scribbling on our copy must not reach the model's buffer
      inst.free_output(outs[0].data);
    }
    EXPECT_EQ(stats_of(inst).output_zero_copy, 0u);
  }
  {
    Props p;
    p.models = {gen_model("dup_out")};
    Instance inst(lib().api(), p);
    ASSERT_EQ(inst.rc(), 0) << inst.error();
    nns_tensors_desc oinfo{};
    std::vector<GstTensorMemory> outs;
    ASSERT_EQ(inst.invoke_dynamic(info, ins, oinfo, outs), 0) << inst.error();
    ASSERT_EQ(outs.size(), 2u);
    EXPECT_NE(outs[0].data, outs[1].data);
    EXPECT_FLOAT_EQ(static_cast<float *>(outs[1].data)[3], 8.f);
    inst.free_output(outs[0].data);
    inst.free_output(outs[1].data);
  }
}

TEST(PytorchBackend, BoolOutputIsUint8) {
  REQUIRE_BACKEND();
  Props p;
  p.models = {gen_model("bool_out")};
  p.input = tensors_desc({tensor_desc(_NNS_INT32, {4})});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc in, out;
  ASSERT_EQ(inst.model_info(in, out), 0) << inst.error();
  EXPECT_EQ(out.tensors[0].type, static_cast<uint32_t>(_NNS_UINT8));
  std::vector<int32_t> x{-1, 0, 5, 7};
  std::vector<uint8_t> o(4, 9);
  std::vector<GstTensorMemory> ins{{x.data(), 16}};
  std::vector<GstTensorMemory> outs{{o.data(), 4}};
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  EXPECT_EQ(o, (std::vector<uint8_t>{0, 0, 1, 1}));
}

// ---- errors ----

TEST(PytorchBackendErrors, MissingModelFile) {
  REQUIRE_BACKEND();
  Props p;
  p.models = {"/nonexistent/dir/model.pt"};
  Instance inst(lib().api(), p);
  EXPECT_EQ(inst.rc(), -ENOENT);
  EXPECT_NE(inst.error().find("/nonexistent/dir/model.pt"), std::string::npos) << inst.error();
  EXPECT_NE(inst.error().find("does not exist"), std::string::npos) << inst.error();
}

TEST(PytorchBackendErrors, CorruptModelFile) {
  REQUIRE_BACKEND();
  std::string dir = nns::test::make_temp_dir();
  std::string path = dir + "/corrupt.pt";
  std::ofstream(path) << "this is a text file, not a TorchScript archive\n";
  Props p;
  p.models = {path};
  Instance inst(lib().api(), p);
  EXPECT_EQ(inst.rc(), -EINVAL);
  EXPECT_NE(inst.error().find("cannot load TorchScript model '" + path + "'"), std::string::npos)
      << inst.error();
  // torch's own reason is included, without its C++ backtrace.
  EXPECT_NE(inst.error().find("PytorchStreamReader"), std::string::npos) << inst.error();
  EXPECT_EQ(inst.error().find("frame #"), std::string::npos) << inst.error();
  std::filesystem::remove_all(dir);
}

TEST(PytorchBackendErrors, WrongInputShapeCarriesTorchMessage) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = lenet_props();
  p.input = tensors_desc({tensor_desc(_NNS_UINT8, {2, 28, 28, 1})});  // two channels
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  std::vector<uint8_t> data(2 * 784), scores(10);
  std::vector<GstTensorMemory> ins{{data.data(), data.size()}};
  std::vector<GstTensorMemory> outs{{scores.data(), 10}};
  EXPECT_EQ(inst.invoke(ins, outs), -EIO);
  std::string e = inst.error();
  EXPECT_NE(e.find(shared_model("pytorch_lenet5.pt")), std::string::npos) << e;
  EXPECT_NE(e.find("uint8 2:28:28:1"), std::string::npos) << e;
  EXPECT_NE(e.find("channels"), std::string::npos) << e;  // torch: "expected ... 1 channels"
  EXPECT_EQ(e.find("Traceback"), std::string::npos) << e;
}

TEST(PytorchBackendErrors, OutputPropertiesDisagreeWithModel) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = lenet_props();
  p.output = tensors_desc({tensor_desc(_NNS_FLOAT32, {10, 1})});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  std::vector<uint8_t> digit(784);
  std::vector<float> scores(10);
  std::vector<GstTensorMemory> ins{{digit.data(), 784}};
  std::vector<GstTensorMemory> outs{{scores.data(), 40}};
  EXPECT_NE(inst.invoke(ins, outs), 0);
  EXPECT_NE(inst.error().find("output tensor #0 is uint8 [1,10]"), std::string::npos)
      << inst.error();
  EXPECT_NE(inst.error().find("float32 10:1"), std::string::npos) << inst.error();
  nns_tensors_desc in, out;
  EXPECT_NE(inst.model_info(in, out), 0);  // the probe run finds the same disagreement
}

TEST(PytorchBackendErrors, InputSizeAndCountChecked) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = lenet_props();
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  std::vector<uint8_t> digit(700), scores(10);
  std::vector<GstTensorMemory> ins{{digit.data(), 700}};
  std::vector<GstTensorMemory> outs{{scores.data(), 10}};
  EXPECT_EQ(inst.invoke(ins, outs), -EINVAL);
  EXPECT_NE(inst.error().find("input tensor #0 has 700 bytes, but uint8 1:28:28:1 needs 784"),
            std::string::npos)
      << inst.error();
  std::vector<GstTensorMemory> two{{digit.data(), 700}, {digit.data(), 700}};
  EXPECT_EQ(inst.invoke(two, outs), -EINVAL);
  EXPECT_NE(inst.error().find("configured for 1 input tensor(s), got 2"), std::string::npos)
      << inst.error();
}

TEST(PytorchBackendErrors, UnsupportedResultKind) {
  REQUIRE_BACKEND();
  Props p;
  p.models = {gen_model("dict_out")};
  p.input = tensors_desc({tensor_desc(_NNS_FLOAT32, {2})});
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  nns_tensors_desc in, out;
  EXPECT_NE(inst.model_info(in, out), 0);
  EXPECT_NE(inst.error().find("only tensors and tuples/lists of tensors"), std::string::npos)
      << inst.error();
}

TEST(PytorchBackendErrors, CustomOptions) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  {
    Props p = lenet_props();
    p.custom = "NumThreads:1,use_gpu:false";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), 0) << inst.error();
  }
  for (const char *opt : {"OptimizeForInference:false", "OptimizeForInference:true"}) {
    Props p = lenet_props();
    p.custom = opt;
    Instance inst(lib().api(), p);
    ASSERT_EQ(inst.rc(), 0) << opt << ": " << inst.error();
    std::vector<uint8_t> digit =
        nns::test::read_file(nns::test::shared_models_dir() + "/data/9.raw");
    std::vector<uint8_t> scores(10);
    std::vector<GstTensorMemory> ins{{digit.data(), 784}};
    std::vector<GstTensorMemory> outs{{scores.data(), 10}};
    ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
    EXPECT_EQ(scores[9], 254) << opt;
    EXPECT_EQ(stats_of(inst).optimized, std::string(opt).find("true") != std::string::npos) << opt;
  }
  {
    Props p = lenet_props();
    p.custom = "numthreads:1, Bogus_Key:3";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find("unknown custom option 'Bogus_Key'"), std::string::npos)
        << inst.error();
  }
  {
    Props p = lenet_props();
    p.custom = "NumThreads:many";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find("NumThreads:many"), std::string::npos) << inst.error();
  }
  {
    Props p = lenet_props();
    p.custom = "use_gpu";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -EINVAL);
    EXPECT_NE(inst.error().find("'use_gpu' is not of the form key:value"), std::string::npos)
        << inst.error();
  }
  {
    Props p = lenet_props();
    p.custom = "use_gpu:true";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -ENODEV);
    EXPECT_NE(inst.error().find("no usable CUDA device"), std::string::npos) << inst.error();
  }
}

TEST(PytorchBackendErrors, Accelerator) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  {
    Props p = lenet_props();
    p.accelerator = "true:gpu";
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), -ENODEV);
    EXPECT_NE(inst.error().find("accelerator=true:gpu"), std::string::npos) << inst.error();
  }
  for (const char *a : {"true:gpu,cpu", "true:cpu", "false:gpu", "true:npu,auto"}) {
    Props p = lenet_props();
    p.accelerator = a;
    Instance inst(lib().api(), p);
    EXPECT_EQ(inst.rc(), 0) << a << ": " << inst.error();
  }
}

TEST(PytorchBackend, ReloadKeepsOldModelOnFailure) {
  REQUIRE_BACKEND();
  NNS_REQUIRE_SHARED_MODELS();
  Props p = lenet_props();
  Instance inst(lib().api(), p);
  ASSERT_EQ(inst.rc(), 0) << inst.error();
  Props bad = lenet_props();
  bad.models = {"/nonexistent/other.pt"};
  EXPECT_EQ(inst.reload(bad), -ENOENT);
  std::vector<uint8_t> digit = nns::test::read_file(nns::test::shared_models_dir() + "/data/9.raw");
  std::vector<uint8_t> scores(10);
  std::vector<GstTensorMemory> ins{{digit.data(), 784}};
  std::vector<GstTensorMemory> outs{{scores.data(), 10}};
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  EXPECT_EQ(scores[9], 254);
  EXPECT_EQ(inst.reload(p), 0) << inst.error();
  ASSERT_EQ(inst.invoke(ins, outs), 0) << inst.error();
  EXPECT_EQ(scores[9], 254);
}

}  // namespace

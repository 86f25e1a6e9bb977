// SPDX-License-Identifier: LGPL-2.1-only
// The python3 filter back end: how returned arrays become outputs (lent or copied), and the
// errors for broken scripts, bad shapes and bad results (messages name the script and carry the
// Python traceback; nothing crashes, and a failed invoke leaves no output behind).
#include "filter_python3_util.h"

namespace {

using namespace nns::test::python3;

bool has(const std::string &s, const std::string &what) {
  return s.find(what) != std::string::npos;
}

// output_cases.py: one uint8 tensor of 8 in, two of 4 out; custom picks the case.
class OutputCases : public ::testing::Test {
 protected:
  uint8_t in_[8] = {10, 11, 12, 13, 14, 15, 16, 17};
  std::vector<GstTensorMemory> ins_{{in_, 8}};
  std::unique_ptr<Filter> f_;

  void open(const char *mode) {
    f_ = std::make_unique<Filter>(script("output_cases.py"), mode);
    ASSERT_EQ(f_->rc, 0) << f_->error();
  }
  void expect(const GstTensorMemory &o, std::vector<uint8_t> want) {
    ASSERT_NE(o.data, nullptr);
    ASSERT_EQ(o.size, 4u);
    const auto *p = static_cast<const uint8_t *>(o.data);
    EXPECT_TRUE(p + 4 <= in_ || p >= in_ + 8) << "output inside the input buffer";
    EXPECT_EQ(std::vector<uint8_t>(p, p + 4), want);
  }
  // A failed invoke sets no output, and the next one (the script fails once) works.
  void expect_failure_then_recovery(const std::string &msg) {
    std::vector<GstTensorMemory> outs(2);
    EXPECT_NE(f_->invoke(ins_, outs), 0);
    EXPECT_TRUE(has(f_->error(), msg)) << f_->error();
    EXPECT_TRUE(has(f_->error(), "output_cases.py")) << f_->error();
    EXPECT_EQ(outs[0].data, nullptr);
    EXPECT_EQ(outs[1].data, nullptr);
    ASSERT_EQ(f_->invoke(ins_, outs), 0) << f_->error();
    expect(outs[0], {10, 11, 12, 13});
    expect(outs[1], {14, 15, 16, 17});
    f_->release(outs);
  }
};

TEST_F(OutputCases, FreshArraysAreLent) {
  open("copy");
  std::vector<GstTensorMemory> outs(2);
  ASSERT_EQ(f_->invoke(ins_, outs), 0) << f_->error();
  expect(outs[0], {10, 11, 12, 13});
  expect(outs[1], {14, 15, 16, 17});
  f_->release(outs);
}

TEST_F(OutputCases, ViewsOfTheInputAreCopied) {
  for (const char *mode : {"alias", "reshaped_alias"}) {
    open(mode);
    std::vector<GstTensorMemory> outs(2);
    ASSERT_EQ(f_->invoke(ins_, outs), 0) << f_->error();
    expect(outs[0], {10, 11, 12, 13});
    expect(outs[1], {14, 15, 16, 17});
    f_->release(outs);
  }
}

TEST_F(OutputCases, StridedArraysAreMadeContiguous) {
  open("strided");
  std::vector<GstTensorMemory> outs(2);
  ASSERT_EQ(f_->invoke(ins_, outs), 0) << f_->error();
  expect(outs[0], {0, 2, 4, 6});
  expect(outs[1], {7, 5, 3, 1});
  f_->release(outs);
}

TEST_F(OutputCases, ShapedArraysOfTheRightSizeAreAccepted) {
  open("2d");
  std::vector<GstTensorMemory> outs(2);
  ASSERT_EQ(f_->invoke(ins_, outs), 0) << f_->error();
  expect(outs[0], {0, 1, 2, 3});
  expect(outs[1], {4, 5, 6, 7});
  f_->release(outs);
}

TEST_F(OutputCases, SameArrayTwiceGivesTwoBuffers) {
  open("same");
  std::vector<GstTensorMemory> outs(2);
  ASSERT_EQ(f_->invoke(ins_, outs), 0) << f_->error();
  expect(outs[0], {0, 1, 2, 3});
  expect(outs[1], {0, 1, 2, 3});
  EXPECT_NE(outs[0].data, outs[1].data);
  f_->release(outs);
}

TEST_F(OutputCases, KeptArrayIsLentOnceAtATime) {
  open("kept");
  std::vector<GstTensorMemory> first(2), second(2), third(2);
  ASSERT_EQ(f_->invoke(ins_, first), 0) << f_->error();
  expect(first[0], {0, 1, 2, 3});
  // Still lent: the next result is a copy.
  ASSERT_EQ(f_->invoke(ins_, second), 0) << f_->error();
  expect(second[0], {0, 1, 2, 3});
  EXPECT_NE(second[0].data, first[0].data);
  void *lent = first[0].data;
  f_->release(first);
  f_->release(second);
  // Returned: the module's array is lent directly again (zero copy).
  ASSERT_EQ(f_->invoke(ins_, third), 0) << f_->error();
  EXPECT_EQ(third[0].data, lent);
  f_->release(third);
}

TEST_F(OutputCases, OutputsOutliveTheFilter) {
  open("copy");
  std::vector<GstTensorMemory> outs(2);
  ASSERT_EQ(f_->invoke(ins_, outs), 0) << f_->error();
  void *priv = f_->priv;
  f_->priv = nullptr;
  backend()->close(priv);
  f_.reset();
  // Downstream still holds the buffers; they stay valid and are released without the instance.
  EXPECT_EQ(static_cast<const uint8_t *>(outs[1].data)[3], 17);
  backend()->free_output(priv, outs[0].data);
  backend()->free_output(priv, outs[1].data);
  backend()->free_output(priv, outs[1].data);  // unknown pointer now: ignored
}

TEST_F(OutputCases, RaiseInInvoke_n) {
  open("raise");
  expect_failure_then_recovery("KeyError: 'raise case'");
}
TEST_F(OutputCases, NotAnArray_n) {
  open("not_array");
  expect_failure_then_recovery("output 0 is a bytes, not a numpy array");
}
TEST_F(OutputCases, TupleInsteadOfList_n) {
  open("not_list");
  expect_failure_then_recovery("invoke() returned tuple; expected a list of numpy arrays");
}
TEST_F(OutputCases, None_n) {
  open("none");
  expect_failure_then_recovery("invoke() returned NoneType");
}
TEST_F(OutputCases, WrongCount_n) {
  open("count");
  expect_failure_then_recovery("invoke() returned 1 arrays; the script's output has 2 tensors");
}
TEST_F(OutputCases, SecondOutputWrongType_n) {
  open("second_bad");
  expect_failure_then_recovery("output 1 has numpy type int32; expected uint8");
}
TEST_F(OutputCases, ShortOutput_n) {
  open("short");
  expect_failure_then_recovery("output 1 has 3 bytes; expected 4 (4 uint8)");
}
TEST_F(OutputCases, SignednessMismatch_n) {
  open("int8");
  expect_failure_then_recovery("output 1 has numpy type int8; expected uint8");
}

TEST_F(OutputCases, InputSizeMismatch_n) {
  open("copy");
  std::vector<GstTensorMemory> ins{{in_, 7}}, outs(2);
  EXPECT_NE(f_->invoke(ins, outs), 0);
  EXPECT_TRUE(has(f_->error(), "input tensor 0 has 7 bytes; expected 8 (8 uint8)")) << f_->error();
  std::vector<GstTensorMemory> two{{in_, 8}, {in_, 8}};
  EXPECT_NE(f_->invoke(two, outs), 0);
  EXPECT_TRUE(has(f_->error(), "invoked with 2 inputs and 2 outputs; the script has 1 and 2"))
      << f_->error();
}

TEST(FilterPython3Errors, SyntaxError_n) {
  REQUIRE_BACKEND();
  std::string path = script("bad_syntax.py");
  Filter f(path);
  EXPECT_NE(f.rc, 0);
  EXPECT_EQ(f.priv, nullptr);
  std::string e = f.error();
  EXPECT_TRUE(has(e, "'" + path + "'")) << e;
  EXPECT_TRUE(has(e, "SyntaxError")) << e;
  EXPECT_TRUE(has(e, "line 7")) << e;
  EXPECT_TRUE(has(e, "def invoke(self, input_array)")) << e;  // the offending source line
}

TEST(FilterPython3Errors, RaiseInInvokeHasTraceback_n) {
  REQUIRE_BACKEND();
  std::string path = script("raise_invoke.py");
  Filter f(path);
  ASSERT_EQ(f.rc, 0) << f.error();
  float x[4] = {};
  std::vector<GstTensorMemory> ins{{x, sizeof x}}, outs(1);
  EXPECT_EQ(f.invoke(ins, outs), -EINVAL);
  std::string e = f.error();
  // First line: what failed and the exception; then the traceback with both script frames.
  EXPECT_EQ(e.rfind("Python script '" + path +
                        "': invoke() raised: ValueError: input rejected "
                        "by raise_invoke.py: 4 elements\n",
                    0),
            0u)
      << e;
  EXPECT_TRUE(has(e, "Traceback (most recent call last):")) << e;
  EXPECT_TRUE(has(e, "File \"" + path + "\", line 19, in invoke")) << e;
  EXPECT_TRUE(has(e, "File \"" + path + "\", line 8, in check_input")) << e;
  EXPECT_EQ(outs[0].data, nullptr);
}

TEST(FilterPython3Errors, SysExitDoesNotEndTheProcess_n) {
  REQUIRE_BACKEND();
  Filter f(script("exit_invoke.py"));
  ASSERT_EQ(f.rc, 0) << f.error();
  uint8_t x[4] = {};
  std::vector<GstTensorMemory> ins{{x, 4}}, outs(1);
  EXPECT_NE(f.invoke(ins, outs), 0);
  EXPECT_TRUE(has(f.error(), "SystemExit: 3")) << f.error();
  EXPECT_NE(f.invoke(ins, outs), 0);  // still here, still failing cleanly
}

TEST(FilterPython3Errors, LoadFailures_n) {
  REQUIRE_BACKEND();
  struct Case {
    const char *file;
    const char *custom;
    std::vector<std::string> want;
  } cases[] = {
      {"no_such_script.py", nullptr, {"cannot open Python script", "No such file or directory"}},
      {"raise_init.py",
       "a b",
       {"CustomFilter(a b) raised: RuntimeError: constructor refuses "
        "arguments ('a', 'b')",
        "line 5, in __init__"}},
      {"raise_import.py",
       nullptr,
       {"failed to load: ModuleNotFoundError: No module named "
        "'this_module_does_not_exist_anywhere'",
        "line 4"}},
      {"no_class.py", nullptr, {"defines no class CustomFilter"}},
      {"no_dims.py",
       nullptr,
       {"CustomFilter needs setInputDim(self, shapes) or both "
        "getInputDim(self) and getOutputDim(self)"}},
  };
  for (const Case &c : cases) {
    std::string path = script(c.file);
    Filter f(path, c.custom);
    EXPECT_NE(f.rc, 0) << c.file;
    EXPECT_EQ(f.priv, nullptr);
    EXPECT_TRUE(has(f.error(), path)) << f.error();
    for (const std::string &w : c.want)
      EXPECT_TRUE(has(f.error(), w)) << c.file << ": " << f.error();
  }
  // A folder is not a script.
  Filter dir(std::string(NNS_SOURCE_DIR) + "/tests/data/python");
  EXPECT_NE(dir.rc, 0);
  EXPECT_TRUE(has(dir.error(), "is not a regular file")) << dir.error();
}

TEST(FilterPython3Errors, NotExactlyOneModel_n) {
  REQUIRE_BACKEND();
  std::string a = script("passthrough.py");
  const char *models[] = {a.c_str(), a.c_str()};
  auto none = make_desc({});
  nns_filter_props p{};
  p.model_files = models;
  p.num_models = 2;
  p.input = p.output = none.get();
  void *priv = nullptr;
  char err[512];
  EXPECT_EQ(backend()->open(&p, &priv, err, sizeof err), -EINVAL);
  EXPECT_TRUE(has(err, "exactly one Python script")) << err;
  EXPECT_EQ(priv, nullptr);
}

TEST(FilterPython3Errors, BadShapes_n) {
  REQUIRE_BACKEND();
  struct Case {
    const char *custom;
    const char *want;
  } cases[] = {
      {"none",
       "getOutputDim() returned NoneType; expected a list of nnstreamer_python.TensorShape"},
      {"empty", "getOutputDim() returned 0 tensors; expected 1 to 256"},
      {"int", "getOutputDim(), tensor 0 is a int, not a nnstreamer_python.TensorShape"},
      {"negative", "getOutputDim(), tensor 0 dimension 1 is -1; dimensions are integers"},
      {"fraction", "getOutputDim(), tensor 0 dimension 1 is 2.5"},
      {"complex",
       "getOutputDim(), tensor 0 type is numpy type 'complex64', which NNStreamer has "
       "no tensor type for"},
      {"object", "numpy type 'object'"},
      {"zero_inside", "getOutputDim(), tensor 0 dimension 2 is 2 after a 0 dimension"},
      {"huge", "dimension 0 is 8589934592"},
      {"string_dims", "dimension 0 is a str, not an integer"},
      {"raise", "getOutputDim() raised: IndexError: getOutputDim broke"},
  };
  for (const Case &c : cases) {
    Filter f(script("bad_dims.py"), c.custom);
    EXPECT_NE(f.rc, 0) << c.custom;
    EXPECT_TRUE(has(f.error(), c.want)) << c.custom << ": " << f.error();
    EXPECT_TRUE(has(f.error(), "bad_dims.py")) << f.error();
  }
  // Accepted forms: integral floats, trailing zeros (NNStreamer's padding).
  Filter ok1(script("bad_dims.py"), "float_ok");
  ASSERT_EQ(ok1.rc, 0) << ok1.error();
  ASSERT_EQ(ok1.model_info(), 0);
  EXPECT_EQ(dims_of(ok1.out->tensors[0]), (std::vector<uint32_t>{3, 2}));
  Filter ok2(script("bad_dims.py"), "trailing_zero");
  ASSERT_EQ(ok2.rc, 0) << ok2.error();
  ASSERT_EQ(ok2.model_info(), 0);
  EXPECT_EQ(dims_of(ok2.out->tensors[0]), (std::vector<uint32_t>{3, 2}));
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// Pipeline API: switches (input-selector, output-selector), valves, typed element properties,
// tensor_if custom conditions, availability checks, handle checks, and a real model
// (MobileNet v2 on ONNX Runtime classifying the orange photo through appsrc -> tensor_sink).
#include <algorithm>
#include <fstream>

#include "api/ml_pipeline_test_util.h"

using namespace capi_test;

namespace {

struct Pipe {
  ml_pipeline_h p = nullptr;
  explicit Pipe(const std::string &d) {
    EXPECT_EQ(ml_pipeline_construct(d.c_str(), nullptr, nullptr, &p), ML_ERROR_NONE) << ml_error();
  }
  ~Pipe() {
    if (p) {
      EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE) << ml_error();
    }
  }
};

void push_u8(ml_pipeline_src_h src, std::vector<uint8_t> v) {
  ml_tensors_info_h info = make_info({{ML_TENSOR_TYPE_UINT8, {static_cast<unsigned>(v.size())}}});
  ml_tensors_data_h d = make_data(info, {v});
  EXPECT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_AUTO_FREE), ML_ERROR_NONE)
      << ml_error();
  ml_tensors_info_destroy(info);
}

std::string error() {
  return ml_error();
}

}  // namespace

TEST(MlPipelineControls, ValveClosesAndOpens) {
  // tee without queues pushes to its pads in order on one thread: when "seen" has frame k,
  // frame k has already passed (or been dropped by) the valve.
  Pipe x("appsrc name=src caps=" + tensor_caps("2:1:1:1", "uint8") +
         " ! tee name=t t. ! valve name=v drop=false ! tensor_sink name=sink async=false "
         "t. ! tensor_sink name=seen async=false");
  ml_pipeline_src_h src = nullptr;
  ml_pipeline_valve_h v = nullptr;
  ml_pipeline_sink_h s = nullptr, s2 = nullptr;
  Collector c, seen;
  ASSERT_EQ(ml_pipeline_src_get_handle(x.p, "src", &src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_valve_get_handle(x.p, "v", &v), ML_ERROR_NONE) << error();
  ASSERT_EQ(ml_pipeline_sink_register(x.p, "sink", Collector::cb, &c, &s), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_sink_register(x.p, "seen", Collector::cb, &seen, &s2), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(x.p), ML_ERROR_NONE);
  push_u8(src, {1, 1});
  ASSERT_TRUE(seen.wait_for(1));
  ASSERT_EQ(ml_pipeline_valve_set_open(v, false), ML_ERROR_NONE);
  push_u8(src, {2, 2});
  push_u8(src, {3, 3});
  ASSERT_TRUE(seen.wait_for(3));
  ASSERT_EQ(ml_pipeline_valve_set_open(v, true), ML_ERROR_NONE);
  push_u8(src, {4, 4});
  ASSERT_TRUE(seen.wait_for(4));
  {
    std::lock_guard lk(c.m);
    ASSERT_EQ(c.frames.size(), 2u);  // 2 and 3 were dropped
    EXPECT_EQ(c.frames[0].tensors[0], (Bytes{1, 1}));
    EXPECT_EQ(c.frames[1].tensors[0], (Bytes{4, 4}));
  }
  EXPECT_EQ(ml_pipeline_valve_release_handle(v), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_valve_set_open(v, true), ML_ERROR_INVALID_PARAMETER);
  ml_pipeline_valve_h bad = nullptr;
  EXPECT_EQ(ml_pipeline_valve_get_handle(x.p, "sink", &bad), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("'sink' is a tensor_sink, not a valve"), std::string::npos) << error();
  EXPECT_EQ(ml_pipeline_valve_get_handle(x.p, nullptr, &bad), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_valve_get_handle(x.p, "v", nullptr), ML_ERROR_INVALID_PARAMETER);
}

TEST(MlPipelineControls, OutputSelectorRoutes) {
  Pipe x("appsrc name=src caps=" + tensor_caps("2:1:1:1", "uint8") +
         " ! output-selector name=outs outs.src_0 ! tensor_sink name=s0 async=false "
         "outs.src_1 ! tensor_sink name=s1 async=false");
  ml_pipeline_switch_h sw = nullptr;
  ml_pipeline_switch_e type = ML_PIPELINE_SWITCH_INPUT_SELECTOR;
  ASSERT_EQ(ml_pipeline_switch_get_handle(x.p, "outs", &type, &sw), ML_ERROR_NONE) << error();
  EXPECT_EQ(type, ML_PIPELINE_SWITCH_OUTPUT_SELECTOR);
  char **list = nullptr;
  ASSERT_EQ(ml_pipeline_switch_get_pad_list(sw, &list), ML_ERROR_NONE);
  std::vector<std::string> names;
  for (int i = 0; list[i]; ++i) {
    names.emplace_back(list[i]);
    free(list[i]);
  }
  free(list);
  std::sort(names.begin(), names.end());
  EXPECT_EQ(names, (std::vector<std::string>{"src_0", "src_1"}));
  Collector c0, c1;
  ml_pipeline_sink_h h0 = nullptr, h1 = nullptr;
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(x.p, "s0", Collector::cb, &c0, &h0), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_sink_register(x.p, "s1", Collector::cb, &c1, &h1), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_src_get_handle(x.p, "src", &src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(x.p), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_switch_select(sw, "src_0"), ML_ERROR_NONE) << error();
  push_u8(src, {1, 0});
  ASSERT_TRUE(c0.wait_for(1));
  ASSERT_EQ(ml_pipeline_switch_select(sw, "src_1"), ML_ERROR_NONE) << error();
  push_u8(src, {2, 0});
  ASSERT_TRUE(c1.wait_for(1));
  EXPECT_EQ(c0.count(), 1u);
  EXPECT_EQ(c1.frames[0].tensors[0], (Bytes{2, 0}));
  EXPECT_EQ(ml_pipeline_switch_select(sw, "src_7"), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("no selectable pad 'src_7' (its pads: src_0, src_1)"), std::string::npos)
      << error();
  EXPECT_EQ(ml_pipeline_switch_select(sw, nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_switch_get_pad_list(sw, nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_switch_release_handle(sw), ML_ERROR_NONE);
}

TEST(MlPipelineControls, InputSelectorChoosesSource) {
  std::string caps = tensor_caps("2:1:1:1", "uint8");
  Pipe x(
      "input-selector name=ins ! tensor_sink name=sink async=false "
      "appsrc name=a caps=" +
      caps + " ! ins.sink_0 appsrc name=b caps=" + caps + " ! ins.sink_1");
  ml_pipeline_switch_h sw = nullptr;
  ml_pipeline_switch_e type = ML_PIPELINE_SWITCH_OUTPUT_SELECTOR;
  ASSERT_EQ(ml_pipeline_switch_get_handle(x.p, "ins", &type, &sw), ML_ERROR_NONE) << error();
  EXPECT_EQ(type, ML_PIPELINE_SWITCH_INPUT_SELECTOR);
  ml_pipeline_src_h a = nullptr, b = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(x.p, "a", &a), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_src_get_handle(x.p, "b", &b), ML_ERROR_NONE);
  Collector c;
  ml_pipeline_sink_h s = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(x.p, "sink", Collector::cb, &c, &s), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_switch_select(sw, "sink_1"), ML_ERROR_NONE) << error();
  ASSERT_EQ(ml_pipeline_start(x.p), ML_ERROR_NONE);
  push_u8(a, {10, 10});  // not selected: dropped
  push_u8(b, {20, 20});
  ASSERT_TRUE(c.wait_for(1));
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  std::lock_guard lk(c.m);
  ASSERT_EQ(c.frames.size(), 1u);
  EXPECT_EQ(c.frames[0].tensors[0], (Bytes{20, 20}));
}

TEST(MlPipelineControls, ElementProperties) {
  Pipe x(
      "videotestsrc name=vsrc num-buffers=5 ! video/x-raw,width=4,height=4 ! "
      "tensor_converter name=conv ! tensor_sink name=sink async=false "
      "audiotestsrc name=asrc num-buffers=1 ! fakesink name=fs async=false");
  ml_pipeline_element_h v = nullptr, a = nullptr, sink = nullptr, fs = nullptr;
  ASSERT_EQ(ml_pipeline_element_get_handle(x.p, "vsrc", &v), ML_ERROR_NONE) << error();
  ASSERT_EQ(ml_pipeline_element_get_handle(x.p, "asrc", &a), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_element_get_handle(x.p, "sink", &sink), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_element_get_handle(x.p, "fs", &fs), ML_ERROR_NONE);
  // bool
  int32_t bv = -1;
  ASSERT_EQ(ml_pipeline_element_set_property_bool(sink, "emit-signal", 0), ML_ERROR_NONE)
      << error();
  ASSERT_EQ(ml_pipeline_element_get_property_bool(sink, "emit-signal", &bv), ML_ERROR_NONE);
  EXPECT_EQ(bv, 0);
  ASSERT_EQ(ml_pipeline_element_set_property_bool(sink, "emit-signal", 1), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_element_get_property_bool(sink, "emit-signal", &bv), ML_ERROR_NONE);
  EXPECT_EQ(bv, 1);
  // int32
  int32_t iv = 0;
  ASSERT_EQ(ml_pipeline_element_set_property_int32(v, "num-buffers", 7), ML_ERROR_NONE) << error();
  ASSERT_EQ(ml_pipeline_element_get_property_int32(v, "num-buffers", &iv), ML_ERROR_NONE);
  EXPECT_EQ(iv, 7);
  // int64
  int64_t lv = 0;
  ASSERT_EQ(ml_pipeline_element_set_property_int64(v, "timestamp-offset", 1234567890123LL),
            ML_ERROR_NONE)
      << error();
  ASSERT_EQ(ml_pipeline_element_get_property_int64(v, "timestamp-offset", &lv), ML_ERROR_NONE);
  EXPECT_EQ(lv, 1234567890123LL);
  // uint32
  uint32_t uv = 0;
  ASSERT_EQ(ml_pipeline_element_set_property_uint32(v, "foreground-color", 0xff00ff00u),
            ML_ERROR_NONE)
      << error();
  ASSERT_EQ(ml_pipeline_element_get_property_uint32(v, "foreground-color", &uv), ML_ERROR_NONE);
  EXPECT_EQ(uv, 0xff00ff00u);
  // uint64
  uint64_t u64 = 0;
  ASSERT_EQ(ml_pipeline_element_set_property_uint64(a, "blocksize", 4096),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("is of type uint32"), std::string::npos) << error();
  ASSERT_EQ(ml_pipeline_element_set_property_uint64(fs, "max-lateness", 5),
            ML_ERROR_INVALID_PARAMETER);
  ASSERT_EQ(ml_pipeline_element_set_property_uint64(fs, "throttle-time", 12345), ML_ERROR_NONE)
      << error();
  ASSERT_EQ(ml_pipeline_element_get_property_uint64(fs, "throttle-time", &u64), ML_ERROR_NONE);
  EXPECT_EQ(u64, 12345u);
  // double
  double dv = 0;
  ASSERT_EQ(ml_pipeline_element_set_property_double(a, "freq", 523.25), ML_ERROR_NONE) << error();
  ASSERT_EQ(ml_pipeline_element_get_property_double(a, "freq", &dv), ML_ERROR_NONE);
  EXPECT_DOUBLE_EQ(dv, 523.25);
  // enum (videotestsrc pattern 1 = snow)
  uint32_t ev = 0;
  ASSERT_EQ(ml_pipeline_element_set_property_enum(v, "pattern", 1), ML_ERROR_NONE) << error();
  ASSERT_EQ(ml_pipeline_element_get_property_enum(v, "pattern", &ev), ML_ERROR_NONE);
  EXPECT_EQ(ev, 1u);
  EXPECT_EQ(ml_pipeline_element_set_property_enum(v, "pattern", 9999), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("9999 is not a value of property 'pattern'"), std::string::npos)
      << error();
  // string
  char *sv = nullptr;
  ASSERT_EQ(ml_pipeline_element_set_property_string(fs, "name", "fs"), ML_ERROR_NONE) << error();
  ASSERT_EQ(ml_pipeline_element_get_property_string(v, "name", &sv), ML_ERROR_NONE);
  EXPECT_STREQ(sv, "vsrc");
  free(sv);
  // Wrong type and unknown property: named in ml_error().
  EXPECT_EQ(ml_pipeline_element_set_property_int32(sink, "emit-signal", 1),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(
      error().find("property 'emit-signal' of element 'sink' (tensor_sink) is of type boolean"),
      std::string::npos)
      << error();
  EXPECT_NE(error().find("ml_pipeline_element_set_property_bool"), std::string::npos) << error();
  EXPECT_EQ(ml_pipeline_element_get_property_string(v, "num-buffers", &sv),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_element_set_property_bool(v, "no-such-prop", 1),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("element 'vsrc' (videotestsrc) has no property 'no-such-prop'"),
            std::string::npos)
      << error();
  EXPECT_EQ(ml_pipeline_element_get_property_int32(v, "num-buffers", nullptr),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_element_set_property_int32(v, nullptr, 1), ML_ERROR_INVALID_PARAMETER);
  // Handles of another kind and of a destroyed pipeline.
  ml_pipeline_element_h nope = nullptr;
  EXPECT_EQ(ml_pipeline_element_get_handle(x.p, "missing", &nope), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("no element named 'missing'"), std::string::npos) << error();
  ml_pipeline_valve_h fake_valve = v;
  EXPECT_EQ(ml_pipeline_valve_set_open(fake_valve, true), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("is an element handle of videotestsrc 'vsrc'"), std::string::npos)
      << error();
  EXPECT_NE(error().find("not a valve handle"), std::string::npos) << error();
  EXPECT_EQ(ml_pipeline_element_release_handle(fs), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_element_release_handle(fs), ML_ERROR_INVALID_PARAMETER);
  ASSERT_EQ(ml_pipeline_destroy(x.p), ML_ERROR_NONE);
  x.p = nullptr;
  EXPECT_EQ(ml_pipeline_element_set_property_int32(v, "num-buffers", 1),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("its pipeline was destroyed"), std::string::npos) << error();
}

namespace {

int odd_first(const ml_tensors_data_h data, const ml_tensors_info_h info, int *result, void *user) {
  void *raw = nullptr;
  size_t size = 0;
  unsigned n = 0;
  if (ml_tensors_info_get_count(info, &n) != ML_ERROR_NONE || n != 1) return -1;
  if (ml_tensors_data_get_tensor_data(data, 0, &raw, &size) != ML_ERROR_NONE || size != 2)
    return -1;
  *result = static_cast<uint8_t *>(raw)[0] % 2;
  ++*static_cast<int *>(user);
  return 0;
}

}  // namespace

TEST(MlPipelineControls, TensorIfCustomCondition) {
  int calls = 0;
  ml_pipeline_if_h cond = nullptr;
  ASSERT_EQ(ml_pipeline_tensor_if_custom_register("capi_odd", odd_first, &calls, &cond),
            ML_ERROR_NONE)
      << error();
  ml_pipeline_if_h dup = nullptr;
  EXPECT_EQ(ml_pipeline_tensor_if_custom_register("capi_odd", odd_first, &calls, &dup),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_tensor_if_custom_register(nullptr, odd_first, &calls, &dup),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_tensor_if_custom_register("x", nullptr, &calls, &dup),
            ML_ERROR_INVALID_PARAMETER);
  {
    Pipe x("appsrc name=src caps=" + tensor_caps("2:1:1:1", "uint8") +
           " ! tensor_if name=tif compared-value=CUSTOM compared-value-option=capi_odd "
           "then=PASSTHROUGH else=PASSTHROUGH tif.src_0 ! tensor_sink name=t async=false "
           "tif.src_1 ! tensor_sink name=f async=false");
    Collector t, f;
    ml_pipeline_sink_h ht = nullptr, hf = nullptr;
    ml_pipeline_src_h src = nullptr;
    ASSERT_EQ(ml_pipeline_sink_register(x.p, "t", Collector::cb, &t, &ht), ML_ERROR_NONE);
    ASSERT_EQ(ml_pipeline_sink_register(x.p, "f", Collector::cb, &f, &hf), ML_ERROR_NONE);
    ASSERT_EQ(ml_pipeline_src_get_handle(x.p, "src", &src), ML_ERROR_NONE);
    ASSERT_EQ(ml_pipeline_start(x.p), ML_ERROR_NONE);
    for (uint8_t i = 0; i < 6; ++i) push_u8(src, {i, 0});
    ASSERT_TRUE(t.wait_for(3));
    ASSERT_TRUE(f.wait_for(3));
    EXPECT_EQ(t.frames[0].tensors[0][0], 1);
    EXPECT_EQ(t.frames[2].tensors[0][0], 5);
    EXPECT_EQ(f.frames[1].tensors[0][0], 2);
    EXPECT_EQ(calls, 6);
    EXPECT_EQ(ml_pipeline_tensor_if_custom_unregister(cond), ML_ERROR_INVALID_PARAMETER);
    EXPECT_NE(error().find("'capi_odd' is used by 1 pipeline(s)"), std::string::npos) << error();
  }
  EXPECT_EQ(ml_pipeline_tensor_if_custom_unregister(cond), ML_ERROR_NONE) << error();
  EXPECT_EQ(ml_pipeline_tensor_if_custom_unregister(cond), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_tensor_if_custom_unregister(nullptr), ML_ERROR_INVALID_PARAMETER);
}

TEST(MlPipelineControls, Availability) {
  bool av = false;
  ASSERT_EQ(ml_check_element_availability("tensor_filter", &av), ML_ERROR_NONE);
  EXPECT_TRUE(av);
  ASSERT_EQ(ml_check_element_availability("no_such_element_xyz", &av), ML_ERROR_NONE);
  EXPECT_FALSE(av);
  EXPECT_EQ(ml_check_element_availability(nullptr, &av), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_check_element_availability("tensor_sink", nullptr), ML_ERROR_INVALID_PARAMETER);

  ASSERT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_CUSTOM_FILTER, ML_NNFW_HW_ANY, &av),
            ML_ERROR_NONE);
  EXPECT_TRUE(av);
  ASSERT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_CUSTOM_FILTER, ML_NNFW_HW_AUTO, &av),
            ML_ERROR_NONE);
  EXPECT_TRUE(av);
  ASSERT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_CUSTOM_FILTER, ML_NNFW_HW_GPU, &av),
            ML_ERROR_NONE);
  EXPECT_FALSE(av);  // no accelerator check in the back end: CPU only
  ASSERT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_CUSTOM_FILTER, ML_NNFW_HW_NPU_SR, &av),
            ML_ERROR_NONE);
  EXPECT_FALSE(av);
  ASSERT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_VIVANTE, ML_NNFW_HW_ANY, &av), ML_ERROR_NONE);
  EXPECT_FALSE(av);  // no such back end
  ASSERT_EQ(ml_check_nnfw_availability_full(ML_NNFW_TYPE_CUSTOM_FILTER, ML_NNFW_HW_AUTO, "x", &av),
            ML_ERROR_NONE);
  EXPECT_TRUE(av);
  // As NNStreamer: ANY names no framework.
  EXPECT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_ANY, ML_NNFW_HW_ANY, &av),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("ML_NNFW_TYPE_ANY names no framework"), std::string::npos) << error();
  EXPECT_EQ(ml_check_nnfw_availability(static_cast<ml_nnfw_type_e>(999), ML_NNFW_HW_ANY, &av),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(error().find("nnfw 999 is not an ml_nnfw_type_e value"), std::string::npos) << error();
  EXPECT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_CUSTOM_FILTER,
                                       static_cast<ml_nnfw_hw_e>(0x9999), &av),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_CUSTOM_FILTER, ML_NNFW_HW_ANY, nullptr),
            ML_ERROR_INVALID_PARAMETER);
}

// orange.raw (HWC uint8) normalised here to CHW float32 -> appsrc -> MobileNet v2 (ONNX) ->
// tensor_sink: class 950 "orange".
TEST(MlPipelineControls, MobilenetOnnxruntimeClassifiesOrange) {
  std::string sh = shared_models_dir();
  if (sh.empty()) GTEST_SKIP() << "../shared/models is not beside the project; skipping model test";
  bool av = false;
  ASSERT_EQ(ml_check_nnfw_availability(ML_NNFW_TYPE_ONNX_RUNTIME, ML_NNFW_HW_ANY, &av),
            ML_ERROR_NONE);
  if (!av) GTEST_SKIP() << "the onnxruntime back end is not built in this tree";
  std::ifstream f(sh + "/data/orange.raw", std::ios::binary);
  Bytes img((std::istreambuf_iterator<char>(f)), {});
  ASSERT_EQ(img.size(), 224u * 224 * 3);
  const float mean[3] = {123.675f, 116.28f, 103.53f}, sd[3] = {58.395f, 57.12f, 57.375f};
  std::vector<float> chw(img.size());
  for (std::size_t y = 0; y < 224; ++y)
    for (std::size_t x = 0; x < 224; ++x)
      for (std::size_t c = 0; c < 3; ++c)
        chw[c * 224 * 224 + y * 224 + x] = (img[(y * 224 + x) * 3 + c] - mean[c]) / sd[c];
  Pipe x("appsrc name=src caps=" + tensor_caps("224:224:3:1", "float32") +
         " ! tensor_filter framework=onnxruntime model=" + sh +
         "/models/mobilenet_v2_quant.onnx custom=NumThreads:1 ! tensor_sink name=sink async=false");
  Collector c;
  ml_pipeline_sink_h s = nullptr;
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(x.p, "sink", Collector::cb, &c, &s), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_src_get_handle(x.p, "src", &src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(x.p), ML_ERROR_NONE) << error();
  ml_tensors_info_h info = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_tensors_info(src, &info), ML_ERROR_NONE) << error();
  ml_tensors_data_h d = make_data(info, {f32_bytes(chw)});
  ASSERT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_AUTO_FREE), ML_ERROR_NONE)
      << error();
  ml_tensors_info_destroy(info);
  ASSERT_TRUE(c.wait_for(1, 60));
  std::lock_guard lk(c.m);
  auto scores = as_f32(c.frames[0].tensors[0]);
  ASSERT_EQ(scores.size(), 1000u);
  EXPECT_EQ(std::max_element(scores.begin(), scores.end()) - scores.begin(), 950);
}

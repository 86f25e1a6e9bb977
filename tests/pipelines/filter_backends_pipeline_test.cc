// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter with the real inference back ends (onnxruntime, opencv) in gst-launch
// pipelines: generated models against torch's references, mobilenet on orange (950), LeNet on 9,
// and the bus errors a user sees for back-end problems.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>

#include "backends/backend_loader.h"
#include "support/harness.h"

namespace nns::test {
namespace {

bool have_element(const char *name) {
  GstElementFactory *f = gst_element_factory_find(name);
  if (f) gst_object_unref(f);
  return f != nullptr;
}

class FilterPipeline : public ::testing::Test {
 protected:
  void SetUp() override {
    if (!have_element("tensor_filter")) GTEST_SKIP() << "tensor_filter is not built yet";
    dir_ = make_temp_dir();
  }
  void TearDown() override {
    if (!dir_.empty()) std::filesystem::remove_all(dir_);
  }
  // GTEST_SKIP only leaves this function: callers return when IsSkipped().
  void need_backend(const char *name) {
    if (!std::filesystem::exists(backend_path(name)))
      GTEST_SKIP() << backend_path(name) << " is not built";
  }
  std::string write(const std::string &name, const void *data, std::size_t size) {
    std::string path = dir_ + "/" + name;
    std::ofstream(path, std::ios::binary).write(static_cast<const char *>(data), size);
    return path;
  }
  // Runs `desc` whose last element is `filesink location=OUT`; returns the bytes written.
  std::vector<uint8_t> run_to_file(const std::string &desc, RunResult *res = nullptr) {
    std::string out = dir_ + "/out.bin";
    std::filesystem::remove(out);
    RunResult r = run_pipeline(desc + " ! filesink location=" + out, 60);
    if (res) *res = r;
    EXPECT_TRUE(r.eos) << desc << "\n" << r.error_text;
    return std::filesystem::exists(out) ? read_file(out) : std::vector<uint8_t>{};
  }
  std::string dir_;
};

// The back ends reading ONNX, and armnn reading the .tflite twins, run the generated models: the
// filter's output frame is the model outputs one after the other. (A missing .tflite twin is
// reported by filter_conformance_test.)
TEST_F(FilterPipeline, GeneratedModelsMatchReference) {
  const std::pair<const char *, const char *> kinds[] = {{"onnxruntime", "onnx"},
                                                         {"opencv", "onnx"},
                                                         {"armnn", "tflite"},
                                                         {"tensorflow2-lite", "tflite"}};
  for (const auto &[backend, kind] : kinds) {
    if (!std::filesystem::exists(backend_path(backend))) continue;
    for (const char *name : {"add_mul", "conv_net", "uint8_scale"}) {
      SCOPED_TRACE(std::string(backend) + " " + name);
      auto m = load_ref(name);
      ASSERT_TRUE(m) << "generated models missing in " << models_dir();
      if (m->file(kind).empty()) continue;
      std::vector<uint8_t> in;
      std::string dims, types;
      for (const auto &t : m->inputs) {
        in.insert(in.end(), t.bytes.begin(), t.bytes.end());
        dims += (dims.empty() ? "" : ",") + desc_dims_string(t.desc);
        types += (types.empty() ? "" : ",") + std::string(type_name(desc_type(t.desc)));
      }
      std::string in_file = write(std::string(name) + ".in", in.data(), in.size());
      auto got =
          run_to_file("filesrc location=" + in_file + " blocksize=" + std::to_string(in.size()) +
                      " ! application/octet-stream ! tensor_converter input-dim=" + dims +
                      " input-type=" + types + " ! tensor_filter framework=" + backend +
                      " model=" + m->file(kind));
      std::size_t off = 0;
      for (std::size_t i = 0; i < m->outputs.size(); ++i) {
        std::size_t n = m->outputs[i].bytes.size();
        ASSERT_LE(off + n, got.size());
        EXPECT_EQ(compare(m->outputs[i], got.data() + off, n, m->abs_tol, m->rel_tol), "")
            << "output " << i;
        off += n;
      }
      EXPECT_EQ(off, got.size());
    }
  }
}

// A model with a free batch axis runs when input= gives the sizes.
TEST_F(FilterPipeline, FreeDimensionFromInputProperty) {
  need_backend("onnxruntime");
  if (IsSkipped()) return;
  auto m = load_ref("add_mul_dynamic");
  ASSERT_TRUE(m);
  std::vector<uint8_t> in = m->inputs[0].bytes;
  in.insert(in.end(), m->inputs[1].bytes.begin(), m->inputs[1].bytes.end());
  std::string f = write("dyn.in", in.data(), in.size());
  auto got = run_to_file("filesrc location=" + f +
                         " blocksize=96 ! application/octet-stream ! tensor_converter "
                         "input-dim=4:3:1,4:3:1 input-type=float32,float32 ! tensor_filter "
                         "framework=onnxruntime model=" +
                         m->file("onnx") + " input=4:3:1,4:3:1 inputtype=float32,float32");
  ASSERT_EQ(got.size(), 96u);
  EXPECT_EQ(compare(m->outputs[0], got.data(), 48, 1e-6, 0), "");
  EXPECT_EQ(compare(m->outputs[1], got.data() + 48, 48, 1e-6, 0), "");
}

// No copy between the GstBuffer and ONNX Runtime: the pointer ORT got for the input is the
// appsrc buffer's own memory (and onnxruntime_test checks ORT writes the outputs in place).
TEST_F(FilterPipeline, OnnxruntimeGetsTheBuffersMemory) {
  need_backend("onnxruntime");
  if (IsSkipped()) return;
  auto m = load_ref("uint8_scale");
  ASSERT_TRUE(m);
  std::vector<uint8_t> data = m->inputs[0].bytes;
  std::string out = dir_ + "/zc.out";
  std::string desc =
      "appsrc name=src caps=other/tensors,format=static,num_tensors=1,"
      "dimensions=3:8:8:1,types=uint8,framerate=0/1 ! tensor_filter "
      "framework=onnxruntime model=" +
      m->file("onnx") + " ! filesink location=" + out;
  GError *e = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &e);
  ASSERT_TRUE(p) << (e ? e->message : "");
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src");
  GstBuffer *buf = gst_buffer_new_wrapped_full(GST_MEMORY_FLAG_READONLY, data.data(), data.size(),
                                               0, data.size(), nullptr, nullptr);
  GstFlowReturn ret;
  g_signal_emit_by_name(src, "push-buffer", buf, &ret);
  gst_buffer_unref(buf);
  g_signal_emit_by_name(src, "end-of-stream", &ret);
  RunResult r = run_pipeline(p, 30);
  gst_object_unref(src);
  gst_object_unref(p);
  ASSERT_TRUE(r.eos) << r.error_text;
  void *h = dlopen(backend_path("onnxruntime").c_str(), RTLD_NOW | RTLD_NOLOAD);
  ASSERT_NE(h, nullptr) << "tensor_filter did not load " << backend_path("onnxruntime");
  auto last = reinterpret_cast<const void *(*)()>(dlsym(h, "nns_filter_onnxruntime_last_input"));
  ASSERT_NE(last, nullptr);
  EXPECT_EQ(last(), static_cast<const void *>(data.data()));
  dlclose(h);
  auto got = read_file(out);
  EXPECT_EQ(compare(m->outputs[0], got.data(), got.size(), m->abs_tol, m->rel_tol), "");
}

std::size_t argmax_f32(const std::vector<uint8_t> &bytes) {
  const auto *f = reinterpret_cast<const float *>(bytes.data());
  std::size_t n = bytes.size() / 4;
  return n ? std::max_element(f, f + n) - f : SIZE_MAX;
}

// orange.raw (HWC uint8) -> float32 with torchvision's ImageNet normalisation ((x / 255 - mean) /
// std per channel) -> CHW -> mobilenet_v2_quant.onnx (1000 classes) -> 950 "orange".
TEST_F(FilterPipeline, MobilenetOnnxruntimeOrange) {
  NNS_REQUIRE_SHARED_MODELS();
  need_backend("onnxruntime");
  if (IsSkipped()) return;
  std::string sh = shared_models_dir();
  std::string model = sh + "/models/mobilenet_v2_quant.onnx";
  std::string filter =
      " ! tensor_filter framework=onnxruntime model=" + model + " custom=NumThreads:1";
  if (have_element("tensor_transform")) {
    auto got = run_to_file(
        "filesrc location=" + sh +
        "/data/orange.raw blocksize=150528 ! application/octet-stream ! tensor_converter "
        "input-dim=3:224:224:1 input-type=uint8 ! tensor_transform mode=arithmetic "
        "option=typecast:float32,per-channel:true@0,add:-123.675@0,add:-116.280@1,"
        "add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! tensor_transform "
        "mode=transpose option=1:2:0:3" +
        filter);
    ASSERT_EQ(got.size(), 4000u);
    EXPECT_EQ(argmax_f32(got), 950u);
  }
  // The same with the float CHW input made here (only converter and filter involved).
  std::vector<uint8_t> img = read_file(sh + "/data/orange.raw");
  ASSERT_EQ(img.size(), 224u * 224 * 3);
  const float mean[3] = {123.675f, 116.28f, 103.53f}, stdev[3] = {58.395f, 57.12f, 57.375f};
  std::vector<float> chw(img.size());
  for (std::size_t y = 0; y < 224; ++y)
    for (std::size_t x = 0; x < 224; ++x)
      for (std::size_t c = 0; c < 3; ++c)
        chw[c * 224 * 224 + y * 224 + x] = (img[(y * 224 + x) * 3 + c] - mean[c]) / stdev[c];
  std::string f = write("orange.chw", chw.data(), chw.size() * 4);
  auto got = run_to_file("filesrc location=" + f + " blocksize=" + std::to_string(chw.size() * 4) +
                         " ! application/octet-stream ! tensor_converter input-dim=224:224:3:1 "
                         "input-type=float32" +
                         filter);
  ASSERT_EQ(got.size(), 4000u);
  EXPECT_EQ(argmax_f32(got), 950u);
}

// 9.raw -> (x - 127.5) / 127.5 -> Caffe LeNet in OpenCV -> class 9.
TEST_F(FilterPipeline, LenetOpencvNine) {
  NNS_REQUIRE_SHARED_MODELS();
  need_backend("opencv");
  if (IsSkipped()) return;
  std::string sh = shared_models_dir();
  std::string filter = " ! tensor_filter framework=opencv model=" + std::string(NNS_SOURCE_DIR) +
                       "/tests/data/lenet_deploy.prototxt," + sh +
                       "/models/lenet_iter_9000.caffemodel";
  if (have_element("tensor_transform")) {
    auto got = run_to_file("filesrc location=" + sh +
                           "/data/9.raw blocksize=784 ! application/octet-stream ! "
                           "tensor_converter input-dim=28:28:1:1 input-type=uint8 ! "
                           "tensor_transform mode=arithmetic "
                           "option=typecast:float32,add:-127.5,div:127.5" +
                           filter);
    ASSERT_EQ(got.size(), 40u);
    EXPECT_EQ(argmax_f32(got), 9u);
  }
  std::vector<uint8_t> raw = read_file(sh + "/data/9.raw");
  std::vector<float> x(raw.size());
  for (std::size_t i = 0; i < raw.size(); ++i) x[i] = (raw[i] - 127.5f) / 127.5f;
  std::string f = write("nine.f32", x.data(), x.size() * 4);
  auto got = run_to_file("filesrc location=" + f +
                         " blocksize=3136 ! application/octet-stream ! tensor_converter "
                         "input-dim=28:28:1:1 input-type=float32" +
                         filter);
  ASSERT_EQ(got.size(), 40u);
  EXPECT_EQ(argmax_f32(got), 9u);
}

// The generated Darknet model through tensor_filter: no input= (the shape comes from the .cfg's
// [net] section, so the converter's 8:6:3:1 caps must match it), .weights named first.
TEST_F(FilterPipeline, DarknetOpencvMatchesReference) {
  need_backend("opencv");
  if (IsSkipped()) return;
  auto m = load_ref("tiny_darknet");
  ASSERT_TRUE(m) << "generated models missing in " << models_dir();
  const std::vector<uint8_t> &x = m->inputs[0].bytes;
  std::string f = write("darknet.in", x.data(), x.size());
  auto got = run_to_file("filesrc location=" + f + " blocksize=" + std::to_string(x.size()) +
                         " ! application/octet-stream ! tensor_converter input-dim=8:6:3:1 "
                         "input-type=float32 ! tensor_filter framework=opencv model=" +
                         m->file("darknet_weights") + "," + m->file("darknet_cfg"));
  EXPECT_EQ(compare(m->outputs[0], got.data(), got.size(), 1e-5, 0), "");
}

// What the user sees on the bus when the back end refuses.
TEST_F(FilterPipeline, BackendErrorsReachTheBus) {
  need_backend("onnxruntime");
  if (IsSkipped()) return;
  auto m = load_ref("add_mul_dynamic");
  auto a = load_ref("add_mul");
  ASSERT_TRUE(m && a);
  std::vector<uint8_t> in(96, 0);
  std::string f = write("in.raw", in.data(), in.size());
  std::string src = "filesrc location=" + f +
                    " blocksize=96 ! application/octet-stream ! tensor_converter "
                    "input-dim=4:3:1,4:3:1 input-type=float32,float32 ! ";
  struct Case {
    std::string filter;
    std::vector<std::string> expect;
  } cases[] = {
      {"tensor_filter name=tf framework=onnxruntime model=" + m->file("onnx"),
       {"free dimensions", "'a'", "input="}},
      {"tensor_filter name=tf framework=onnxruntime model=" + a->file("onnx") + " custom=Threads:2",
       {"unknown custom option key 'Threads'", "NumThreads"}},
      {"tensor_filter name=tf framework=onnxruntime model=" + dir_ + "/none.onnx", {"none.onnx"}},
      {"tensor_filter name=tf framework=onnxruntime model=" + a->file("onnx") +
           " input=4:3:1,4:3:1 inputtype=uint8,float32",
       {"input= tensor 0 is uint8 4:3:1 but model input 'a' is float32 4:3:1"}},
  };
  for (const auto &c : cases) {
    SCOPED_TRACE(c.filter);
    RunResult r = run_pipeline(src + c.filter + " ! fakesink", 30);
    EXPECT_TRUE(r.error) << "expected a bus error";
    EXPECT_EQ(r.error_text.rfind("tf:", 0), 0u) << r.error_text;
    for (const auto &e : c.expect)
      EXPECT_NE(r.error_text.find(e), std::string::npos) << r.error_text;
  }
  // Input of the wrong type from upstream: caps cannot match the model.
  std::vector<uint8_t> u8(24, 1);
  std::string g = write("u8.raw", u8.data(), u8.size());
  RunResult r = run_pipeline("filesrc location=" + g +
                                 " blocksize=24 ! application/octet-stream ! tensor_converter "
                                 "input-dim=4:3:1,4:3:1 input-type=uint8,uint8 ! tensor_filter "
                                 "name=tf framework=onnxruntime model=" +
                                 a->file("onnx") + " ! fakesink",
                             30);
  EXPECT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("uint8"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("float32"), std::string::npos) << r.error_text;
}

}  // namespace
}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder element + direct_video / image_labeling decoders + custom-code.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "support/harness.h"
#include "tensor_decoder_custom.h"

using nns::test::HarnessPtr;
using nns::test::run_pipeline;

namespace {

GstBuffer *bytes_buffer(const std::vector<uint8_t> &v) {
  GstBuffer *b = gst_buffer_new_allocate(nullptr, v.size(), nullptr);
  gst_buffer_fill(b, 0, v.data(), v.size());
  return b;
}

std::vector<uint8_t> buffer_bytes(GstBuffer *b) {
  std::vector<uint8_t> v(gst_buffer_get_size(b));
  gst_buffer_extract(b, 0, v.data(), v.size());
  return v;
}

// Runs one buffer through "tensor_decoder <props>" with the given input caps.
struct OneShot {
  HarnessPtr h;
  GstBuffer *out = nullptr;
  std::string out_caps;
  ~OneShot() {
    if (out) gst_buffer_unref(out);
  }
};

void run_one(OneShot &r, const std::string &props, const std::string &in_caps,
             const std::vector<uint8_t> &data) {
  r.h.reset(gst_harness_new_parse(("tensor_decoder " + props).c_str()));
  gst_harness_set_src_caps_str(r.h.get(), in_caps.c_str());
  ASSERT_EQ(gst_harness_push(r.h.get(), bytes_buffer(data)), GST_FLOW_OK);
  r.out = gst_harness_pull(r.h.get());
  ASSERT_NE(r.out, nullptr);
  GstCaps *c = gst_pad_get_current_caps(r.h->sinkpad);
  ASSERT_NE(c, nullptr);
  gchar *s = gst_caps_to_string(c);
  r.out_caps = s;
  g_free(s);
  gst_caps_unref(c);
}

std::string write_temp(const std::string &name, const std::string &text) {
  std::string path = nns::test::make_temp_dir() + "/" + name;
  std::ofstream(path) << text;
  return path;
}

// A pipeline head producing one uint8 tensor with the given dims (from a file of zeros).
std::string tensor_src(const std::string &dims, std::size_t bytes) {
  std::string path = write_temp("zeros.bin", std::string(bytes, '\0'));
  return "filesrc location=" + path +
         " blocksize=-1 num-buffers=1 ! application/octet-stream ! "
         "tensor_converter input-dim=" +
         dims + " input-type=uint8 ! ";
}

}  // namespace

TEST(TensorDecoder, PropertiesAndDefaults) {
  GstElement *e = gst_element_factory_make("tensor_decoder", nullptr);
  ASSERT_NE(e, nullptr);
  gchar *mode = nullptr, *opt = nullptr, *subs = nullptr;
  gboolean silent = FALSE;
  g_object_get(e, "mode", &mode, "option1", &opt, "sub-plugins", &subs, "silent", &silent, nullptr);
  EXPECT_STREQ(mode, "");
  EXPECT_EQ(opt, nullptr);
  EXPECT_TRUE(silent);
  std::string s = subs ? subs : "";
  EXPECT_NE(s.find("direct_video"), std::string::npos) << s;
  EXPECT_NE(s.find("image_labeling"), std::string::npos) << s;
  g_free(mode);
  g_free(opt);
  g_free(subs);
  g_object_set(e, "option9", "x", nullptr);
  g_object_get(e, "option9", &opt, nullptr);
  EXPECT_STREQ(opt, "x");
  g_free(opt);
  gst_object_unref(e);
}

TEST(TensorDecoder, DirectVideoRgbPadsRowsTo4Bytes) {
  // 3 channels x 3 pixels = 9 bytes per row -> stride 12.
  std::vector<uint8_t> in(3 * 3 * 2);
  for (std::size_t i = 0; i < in.size(); ++i) in[i] = static_cast<uint8_t>(i + 1);
  OneShot r;
  run_one(r, "mode=direct_video",
          "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)3:3:2:1,"
          "framerate=30/1",
          in);
  EXPECT_NE(r.out_caps.find("format=(string)RGB"), std::string::npos) << r.out_caps;
  EXPECT_NE(r.out_caps.find("width=(int)3"), std::string::npos) << r.out_caps;
  EXPECT_NE(r.out_caps.find("height=(int)2"), std::string::npos) << r.out_caps;
  auto out = buffer_bytes(r.out);
  std::vector<uint8_t> want = {1,  2,  3,  4,  5,  6,  7,  8,  9,  0, 0, 0,
                               10, 11, 12, 13, 14, 15, 16, 17, 18, 0, 0, 0};
  EXPECT_EQ(out, want);
}

TEST(TensorDecoder, DirectVideoDefaultsByChannels) {
  for (auto [ch, fmt] : {std::pair{1, "GRAY8"}, std::pair{4, "BGRx"}}) {
    std::vector<uint8_t> in(ch * 4 * 2, 7);
    OneShot r;
    run_one(r, "mode=direct_video",
            "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)" +
                std::to_string(ch) + ":4:2:1,framerate=0/1",
            in);
    EXPECT_NE(r.out_caps.find(std::string("format=(string)") + fmt), std::string::npos)
        << r.out_caps;
    EXPECT_EQ(buffer_bytes(r.out), in);  // 4*ch is a multiple of 4: no padding
  }
}

TEST(TensorDecoder, DirectVideoOption1Format) {
  std::vector<uint8_t> in(4 * 2 * 2, 3);
  OneShot r;
  run_one(r, "mode=direct_video option1=RGBA",
          "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)4:2:2:1,"
          "framerate=0/1",
          in);
  EXPECT_NE(r.out_caps.find("format=(string)RGBA"), std::string::npos) << r.out_caps;
}

TEST(TensorDecoder, DirectVideoPipeline) {
  auto r = run_pipeline(
      "videotestsrc num-buffers=2 ! video/x-raw,format=RGB,width=30,height=20 ! "
      "tensor_converter ! tensor_decoder mode=direct_video ! videoconvert ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(TensorDecoder, ImageLabelingArgmax) {
  std::string labels = write_temp("labels.txt", "cat\ndog\norange\nbanana\n");
  std::vector<float> scores = {0.1f, 0.3f, 0.9f, 0.2f};
  std::vector<uint8_t> in(reinterpret_cast<uint8_t *>(scores.data()),
                          reinterpret_cast<uint8_t *>(scores.data()) + 16);
  OneShot r;
  run_one(r, "mode=image_labeling option1=" + labels,
          "other/tensors,format=static,num_tensors=1,types=float32,dimensions=(string)4:1:1:1,"
          "framerate=0/1",
          in);
  EXPECT_NE(r.out_caps.find("text/x-raw"), std::string::npos) << r.out_caps;
  EXPECT_NE(r.out_caps.find("utf8"), std::string::npos) << r.out_caps;
  auto out = buffer_bytes(r.out);
  EXPECT_EQ(std::string(out.begin(), out.end()), "orange");
}

TEST(TensorDecoder, ImageLabelingUint8FirstMaxWins) {
  std::string labels = write_temp("labels.txt", "a\nb\nc\n");
  OneShot r;
  run_one(
      r, "mode=image_labeling option1=" + labels,
      "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)3:1,framerate=0/1",
      {5, 9, 9});
  auto out = buffer_bytes(r.out);
  EXPECT_EQ(std::string(out.begin(), out.end()), "b");
}

// mobilenet_v2_quant.onnx (onnxruntime) on orange.raw with torchvision's ImageNet
// normalisation -> index 950 of the 1000-line ImageNet labels -> "orange".
TEST(TensorDecoder, ImageLabelingMobilenetOrange) {
  NNS_REQUIRE_SHARED_MODELS();
  const char *fdir = g_getenv("NNSTREAMER_FILTERS");
  if (!fdir || !std::filesystem::exists(std::string(fdir) + "/libnnstreamer_filter_onnxruntime.so"))
    GTEST_SKIP() << "onnxruntime filter back end not built";
  std::string d = nns::test::shared_models_dir();
  std::string labels = nns::test::imagenet_labels_1000();
  ASSERT_FALSE(labels.empty()) << "build/data/imagenet_labels_1000.txt was not generated from " << d
                               << "/labels/labels.txt; re-run cmake";
  std::string desc =
      "filesrc location=" + d +
      "/data/orange.raw blocksize=-1 ! "
      "application/octet-stream ! tensor_converter input-dim=3:224:224:1 input-type=uint8 ! "
      "tensor_transform mode=arithmetic option=typecast:float32,per-channel:true@0,"
      "add:-123.675@0,add:-116.280@1,add:-103.530@2,div:58.3950@0,div:57.1200@1,div:57.3750@2 ! "
      "tensor_transform mode=transpose option=1:2:0:3 ! "
      "tensor_filter framework=onnxruntime model=" +
      d +
      "/models/mobilenet_v2_quant.onnx ! "
      "tensor_decoder mode=image_labeling option1=" +
      labels +
      " ! "
      "appsink name=out sync=false";
  GError *err = nullptr;
  GstElement *pipe = gst_parse_launch(desc.c_str(), &err);
  ASSERT_NE(pipe, nullptr) << (err ? err->message : "");
  GstElement *sink = gst_bin_get_by_name(GST_BIN(pipe), "out");
  gst_element_set_state(pipe, GST_STATE_PLAYING);
  GstSample *s = nullptr;
  // try-pull-sample: a pipeline error must fail the test, not hang it.
  g_signal_emit_by_name(sink, "try-pull-sample", static_cast<GstClockTime>(60 * GST_SECOND), &s);
  if (!s) {
    GstBus *bus = gst_element_get_bus(pipe);
    GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
    std::string why = "no sample within 60 s";
    if (m) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      why = e->message;
      g_error_free(e);
      gst_message_unref(m);
    }
    gst_object_unref(bus);
    gst_element_set_state(pipe, GST_STATE_NULL);
    gst_object_unref(sink);
    gst_object_unref(pipe);
    FAIL() << why;
  }
  auto out = buffer_bytes(gst_sample_get_buffer(s));
  EXPECT_EQ(std::string(out.begin(), out.end()), "orange");
  gst_sample_unref(s);
  gst_element_set_state(pipe, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(pipe);
}

namespace {
int custom_sum(const GstTensorMemory *input, const GstTensorsConfig *config, void *data,
               GstBuffer *out) {
  (void)config;
  int s = *static_cast<int *>(data);
  for (size_t i = 0; i < input[0].size; ++i) s += static_cast<const uint8_t *>(input[0].data)[i];
  GstMemory *m = gst_allocator_alloc(nullptr, sizeof s, nullptr);
  GstMapInfo map;
  gst_memory_map(m, &map, GST_MAP_WRITE);
  memcpy(map.data, &s, sizeof s);
  gst_memory_unmap(m, &map);
  gst_buffer_append_memory(out, m);
  return 0;
}
}  // namespace

TEST(TensorDecoder, CustomCode) {
  static int base = 100;
  ASSERT_EQ(nnstreamer_decoder_custom_register("sum", custom_sum, &base), 0);
  EXPECT_NE(nnstreamer_decoder_custom_register("sum", custom_sum, &base), 0);
  OneShot r;
  run_one(
      r, "mode=custom-code option1=sum",
      "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)3:1,framerate=0/1",
      {1, 2, 3});
  auto out = buffer_bytes(r.out);
  ASSERT_EQ(out.size(), 4u);
  int v;
  memcpy(&v, out.data(), 4);
  EXPECT_EQ(v, 106);
  EXPECT_EQ(nnstreamer_decoder_custom_unregister("sum"), 0);
  EXPECT_NE(nnstreamer_decoder_custom_unregister("sum"), 0);
}

// ---- negative: bus error texts ----

TEST(TensorDecoderErrors, UnknownModeListsAvailable) {
  auto r = run_pipeline(tensor_src("3:4:4:1", 48) + "tensor_decoder mode=nosuch ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("unknown mode 'nosuch'"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("direct_video"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("tensordecoder0"), std::string::npos) << r.error_text;
}

// As upstream: an unknown option1 is no error; the default format of the channel count is used
// and a bus warning names the option and its value.
TEST(TensorDecoder, DirectVideoUnknownOption1WarnsAndUsesDefault) {
  auto r = run_pipeline(
      "videotestsrc num-buffers=1 ! video/x-raw,format=RGB,width=4,height=4 ! tensor_converter "
      "! tensor_decoder mode=direct_video option1=NV12 ! video/x-raw,format=RGB ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_NE(r.warning_text.find("option1='NV12'"), std::string::npos) << r.warning_text;
  EXPECT_NE(r.warning_text.find("not a supported video format"), std::string::npos)
      << r.warning_text;
}

// GRAY16_LE / GRAY16_BE from a 2-byte tensor: bytes copied as they are, rows padded to 4 bytes
// (3 pixels x 2 bytes = 6 -> stride 8).
TEST(TensorDecoder, DirectVideoGray16) {
  for (const char *fmt : {"GRAY16_LE", "GRAY16_BE"}) {
    SCOPED_TRACE(fmt);
    std::vector<uint8_t> in(2 * 3 * 2);
    for (std::size_t i = 0; i < in.size(); ++i) in[i] = static_cast<uint8_t>(i + 1);
    OneShot r;
    run_one(r, std::string("mode=direct_video option1=") + fmt,
            "other/tensors,format=static,num_tensors=1,types=uint16,dimensions=(string)1:3:2:1,"
            "framerate=0/1",
            in);
    EXPECT_NE(r.out_caps.find(std::string("format=(string)") + fmt), std::string::npos)
        << r.out_caps;
    EXPECT_NE(r.out_caps.find("width=(int)3"), std::string::npos) << r.out_caps;
    std::vector<uint8_t> want = {1, 2, 3, 4, 5, 6, 0, 0, 7, 8, 9, 10, 11, 12, 0, 0};
    EXPECT_EQ(buffer_bytes(r.out), want);
  }
}

TEST(TensorDecoderErrors, DirectVideoGray16NeedsTwoByteElements) {
  auto r = run_pipeline(tensor_src("1:4:4:1", 16) +
                        "tensor_decoder mode=direct_video option1=GRAY16_LE ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("format GRAY16_LE needs 2"), std::string::npos) << r.error_text;
}

TEST(TensorDecoderErrors, MissingLabelFile) {
  auto r = run_pipeline(
      "videotestsrc num-buffers=1 ! video/x-raw,format=GRAY8,width=4,height=1 ! tensor_converter "
      "! tensor_decoder mode=image_labeling option1=/nonexistent/labels.txt ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("cannot read label file '/nonexistent/labels.txt'"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorDecoderErrors, LabelFileShorterThanClasses) {
  std::string labels = write_temp("short.txt", "a\nb\n");
  auto r = run_pipeline(tensor_src("4:1:1:1", 4) +
                        "tensor_decoder mode=image_labeling option1=" + labels + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("has 2 labels, the tensor has 4 classes"), std::string::npos)
      << r.error_text;
}

TEST(TensorDecoderErrors, DirectVideoWrongChannels) {
  auto r = run_pipeline(tensor_src("2:4:2:1", 16) + "tensor_decoder mode=direct_video ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("mode 'direct_video' cannot decode input"), std::string::npos)
      << r.error_text;
}

TEST(TensorDecoderErrors, CustomCodeNotRegistered) {
  auto r = run_pipeline(
      "videotestsrc num-buffers=1 ! video/x-raw,format=GRAY8,width=4,height=2 ! tensor_converter "
      "! tensor_decoder mode=custom-code option1=nobody ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("no custom decoder 'nobody'"), std::string::npos) << r.error_text;
}

TEST(TensorDecoder, OctetStreamConcatenatesTensors) {
  // One tensor: the bytes pass through unchanged, the framerate is kept.
  std::vector<uint8_t> in = {9, 8, 7, 6, 5, 4};
  OneShot r;
  run_one(r, "mode=octet_stream",
          "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)6:1:1:1,"
          "framerate=15/1",
          in);
  EXPECT_NE(r.out_caps.find("application/octet-stream"), std::string::npos) << r.out_caps;
  EXPECT_NE(r.out_caps.find("framerate=(fraction)15/1"), std::string::npos) << r.out_caps;
  EXPECT_EQ(buffer_bytes(r.out), in);

  // Two tensors (uint8 x3, float32 x2) in two memories: one buffer of 3 + 8 bytes in order.
  HarnessPtr h(gst_harness_new_parse("tensor_decoder mode=octet_stream"));
  gst_harness_set_src_caps_str(h.get(),
                               "other/tensors,format=static,num_tensors=2,types=(string)\"uint8,"
                               "float32\",dimensions=(string)\"3,2\",framerate=0/1");
  std::vector<uint8_t> a = {1, 2, 3};
  float f[2] = {1.5f, -2.0f};
  GstBuffer *b = gst_buffer_new();
  GstBuffer *ba = bytes_buffer(a);
  gst_buffer_append_memory(b, gst_buffer_get_memory(ba, 0));
  gst_buffer_unref(ba);
  GstBuffer *bf = gst_buffer_new_allocate(nullptr, sizeof f, nullptr);
  gst_buffer_fill(bf, 0, f, sizeof f);
  gst_buffer_append_memory(b, gst_buffer_get_memory(bf, 0));
  gst_buffer_unref(bf);
  ASSERT_EQ(gst_harness_push(h.get(), b), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(out, nullptr);
  auto got = buffer_bytes(out);
  gst_buffer_unref(out);
  ASSERT_EQ(got.size(), 3u + sizeof f);
  EXPECT_EQ(std::vector<uint8_t>(got.begin(), got.begin() + 3), a);
  EXPECT_EQ(std::memcmp(got.data() + 3, f, sizeof f), 0);
}

TEST(TensorDecoder, OctetStreamRoundTripsThroughTheConverter) {
  // tensor_converter (octet -> tensor) and tensor_decoder mode=octet_stream are inverses.
  std::string payload = "nnstreamer-cpp!";  // 15 bytes
  std::string in = write_temp("payload.bin", payload);
  std::string out = nns::test::make_temp_dir() + "/out.bin";
  auto r = run_pipeline("filesrc location=" + in +
                        " blocksize=15 ! application/octet-stream ! tensor_converter "
                        "input-dim=15 input-type=uint8 ! tensor_decoder mode=octet_stream ! "
                        "filesink location=" +
                        out);
  ASSERT_TRUE(r.eos) << r.error_text;
  auto got = nns::test::read_file(out);
  EXPECT_EQ(std::string(got.begin(), got.end()), payload);
}

// As GstHarness tests and applications do with NNStreamer: created and PLAYING with default
// properties (no mode), configured afterwards. The state change succeeds; caps arriving before
// the mode is set get a bus error naming the property.
TEST(TensorDecoder, PlayingWithoutModeThenConfigured) {
  const char *caps =
      "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)1:4:2:1,"
      "framerate=0/1";
  {
    HarnessPtr h(gst_harness_new("tensor_decoder"));
    EXPECT_NE(gst_element_set_state(h->element, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
    g_object_set(h->element, "mode", "direct_video", nullptr);
    gst_harness_set_src_caps_str(h.get(), caps);
    std::vector<uint8_t> in(8, 5);
    ASSERT_EQ(gst_harness_push(h.get(), bytes_buffer(in)), GST_FLOW_OK);
    GstBuffer *out = gst_harness_pull(h.get());
    ASSERT_NE(out, nullptr);
    EXPECT_EQ(buffer_bytes(out), in);
    gst_buffer_unref(out);
  }
  HarnessPtr h(gst_harness_new("tensor_decoder"));
  GstBus *bus = gst_bus_new();
  gst_element_set_bus(h->element, bus);
  EXPECT_NE(gst_element_set_state(h->element, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  gst_harness_set_src_caps_str(h.get(), caps);
  EXPECT_NE(gst_harness_push(h.get(), bytes_buffer(std::vector<uint8_t>(8))), GST_FLOW_OK);
  GstMessage *msg = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
  ASSERT_NE(msg, nullptr);
  GError *err = nullptr;
  gst_message_parse_error(msg, &err, nullptr);
  std::string text = err->message;
  g_error_free(err);
  gst_message_unref(msg);
  EXPECT_NE(text.find("property 'mode' is not set"), std::string::npos) << text;
  gst_element_set_bus(h->element, nullptr);
  gst_object_unref(bus);
}

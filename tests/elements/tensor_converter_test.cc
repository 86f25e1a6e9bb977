// SPDX-License-Identifier: LGPL-2.1-only
// tensor_converter: every media type, exact bytes, zero-copy, negotiation, timestamps,
// custom-code callbacks, converter sub-plugins and the bus errors of bad input.
#include <gst/audio/audio.h>
#include <gst/video/video.h>
#include <gtest/gtest.h>

#include <chrono>
#include <cstring>
#include <fstream>

#include "core/meta_header.h"
#include "core/nns_conf.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "nnstreamer_plugin_api_converter.h"
#include "support/harness.h"
#include "tensor_converter_custom.h"

namespace {

using nns::test::HarnessPtr;
using nns::test::run_pipeline;

// A tensor_converter in a GstHarness, with its own bus to read posted errors.
struct Conv {
  explicit Conv(const std::string &props = "") {
    el = GST_ELEMENT(gst_object_ref_sink(gst_element_factory_make("tensor_converter", nullptr)));
    for (const auto &kv : nns::split(props, " ")) {
      auto eq = kv.find('=');
      if (eq != std::string::npos)
        gst_util_set_object_arg(G_OBJECT(el), kv.substr(0, eq).c_str(), kv.substr(eq + 1).c_str());
    }
    bus = gst_bus_new();
    gst_element_set_bus(el, bus);
    h.reset(gst_harness_new_with_element(el, "sink", "src"));
  }
  ~Conv() {
    h.reset();
    gst_element_set_bus(el, nullptr);
    gst_object_unref(el);
    gst_object_unref(bus);
  }
  std::string error() {
    GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR);
    if (!m) return "";
    GError *err = nullptr;
    gst_message_parse_error(m, &err, nullptr);
    std::string s = err->message;
    g_error_free(err);
    gst_message_unref(m);
    return s;
  }
  nns::TensorsConfig out_config() {
    GstPad *src = gst_element_get_static_pad(el, "src");
    GstCaps *caps = gst_pad_get_current_caps(src);
    gst_object_unref(src);
    EXPECT_NE(caps, nullptr);
    if (!caps) return {};
    nns::TensorsConfig c = nns::gst::config_from_caps(caps);
    gst_caps_unref(caps);
    return c;
  }
  GstFlowReturn push(GstBuffer *b) { return gst_harness_push(h.get(), b); }
  GstBuffer *pull() { return gst_harness_try_pull(h.get()); }

  GstElement *el;
  GstBus *bus;
  HarnessPtr h;
};

GstBuffer *buffer_of(const std::vector<uint8_t> &v) {
  return gst_buffer_new_memdup(v.data(), v.size());
}

std::vector<uint8_t> bytes_of(GstBuffer *b) {
  std::vector<uint8_t> v(gst_buffer_get_size(b));
  gst_buffer_extract(b, 0, v.data(), v.size());
  return v;
}

std::vector<uint8_t> memory_bytes(GstMemory *m) {
  nns::gst::MemoryMap map(m, GST_MAP_READ);
  return std::vector<uint8_t>(map.data(), map.data() + map.size());
}

const guint8 *memory_data(GstMemory *m) {
  nns::gst::MemoryMap map(m, GST_MAP_READ);
  return map.data();
}

std::string write_temp(const std::string &name, const std::string &data) {
  static std::string dir = nns::test::make_temp_dir();
  std::string p = dir + "/" + name;
  std::ofstream(p, std::ios::binary) << data;
  return p;
}

// ---- video ---------------------------------------------------------------------------------

struct VideoCase {
  const char *format;
  int width;
  const char *dims;  // expected with height 3
  const char *type;
  bool zero_copy;
};

class VideoFormats : public ::testing::TestWithParam<VideoCase> {};

TEST_P(VideoFormats, ExactBytesStrideRemovalAndZeroCopy) {
  const VideoCase &c = GetParam();
  const int height = 3;
  GstVideoInfo vi;
  ASSERT_TRUE(
      gst_video_info_set_format(&vi, gst_video_format_from_string(c.format), c.width, height));
  const bool planar = GST_VIDEO_INFO_N_PLANES(&vi) == 3;
  const gsize pixel = planar ? 1 : GST_VIDEO_INFO_COMP_PSTRIDE(&vi, 0);
  const gsize row = c.width * pixel;
  std::vector<uint8_t> in(GST_VIDEO_INFO_SIZE(&vi), 0xEE), expected;
  for (guint p = 0; p < GST_VIDEO_INFO_N_PLANES(&vi); ++p)
    for (int r = 0; r < height; ++r)
      for (gsize x = 0; x < row; ++x) {
        uint8_t v = static_cast<uint8_t>(p * 61 + r * 17 + x);
        in[GST_VIDEO_INFO_PLANE_OFFSET(&vi, p) + r * GST_VIDEO_INFO_PLANE_STRIDE(&vi, p) + x] = v;
        expected.push_back(v);
      }

  Conv conv;
  GstCaps *caps = gst_video_info_to_caps(&vi);
  gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, 30, 1, nullptr);
  gst_harness_set_src_caps(conv.h.get(), caps);
  GstBuffer *inbuf = buffer_of(in);
  GstMemory *inmem = gst_buffer_peek_memory(inbuf, 0);
  const guint8 *indata = memory_data(inmem);
  ASSERT_EQ(conv.push(inbuf), GST_FLOW_OK) << conv.error();
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  auto cfg = conv.out_config();
  EXPECT_EQ(cfg.info.dims_string(), c.dims);
  EXPECT_EQ(cfg.info.types_string(), c.type);
  EXPECT_EQ(cfg.rate_n, 30);
  ASSERT_EQ(gst_buffer_n_memory(out.get()), 1u);
  EXPECT_EQ(memory_bytes(gst_buffer_peek_memory(out.get(), 0)), expected);
  const bool shared = memory_data(gst_buffer_peek_memory(out.get(), 0)) == indata;
  EXPECT_EQ(shared, c.zero_copy);
}

INSTANTIATE_TEST_SUITE_P(TensorConverter, VideoFormats,
                         ::testing::Values(VideoCase{"RGB", 4, "3:4:3:1", "uint8", true},
                                           VideoCase{"RGB", 5, "3:5:3:1", "uint8", false},
                                           VideoCase{"BGR", 4, "3:4:3:1", "uint8", true},
                                           VideoCase{"BGR", 6, "3:6:3:1", "uint8", false},
                                           VideoCase{"RGBx", 5, "4:5:3:1", "uint8", true},
                                           VideoCase{"BGRx", 5, "4:5:3:1", "uint8", true},
                                           VideoCase{"xRGB", 3, "4:3:3:1", "uint8", true},
                                           VideoCase{"xBGR", 3, "4:3:3:1", "uint8", true},
                                           VideoCase{"RGBA", 3, "4:3:3:1", "uint8", true},
                                           VideoCase{"BGRA", 3, "4:3:3:1", "uint8", true},
                                           VideoCase{"ARGB", 3, "4:3:3:1", "uint8", true},
                                           VideoCase{"ABGR", 3, "4:3:3:1", "uint8", true},
                                           VideoCase{"GRAY8", 8, "1:8:3:1", "uint8", true},
                                           VideoCase{"GRAY8", 7, "1:7:3:1", "uint8", false},
                                           VideoCase{"GRAY16_LE", 4, "1:4:3:1", "uint16", true},
                                           VideoCase{"GRAY16_BE", 5, "1:5:3:1", "uint16", false},
                                           VideoCase{"RGBP", 4, "4:3:3:1", "uint8", true},
                                           VideoCase{"BGRP", 5, "5:3:3:1", "uint8", false}),
                         [](const auto &info) {
                           return std::string(info.param.format) + "_w" +
                                  std::to_string(info.param.width);
                         });

TEST(TensorConverter, Rgb224IsZeroCopy) {
  Conv conv;
  gst_harness_set_src_caps_str(conv.h.get(),
                               "video/x-raw,format=RGB,width=224,height=224,framerate=30/1");
  GstBuffer *in = gst_harness_create_buffer(conv.h.get(), 224 * 224 * 3);
  GstMemory *mem = gst_buffer_peek_memory(in, 0);
  ASSERT_EQ(conv.push(in), GST_FLOW_OK);
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  ASSERT_EQ(gst_buffer_n_memory(out.get()), 1u);
  EXPECT_EQ(gst_buffer_peek_memory(out.get(), 0), mem);  // the very same GstMemory
  EXPECT_EQ(conv.out_config().info.dims_string(), "3:224:224:1");
}

TEST(TensorConverter, VideoFramesPerTensorAggregates) {
  Conv conv("frames-per-tensor=2");
  gst_harness_set_src_caps_str(conv.h.get(),
                               "video/x-raw,format=GRAY8,width=4,height=2,framerate=10/1");
  for (int f = 0; f < 4; ++f) {
    GstBuffer *b = buffer_of(std::vector<uint8_t>(8, static_cast<uint8_t>(f + 1)));
    GST_BUFFER_PTS(b) = f * 100 * GST_MSECOND;
    GST_BUFFER_DURATION(b) = 100 * GST_MSECOND;
    ASSERT_EQ(conv.push(b), GST_FLOW_OK);
  }
  EXPECT_EQ(conv.out_config().info.dims_string(), "1:4:2:2");
  for (int o = 0; o < 2; ++o) {
    nns::gst::BufferPtr out(conv.pull());
    ASSERT_TRUE(out);
    std::vector<uint8_t> expected(8, static_cast<uint8_t>(2 * o + 1));
    expected.insert(expected.end(), 8, static_cast<uint8_t>(2 * o + 2));
    EXPECT_EQ(bytes_of(out.get()), expected);
    EXPECT_EQ(GST_BUFFER_PTS(out.get()), o * 200 * GST_MSECOND);
    EXPECT_EQ(GST_BUFFER_DURATION(out.get()), 200 * GST_MSECOND);
  }
  EXPECT_EQ(conv.pull(), nullptr);
}

// ---- audio ---------------------------------------------------------------------------------

class AudioFormats : public ::testing::TestWithParam<const char *> {};

TEST_P(AudioFormats, ValuesExactInNativeOrder) {
  const char *format = GetParam();
  GstAudioFormat af = gst_audio_format_from_string(format);
  const GstAudioFormatInfo *fi = gst_audio_format_get_info(af);
  const int width = GST_AUDIO_FORMAT_INFO_WIDTH(fi) / 8;
  const bool big = GST_AUDIO_FORMAT_INFO_ENDIANNESS(fi) == G_BIG_ENDIAN && width > 1;
  // Native-order bytes of 6 samples (2 channels x 3 frames), then the stream's order.
  std::vector<uint8_t> native(6 * width);
  for (int i = 0; i < 6; ++i) {
    for (int b = 0; b < width; ++b) native[i * width + b] = static_cast<uint8_t>(i * 16 + b + 1);
  }
  std::vector<uint8_t> stream = native;
  if (big != (G_BYTE_ORDER == G_BIG_ENDIAN))
    for (int i = 0; i < 6; ++i)
      std::reverse(stream.begin() + i * width, stream.begin() + (i + 1) * width);
  if (width == 1) stream = native;

  Conv conv("frames-per-tensor=3");
  gst_harness_set_src_caps_str(conv.h.get(), (std::string("audio/x-raw,format=") + format +
                                              ",channels=2,rate=16000,layout=interleaved")
                                                 .c_str());
  ASSERT_EQ(conv.push(buffer_of(stream)), GST_FLOW_OK) << conv.error();
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  EXPECT_EQ(bytes_of(out.get()), native);
  auto cfg = conv.out_config();
  EXPECT_EQ(cfg.info.dims_string(), "2:3");
  EXPECT_EQ(cfg.rate_n, 16000);
  std::string f = format;
  const char *type = f[0] == 'F' ? (width == 4 ? "float32" : "float64") : nullptr;
  if (!type) {
    static const char *s[] = {"", "int8", "int16", "", "int32"};
    static const char *u[] = {"", "uint8", "uint16", "", "uint32"};
    type = f[0] == 'S' ? s[width] : u[width];
  }
  EXPECT_EQ(cfg.info.types_string(), type);
}

INSTANTIATE_TEST_SUITE_P(TensorConverter, AudioFormats,
                         ::testing::Values("S8", "U8", "S16LE", "S16BE", "U16LE", "U16BE", "S32LE",
                                           "S32BE", "U32LE", "U32BE", "F32LE", "F32BE", "F64LE",
                                           "F64BE"));

TEST(TensorConverter, AudioDefaultSplitsIntoSampleFramesWithTimestamps) {
  Conv conv;  // frames-per-tensor=1: one tensor per sample frame, as NNStreamer
  gst_harness_set_src_caps_str(conv.h.get(),
                               "audio/x-raw,format=S16LE,channels=1,rate=4,layout=interleaved");
  GstBuffer *b = buffer_of({1, 0, 2, 0, 3, 0});
  GST_BUFFER_PTS(b) = GST_SECOND;
  ASSERT_EQ(conv.push(b), GST_FLOW_OK);
  for (int i = 0; i < 3; ++i) {
    nns::gst::BufferPtr out(conv.pull());
    ASSERT_TRUE(out);
    EXPECT_EQ(bytes_of(out.get()), (std::vector<uint8_t>{static_cast<uint8_t>(i + 1), 0}));
    EXPECT_EQ(GST_BUFFER_PTS(out.get()), GST_SECOND + i * GST_SECOND / 4);
  }
  EXPECT_EQ(conv.out_config().info.dims_string(), "1:1");
}

// ---- text ----------------------------------------------------------------------------------

TEST(TensorConverter, TextPadsTruncatesAndAggregates) {
  Conv conv("input-dim=8 input-type=uint8 frames-per-tensor=2");  // per-frame dims
  gst_harness_set_src_caps_str(conv.h.get(), "text/x-raw,format=utf8");
  ASSERT_EQ(conv.push(buffer_of({'h', 'e', 'l', 'l', 'o'})), GST_FLOW_OK);
  ASSERT_EQ(conv.push(buffer_of({'0', '1', '2', '3', '4', '5', '6', '7', '8', '9'})), GST_FLOW_OK);
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  EXPECT_EQ(bytes_of(out.get()), (std::vector<uint8_t>{'h', 'e', 'l', 'l', 'o', 0, 0, 0, '0', '1',
                                                       '2', '3', '4', '5', '6', '7'}));
  EXPECT_EQ(conv.out_config().info.dims_string(), "8:2");
  EXPECT_EQ(conv.out_config().info.types_string(), "uint8");
}

// ---- octet stream --------------------------------------------------------------------------

TEST(TensorConverter, OctetSingleTensorZeroCopyAndSeveralFramesPerBuffer) {
  Conv conv("input-dim=2:2 input-type=uint8");
  gst_harness_set_src_caps_str(conv.h.get(), "application/octet-stream");
  GstBuffer *in = buffer_of({1, 2, 3, 4});
  const guint8 *data = memory_data(gst_buffer_peek_memory(in, 0));
  ASSERT_EQ(conv.push(in), GST_FLOW_OK);
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  EXPECT_EQ(memory_data(gst_buffer_peek_memory(out.get(), 0)), data);
  EXPECT_EQ(conv.out_config().info.dims_string(), "2:2");
  // Two frames in one buffer give two tensors.
  ASSERT_EQ(conv.push(buffer_of({1, 2, 3, 4, 5, 6, 7, 8})), GST_FLOW_OK);
  nns::gst::BufferPtr a(conv.pull()), b(conv.pull());
  ASSERT_TRUE(a && b);
  EXPECT_EQ(bytes_of(b.get()), (std::vector<uint8_t>{5, 6, 7, 8}));
}

TEST(TensorConverter, OctetFromFileWithByteSegment) {
  std::string in = write_temp("octet8.bin", "ABCDEFGH");
  std::string out = nns::test::make_temp_dir() + "/octet.out";
  // filesrc sends a BYTES segment: the element turns it into a TIME one.
  auto r = run_pipeline("filesrc location=" + in +
                        " blocksize=8 ! application/octet-stream ! tensor_converter "
                        "input-dim=2:2 input-type=uint8 ! filesink location=" +
                        out);
  ASSERT_TRUE(r.eos) << r.error_text;
  auto got = nns::test::read_file(out);
  EXPECT_EQ(std::string(got.begin(), got.end()), "ABCDEFGH");
}

TEST(TensorConverter, OctetSplitsIntoSeveralTensorsSharingMemory) {
  Conv conv("input-dim=2,3 input-type=uint8,int16");
  gst_harness_set_src_caps_str(conv.h.get(), "application/octet-stream");
  GstBuffer *in = buffer_of({1, 2, 10, 0, 20, 0, 30, 0});
  const guint8 *data = memory_data(gst_buffer_peek_memory(in, 0));
  ASSERT_EQ(conv.push(in), GST_FLOW_OK);
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  ASSERT_EQ(gst_buffer_n_memory(out.get()), 2u);
  EXPECT_EQ(memory_bytes(gst_buffer_peek_memory(out.get(), 0)), (std::vector<uint8_t>{1, 2}));
  EXPECT_EQ(memory_bytes(gst_buffer_peek_memory(out.get(), 1)),
            (std::vector<uint8_t>{10, 0, 20, 0, 30, 0}));
  EXPECT_EQ(memory_data(gst_buffer_peek_memory(out.get(), 1)), data + 2);
  auto cfg = conv.out_config();
  EXPECT_EQ(cfg.info.dims_string(), "2,3");
  EXPECT_EQ(cfg.info.types_string(), "uint8,int16");
}

TEST(TensorConverter, OctetToFlexibleWhenDownstreamWantsIt) {
  Conv conv;
  gst_harness_set_sink_caps_str(conv.h.get(), "other/tensors,format=flexible");
  gst_harness_set_src_caps_str(conv.h.get(), "application/octet-stream");
  ASSERT_EQ(conv.push(buffer_of({9, 8, 7, 6, 5})), GST_FLOW_OK) << conv.error();
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  EXPECT_EQ(conv.out_config().info.format, nns::TensorFormat::kFlexible);
  nns::MetaHeader h = nns::gst::memory_header(gst_buffer_peek_memory(out.get(), 0));
  EXPECT_EQ(h.type, nns::TensorType::kUInt8);
  EXPECT_EQ(nns::dims_to_string(h.dims), "5:1:1:1");
  EXPECT_EQ(h.media_type, nns::MediaType::kOctet);
  auto all = bytes_of(out.get());
  EXPECT_EQ(std::vector<uint8_t>(all.begin() + nns::kMetaHeaderSize, all.end()),
            (std::vector<uint8_t>{9, 8, 7, 6, 5}));
}

TEST(TensorConverter, VideoToFlexibleAddsHeaders) {
  Conv conv;
  gst_harness_set_sink_caps_str(conv.h.get(), "other/tensors,format=flexible");
  gst_harness_set_src_caps_str(conv.h.get(),
                               "video/x-raw,format=GRAY8,width=4,height=1,framerate=0/1");
  ASSERT_EQ(conv.push(buffer_of({1, 2, 3, 4})), GST_FLOW_OK) << conv.error();
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  nns::MetaHeader h = nns::gst::memory_header(gst_buffer_peek_memory(out.get(), 0));
  EXPECT_EQ(nns::dims_to_string(h.dims), "1:4:1:1");
  EXPECT_EQ(h.media_type, nns::MediaType::kVideo);
}

// ---- flexible in ---------------------------------------------------------------------------

GstBuffer *flexible_buffer(nns::TensorType type, std::initializer_list<uint32_t> dims,
                           const std::vector<uint8_t> &payload) {
  nns::MetaHeader h;
  h.type = type;
  h.dims = nns::make_dims(dims);
  h.format = nns::TensorFormat::kFlexible;
  nns::gst::MemoryPtr p(
      gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, const_cast<uint8_t *>(payload.data()),
                             payload.size(), 0, payload.size(), nullptr, nullptr));
  GstBuffer *b = gst_buffer_new();
  gst_buffer_append_memory(b, nns::gst::memory_with_header(h, p.get()));
  return b;
}

TEST(TensorConverter, FlexibleToStaticWithPropertiesSharesPayload) {
  Conv conv("input-dim=2:2 input-type=int16");
  gst_harness_set_src_caps_str(conv.h.get(), "other/tensors,format=flexible,framerate=5/1");
  std::vector<uint8_t> payload{1, 0, 2, 0, 3, 0, 4, 0};
  GstBuffer *in = flexible_buffer(nns::TensorType::kInt16, {2, 2}, payload);
  const guint8 *data = memory_data(gst_buffer_peek_memory(in, 0));
  ASSERT_EQ(conv.push(in), GST_FLOW_OK) << conv.error();
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  EXPECT_EQ(bytes_of(out.get()), payload);
  EXPECT_EQ(memory_data(gst_buffer_peek_memory(out.get(), 0)), data + nns::kMetaHeaderSize);
  auto cfg = conv.out_config();
  EXPECT_EQ(cfg.info.format, nns::TensorFormat::kStatic);
  EXPECT_EQ(cfg.info.dims_string(), "2:2");
  EXPECT_EQ(cfg.info.types_string(), "int16");
  EXPECT_EQ(cfg.rate_n, 5);
}

TEST(TensorConverter, FlexibleToStaticFromHeadersFollowsChanges) {
  Conv conv;
  gst_harness_set_sink_caps_str(conv.h.get(), "other/tensors,format=static");
  gst_harness_set_src_caps_str(conv.h.get(), "other/tensors,format=flexible");
  ASSERT_EQ(conv.push(flexible_buffer(nns::TensorType::kUInt8, {3}, {1, 2, 3})), GST_FLOW_OK)
      << conv.error();
  nns::gst::BufferPtr a(conv.pull());
  ASSERT_TRUE(a);
  EXPECT_EQ(conv.out_config().info.dims_string(), "3");
  ASSERT_EQ(conv.push(flexible_buffer(nns::TensorType::kFloat32, {1}, {0, 0, 128, 63})),
            GST_FLOW_OK);
  nns::gst::BufferPtr b(conv.pull());
  ASSERT_TRUE(b);
  EXPECT_EQ(conv.out_config().info.types_string(), "float32");
}

TEST(TensorConverter, FlexiblePassesThroughToFlexible) {
  Conv conv;
  gst_harness_set_sink_caps_str(conv.h.get(), "other/tensors,format=flexible");
  gst_harness_set_src_caps_str(conv.h.get(), "other/tensors,format=flexible");
  GstBuffer *in = flexible_buffer(nns::TensorType::kUInt8, {2}, {7, 8});
  GstMemory *mem = gst_buffer_peek_memory(in, 0);
  ASSERT_EQ(conv.push(in), GST_FLOW_OK);
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  EXPECT_EQ(gst_buffer_peek_memory(out.get(), 0), mem);
}

// ---- timestamps ----------------------------------------------------------------------------

TEST(TensorConverter, SetTimestampFromFramerate) {
  Conv conv;
  gst_harness_set_src_caps_str(conv.h.get(),
                               "video/x-raw,format=GRAY8,width=4,height=1,framerate=10/1");
  for (int i = 0; i < 3; ++i) ASSERT_EQ(conv.push(buffer_of({1, 2, 3, 4})), GST_FLOW_OK);
  for (int i = 0; i < 3; ++i) {
    nns::gst::BufferPtr out(conv.pull());
    ASSERT_TRUE(out);
    EXPECT_EQ(GST_BUFFER_PTS(out.get()), i * 100 * GST_MSECOND);
    EXPECT_EQ(GST_BUFFER_DURATION(out.get()), 100 * GST_MSECOND);
  }
}

TEST(TensorConverter, SetTimestampOffKeepsInvalidPts) {
  Conv conv("set-timestamp=false");
  gst_harness_set_src_caps_str(conv.h.get(),
                               "video/x-raw,format=GRAY8,width=4,height=1,framerate=10/1");
  ASSERT_EQ(conv.push(buffer_of({1, 2, 3, 4})), GST_FLOW_OK);
  nns::gst::BufferPtr out(conv.pull());
  ASSERT_TRUE(out);
  EXPECT_FALSE(GST_BUFFER_PTS_IS_VALID(out.get()));
  EXPECT_FALSE(GST_BUFFER_DURATION_IS_VALID(out.get()));
}

// ---- custom-code and sub-plugins -----------------------------------------------------------

GstBuffer *double_as_float(GstBuffer *in, void *data, GstTensorsConfig *config) {
  auto *calls = static_cast<int *>(data);
  ++*calls;
  auto bytes = bytes_of(in);
  std::vector<float> f(bytes.begin(), bytes.end());
  for (auto &x : f) x *= 2;
  GstBuffer *out = gst_buffer_new_memdup(f.data(), f.size() * sizeof(float));
  config->info.num_tensors = 1;
  config->info.info[0].type = _NNS_FLOAT32;
  config->info.info[0].dimension[0] = static_cast<uint32_t>(f.size());
  config->info.info[0].dimension[1] = 1;
  config->rate_n = 0;
  config->rate_d = 1;
  return out;
}

TEST(TensorConverter, CustomCodeCallback) {
  int calls = 0;
  ASSERT_EQ(nnstreamer_converter_custom_register("double_f32", double_as_float, &calls), 0);
  EXPECT_EQ(nnstreamer_converter_custom_register("double_f32", double_as_float, &calls), -EINVAL);
  EXPECT_EQ(nnstreamer_converter_custom_register("", double_as_float, nullptr), -EINVAL);
  EXPECT_EQ(nnstreamer_converter_custom_register("x", nullptr, nullptr), -EINVAL);
  {
    Conv conv("mode=custom-code:double_f32");
    gst_harness_set_src_caps_str(conv.h.get(), "application/octet-stream");
    ASSERT_EQ(conv.push(buffer_of({1, 2, 3})), GST_FLOW_OK) << conv.error();
    nns::gst::BufferPtr out(conv.pull());
    ASSERT_TRUE(out);
    auto b = bytes_of(out.get());
    ASSERT_EQ(b.size(), 12u);
    float f[3];
    std::memcpy(f, b.data(), 12);
    EXPECT_EQ(f[0], 2.f);
    EXPECT_EQ(f[2], 6.f);
    EXPECT_EQ(conv.out_config().info.dims_string(), "3:1");
    EXPECT_EQ(conv.out_config().info.types_string(), "float32");
    EXPECT_EQ(calls, 1);
    gchar *mode = nullptr;
    g_object_get(conv.el, "mode", &mode, nullptr);
    EXPECT_STREQ(mode, "custom-code:double_f32");
    g_free(mode);
  }
  EXPECT_EQ(nnstreamer_converter_custom_unregister("double_f32"), 0);
  EXPECT_EQ(nnstreamer_converter_custom_unregister("double_f32"), -EINVAL);
}

gboolean inproc_out_config(const GstCaps *, GstTensorsConfig *config) {
  config->info.num_tensors = 1;
  config->info.info[0].type = _NNS_UINT8;
  config->info.info[0].dimension[0] = 2;
  config->rate_n = 0;
  config->rate_d = 1;
  return TRUE;
}
GstBuffer *inproc_convert(GstBuffer *in, GstTensorsConfig *config, void *) {
  inproc_out_config(nullptr, config);
  return in;  // returning the input moves the element's reference (no extra ref: that leaked)
}
GstCaps *inproc_caps(const GstTensorsConfig *) {
  return gst_caps_from_string("application/x-nns-inproc");
}

TEST(TensorConverter, InProcessSubpluginRegistration) {
  static NNStreamerExternalConverter bad = {"bad",       nullptr, inproc_out_config,
                                            inproc_caps, nullptr, nullptr};
  EXPECT_FALSE(registerExternalConverter(&bad));
  static NNStreamerExternalConverter ex = {"inproc",    inproc_convert, inproc_out_config,
                                           inproc_caps, nullptr,        nullptr};
  ASSERT_TRUE(registerExternalConverter(&ex));
  EXPECT_FALSE(registerExternalConverter(&ex));  // taken
  // The registry keeps its own copy of the table (the caller may free its struct).
  const NNStreamerExternalConverter *found = nnstreamer_converter_find("inproc");
  ASSERT_NE(found, nullptr);
  EXPECT_NE(found, &ex);
  EXPECT_STREQ(found->name, "inproc");
  EXPECT_EQ(found->convert, &inproc_convert);
  {
    Conv conv;
    gchar *list = nullptr;
    g_object_get(conv.el, "sub-plugins", &list, nullptr);
    EXPECT_NE(std::string(list).find("inproc"), std::string::npos) << list;
    g_free(list);
    gst_harness_set_src_caps_str(conv.h.get(), "application/x-nns-inproc");
    GstBuffer *in = buffer_of({5, 6});
    GstMemory *mem = gst_buffer_peek_memory(in, 0);
    ASSERT_EQ(conv.push(in), GST_FLOW_OK) << conv.error();
    nns::gst::BufferPtr out(conv.pull());
    ASSERT_TRUE(out);
    EXPECT_EQ(gst_buffer_peek_memory(out.get(), 0), mem);
    EXPECT_EQ(conv.out_config().info.dims_string(), "2");
  }
  unregisterExternalConverter("inproc");
  EXPECT_EQ(nnstreamer_converter_find("inproc"), nullptr);
}

#ifdef NNS_TEST_CONVERTERS_DIR
TEST(TensorConverter, LoadsSubpluginFilesBothWays) {
  setenv("NNSTREAMER_CONVERTERS", NNS_TEST_CONVERTERS_DIR, 1);
  nns::Conf::reload();
  for (const char *name : {"testentry", "testctor"}) {
    SCOPED_TRACE(name);
    ASSERT_NE(nnstreamer_converter_find(name), nullptr);
    Conv conv;
    gst_harness_set_src_caps_str(conv.h.get(),
                                 (std::string("application/x-nns-") + name + ",n=3").c_str());
    ASSERT_EQ(conv.push(buffer_of({1, 2, 3})), GST_FLOW_OK) << conv.error();
    nns::gst::BufferPtr out(conv.pull());
    ASSERT_TRUE(out);
    EXPECT_EQ(conv.out_config().info.types_string(), "float32");
    EXPECT_EQ(conv.out_config().info.dims_string(), "3:1");
    auto b = bytes_of(out.get());
    float f[3];
    std::memcpy(f, b.data(), 12);
    EXPECT_EQ(f[2], 3.f);
  }
}
#endif

// ---- negotiation ---------------------------------------------------------------------------

TEST(TensorConverter, DownstreamTensorCapsDriveVideoScaling) {
  auto r = run_pipeline(
      "videotestsrc num-buffers=2 ! videoconvert ! videoscale ! tensor_converter ! "
      "other/tensors,num_tensors=1,dimensions=3:32:24,types=uint8 ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(TensorConverter, OrangePngMatchesGolden) {
  NNS_REQUIRE_SHARED_MODELS();
  std::string data = nns::test::shared_models_dir() + "/data/";
  std::string out = nns::test::make_temp_dir() + "/orange.out";
  auto r = run_pipeline("filesrc location=" + data +
                        "orange.png ! pngdec ! videoconvert ! videoscale ! "
                        "video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! "
                        "filesink location=" +
                        out);
  ASSERT_TRUE(r.eos) << r.error_text;
  auto got = nns::test::read_file(out);
  auto want = nns::test::read_file(data + "orange.raw");
  ASSERT_EQ(got.size(), 224u * 224 * 3);
  EXPECT_TRUE(got == want);
}

// ---- errors on the bus ---------------------------------------------------------------------

void expect_error(const nns::test::RunResult &r, std::initializer_list<const char *> words) {
  ASSERT_TRUE(r.error) << "no error; eos=" << r.eos;
  EXPECT_EQ(r.error_source.rfind("tensorconverter", 0), 0u) << r.error_text;
  for (const char *w : words) EXPECT_NE(r.error_text.find(w), std::string::npos) << r.error_text;
}

TEST(TensorConverterErrors, TextWithoutInputDim) {
  std::string f = write_temp("text.txt", "hello");
  expect_error(run_pipeline("filesrc location=" + f +
                            " ! text/x-raw,format=utf8 ! tensor_converter ! fakesink"),
               {"tensorconverter", "input-dim", "text/x-raw", "got none"});
}

TEST(TensorConverterErrors, OctetWithoutProperties) {
  std::string f = write_temp("octet.bin", "0123");
  expect_error(run_pipeline("filesrc location=" + f +
                            " ! application/octet-stream ! tensor_converter ! fakesink"),
               {"input-dim", "input-type", "application/octet-stream"});
  expect_error(run_pipeline("filesrc location=" + f +
                            " ! application/octet-stream ! tensor_converter input-dim=4 ! "
                            "fakesink"),
               {"input-type is required", "input-dim='4'"});
}

TEST(TensorConverterErrors, MalformedInputDim) {
  std::string f = write_temp("octet2.bin", "0123");
  expect_error(run_pipeline("filesrc location=" + f +
                            " ! application/octet-stream ! tensor_converter input-dim=a:b "
                            "input-type=uint8 ! fakesink"),
               {"input-dim", "'a'", "'a:b'"});
}

TEST(TensorConverterErrors, MalformedInputType) {
  std::string f = write_temp("octet3.bin", "0123");
  expect_error(run_pipeline("filesrc location=" + f +
                            " ! application/octet-stream ! tensor_converter input-dim=4 "
                            "input-type=float8 ! fakesink"),
               {"input-type", "'float8'"});
}

TEST(TensorConverterErrors, OctetSizeMismatch) {
  std::string f = write_temp("octet10.bin", "0123456789");
  expect_error(run_pipeline("filesrc location=" + f +
                            " blocksize=10 ! application/octet-stream ! tensor_converter "
                            "input-dim=4 input-type=uint8 ! fakesink"),
               {"10 bytes", "expected 4", "input-dim='4'"});
}

TEST(TensorConverterErrors, UnknownCustomCode) {
  std::string f = write_temp("octet4.bin", "0123");
  expect_error(run_pipeline("filesrc location=" + f +
                            " ! application/octet-stream ! tensor_converter "
                            "mode=custom-code:nosuchfunc ! fakesink"),
               {"mode=custom-code:nosuchfunc", "'nosuchfunc'"});
}

TEST(TensorConverterErrors, BadMode) {
  expect_error(run_pipeline("videotestsrc num-buffers=1 ! tensor_converter mode=magic ! fakesink"),
               {"mode='magic'", "custom-code"});
}

TEST(TensorConverterErrors, PropertiesContradictVideo) {
  expect_error(run_pipeline("videotestsrc num-buffers=1 ! video/x-raw,format=RGB,width=4,height=4"
                            " ! tensor_converter input-dim=3:4:4:1 input-type=float32 ! fakesink"),
               {"input-type='float32'", "uint8 3:4:4:1"});
}

TEST(TensorConverterErrors, DownstreamRejectsTensor) {
  expect_error(run_pipeline("videotestsrc num-buffers=1 ! video/x-raw,format=RGB,width=4,height=4"
                            " ! tensor_converter input-dim=3:4:4:1 ! other/tensors,format=static,"
                            "types=float32 ! fakesink"),
               {"downstream accepts", "uint8"});
}

TEST(TensorConverterErrors, UnsupportedVideoFormat) {
  Conv conv;
  gst_harness_set_src_caps_str(conv.h.get(), "video/x-raw,format=I420,width=4,height=4");
  std::string e = conv.error();
  EXPECT_NE(e.find("format='I420'"), std::string::npos) << e;
  EXPECT_NE(e.find("RGB"), std::string::npos) << e;
}

TEST(TensorConverterErrors, VideoBufferSizeMismatch) {
  Conv conv;
  gst_harness_set_src_caps_str(conv.h.get(), "video/x-raw,format=RGB,width=4,height=2");
  EXPECT_EQ(conv.push(buffer_of(std::vector<uint8_t>(20))), GST_FLOW_ERROR);
  std::string e = conv.error();
  EXPECT_NE(e.find("20 bytes, expected 24"), std::string::npos) << e;
}

TEST(TensorConverterErrors, AudioBufferNotWholeSamples) {
  Conv conv;
  gst_harness_set_src_caps_str(conv.h.get(),
                               "audio/x-raw,format=S16LE,channels=2,rate=8000,layout=interleaved");
  EXPECT_EQ(conv.push(buffer_of(std::vector<uint8_t>(6))), GST_FLOW_ERROR);
  std::string e = conv.error();
  EXPECT_NE(e.find("6 bytes, expected a multiple of 4"), std::string::npos) << e;
}

TEST(TensorConverterErrors, FlexibleSizeMismatch) {
  Conv conv("input-dim=4 input-type=uint8");
  gst_harness_set_src_caps_str(conv.h.get(), "other/tensors,format=flexible");
  EXPECT_EQ(conv.push(flexible_buffer(nns::TensorType::kUInt8, {3}, {1, 2, 3})), GST_FLOW_ERROR);
  std::string e = conv.error();
  EXPECT_NE(e.find("flexible tensor 0 carries 3 bytes"), std::string::npos) << e;
  EXPECT_NE(e.find("input-dim='4'"), std::string::npos) << e;
}

// ---- performance ---------------------------------------------------------------------------

int g_dropped = 0;
GstFlowReturn drop_chain(GstPad *, GstObject *, GstBuffer *b) {
  ++g_dropped;
  gst_buffer_unref(b);
  return GST_FLOW_OK;
}

// Best of 5 runs of `n` buffers pushed straight into `el`'s sink pad, its src pad linked to a
// pad that drops buffers: the element's own per-buffer cost plus one pad push.
double chain_ns(GstElement *el, const char *caps_str, gsize size, int n) {
  GstPad *sink = gst_element_get_static_pad(el, "sink");
  GstPad *src = gst_element_get_static_pad(el, "src");
  GstPad *drop = gst_pad_new("drop", GST_PAD_SINK);
  gst_pad_set_chain_function(drop, drop_chain);
  gst_pad_set_active(drop, TRUE);
  EXPECT_EQ(gst_pad_link(src, drop), GST_PAD_LINK_OK);
  gst_element_set_state(el, GST_STATE_PLAYING);
  gst_pad_send_event(sink, gst_event_new_stream_start("perf"));
  GstCaps *caps = gst_caps_from_string(caps_str);
  gst_pad_send_event(sink, gst_event_new_caps(caps));
  gst_caps_unref(caps);
  GstSegment seg;
  gst_segment_init(&seg, GST_FORMAT_TIME);
  gst_pad_send_event(sink, gst_event_new_segment(&seg));
  GstBuffer *proto = gst_buffer_new_allocate(nullptr, size, nullptr);
  gst_buffer_memset(proto, 0, 7, size);
  double best = 1e12;
  g_dropped = 0;
  for (int run = 0; run < 5; ++run) {
    auto t0 = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) {
      GstBuffer *b = gst_buffer_ref(proto);
      if (gst_pad_chain(sink, b) != GST_FLOW_OK) ADD_FAILURE() << "chain failed";
    }
    auto t1 = std::chrono::steady_clock::now();
    best = std::min(best, std::chrono::duration<double, std::nano>(t1 - t0).count() / n);
  }
  gst_buffer_unref(proto);
  EXPECT_EQ(g_dropped, 5 * n);
  gst_element_set_state(el, GST_STATE_NULL);
  gst_pad_unlink(src, drop);
  gst_object_unref(drop);
  gst_object_unref(src);
  gst_object_unref(sink);
  return best;
}

TEST(TensorConverterPerf, Gray8x4PerBufferOverhead) {
  const char *caps = "video/x-raw,format=GRAY8,width=4,height=4,framerate=30/1";
  GstElement *conv = gst_element_factory_make("tensor_converter", nullptr);
  GstElement *ident = gst_element_factory_make("identity", nullptr);
  gst_object_ref_sink(conv);
  gst_object_ref_sink(ident);
  const int n = 20000;
  double c = chain_ns(conv, caps, 16, n);
  double i = chain_ns(ident, caps, 16, n);
  double rgb = chain_ns(conv, "video/x-raw,format=RGB,width=224,height=224,framerate=30/1",
                        224 * 224 * 3, 2000);
  double padded =
      chain_ns(conv, "video/x-raw,format=RGB,width=225,height=224,framerate=30/1", 676 * 224, 2000);
  std::printf(
      "tensor_converter GRAY8 4x4: %.0f ns/buffer (identity: %.0f ns/buffer); "
      "RGB 224x224 (shared): %.0f ns; RGB 225x224 (stride removal): %.0f ns\n",
      c, i, rgb, padded);
  gst_object_unref(conv);
  gst_object_unref(ident);
  // Target is 1.5 us; the bound is looser so a loaded machine does not fail the suite.
  EXPECT_LT(c, 5000.0);
}

}  // namespace

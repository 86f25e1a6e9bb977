// SPDX-License-Identifier: LGPL-2.1-only
// Wire-format sub-plugins: tensor_converter with other/protobuf-tensor, other/flatbuf-tensor,
// other/flexbuf input (bytes made by nns_wire), corrupt input -> bus error, and the decoder
// sub-plugins driven directly through nns_decoder_subplugin_entry (dlopen), chained with the
// converter for a full tensors -> bytes -> tensors round trip.
#include <gtest/gtest.h>

#include "support/harness.h"

#ifdef NNS_HAVE_WIRE
#include <dlfcn.h>

#include <cstring>
#include <fstream>

#include "nnstreamer/nnstreamer_plugin_api_decoder.h"
#include "wire.h"

namespace {

using nns::test::HarnessPtr;
using nns::wire::Format;

constexpr Format kFormats[] = {Format::kProtobuf, Format::kFlatbuf, Format::kFlexbuf};

std::string caps_of(GstPad *pad) {
  GstCaps *c = gst_pad_get_current_caps(pad);
  if (!c) return "";
  gchar *s = gst_caps_to_string(c);
  std::string r = s;
  g_free(s);
  gst_caps_unref(c);
  return r;
}

GstBuffer *buffer_of(const std::vector<uint8_t> &v) {
  return gst_buffer_new_memdup(v.data(), v.size());
}

std::vector<uint8_t> bytes_of(GstMemory *m) {
  GstMapInfo map;
  EXPECT_TRUE(gst_memory_map(m, &map, GST_MAP_READ));
  std::vector<uint8_t> r(map.data, map.data + map.size);
  gst_memory_unmap(m, &map);
  return r;
}

// Two tensors: uint8 3:4 "a" and float32 2:2:2 unnamed, at 30/1.
struct Sample {
  std::vector<uint8_t> a = std::vector<uint8_t>(12), b = std::vector<uint8_t>(32);
  nns::wire::Frame frame;
  Sample() {
    for (std::size_t i = 0; i < a.size(); ++i) a[i] = static_cast<uint8_t>(i * 7 + 1);
    for (std::size_t i = 0; i < b.size(); ++i) b[i] = static_cast<uint8_t>(200 - i);
    frame.rate_n = 30;
    frame.rate_d = 1;
    nns::wire::Tensor ta, tb;
    ta.name = "a";
    ta.type = 5;
    ta.dims[0] = 3;
    ta.dims[1] = 4;
    ta.data = a.data();
    ta.size = a.size();
    tb.type = 7;
    tb.dims[0] = tb.dims[1] = tb.dims[2] = 2;
    tb.data = b.data();
    tb.size = b.size();
    frame.tensors = {ta, tb};
  }
};

void expect_sample_tensors(GstBuffer *out, const Sample &s, const std::string &caps) {
  ASSERT_EQ(2u, gst_buffer_n_memory(out));
  EXPECT_EQ(s.a, bytes_of(gst_buffer_peek_memory(out, 0)));
  EXPECT_EQ(s.b, bytes_of(gst_buffer_peek_memory(out, 1)));
  EXPECT_NE(std::string::npos, caps.find("other/tensors")) << caps;
  EXPECT_NE(std::string::npos, caps.find("float32")) << caps;
  EXPECT_NE(std::string::npos, caps.find("3:4")) << caps;
  EXPECT_NE(std::string::npos, caps.find("2:2:2")) << caps;
  EXPECT_NE(std::string::npos, caps.find("30/1")) << caps;
}

GstBuffer *convert_once(Format fmt, const std::vector<uint8_t> &bytes, std::string *caps) {
  HarnessPtr h(gst_harness_new_parse("tensor_converter"));
  gst_harness_set_src_caps_str(
      h.get(), (std::string(nns::wire::media_type(fmt)) + ",framerate=(fraction)30/1").c_str());
  EXPECT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), buffer_of(bytes)));
  GstBuffer *out = gst_harness_try_pull(h.get());
  *caps = caps_of(h->sinkpad);
  return out;
}

TEST(WirePipeline, ConverterDecodesEachFormat) {
  Sample s;
  for (Format fmt : kFormats) {
    SCOPED_TRACE(nns::wire::format_name(fmt));
    std::vector<uint8_t> bytes;
    nns::wire::encode(fmt, s.frame, bytes);
    std::string caps;
    GstBuffer *out = convert_once(fmt, bytes, &caps);
    ASSERT_NE(nullptr, out);
    expect_sample_tensors(out, s, caps);
    gst_buffer_unref(out);
  }
}

TEST(WirePipeline, CorruptInputIsABusError) {
  const std::string dir = nns::test::make_temp_dir();
  for (Format fmt : kFormats) {
    SCOPED_TRACE(nns::wire::format_name(fmt));
    Sample s;
    std::vector<uint8_t> bytes;
    nns::wire::encode(fmt, s.frame, bytes);
    bytes.resize(bytes.size() / 2);  // truncated
    const std::string path = dir + "/bad_" + nns::wire::format_name(fmt);
    std::ofstream(path, std::ios::binary)
        .write(reinterpret_cast<const char *>(bytes.data()), bytes.size());
    auto r = nns::test::run_pipeline("filesrc location=" + path + " ! " +
                                     nns::wire::media_type(fmt) + " ! tensor_converter ! fakesink");
    EXPECT_TRUE(r.error);
    EXPECT_NE(std::string::npos, r.error_text.find("tensorconverter")) << r.error_text;
    EXPECT_NE(std::string::npos, r.error_text.find(nns::wire::format_name(fmt))) << r.error_text;
  }
}

const GstTensorDecoderDef *load_decoder(Format fmt) {
  const std::string path = std::string(NNS_BUILD_DIR) +
                           "/subplugins/decoders/libnnstreamer_decoder_" +
                           nns::wire::format_name(fmt) + ".so";
  void *h = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  EXPECT_NE(nullptr, h) << dlerror();
  if (!h) return nullptr;
  auto entry =
      reinterpret_cast<nns_decoder_subplugin_entry_fn>(dlsym(h, NNS_DECODER_SUBPLUGIN_ENTRY));
  EXPECT_NE(nullptr, entry);
  return entry ? entry() : nullptr;  // left loaded for the process
}

TEST(WireDecoder, EntryEncodesAndConverterRoundTrips) {
  Sample s;
  for (Format fmt : kFormats) {
    SCOPED_TRACE(nns::wire::format_name(fmt));
    const GstTensorDecoderDef *d = load_decoder(fmt);
    ASSERT_NE(nullptr, d);
    EXPECT_STREQ(nns::wire::format_name(fmt), d->modename);
    void *priv = nullptr;
    ASSERT_TRUE(d->init(&priv));
    EXPECT_TRUE(d->setOption(&priv, 0, "anything"));

    GstTensorsConfig cfg;
    std::memset(&cfg, 0, sizeof(cfg));
    cfg.rate_n = 30;
    cfg.rate_d = 1;
    cfg.info.num_tensors = 2;
    cfg.info.info[0].name = const_cast<char *>("a");
    cfg.info.info[0].type = _NNS_UINT8;
    cfg.info.info[0].dimension[0] = 3;
    cfg.info.info[0].dimension[1] = 4;
    cfg.info.info[1].type = _NNS_FLOAT32;
    cfg.info.info[1].dimension[0] = cfg.info.info[1].dimension[1] = cfg.info.info[1].dimension[2] =
        2;

    GstCaps *caps = d->getOutCaps(&priv, &cfg);
    ASSERT_NE(nullptr, caps);
    gchar *cs = gst_caps_to_string(caps);
    EXPECT_EQ(std::string(nns::wire::media_type(fmt)) + ", framerate=(fraction)30/1",
              std::string(cs));
    g_free(cs);
    gst_caps_unref(caps);

    GstTensorMemory in[2] = {{s.a.data(), s.a.size()}, {s.b.data(), s.b.size()}};
    GstBuffer *out = gst_buffer_new();
    ASSERT_EQ(GST_FLOW_OK, d->decode(&priv, &cfg, in, out));
    ASSERT_EQ(1u, gst_buffer_n_memory(out));
    std::vector<uint8_t> bytes = bytes_of(gst_buffer_peek_memory(out, 0));
    gst_buffer_unref(out);
    // Same bytes as the library's encoder; decodes back exactly.
    std::vector<uint8_t> want;
    nns::wire::encode(fmt, s.frame, want);
    EXPECT_EQ(want, bytes);
    std::string ccaps;
    GstBuffer *back = convert_once(fmt, bytes, &ccaps);
    ASSERT_NE(nullptr, back);
    expect_sample_tensors(back, s, ccaps);
    gst_buffer_unref(back);

    // A size mismatch is refused, not serialised.
    in[1].size = 31;
    GstBuffer *bad = gst_buffer_new();
    EXPECT_EQ(GST_FLOW_ERROR, d->decode(&priv, &cfg, in, bad));
    gst_buffer_unref(bad);
    d->exit(&priv);
  }
}

}  // namespace
#else
TEST(WirePipeline, Skipped) {
  GTEST_SKIP() << "protobuf/flatbuffers not found: wire sub-plugins not built";
}
#endif

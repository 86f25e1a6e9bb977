// SPDX-License-Identifier: LGPL-2.1-only
// Wire-format sub-plugins: tensor_converter with other/protobuf-tensor, other/flatbuf-tensor,
// other/flexbuf input (bytes made by nns_wire), corrupt input -> bus error, and the decoder
// sub-plugins driven directly through nns_decoder_subplugin_entry (dlopen), chained with the
// converter for a full tensors -> bytes -> tensors round trip.
#include <gtest/gtest.h>

#include "support/harness.h"

#ifdef NNS_HAVE_WIRE
#include <dlfcn.h>
#include <flatbuffers/flexbuffers.h>

#include <algorithm>
#include <cstring>
#include <fstream>

#include "core/meta_header.h"
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
    // The sub-plugin's reason reaches the bus (nns_converter_subplugin_last_error).
    const std::string reason = std::string("returned no buffer: ") + nns::wire::format_name(fmt) +
                               ": input (" + std::to_string(bytes.size()) + " bytes)";
    EXPECT_NE(std::string::npos, r.error_text.find(reason)) << r.error_text;
    if (fmt == Format::kProtobuf)
      EXPECT_NE(std::string::npos,
                r.error_text.find("truncated at byte " + std::to_string(bytes.size())))
          << r.error_text;
    else
      EXPECT_NE(std::string::npos, r.error_text.find("truncated")) << r.error_text;
  }
}

// A frame that parses but lies (num_tensor disagrees): the reason names the field.
TEST(WirePipeline, InconsistentFrameReasonOnBus) {
  const std::string dir = nns::test::make_temp_dir();
  Sample s;
  std::vector<uint8_t> bytes;
  nns::wire::encode(Format::kFlexbuf, s.frame, bytes);
  // Re-encode with a wrong count through the flexbuffers builder.
  flexbuffers::Builder b;
  b.Map([&]() {
    b.UInt("num_tensors", 3);
    b.Vector("tensor_0", [&]() {
      b.String("a");
      b.Int(5);
      b.Vector(std::vector<uint32_t>{4}.data(), 1);
      b.Blob(s.a.data(), 4);
    });
  });
  b.Finish();
  const std::string path = dir + "/lying.flexbuf";
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char *>(b.GetBuffer().data()), b.GetSize());
  auto r = nns::test::run_pipeline("filesrc location=" + path +
                                   " ! other/flexbuf ! tensor_converter ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(std::string::npos, r.error_text.find("flexbuf: tensor_1: missing or not a vector"))
      << r.error_text;
}

// tensor_decoder mode=<fmt> ! tensor_converter inside one bin: exact tensors and caps back for
// every type, ranks 1, 3 and 16, and a three-tensor frame.
struct RoundTripCase {
  std::vector<std::pair<std::string, std::string>> tensors;  // (type, dims)
};

std::size_t type_bytes(const std::string &t) {
  if (t == "int8" || t == "uint8") return 1;
  if (t == "int16" || t == "uint16" || t == "float16") return 2;
  if (t == "int32" || t == "uint32" || t == "float32") return 4;
  return 8;
}

std::size_t dims_elements(const std::string &d) {
  std::size_t n = 1, v = 0;
  for (char c : d + ":") {
    if (c == ':') {
      n *= v;
      v = 0;
    } else {
      v = v * 10 + static_cast<std::size_t>(c - '0');
    }
  }
  return n;
}

void round_trip(Format fmt, const RoundTripCase &rc) {
  std::string types, dims;
  for (const auto &t : rc.tensors) {
    types += (types.empty() ? "" : ",") + t.first;
    dims += (dims.empty() ? "" : ",") + t.second;
  }
  const std::string caps =
      "other/tensors,format=static,num_tensors=" + std::to_string(rc.tensors.size()) +
      ",types=(string)\"" + types + "\",dimensions=(string)\"" + dims +
      "\",framerate=(fraction)15/1";
  SCOPED_TRACE(std::string(nns::wire::format_name(fmt)) + " " + caps);
  HarnessPtr h(gst_harness_new_parse(
      (std::string("tensor_decoder mode=") + nns::wire::format_name(fmt) + " ! tensor_converter")
          .c_str()));
  gst_harness_set_src_caps_str(h.get(), caps.c_str());
  GstBuffer *in = gst_buffer_new();
  std::vector<std::vector<uint8_t>> want;
  for (std::size_t i = 0; i < rc.tensors.size(); ++i) {
    std::vector<uint8_t> v(type_bytes(rc.tensors[i].first) * dims_elements(rc.tensors[i].second));
    for (std::size_t k = 0; k < v.size(); ++k) v[k] = static_cast<uint8_t>(k * 31 + i * 7 + 3);
    gpointer copy = g_memdup2(v.data(), v.size());
    gst_buffer_append_memory(in, gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, copy, v.size(), 0,
                                                        v.size(), copy, g_free));
    want.push_back(std::move(v));
  }
  ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in));
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(nullptr, out);
  ASSERT_EQ(want.size(), gst_buffer_n_memory(out));
  for (std::size_t i = 0; i < want.size(); ++i)
    EXPECT_EQ(want[i], bytes_of(gst_buffer_peek_memory(out, static_cast<guint>(i)))) << i;
  gst_buffer_unref(out);
  std::string got = caps_of(h->sinkpad);
  got.erase(std::remove(got.begin(), got.end(), '\\'), got.end());  // "a\,b" -> "a,b"
  EXPECT_NE(std::string::npos, got.find(types)) << got;
  EXPECT_NE(std::string::npos, got.find(dims)) << got;
  EXPECT_NE(std::string::npos, got.find("15/1")) << got;
}

TEST(WirePipeline, DecoderConverterRoundTripEveryTypeAndRank) {
  const char *types[] = {"int32",   "uint32",  "int16", "uint16", "int8",   "uint8",
                         "float64", "float32", "int64", "uint64", "float16"};
  const std::string rank16 = "2:1:1:1:1:1:1:1:1:1:1:1:1:1:1:3";
  for (Format fmt : kFormats) {
    for (const char *t : types) {
      for (const std::string &d : {std::string("7"), std::string("3:2:4"), rank16})
        round_trip(fmt, {{{t, d}}});
    }
    round_trip(fmt, {{{"uint8", "3:4"}, {"float32", "2:2:2"}, {"int64", "5"}}});
  }
}

// End to end: a flexbuf file whose frame is format=flexible (each tensor = 128-byte header +
// payload) -> tensor_converter (flexible output) -> tensor_decoder mode=octet_stream: the
// payloads, headers stripped, one after the other.
TEST(WirePipeline, FlexibleFrameThroughConverterAndDecoder) {
  const std::string dir = nns::test::make_temp_dir();
  std::vector<std::vector<uint8_t>> mems;
  std::vector<uint8_t> want;
  nns::wire::Frame f;
  f.format = 1;
  f.rate_n = 0;
  f.rate_d = 1;
  const std::pair<nns::TensorType, nns::Dims> specs[] = {{nns::TensorType::kUInt8, {5}},
                                                         {nns::TensorType::kInt16, {2, 3}}};
  for (const auto &sp : specs) {
    nns::MetaHeader h;
    h.type = sp.first;
    h.dims = sp.second;
    h.format = nns::TensorFormat::kFlexible;
    std::vector<uint8_t> m(nns::kMetaHeaderSize + h.payload_size());
    nns::write_meta_header(h, m.data());
    for (std::size_t k = nns::kMetaHeaderSize; k < m.size(); ++k)
      m[k] = static_cast<uint8_t>(k * 5 + mems.size());
    want.insert(want.end(), m.begin() + nns::kMetaHeaderSize, m.end());
    mems.push_back(std::move(m));
  }
  for (std::size_t i = 0; i < mems.size(); ++i) {
    nns::wire::Tensor t;
    t.type = static_cast<uint32_t>(specs[i].first);
    std::copy(specs[i].second.begin(), specs[i].second.end(), t.dims.begin());
    t.data = mems[i].data();
    t.size = mems[i].size();
    f.tensors.push_back(t);
  }
  std::vector<uint8_t> bytes;
  nns::wire::encode(Format::kFlexbuf, f, bytes);
  const std::string in = dir + "/flex.flexbuf", out = dir + "/out.bin";
  std::ofstream(in, std::ios::binary)
      .write(reinterpret_cast<const char *>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  auto r = nns::test::run_pipeline("filesrc location=" + in +
                                   " ! other/flexbuf,framerate=0/1 ! tensor_converter ! "
                                   "other/tensors,format=flexible ! tensor_decoder "
                                   "mode=octet_stream ! filesink location=" +
                                   out);
  ASSERT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(want, nns::test::read_file(out));
}

// Flexible input to the wire decoders, as NNStreamer does it: the frame says format=flexible and
// each tensor's data is its whole memory, 128-byte header included; the converter reads such a
// frame back into the same flexible memories.
TEST(WirePipeline, FlexibleInputKeepsHeadersInFrameAndRoundTrips) {
  std::vector<std::vector<uint8_t>> mems;
  const std::pair<nns::TensorType, nns::Dims> specs[] = {{nns::TensorType::kUInt8, {5}},
                                                         {nns::TensorType::kFloat32, {2, 3}}};
  for (const auto &sp : specs) {
    nns::MetaHeader h;
    h.type = sp.first;
    h.dims = sp.second;
    h.format = nns::TensorFormat::kFlexible;
    std::vector<uint8_t> m(nns::kMetaHeaderSize + h.payload_size());
    nns::write_meta_header(h, m.data());
    for (std::size_t k = nns::kMetaHeaderSize; k < m.size(); ++k)
      m[k] = static_cast<uint8_t>(k * 3 + mems.size());
    mems.push_back(std::move(m));
  }
  auto flexible_buffer = [&] {
    GstBuffer *in = gst_buffer_new();
    for (const auto &m : mems) {
      gpointer copy = g_memdup2(m.data(), m.size());
      gst_buffer_append_memory(in, gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, copy, m.size(),
                                                          0, m.size(), copy, g_free));
    }
    return in;
  };
  const char *in_caps = "other/tensors,format=flexible,framerate=(fraction)10/1";
  for (Format fmt : kFormats) {
    SCOPED_TRACE(nns::wire::format_name(fmt));
    const std::string mode = std::string("tensor_decoder mode=") + nns::wire::format_name(fmt);
    HarnessPtr h(gst_harness_new_parse(mode.c_str()));
    gst_harness_set_src_caps_str(h.get(), in_caps);
    ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), flexible_buffer()));
    GstBuffer *out = gst_harness_pull(h.get());
    ASSERT_NE(nullptr, out);
    std::vector<uint8_t> bytes(gst_buffer_get_size(out));
    gst_buffer_extract(out, 0, bytes.data(), bytes.size());
    gst_buffer_unref(out);
    nns::wire::Frame f = nns::wire::decode(fmt, bytes.data(), bytes.size());
    EXPECT_EQ(1u, f.format);
    ASSERT_EQ(2u, f.tensors.size());
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(mems[i],
                std::vector<uint8_t>(f.tensors[i].data, f.tensors[i].data + f.tensors[i].size))
          << i;
      EXPECT_EQ(static_cast<uint32_t>(specs[i].first), f.tensors[i].type) << i;
      EXPECT_EQ(specs[i].second[0], f.tensors[i].dims[0]) << i;
    }

    HarnessPtr rt(gst_harness_new_parse((mode + " ! tensor_converter").c_str()));
    gst_harness_set_src_caps_str(rt.get(), in_caps);
    ASSERT_EQ(GST_FLOW_OK, gst_harness_push(rt.get(), flexible_buffer()));
    GstBuffer *back = gst_harness_pull(rt.get());
    ASSERT_NE(nullptr, back);
    ASSERT_EQ(2u, gst_buffer_n_memory(back));
    for (guint i = 0; i < 2; ++i) EXPECT_EQ(mems[i], bytes_of(gst_buffer_peek_memory(back, i)));
    gst_buffer_unref(back);
    EXPECT_NE(std::string::npos, caps_of(rt->sinkpad).find("flexible")) << caps_of(rt->sinkpad);
  }
}

// Misaligned single-memory input (a share at byte 1) and multi-memory input: the converter
// copies to aligned memory for the flatbuffers formats and decodes exactly.
GstMemory *owned_memory(const uint8_t *p, std::size_t n) {
  gpointer copy = g_memdup2(p, n);
  return gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, copy, n, 0, n, copy, g_free);
}

TEST(WirePipeline, ConverterHandlesMisalignedAndSplitInput) {
  Sample s;
  for (Format fmt : kFormats) {
    SCOPED_TRACE(nns::wire::format_name(fmt));
    std::vector<uint8_t> bytes;
    nns::wire::encode(fmt, s.frame, bytes);
    for (int split = 0; split < 2; ++split) {
      GstBuffer *in = gst_buffer_new();
      if (split) {
        const std::size_t half = bytes.size() / 2 + 1;
        gst_buffer_append_memory(in, owned_memory(bytes.data(), half));
        gst_buffer_append_memory(in, owned_memory(bytes.data() + half, bytes.size() - half));
      } else {
        std::vector<uint8_t> shifted(bytes.size() + 1);
        std::memcpy(shifted.data() + 1, bytes.data(), bytes.size());
        GstMemory *whole = owned_memory(shifted.data(), shifted.size());
        gst_buffer_append_memory(in, gst_memory_share(whole, 1, static_cast<gssize>(bytes.size())));
        gst_memory_unref(whole);
      }
      HarnessPtr h(gst_harness_new_parse("tensor_converter"));
      gst_harness_set_src_caps_str(
          h.get(), (std::string(nns::wire::media_type(fmt)) + ",framerate=(fraction)30/1").c_str());
      ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in)) << "split " << split;
      GstBuffer *out = gst_harness_try_pull(h.get());
      ASSERT_NE(nullptr, out);
      expect_sample_tensors(out, s, caps_of(h->sinkpad));
      gst_buffer_unref(out);
    }
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
    // ... and the reason is in the DecoderErrorSlot tensor_decoder reads (magic, message).
    ASSERT_EQ(0, std::memcmp(priv, "NNSDERR", 8));
    EXPECT_NE(std::string::npos,
              std::string(static_cast<const char *>(priv) + 8).find("tensor 1: carries 31 bytes"))
        << static_cast<const char *>(priv) + 8;
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

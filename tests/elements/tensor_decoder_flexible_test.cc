// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder with flexible input (other/tensors,format=flexible): the tensors come from each
// buffer's 128-byte headers, the decoder sees a static config and the payload only, and the
// output caps follow when the tensors change. Corrupt headers end in a bus error naming the
// tensor and the header field.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <fstream>
#include <string>
#include <vector>

#include "core/meta_header.h"
#include "support/harness.h"

using nns::test::HarnessPtr;

namespace {

constexpr const char *kFlexCaps = "other/tensors,format=flexible,framerate=(fraction)30/1";

// One flexible memory: header for (type, dims) + payload bytes i*mul+add.
GstMemory *flex_memory(nns::TensorType type, nns::Dims dims, uint8_t mul, uint8_t add,
                       std::vector<uint8_t> *payload_out = nullptr) {
  nns::MetaHeader h;
  h.type = type;
  h.dims = dims;
  h.format = nns::TensorFormat::kFlexible;
  const std::size_t n = h.payload_size();
  std::vector<uint8_t> bytes(nns::kMetaHeaderSize + n);
  nns::write_meta_header(h, bytes.data());
  for (std::size_t i = 0; i < n; ++i)
    bytes[nns::kMetaHeaderSize + i] = static_cast<uint8_t>(i * mul + add);
  if (payload_out) payload_out->assign(bytes.begin() + nns::kMetaHeaderSize, bytes.end());
  GstMemory *m = gst_allocator_alloc(nullptr, bytes.size(), nullptr);
  GstMapInfo w;
  gst_memory_map(m, &w, GST_MAP_WRITE);
  std::copy(bytes.begin(), bytes.end(), w.data);
  gst_memory_unmap(m, &w);
  return m;
}

std::vector<uint8_t> buffer_bytes(GstBuffer *b) {
  std::vector<uint8_t> v(gst_buffer_get_size(b));
  gst_buffer_extract(b, 0, v.data(), v.size());
  return v;
}

std::vector<uint8_t> memory_bytes(GstMemory *m) {
  GstMapInfo map;
  gst_memory_map(m, &map, GST_MAP_READ);
  std::vector<uint8_t> v(map.data, map.data + map.size);
  gst_memory_unmap(m, &map);
  return v;
}

std::string current_caps(GstPad *pad) {
  GstCaps *c = gst_pad_get_current_caps(pad);
  if (!c) return "";
  gchar *s = gst_caps_to_string(c);
  std::string r = s;
  g_free(s);
  gst_caps_unref(c);
  return r;
}

TEST(TensorDecoderFlexible, OctetStreamGetsPayloadsForChangingTensors) {
  HarnessPtr h(gst_harness_new_parse("tensor_decoder mode=octet_stream"));
  gst_harness_set_src_caps_str(h.get(), kFlexCaps);
  // Buffer 1: two tensors (uint8 4, float32 2:2); buffer 2: one int16 3:1:2.
  std::vector<uint8_t> a, b, c;
  GstBuffer *in1 = gst_buffer_new();
  gst_buffer_append_memory(in1, flex_memory(nns::TensorType::kUInt8, {4}, 3, 1, &a));
  gst_buffer_append_memory(in1, flex_memory(nns::TensorType::kFloat32, {2, 2}, 5, 7, &b));
  ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in1));
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(nullptr, out);
  std::vector<uint8_t> want = a;
  want.insert(want.end(), b.begin(), b.end());
  EXPECT_EQ(want, buffer_bytes(out));
  gst_buffer_unref(out);
  EXPECT_NE(std::string::npos, current_caps(h->sinkpad).find("application/octet-stream"));

  GstBuffer *in2 = gst_buffer_new();
  gst_buffer_append_memory(in2, flex_memory(nns::TensorType::kInt16, {3, 1, 2}, 11, 2, &c));
  ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in2));
  out = gst_harness_pull(h.get());
  ASSERT_NE(nullptr, out);
  EXPECT_EQ(c, buffer_bytes(out));
  gst_buffer_unref(out);
}

TEST(TensorDecoderFlexible, DirectVideoRenegotiatesWhenDimsChange) {
  HarnessPtr h(gst_harness_new_parse("tensor_decoder mode=direct_video"));
  gst_harness_set_src_caps_str(h.get(), kFlexCaps);
  std::vector<uint8_t> p1, p2;
  GstBuffer *in = gst_buffer_new();
  gst_buffer_append_memory(in, flex_memory(nns::TensorType::kUInt8, {3, 4, 2}, 1, 0, &p1));
  ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in));
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(nullptr, out);
  EXPECT_EQ(p1, buffer_bytes(out));
  gst_buffer_unref(out);
  std::string caps = current_caps(h->sinkpad);
  EXPECT_NE(std::string::npos, caps.find("width=(int)4")) << caps;
  EXPECT_NE(std::string::npos, caps.find("height=(int)2")) << caps;
  EXPECT_NE(std::string::npos, caps.find("RGB")) << caps;

  in = gst_buffer_new();
  gst_buffer_append_memory(in, flex_memory(nns::TensorType::kUInt8, {3, 8, 3}, 7, 1, &p2));
  ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in));
  out = gst_harness_pull(h.get());
  ASSERT_NE(nullptr, out);
  EXPECT_EQ(p2, buffer_bytes(out));
  gst_buffer_unref(out);
  caps = current_caps(h->sinkpad);
  EXPECT_NE(std::string::npos, caps.find("width=(int)8")) << caps;
  EXPECT_NE(std::string::npos, caps.find("height=(int)3")) << caps;
}

TEST(TensorDecoderFlexible, ImageLabelingReadsFlexibleScores) {
  const std::string dir = nns::test::make_temp_dir();
  const std::string labels = dir + "/labels.txt";
  std::ofstream(labels) << "zero\none\ntwo\nthree\n";
  HarnessPtr h(
      gst_harness_new_parse(("tensor_decoder mode=image_labeling option1=" + labels).c_str()));
  gst_harness_set_src_caps_str(h.get(), kFlexCaps);
  GstBuffer *in = gst_buffer_new();
  GstMemory *m = flex_memory(nns::TensorType::kUInt8, {4}, 0, 0);
  GstMapInfo w;
  gst_memory_map(m, &w, GST_MAP_WRITE);
  w.data[nns::kMetaHeaderSize + 2] = 200;  // "two" wins
  gst_memory_unmap(m, &w);
  gst_buffer_append_memory(in, m);
  ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in));
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(nullptr, out);
  std::vector<uint8_t> text = buffer_bytes(out);
  gst_buffer_unref(out);
  EXPECT_STREQ("two", std::string(text.begin(), text.end()).c_str());
}

// Flexible tensors -> protobuf bytes -> tensor_converter: as NNStreamer, the frame keeps each
// tensor's flexible header, so the converter gives back the same flexible tensors.
TEST(TensorDecoderFlexible, WireDecoderRoundTrip) {
  HarnessPtr h(gst_harness_new_parse("tensor_decoder mode=protobuf ! tensor_converter"));
  gst_harness_set_src_caps_str(h.get(), kFlexCaps);
  std::vector<uint8_t> a, b;
  GstBuffer *in = gst_buffer_new();
  gst_buffer_append_memory(in, flex_memory(nns::TensorType::kUInt16, {2, 3}, 9, 4, &a));
  gst_buffer_append_memory(in, flex_memory(nns::TensorType::kInt8, {5}, 3, 3, &b));
  ASSERT_EQ(GST_FLOW_OK, gst_harness_push(h.get(), in));
  GstBuffer *out = gst_harness_pull(h.get());
  ASSERT_NE(nullptr, out);
  ASSERT_EQ(2u, gst_buffer_n_memory(out));
  const std::vector<uint8_t> m0 = memory_bytes(gst_buffer_peek_memory(out, 0));
  const std::vector<uint8_t> m1 = memory_bytes(gst_buffer_peek_memory(out, 1));
  gst_buffer_unref(out);
  ASSERT_EQ(m0.size(), nns::kMetaHeaderSize + a.size());
  ASSERT_EQ(m1.size(), nns::kMetaHeaderSize + b.size());
  EXPECT_EQ(a, std::vector<uint8_t>(m0.begin() + nns::kMetaHeaderSize, m0.end()));
  EXPECT_EQ(b, std::vector<uint8_t>(m1.begin() + nns::kMetaHeaderSize, m1.end()));
  const nns::MetaHeader h0 = nns::parse_meta_header(m0.data(), m0.size());
  const nns::MetaHeader h1 = nns::parse_meta_header(m1.data(), m1.size());
  EXPECT_EQ(h0.type, nns::TensorType::kUInt16);
  EXPECT_TRUE(nns::dims_equal(h0.dims, nns::make_dims({2, 3})));
  EXPECT_EQ(h1.type, nns::TensorType::kInt8);
  std::string caps = current_caps(h->sinkpad);
  EXPECT_NE(std::string::npos, caps.find("flexible")) << caps;
}

std::string write_file(const std::string &name, const std::vector<uint8_t> &bytes) {
  const std::string path = nns::test::make_temp_dir() + "/" + name;
  std::ofstream(path, std::ios::binary)
      .write(reinterpret_cast<const char *>(bytes.data()),
             static_cast<std::streamsize>(bytes.size()));
  return path;
}

std::vector<uint8_t> flex_bytes(nns::TensorType type, nns::Dims dims) {
  GstMemory *m = flex_memory(type, dims, 1, 0);
  std::vector<uint8_t> v = memory_bytes(m);
  gst_memory_unref(m);
  return v;
}

nns::test::RunResult run_flex_file(const std::vector<uint8_t> &bytes) {
  const std::string path = write_file("flex.bin", bytes);
  return nns::test::run_pipeline("filesrc location=" + path +
                                 " num-buffers=1 ! other/tensors,format=flexible,framerate=0/1 ! "
                                 "tensor_decoder mode=octet_stream ! fakesink");
}

TEST(TensorDecoderFlexible, FileOfOneFlexibleTensorDecodes) {
  auto r = run_flex_file(flex_bytes(nns::TensorType::kUInt8, {16}));
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_FALSE(r.error) << r.error_text;
}

TEST(TensorDecoderFlexible, CorruptHeaderIsABusErrorNamingTensorAndField) {
  std::vector<uint8_t> bytes = flex_bytes(nns::TensorType::kUInt8, {16});
  bytes[8] = 77;  // type field
  auto r = run_flex_file(bytes);
  ASSERT_TRUE(r.error);
  EXPECT_NE(std::string::npos, r.error_text.find("tensordecoder")) << r.error_text;
  EXPECT_NE(std::string::npos, r.error_text.find("input tensor 0")) << r.error_text;
  EXPECT_NE(std::string::npos, r.error_text.find("type 77")) << r.error_text;

  bytes = flex_bytes(nns::TensorType::kUInt8, {16});
  bytes[0] ^= 0xff;  // magic
  r = run_flex_file(bytes);
  ASSERT_TRUE(r.error);
  EXPECT_NE(std::string::npos, r.error_text.find("input tensor 0")) << r.error_text;
  EXPECT_NE(std::string::npos, r.error_text.find("magic")) << r.error_text;

  bytes = flex_bytes(nns::TensorType::kUInt8, {16});
  bytes.erase(bytes.end() - 3, bytes.end());  // payload shorter than the header says
  r = run_flex_file(bytes);
  ASSERT_TRUE(r.error);
  EXPECT_NE(std::string::npos, r.error_text.find("input tensor 0")) << r.error_text;
  EXPECT_NE(std::string::npos, r.error_text.find("13 bytes after its header")) << r.error_text;
}

TEST(TensorDecoderFlexible, SparseHeaderIsRefusedWithAHint) {
  nns::MetaHeader h;
  h.type = nns::TensorType::kUInt8;
  h.dims = {4};
  h.format = nns::TensorFormat::kSparse;
  h.nnz = 1;
  std::vector<uint8_t> bytes(nns::kMetaHeaderSize + h.payload_size());
  nns::write_meta_header(h, bytes.data());
  auto r = run_flex_file(bytes);
  ASSERT_TRUE(r.error);
  EXPECT_NE(std::string::npos, r.error_text.find("tensor_sparse_dec")) << r.error_text;
}

}  // namespace

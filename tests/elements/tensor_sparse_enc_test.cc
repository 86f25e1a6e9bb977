// SPDX-License-Identifier: LGPL-2.1-only
// tensor_sparse_enc / tensor_sparse_dec: byte layout of encoded frames (golden), round trip of
// every type and multi-tensor frames, timestamps, caps, and bus errors for bad input.
#include <gtest/gtest.h>

#include <random>

#include "core/sparse.h"
#include "elements/cycle_check.h"
#include "elements/flow_harness.h"

namespace {

using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::Frame;
using nns::test::static_caps;

TEST(TensorSparseEnc, EncodesToUpstreamByteLayout) {
  AppPipeline p("appsrc name=src ! tensor_sparse_enc ! appsink name=out");
  p.set_caps("src", static_caps("4:2", "int16"));
  std::vector<int16_t> dense{0, 5, 0, 0, -3, 0, 0, 7};
  p.push("src", {{nns::test::bytes_of(dense)}, 40 * GST_MSECOND, 10 * GST_MSECOND});
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 1u);
  ASSERT_EQ(out[0].mems.size(), 1u);
  const Bytes &m = out[0].mems[0];
  // golden: header words then values 5,-3,7 (int16) then indices 1,4,7 (uint32)
  Bytes golden(128 + 6 + 12, 0);
  uint32_t words[22] = {0xfeedcced, 0xDE001000, 2, 4, 2};
  words[19] = 2;  // sparse
  words[20] = 4;  // media: tensor
  words[21] = 3;  // nnz
  std::memcpy(golden.data(), words, sizeof words);
  int16_t vals[3] = {5, -3, 7};
  uint32_t idx[3] = {1, 4, 7};
  std::memcpy(golden.data() + 128, vals, 6);
  std::memcpy(golden.data() + 134, idx, 12);
  EXPECT_EQ(m, golden);
  EXPECT_EQ(out[0].pts, 40 * GST_MSECOND);
  EXPECT_EQ(out[0].duration, 10 * GST_MSECOND);
  EXPECT_NE(out[0].caps.find("format=(string)sparse"), std::string::npos) << out[0].caps;
}

TEST(TensorSparseEnc, RoundTripEveryTypeMultiTensor) {
  const char *types[] = {"int32", "uint32",  "int16",   "uint16", "int8",
                         "uint8", "float64", "float32", "int64",  "uint64"};
  std::mt19937 rng(3);
  for (const char *t : types) {
    AppPipeline p("appsrc name=src ! tensor_sparse_enc ! tensor_sparse_dec ! appsink name=out");
    std::string tt = std::string(t) + ",uint8";
    p.set_caps("src", static_caps("3:4:2,5", tt, "30/1"));
    std::size_t esize = nns::type_size(nns::parse_type(t));
    std::vector<Frame> in;
    for (int f = 0; f < 3; ++f) {
      Bytes a(24 * esize, 0), b(5, 0);
      for (std::size_t i = 0; i < 24; ++i)
        if (rng() % 2) a[i * esize] = static_cast<uint8_t>(1 + rng() % 100);
      b[f] = 9;
      in.push_back({{a, b}, static_cast<GstClockTime>(f) * 33 * GST_MSECOND});
      p.push("src", in.back());
    }
    p.eos("src");
    auto r = p.run();
    ASSERT_TRUE(r.eos) << t << ": " << r.error_text;
    auto out = p.frames("out");
    ASSERT_EQ(out.size(), 3u) << t;
    for (int f = 0; f < 3; ++f) {
      EXPECT_EQ(out[f].mems, in[f].mems) << t << " frame " << f;
      EXPECT_EQ(out[f].pts, in[f].pts);
    }
    EXPECT_NE(out[0].caps.find("dimensions=(string)\"3:4:2\\,5\""), std::string::npos)
        << out[0].caps;
    EXPECT_NE(out[0].caps.find("types=(string)\"" + std::string(t) + "\\,uint8\""),
              std::string::npos)
        << out[0].caps;
    EXPECT_NE(out[0].caps.find("framerate=(fraction)30/1"), std::string::npos) << out[0].caps;
  }
}

TEST(TensorSparseEnc, VideoRoundTripThroughGstLaunch) {
  auto direct = nns::test::run_pipeline(
      "videotestsrc num-buffers=3 pattern=ball ! video/x-raw,format=GRAY8,width=32,height=24 ! "
      "tensor_converter ! tensor_sparse_enc ! tensor_sparse_dec ! "
      "other/tensors,format=static,dimensions=(string)1:32:24:1,types=(string)uint8 ! "
      "fakesink");
  EXPECT_TRUE(direct.eos) << direct.error_text;
}

TEST(TensorSparseDec, CorruptSparseMemoryIsABusError) {
  AppPipeline p("appsrc name=src ! tensor_sparse_dec name=dec ! appsink name=out");
  p.set_caps("src", "other/tensors,format=sparse,framerate=(fraction)0/1");
  nns::TensorInfo t{"", nns::TensorType::kUInt8, nns::make_dims({4})};
  Bytes dense{0, 1, 0, 2};
  Bytes enc = nns::sparse_encode(t, dense.data());
  enc.pop_back();  // truncated
  p.push("src", {{enc}, 0});
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("dec: tensor 0: sparse tensor memory has 137 bytes, expected 138"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorSparseDec, ShapeChangeAgainstFixedDownstreamIsABusError) {
  AppPipeline p(
      "appsrc name=src ! tensor_sparse_dec name=dec ! "
      "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=(string)uint8 ! "
      "appsink name=out");
  p.set_caps("src", "other/tensors,format=sparse,framerate=(fraction)0/1");
  nns::TensorInfo t{"", nns::TensorType::kUInt8, nns::make_dims({4})};
  Bytes d4{0, 1, 0, 2};
  p.push("src", {{nns::sparse_encode(t, d4.data())}, 0});
  nns::TensorInfo t5{"", nns::TensorType::kUInt8, nns::make_dims({5})};
  Bytes d5{0, 1, 0, 2, 3};
  p.push("src", {{nns::sparse_encode(t5, d5.data())}, GST_MSECOND});
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("decoded tensors"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("uint8 5"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("uint8 4"), std::string::npos) << r.error_text;
  EXPECT_EQ(p.frames("out").size(), 1u);
}

TEST(TensorSparseEnc, WrongBufferSizeIsABusError) {
  AppPipeline p("appsrc name=src ! tensor_sparse_enc name=enc ! appsink name=out");
  p.set_caps("src", static_caps("4", "float32"));
  p.push("src", {{Bytes(12, 0)}, 0});
  p.eos("src");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("enc: tensor 0 has 12 bytes, expected 16 for float32 4"),
            std::string::npos)
      << r.error_text;
}

// 100 PLAYING<->NULL cycles of tensor_sparse_enc ! tensor_sparse_dec; odd cycles end with EOS.
// No hang, nothing left alive.
TEST(TensorSparseEnc, EncDecHundredPlayingNullCyclesNoHangNoLeak) {
  AppPipeline p("appsrc name=src ! tensor_sparse_enc ! tensor_sparse_dec ! fakesink name=out");
  p.set_caps("src", static_caps("4:2,3", "int16,uint8", "30/1"));
  std::vector<int16_t> dense{0, 5, 0, 0, -3, 0, 0, 7};
  nns::test::state_cycles(p.pipeline(), 100, [&](int i, nns::test::LiveObjects &live) {
    std::size_t before = live.delivered("out");
    p.push("src", {{nns::test::bytes_of(dense), Bytes{0, 1, 0}}, 0});
    p.push("src", {{nns::test::bytes_of(dense), Bytes{2, 0, 0}}, 33 * GST_MSECOND});
    if (i % 2) {
      p.eos("src");
      std::string err;
      EXPECT_TRUE(nns::test::wait_eos(p.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
    }
    EXPECT_TRUE(live.wait_delivered("out", before + 2)) << "cycle " << i;
  });
}

TEST(TensorSparseEnc, PropertiesAsUpstream) {
  for (const char *name : {"tensor_sparse_enc", "tensor_sparse_dec"}) {
    GstElement *e = gst_element_factory_make(name, nullptr);
    ASSERT_NE(e, nullptr) << name;
    gboolean silent = FALSE;
    g_object_get(e, "silent", &silent, nullptr);
    EXPECT_TRUE(silent);
    gst_object_unref(e);
  }
}

}  // namespace

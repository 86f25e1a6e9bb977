// SPDX-License-Identifier: LGPL-2.1-only
// tensor_transform behaviours matched to NNStreamer 2.x: the legacy single-tensor other/tensor
// caps on either side in every mode, flexible input in every mode, arithmetic add:A:B without
// per-channel (first value, warning), caps honesty (a capsfilter asking for a type the mode does
// not make fails, naming both), and PLAYING with default properties (no mode yet).
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "core/meta_header.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

namespace {

using nns::test::HarnessPtr;
using nns::test::run_pipeline;
using Bytes = std::vector<uint8_t>;

struct ModeCase {
  const char *mode;
  const char *option;
};

// Every mode, with an option valid for a uint8 10:1:1:1 tensor.
const ModeCase kModes[] = {
    {"dimchg", "0:1"},        {"typecast", "float32"}, {"arithmetic", "add:1"},
    {"transpose", "1:0:2:3"}, {"stand", "default"},    {"clamp", "0:5"},
    {"padding", "left:1"},
};

GstBuffer *buffer_of(const Bytes &b) {
  GstBuffer *buf = gst_buffer_new_allocate(nullptr, b.size(), nullptr);
  gst_buffer_fill(buf, 0, b.data(), b.size());
  return buf;
}

Bytes bytes_of(GstBuffer *b) {
  Bytes v(gst_buffer_get_size(b));
  gst_buffer_extract(b, 0, v.data(), v.size());
  return v;
}

std::string current_caps(GstPad *pad) {
  nns::gst::CapsPtr c(gst_pad_get_current_caps(pad));
  return c ? nns::gst::caps_to_string(c.get()) : "";
}

HarnessPtr transform_harness(const ModeCase &m) {
  HarnessPtr h(gst_harness_new("tensor_transform"));
  gst_util_set_object_arg(G_OBJECT(h->element), "mode", m.mode);
  g_object_set(h->element, "option", m.option, nullptr);
  return h;
}

// Pops the first message of `type` from `bus` and returns its text ("" if none).
std::string pop_text(GstBus *bus, GstMessageType type) {
  nns::gst::MessagePtr msg(gst_bus_pop_filtered(bus, type));
  if (!msg) return "";
  GError *err = nullptr;
  if (type == GST_MESSAGE_ERROR)
    gst_message_parse_error(msg.get(), &err, nullptr);
  else
    gst_message_parse_warning(msg.get(), &err, nullptr);
  std::string text = err->message;
  g_error_free(err);
  return text;
}

const char *kSrc10 =
    "videotestsrc num-buffers=1 ! video/x-raw,format=GRAY8,width=10,height=1 ! tensor_converter";

}  // namespace

TEST(TensorTransformCompat, LegacyTensorInputEveryMode) {
  for (const ModeCase &m : kModes) {
    SCOPED_TRACE(m.mode);
    HarnessPtr h = transform_harness(m);
    gst_harness_set_src_caps_str(h.get(),
                                 "other/tensor,type=uint8,dimension=10:1:1:1,framerate=0/1");
    Bytes in = {0, 1, 2, 3, 4, 5, 6, 7, 8, 9};
    ASSERT_EQ(gst_harness_push(h.get(), buffer_of(in)), GST_FLOW_OK);
    nns::gst::BufferPtr out(gst_harness_pull(h.get()));
    ASSERT_TRUE(out);
    EXPECT_GT(gst_buffer_get_size(out.get()), 0u);
    EXPECT_NE(current_caps(h->sinkpad).find("other/tensor"), std::string::npos);
  }
}

TEST(TensorTransformCompat, LegacyTensorOutputWhenDownstreamAsksEveryMode) {
  for (const ModeCase &m : kModes) {
    SCOPED_TRACE(m.mode);
    auto r = run_pipeline(std::string(kSrc10) + " ! tensor_transform mode=" + m.mode +
                          " option=" + m.option + " ! other/tensor ! fakesink");
    EXPECT_TRUE(r.eos) << r.error_text;
    // And from a legacy source caps.
    r = run_pipeline(std::string(kSrc10) + " ! other/tensor ! tensor_transform mode=" + m.mode +
                     " option=" + m.option + " ! other/tensor ! fakesink");
    EXPECT_TRUE(r.eos) << r.error_text;
  }
  // The negotiated src caps are the legacy ones, with the typecast's type.
  HarnessPtr h = transform_harness({"typecast", "float32"});
  gst_harness_set_sink_caps_str(h.get(), "other/tensor");
  gst_harness_set_src_caps_str(
      h.get(),
      "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=10:1:1:1,"
      "framerate=0/1");
  ASSERT_EQ(gst_harness_push(h.get(), buffer_of(Bytes(10, 2))), GST_FLOW_OK);
  nns::gst::BufferPtr out(gst_harness_pull(h.get()));
  ASSERT_TRUE(out);
  EXPECT_EQ(gst_buffer_get_size(out.get()), 40u);
  const std::string caps = current_caps(h->sinkpad);
  EXPECT_EQ(caps.rfind("other/tensor,", 0), 0u) << caps;
  EXPECT_NE(caps.find("float32"), std::string::npos) << caps;
}

// A flexible stream (as a capsfilter after tensor_converter makes it) links and flows in every
// mode; typecast rewrites the header's type.
TEST(TensorTransformCompat, FlexibleInputEveryMode) {
  for (const ModeCase &m : kModes) {
    SCOPED_TRACE(m.mode);
    auto r = run_pipeline(std::string(kSrc10) +
                          " ! other/tensors,format=flexible ! tensor_transform mode=" + m.mode +
                          " option=" + m.option + " ! fakesink");
    EXPECT_TRUE(r.eos) << r.error_text;
  }
  HarnessPtr h = transform_harness({"typecast", "float32"});
  gst_harness_set_src_caps_str(h.get(), "other/tensors,format=flexible,framerate=0/1");
  nns::MetaHeader hd;
  hd.type = nns::TensorType::kUInt8;
  hd.dims = nns::make_dims({3});
  hd.format = nns::TensorFormat::kFlexible;
  Bytes mem(nns::kMetaHeaderSize + 3);
  nns::write_meta_header(hd, mem.data());
  mem[128] = 1, mem[129] = 2, mem[130] = 250;
  ASSERT_EQ(gst_harness_push(h.get(), buffer_of(mem)), GST_FLOW_OK);
  nns::gst::BufferPtr out(gst_harness_pull(h.get()));
  ASSERT_TRUE(out);
  Bytes got = bytes_of(out.get());
  ASSERT_EQ(got.size(), nns::kMetaHeaderSize + 12);
  EXPECT_EQ(nns::parse_meta_header(got.data(), got.size()).type, nns::TensorType::kFloat32);
  float f[3];
  std::memcpy(f, got.data() + nns::kMetaHeaderSize, sizeof f);
  EXPECT_EQ(f[0], 1.0f);
  EXPECT_EQ(f[1], 2.0f);
  EXPECT_EQ(f[2], 250.0f);
}

// Upstream reads only A from add:A:B without per-channel; ours too, with a bus warning.
TEST(TensorTransformCompat, ArithmeticSeveralValuesWithoutPerChannelTakesTheFirst) {
  HarnessPtr h = transform_harness({"arithmetic", "add:5:2"});
  GstBus *bus = gst_bus_new();
  gst_element_set_bus(h->element, bus);
  gst_harness_set_src_caps_str(
      h.get(),
      "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)4,framerate=0/1");
  ASSERT_EQ(gst_harness_push(h.get(), buffer_of({1, 2, 3, 4})), GST_FLOW_OK);
  nns::gst::BufferPtr out(gst_harness_pull(h.get()));
  ASSERT_TRUE(out);
  EXPECT_EQ(bytes_of(out.get()), (Bytes{6, 7, 8, 9}));
  const std::string w = pop_text(bus, GST_MESSAGE_WARNING);
  EXPECT_NE(w.find("'add:5:2' has 2 values"), std::string::npos) << w;
  EXPECT_NE(w.find("only the first (5) is used"), std::string::npos) << w;
  gst_element_set_bus(h->element, nullptr);
  gst_object_unref(bus);
}

// A capsfilter asking for a type the mode does not make must not negotiate a flexible stream
// whose caps say uint8 while the data is float32: a negotiation error names both types.
TEST(TensorTransformCompat, CapsfilterAskingAnotherTypeFailsNamingBoth) {
  auto r = run_pipeline(std::string(kSrc10) +
                        " ! tensor_transform name=tt mode=typecast option=float32 ! "
                        "other/tensors,types=uint8 ! fakesink");
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_EQ(r.error_source, "tt");
  EXPECT_NE(r.error_text.find("types=uint8"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("makes float32"), std::string::npos) << r.error_text;
  // Same with dimensions.
  r = run_pipeline(std::string(kSrc10) +
                   " ! tensor_transform name=tt mode=dimchg option=0:1 ! "
                   "other/tensors,dimensions=(string)5:2 ! fakesink");  // converter: 1:10:1:1
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_NE(r.error_text.find("dimensions=5:2"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("makes 10:1:1:1"), std::string::npos) << r.error_text;
  // A matching request still negotiates (static).
  r = run_pipeline(std::string(kSrc10) +
                   " ! tensor_transform mode=typecast option=float32 ! "
                   "other/tensors,types=float32 ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

// Created and PLAYING with default properties, configured afterwards (GstHarness tests do so).
TEST(TensorTransformCompat, PlayingWithoutModeThenConfigured) {
  const char *caps =
      "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=(string)4,framerate=0/1";
  {
    HarnessPtr h(gst_harness_new("tensor_transform"));
    EXPECT_NE(gst_element_set_state(h->element, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
    gst_util_set_object_arg(G_OBJECT(h->element), "mode", "arithmetic");
    g_object_set(h->element, "option", "mul:2", nullptr);
    gst_harness_set_src_caps_str(h.get(), caps);
    ASSERT_EQ(gst_harness_push(h.get(), buffer_of({1, 2, 3, 4})), GST_FLOW_OK);
    nns::gst::BufferPtr out(gst_harness_pull(h.get()));
    ASSERT_TRUE(out);
    EXPECT_EQ(bytes_of(out.get()), (Bytes{2, 4, 6, 8}));
  }
  HarnessPtr h(gst_harness_new("tensor_transform"));
  GstBus *bus = gst_bus_new();
  gst_element_set_bus(h->element, bus);
  EXPECT_NE(gst_element_set_state(h->element, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  gst_harness_set_src_caps_str(h.get(), caps);
  EXPECT_NE(gst_harness_push(h.get(), buffer_of({1, 2, 3, 4})), GST_FLOW_OK);
  const std::string e = pop_text(bus, GST_MESSAGE_ERROR);
  EXPECT_NE(e.find("property 'mode' is not set"), std::string::npos) << e;
  gst_element_set_bus(h->element, nullptr);
  gst_object_unref(bus);
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_transform behaviours NNStreamer's own unit tests check (tests/nnstreamer_plugins):
// an option invalid for the current mode is refused when set (`option` reads back the previous
// value, NULL at first) and the start then posts an error naming the refused text; a typecast
// given last in an arithmetic option is ignored; accelerated and reference paths give the same
// bytes; the option may change between buffers.
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include <cstring>
#include <string>
#include <vector>

#include "support/harness.h"

namespace {

using nns::test::HarnessPtr;

// Upstream's enum values (gtt_mode_type).
enum { kDimchg = 0, kTypecast = 1, kArithmetic = 2, kTranspose = 3, kStand = 4, kClamp = 5 };

std::string option_of(GstElement *e) {
  gchar *s = nullptr;
  g_object_get(e, "option", &s, nullptr);
  std::string out = s ? s : "<NULL>";
  g_free(s);
  return out;
}

struct BadOption {
  int mode;
  const char *option;
};

// The invalid options of upstream's *Properties*_n tests.
const BadOption kBad[] = {
    {kDimchg, "20:21"},
    {kDimchg, "1,2"},
    {kDimchg, "0:2,1:3"},
    {kArithmetic, "typecast"},
    {kArithmetic, "typecast:unknown"},
    {kArithmetic, "typecast:char"},
    {kArithmetic, "typecast:double"},
    {kArithmetic, "add:0xF"},
    {kArithmetic, "add:1U"},
    {kArithmetic, "+2"},
    {kArithmetic, "*2"},
    {kArithmetic, "/2"},
    {kArithmetic, "max"},
    {kArithmetic, "per-channel:false"},
    {kArithmetic, "per-channel:invalid,add:1@2"},
    {kTranspose, "5:2:4:3"},
    {kTranspose, "2:3:1:0"},
    {kTranspose, "0:3"},
    {kClamp, "50:20"},
    {kClamp, "+-1"},
    {kClamp, "+1:-2"},
    {kClamp, "1:1.7e309"},
    {kClamp, "-1.7e309:1"},
    {kStand, "invalid"},
    {kStand, "dc-average:unknown"},
    {kStand, "dc-average,per-channel"},
    {kStand, "dc-average:uint8,per-channel:yes"},
    {kStand, "dc-average:uint8,true"},
};

TEST(TensorTransformUpstream, InvalidOptionIsRefusedWhenSet) {
  for (const auto &b : kBad) {
    SCOPED_TRACE(std::string("mode ") + std::to_string(b.mode) + " option " + b.option);
    HarnessPtr h(gst_harness_new("tensor_transform"));
    ASSERT_TRUE(h);
    g_object_set(h->element, "mode", b.mode, "option", b.option, nullptr);
    EXPECT_EQ(option_of(h->element), "<NULL>");
  }
}

TEST(TensorTransformUpstream, RefusedOptionKeepsThePreviousOne) {
  HarnessPtr h(gst_harness_new("tensor_transform"));
  g_object_set(h->element, "mode", kDimchg, "option", "0:2", nullptr);
  EXPECT_EQ(option_of(h->element), "0:2");
  g_object_set(h->element, "option", "20:21", nullptr);
  EXPECT_EQ(option_of(h->element), "0:2");
  // Without a mode the option is not checked yet (gst-launch may set it before the mode).
  HarnessPtr h2(gst_harness_new("tensor_transform"));
  g_object_set(h2->element, "option", "20:21", nullptr);
  EXPECT_EQ(option_of(h2->element), "20:21");
}

TEST(TensorTransformUpstream, StartPostsAnErrorNamingTheRefusedOption) {
  auto r = nns::test::run_pipeline(
      "fakesrc num-buffers=1 sizetype=fixed sizemax=4 ! "
      "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8,framerate=0/1 ! "
      "tensor_transform name=tt mode=dimchg option=20:21 ! fakesink");
  ASSERT_TRUE(r.error) << "no error (eos=" << r.eos << ")";
  EXPECT_EQ(r.error_source, "tt");
  for (const char *f : {"tt: ", "property 'option' '20:21'", "mode=dimchg", "0..15",
                        "refused when set", "kept no value"})
    EXPECT_NE(r.error_text.find(f), std::string::npos) << "'" << f << "' not in: " << r.error_text;
  // With a valid option before it, the message says which one is kept.
  r = nns::test::run_pipeline(
      "fakesrc num-buffers=1 sizetype=fixed sizemax=4 ! "
      "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8,framerate=0/1 ! "
      "tensor_transform name=tt mode=clamp option=0:1 option=50:20 ! fakesink");
  ASSERT_TRUE(r.error);
  for (const char *f : {"'50:20'", "MIN '50' is larger than MAX '20'", "kept '0:1'"})
    EXPECT_NE(r.error_text.find(f), std::string::npos) << "'" << f << "' not in: " << r.error_text;
}

GstBuffer *u8_buffer(const std::vector<uint8_t> &v) {
  GstBuffer *buf = gst_buffer_new_allocate(nullptr, v.size(), nullptr);
  gst_buffer_fill(buf, 0, v.data(), v.size());
  return buf;
}

// Upstream's arithmetic4 / arithmetic4Accel: uint8 in, float64 out, the final typecast ignored.
std::vector<std::vector<uint8_t>> run_arithmetic4(bool acceleration) {
  HarnessPtr h(gst_harness_new("tensor_transform"));
  g_object_set(h->element, "mode", kArithmetic, "option",
               "typecast:float64,add:0.2,add:0.1,typecast:uint16", nullptr);
  g_object_set(h->element, "acceleration", acceleration, nullptr);
  EXPECT_EQ(option_of(h->element), "typecast:float64,add:0.2,add:0.1,typecast:uint16");
  gst_harness_set_src_caps_str(
      h.get(),
      "other/tensors,format=static,num_tensors=1,dimensions=(string)5,types=uint8,framerate=0/1");
  std::vector<std::vector<uint8_t>> outs;
  for (int b = 0; b < 3; ++b) {
    std::vector<uint8_t> in(5);
    for (int i = 0; i < 5; ++i) in[i] = static_cast<uint8_t>((i + 1) * (b + 1));
    EXPECT_EQ(gst_harness_push(h.get(), u8_buffer(in)), GST_FLOW_OK);
    GstBuffer *out = gst_harness_pull(h.get());
    EXPECT_TRUE(out);
    if (!out) break;
    EXPECT_EQ(gst_buffer_n_memory(out), 1u);
    EXPECT_EQ(gst_buffer_get_size(out), 5 * sizeof(double));
    std::vector<uint8_t> bytes(gst_buffer_get_size(out));
    gst_buffer_extract(out, 0, bytes.data(), bytes.size());
    gst_buffer_unref(out);
    for (int i = 0; i < 5 && bytes.size() == 5 * sizeof(double); ++i) {
      double v;
      std::memcpy(&v, bytes.data() + i * sizeof(double), sizeof v);
      EXPECT_DOUBLE_EQ(v, (i + 1) * (b + 1) + .3);
    }
    outs.push_back(std::move(bytes));
  }
  GstCaps *caps = gst_pad_get_current_caps(h->sinkpad);  // the element's output
  EXPECT_TRUE(caps);
  if (caps) {
    const gchar *types = gst_structure_get_string(gst_caps_get_structure(caps, 0), "types");
    EXPECT_STREQ(types, "float64");
    gst_caps_unref(caps);
  }
  EXPECT_EQ(gst_harness_buffers_received(h.get()), 3u);
  return outs;
}

TEST(TensorTransformUpstream, LastTypecastIsIgnoredAndAccelerationGivesTheSameBytes) {
  auto plain = run_arithmetic4(false);
  auto accel = run_arithmetic4(true);
  EXPECT_EQ(plain, accel);
}

TEST(TensorTransformUpstream, LastTypecastIgnoredIsAWarning) {
  auto r = nns::test::run_pipeline(
      "fakesrc num-buffers=1 sizetype=fixed sizemax=4 ! "
      "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8,framerate=0/1 ! "
      "tensor_transform name=tt mode=arithmetic option=typecast:float32,add:1,typecast:uint16 ! "
      "other/tensors,types=float32 ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_NE(r.warning_text.find("'typecast:uint16' is ignored"), std::string::npos)
      << r.warning_text;
}

// Upstream's arithmeticChangeOptionString: add:.5, then mul:20 set between buffers.
TEST(TensorTransformUpstream, ChangeOptionStringBetweenBuffers) {
  HarnessPtr h(gst_harness_new("tensor_transform"));
  g_object_set(h->element, "mode", kArithmetic, "option", "add:.5", nullptr);
  g_object_set(h->element, "acceleration", FALSE, nullptr);
  gst_harness_set_src_caps_str(
      h.get(),
      "other/tensors,format=static,num_tensors=1,dimensions=(string)5,types=float32,framerate=0/1");
  auto push = [&](float offset) {
    std::vector<float> in(5);
    for (int i = 0; i < 5; ++i) in[i] = static_cast<float>((i + 1) * (i * 3 + 1) + offset);
    GstBuffer *buf = gst_buffer_new_allocate(nullptr, sizeof(float) * 5, nullptr);
    gst_buffer_fill(buf, 0, in.data(), sizeof(float) * 5);
    EXPECT_EQ(gst_harness_push(h.get(), buf), GST_FLOW_OK);
    GstBuffer *out = gst_harness_pull(h.get());
    std::vector<float> res(5);
    if (out) {
      EXPECT_EQ(gst_buffer_get_size(out), sizeof(float) * 5);
      gst_buffer_extract(out, 0, res.data(), sizeof(float) * 5);
      gst_buffer_unref(out);
    }
    return res;
  };
  auto a = push(.2f);
  for (int i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(a[i], (i + 1) * (i * 3 + 1) + .2f + .5f);
  g_object_set(h->element, "mode", kArithmetic, "option", "mul:20", nullptr);
  auto m = push(.9f);
  for (int i = 0; i < 5; ++i) EXPECT_FLOAT_EQ(m[i], ((i + 1) * (i * 3 + 1) + .9f) * 20);
  EXPECT_EQ(gst_harness_buffers_received(h.get()), 2u);
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// Decorated flexible caps (other/tensors,format=flexible with num_tensors / types / dimensions,
// as a capsfilter leaves them: gst/tensor_caps.h) through the pass-through elements, in
// GstHarness: tensor_mux (flexible output when downstream asks for it, decorations checked
// against static inputs at negotiation and against flexible inputs' headers per frame),
// tensor_debug (accepted and propagated both ways, headers that contradict them reported) and
// tensor_rate (static streams only, as NNStreamer's: flexible caps, decorated or not, refused).
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include "core/meta_header.h"
#include "elements/stream_util.h"
#include "gst/tensor_caps.h"

namespace nns::test {
namespace {

const char *kU8x4 =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8,framerate=30/1";

// A harness around `factory` (sink pad `sink`) with a bus that keeps its messages.
struct Elem {
  GstElement *e = nullptr;
  GstBus *bus = nullptr;
  HarnessPtr h;
  Elem(const char *factory, const char *sink, const char *props = nullptr) {
    e = props ? gst_parse_launch((std::string(factory) + " " + props).c_str(), nullptr)
              : gst_element_factory_make(factory, nullptr);
    bus = gst_bus_new();
    gst_element_set_bus(e, bus);
    h.reset(gst_harness_new_with_element(e, sink, "src"));
  }
  ~Elem() {
    gst_bus_set_flushing(bus, TRUE);
    h.reset();
    gst_object_unref(e);
    gst_object_unref(bus);
  }
  std::string messages(GstMessageType type) {
    std::string out;
    while (GstMessage *m = gst_bus_pop_filtered(bus, type)) {
      GError *err = nullptr;
      gchar *dbg = nullptr;
      if (type == GST_MESSAGE_ERROR)
        gst_message_parse_error(m, &err, &dbg);
      else
        gst_message_parse_warning(m, &err, &dbg);
      out += err->message;
      out += "\n";
      g_error_free(err);
      g_free(dbg);
      gst_message_unref(m);
    }
    return out;
  }
};

// One flexible tensor: header (type, dims) + payload.
std::vector<uint8_t> flex_tensor(TensorType type, std::initializer_list<uint32_t> dims,
                                 std::vector<uint8_t> payload) {
  MetaHeader h;
  h.type = type;
  h.dims = make_dims(dims);
  h.format = TensorFormat::kFlexible;
  std::vector<uint8_t> t(kMetaHeaderSize);
  write_meta_header(h, t.data());
  t.insert(t.end(), payload.begin(), payload.end());
  return t;
}

std::string current_caps(GstPad *pad) {
  GstCaps *c = gst_pad_get_current_caps(pad);
  std::string s = nns::gst::caps_to_string(c);
  if (c) gst_caps_unref(c);
  return s;
}

// Caps the element's sink pad answers to a query (what it tells upstream).
std::string sink_query_caps(GstElement *e) {
  GstPad *pad = gst_element_get_static_pad(e, "sink");
  GstCaps *c = gst_pad_query_caps(pad, nullptr);
  gst_object_unref(pad);
  std::string s = nns::gst::caps_to_string(c);
  gst_caps_unref(c);
  return s;
}

}  // namespace

// ---- tensor_mux ---------------------------------------------------------------------------

// Static inputs, downstream that takes flexible tensors only: NNStreamer's tensor_mux then
// outputs flexible tensors (each with its 128-byte header).
TEST(DecoratedCapsMux, StaticInputsFlexibleDownstreamGetHeaders) {
  Elem m("tensor_mux", "sink_0", "sync-mode=nosync");
  gst_harness_set_sink_caps_str(m.h.get(), "other/tensors,format=flexible");
  gst_harness_set_src_caps_str(m.h.get(), kU8x4);
  ASSERT_EQ(gst_harness_push(m.h.get(), make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK)
      << m.messages(GST_MESSAGE_ERROR);
  GstBuffer *out = gst_harness_pull(m.h.get());
  ASSERT_NE(out, nullptr);
  auto t = tensor_bytes(out, 0);
  gst_buffer_unref(out);
  ASSERT_EQ(t.size(), kMetaHeaderSize + 4);
  MetaHeader h = parse_meta_header(t.data(), t.size());
  EXPECT_EQ(h.type, TensorType::kUInt8);
  EXPECT_EQ(dims_to_string(h.dims), "4");
  EXPECT_EQ(t[kMetaHeaderSize + 3], 4);
  EXPECT_EQ(current_caps(m.h->sinkpad),
            "other/tensors, format=(string)flexible, "
            "framerate=(fraction)30/1");
}

// Decorations that describe what the static inputs make are kept in the output caps.
TEST(DecoratedCapsMux, MatchingDecorationIsAcceptedAndKept) {
  Elem m("tensor_mux", "sink_0", "sync-mode=nosync");
  GstHarness *h1 = gst_harness_new_with_element(m.e, "sink_1", nullptr);
  HarnessPtr hp1(h1);
  gst_harness_set_sink_caps_str(
      m.h.get(), "other/tensors,format=flexible,num_tensors=2,types=(string)\"uint8,float32\"");
  gst_harness_set_src_caps_str(m.h.get(), kU8x4);
  gst_harness_set_src_caps_str(h1,
                               "other/tensors,format=static,num_tensors=1,dimensions=(string)2,"
                               "types=float32,framerate=30/1");
  ASSERT_EQ(gst_harness_push(m.h.get(), make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(h1, make_buffer({std::vector<uint8_t>(8, 0)}, 0)), GST_FLOW_OK)
      << m.messages(GST_MESSAGE_ERROR);
  GstBuffer *out = gst_harness_pull(m.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_n_memory(out), 2u);
  EXPECT_EQ(gst_buffer_get_size(out), 2 * kMetaHeaderSize + 4 + 8);
  gst_buffer_unref(out);
  EXPECT_EQ(current_caps(m.h->sinkpad),
            "other/tensors, format=(string)flexible, framerate=(fraction)30/1, "
            "num_tensors=(int)2, types=(string)\"uint8\\,float32\"");
}

// Decorations that contradict the static inputs fail negotiation, naming both.
TEST(DecoratedCapsMux, ContradictingDecorationFailsNamingBoth) {
  Elem m("tensor_mux", "sink_0", "sync-mode=nosync");
  gst_harness_set_sink_caps_str(m.h.get(),
                                "other/tensors,format=flexible,num_tensors=1,types=float32");
  gst_harness_set_src_caps_str(m.h.get(), kU8x4);
  EXPECT_NE(gst_harness_push(m.h.get(), make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  std::string err = m.messages(GST_MESSAGE_ERROR);
  EXPECT_NE(err.find("say types=float32, but sink_0 give uint8"), std::string::npos) << err;
  EXPECT_NE(err.find("format=(string)flexible"), std::string::npos) << err;
  // dimensions too
  Elem d("tensor_mux", "sink_0", "sync-mode=nosync");
  gst_harness_set_sink_caps_str(d.h.get(), "other/tensors,format=flexible,dimensions=(string)3:2");
  gst_harness_set_src_caps_str(d.h.get(), kU8x4);
  EXPECT_NE(gst_harness_push(d.h.get(), make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  err = d.messages(GST_MESSAGE_ERROR);
  EXPECT_NE(err.find("say dimensions=3:2, but sink_0 give 4"), std::string::npos) << err;
}

// Flexible inputs: what the tensors are is known from each frame's headers only; a frame that
// contradicts downstream's decorations is a stream error naming the pads and both values.
TEST(DecoratedCapsMux, FlexibleInputsAreCheckedPerFrame) {
  for (const char *types : {"int8", "uint8"}) {
    SCOPED_TRACE(types);
    Elem m("tensor_mux", "sink_0", "sync-mode=nosync");
    gst_harness_set_sink_caps_str(
        m.h.get(), (std::string("other/tensors,format=flexible,types=") + types).c_str());
    // The input's own caps may carry decorations too: accepted on the sink pad.
    gst_harness_set_src_caps_str(m.h.get(),
                                 "other/tensors,format=flexible,num_tensors=1,"
                                 "types=int8,dimensions=(string)2,framerate=30/1");
    auto t = flex_tensor(TensorType::kInt8, {2}, {7, 9});
    GstFlowReturn ret = gst_harness_push(m.h.get(), make_buffer({t}, 0));
    if (std::string(types) == "int8") {
      ASSERT_EQ(ret, GST_FLOW_OK) << m.messages(GST_MESSAGE_ERROR);
      GstBuffer *out = gst_harness_pull(m.h.get());
      ASSERT_NE(out, nullptr);
      EXPECT_EQ(tensor_bytes(out, 0), t);  // passed on unchanged
      gst_buffer_unref(out);
    } else {
      EXPECT_NE(ret, GST_FLOW_OK);
      std::string err = m.messages(GST_MESSAGE_ERROR);
      EXPECT_NE(err.find("say types=uint8, but the frame from sink_0 carries int8"),
                std::string::npos)
          << err;
    }
  }
}

// Without a flexible downstream, static inputs stay static (no headers).
TEST(DecoratedCapsMux, StaticStaysStaticForAnyDownstream) {
  Elem m("tensor_mux", "sink_0", "sync-mode=nosync");
  gst_harness_set_src_caps_str(m.h.get(), kU8x4);
  ASSERT_EQ(gst_harness_push(m.h.get(), make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(m.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_get_size(out), 4u);
  gst_buffer_unref(out);
  EXPECT_EQ(current_caps(m.h->sinkpad).rfind("other/tensors, format=(string)static", 0), 0u);
}

// ---- tensor_debug -------------------------------------------------------------------------

const char *kDecoratedInt8 =
    "other/tensors,format=flexible,num_tensors=1,types=int8,dimensions=(string)2,"
    "framerate=30/1";

// Accepted, passed downstream unchanged, and downstream's decorations reach upstream through
// the caps query.
TEST(DecoratedCapsDebug, AcceptedAndPropagatedBothWays) {
  Elem d("tensor_debug", "sink", "output-method=disabled");
  gst_harness_set_src_caps_str(d.h.get(), kDecoratedInt8);
  auto t = flex_tensor(TensorType::kInt8, {2}, {7, 9});
  ASSERT_EQ(gst_harness_push(d.h.get(), make_buffer({t}, 0)), GST_FLOW_OK)
      << d.messages(GST_MESSAGE_ERROR);
  GstBuffer *out = gst_harness_pull(d.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(tensor_bytes(out, 0), t);
  gst_buffer_unref(out);
  EXPECT_EQ(current_caps(d.h->sinkpad),
            "other/tensors, format=(string)flexible, num_tensors=(int)1, types=(string)int8, "
            "dimensions=(string)2, framerate=(fraction)30/1");
  EXPECT_EQ(d.messages(GST_MESSAGE_WARNING), "");

  Elem q("tensor_debug", "sink");
  gst_harness_set_sink_caps_str(q.h.get(), "other/tensors,format=flexible,types=uint8");
  EXPECT_EQ(sink_query_caps(q.e),
            "other/tensors, format=(string)flexible, types=(string)uint8, "
            "framerate=(fraction)[ 0/1, 2147483647/1 ]");
}

// Headers that contradict the decorated caps: one warning naming both, the stream goes on.
TEST(DecoratedCapsDebug, HeadersContradictingTheCapsAreReportedOnce) {
  Elem d("tensor_debug", "sink", "output-method=disabled");
  gst_harness_set_src_caps_str(d.h.get(), kDecoratedInt8);
  for (int i = 0; i < 2; ++i) {
    auto t = flex_tensor(TensorType::kFloat32, {2}, std::vector<uint8_t>(8, 0));
    ASSERT_EQ(gst_harness_push(d.h.get(), make_buffer({t}, i)), GST_FLOW_OK);
    gst_buffer_unref(gst_harness_pull(d.h.get()));
  }
  std::string w = d.messages(GST_MESSAGE_WARNING);
  EXPECT_EQ(w,
            std::string(GST_OBJECT_NAME(d.e)) +
                ": the stream contradicts its caps: the output caps other/tensors, "
                "format=(string)flexible, num_tensors=(int)1, types=(string)int8, "
                "dimensions=(string)2, framerate=(fraction)30/1 say types=int8, but the buffer's "
                "flexible headers say float32\n");
  EXPECT_EQ(d.messages(GST_MESSAGE_ERROR), "");
}

// A static stream does not become flexible: decorated flexible caps downstream are refused.
TEST(DecoratedCapsDebug, StaticUpstreamFlexibleDownstreamIsRefused) {
  Elem d("tensor_debug", "sink", "output-method=disabled");
  gst_harness_set_sink_caps_str(d.h.get(), "other/tensors,format=flexible,types=uint8");
  gst_harness_set_src_caps_str(d.h.get(), kU8x4);
  EXPECT_EQ(gst_harness_push(d.h.get(), make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_NOT_NEGOTIATED);
}

// ---- tensor_rate --------------------------------------------------------------------------

// NNStreamer's tensor_rate takes static streams only (other/tensor, other/tensors static):
// flexible caps, decorated or not, are refused at the sink pad, and its caps query answers no
// flexible caps, so a flexible producer cannot link.
TEST(DecoratedCapsRate, FlexibleCapsAreRefused) {
  for (const char *caps : {kDecoratedInt8, "other/tensors,format=flexible,framerate=30/1"}) {
    SCOPED_TRACE(caps);
    Elem r("tensor_rate", "sink", "framerate=15/1");
    gst_harness_set_src_caps_str(r.h.get(), caps);
    auto t = flex_tensor(TensorType::kInt8, {2}, {7, 9});
    EXPECT_EQ(gst_harness_push(r.h.get(), make_buffer({t}, 0)), GST_FLOW_NOT_NEGOTIATED);
    GstPad *sink = gst_element_get_static_pad(r.e, "sink");
    GstCaps *c = gst_caps_from_string(caps);
    EXPECT_FALSE(gst_pad_query_accept_caps(sink, c));
    gst_caps_unref(c);
    gst_object_unref(sink);
  }
  Elem q("tensor_rate", "sink");
  gst_harness_set_sink_caps_str(q.h.get(), "other/tensors,format=flexible,types=uint8");
  EXPECT_EQ(sink_query_caps(q.e), "EMPTY");
}

// Static caps still pass (the decoration question does not arise).
TEST(DecoratedCapsRate, StaticCapsPass) {
  Elem r("tensor_rate", "sink");
  gst_harness_set_src_caps_str(r.h.get(), kU8x4);
  ASSERT_EQ(gst_harness_push(r.h.get(), make_buffer({{1, 2, 3, 4}}, 0, 33333333)), GST_FLOW_OK);
  EXPECT_EQ(current_caps(r.h->sinkpad),
            "other/tensors, format=(string)static, num_tensors=(int)1, dimensions=(string)4, "
            "types=(string)uint8, framerate=(fraction)30/1");
}

}  // namespace nns::test

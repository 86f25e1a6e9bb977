// SPDX-License-Identifier: LGPL-2.1-only
// tensor_demux: default pads, tensorpick groups, caps per pad, flexible input, zero-copy
// (also through mux -> demux), bad input, state cycles.
#include <gtest/gtest.h>

#include "core/meta_header.h"
#include "elements/cycle_check.h"
#include "elements/stream_util.h"
#include "gst/tensor_caps.h"

namespace nns::test {
namespace {

const char *kThree =
    "other/tensors,format=static,num_tensors=3,dimensions=(string)\"4,2:2,3\","
    "types=(string)\"uint8,uint8,int8\",framerate=30/1";

GstBuffer *three(uint8_t v) {
  return make_buffer(
      {std::vector<uint8_t>(4, v), std::vector<uint8_t>(4, v + 1), std::vector<uint8_t>(3, v + 2)},
      v * 1000);
}

std::string pad_caps_dims(GstElement *demux, const char *pad) {
  GstPad *p = gst_element_get_static_pad(demux, pad);
  if (!p) return "(no pad)";
  GstCaps *caps = gst_pad_get_current_caps(p);
  std::string s = caps ? nns::gst::config_from_caps(caps).info.dims_string() : "(no caps)";
  if (caps) gst_caps_unref(caps);
  gst_object_unref(p);
  return s;
}

TEST(TensorDemux, OnePadPerTensorByDefault) {
  Pipe p(appsrc("in", kThree) +
         "! tensor_demux name=d d.src_0 ! queue ! appsink name=o0 sync=false "
         "d.src_1 ! queue ! appsink name=o1 sync=false d.src_2 ! queue ! appsink name=o2 "
         "sync=false");
  for (auto *s : {"o0", "o1", "o2"}) p.collect(s);
  GstBuffer *b0 = three(10);
  GstMemory *m1 = gst_buffer_peek_memory(b0, 1);
  p.push("in", b0);
  p.push("in", three(20));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out("o0").size(), 2u);
  ASSERT_EQ(p.out("o1").size(), 2u);
  ASSERT_EQ(p.out("o2").size(), 2u);
  EXPECT_EQ(tensor_bytes(p.out("o1")[0], 0), std::vector<uint8_t>(4, 11));
  EXPECT_EQ(tensor_bytes(p.out("o2")[1], 0), std::vector<uint8_t>(3, 22));
  EXPECT_EQ(GST_BUFFER_PTS(p.out("o2")[1]), 20000u);
  EXPECT_EQ(gst_buffer_peek_memory(p.out("o1")[0], 0), m1) << "demux must not copy";
}

TEST(TensorDemux, TensorpickGroupsAndCaps) {
  Pipe p(appsrc("in", kThree) +
         "! tensor_demux name=d tensorpick=2,0:1 d.src_0 ! queue ! appsink name=o0 sync=false "
         "d.src_1 ! queue ! appsink name=o1 sync=false");
  p.collect("o0");
  p.collect("o1");
  GstElement *d = p.get("d");
  ASSERT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_PAUSED), GST_STATE_CHANGE_ASYNC);
  p.push("in", three(1));
  ASSERT_EQ(gst_element_get_state(p.pipeline(), nullptr, nullptr, 5 * GST_SECOND),
            GST_STATE_CHANGE_SUCCESS);
  EXPECT_EQ(pad_caps_dims(d, "src_0"), "3");
  EXPECT_EQ(pad_caps_dims(d, "src_1"), "4,2:2");
  GstPad *src1 = gst_element_get_static_pad(d, "src_1");
  GstCaps *caps = gst_pad_get_current_caps(src1);
  auto c = nns::gst::config_from_caps(caps);
  EXPECT_EQ(c.info.types_string(), "uint8,uint8");
  EXPECT_EQ(c.rate_n, 30);
  gst_caps_unref(caps);
  gst_object_unref(src1);
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out("o1").size(), 1u);
  EXPECT_EQ(gst_buffer_n_memory(p.out("o1")[0]), 2u);
  EXPECT_EQ(tensor_bytes(p.out("o0")[0], 0), std::vector<uint8_t>(3, 3));
  gchar *pick = nullptr;
  g_object_get(d, "tensorpick", &pick, nullptr);
  EXPECT_STREQ(pick, "2,0:1");
  g_free(pick);
}

TEST(TensorDemux, TensorpickAlternativeSeparators) {
  Pipe p(appsrc("in", kThree) +
         "! tensor_demux name=d tensorpick=1+2.0 d.src_0 ! queue ! appsink "
         "name=o0 sync=false d.src_1 ! queue ! appsink name=o1 sync=false");
  p.collect("o0");
  p.collect("o1");
  p.push("in", three(1));
  p.eos("in");
  ASSERT_TRUE(p.run().eos);
  ASSERT_EQ(p.out("o0").size(), 1u);
  EXPECT_EQ(tensor_bytes(p.out("o0")[0], 1), std::vector<uint8_t>(3, 3));
}

TEST(TensorDemux, FlexibleInputPadsAtFirstBuffer) {
  Pipe p(appsrc("in", "other/tensors,format=flexible,framerate=0/1") +
         "! tensor_demux name=d d.src_0 ! queue ! appsink name=o0 sync=false d.src_1 ! queue ! "
         "appsink name=o1 "
         "sync=false");
  p.collect("o0");
  p.collect("o1");
  MetaHeader h;
  h.type = TensorType::kUInt8;
  h.dims = make_dims({2});
  h.format = TensorFormat::kFlexible;
  std::vector<uint8_t> t(kMetaHeaderSize + 2, 5);
  write_meta_header(h, t.data());
  p.push("in", make_buffer({t, t}, 0));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  ASSERT_EQ(p.out("o1").size(), 1u);
  EXPECT_EQ(tensor_bytes(p.out("o1")[0], 0), t);
}

// Issue requirement: mux of 4 streams and demux back without any copy.
TEST(TensorDemux, MuxThenDemuxKeepsMemories) {
  const char *caps =
      "other/tensors,format=static,num_tensors=1,dimensions=(string)4,"
      "types=uint8,framerate=30/1";
  std::string desc;
  for (int i = 0; i < 4; ++i)
    desc += appsrc("a" + std::to_string(i), caps) + "! mux.sink_" + std::to_string(i) + " ";
  desc += "tensor_mux name=mux sync-mode=nosync ! tensor_demux name=d ";
  for (int i = 0; i < 4; ++i)
    desc += "d.src_" + std::to_string(i) + " ! queue ! appsink name=o" + std::to_string(i) +
            " sync=false ";
  Pipe p(desc);
  std::vector<GstMemory *> sent[4];
  for (int i = 0; i < 4; ++i) p.collect(("o" + std::to_string(i)).c_str());
  for (int i = 0; i < 4; ++i) {
    std::string src = "a" + std::to_string(i);
    for (int f = 0; f < 5; ++f) {
      GstBuffer *b = make_buffer({std::vector<uint8_t>(4, uint8_t(i * 10 + f))}, f * 33333333);
      sent[i].push_back(gst_buffer_peek_memory(b, 0));
      gst_memory_ref(sent[i].back());
      p.push(src.c_str(), b);
    }
    p.eos(src.c_str());
  }
  auto r = p.run();
  ASSERT_TRUE(r.eos) << r.error_text;
  for (int i = 0; i < 4; ++i) {
    auto &out = p.out("o" + std::to_string(i));
    ASSERT_EQ(out.size(), 5u);
    for (int f = 0; f < 5; ++f) {
      EXPECT_EQ(gst_buffer_peek_memory(out[f], 0), sent[i][f]) << "pad " << i << " frame " << f;
      gst_memory_unref(sent[i][f]);
    }
  }
}

TEST(TensorDemux, TensorpickOutOfRangeIsABusError) {
  Pipe p(appsrc("in", kThree) +
         "! tensor_demux name=d tensorpick=0,1:3 d.src_0 ! queue ! fakesink");
  p.push("in", three(1));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("d: tensorpick='0,1:3': pad 1 picks tensor 3 but the input has "
                              "only 3 tensor(s)"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorDemux, BadTensorpickGrammarIsABusError) {
  auto r = run_pipeline(appsrc("in", kThree) + "! tensor_demux name=d tensorpick=0,x ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("d: tensorpick='0,x': 'x' is not a tensor index"), std::string::npos)
      << r.error_text;
}

TEST(TensorDemux, WrongTensorSizeIsABusError) {
  Pipe p(appsrc("in", kThree) + "! tensor_demux name=d d.src_0 ! queue ! fakesink");
  p.push("in", make_buffer(
                   {std::vector<uint8_t>(4), std::vector<uint8_t>(5), std::vector<uint8_t>(3)}, 0));
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("d: tensor 1 has 5 bytes, expected 4 for uint8 2:2"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorDemux, EosBeforeCapsIsABusError) {
  Pipe p("appsrc name=in format=time ! tensor_demux name=d d.src_0 ! queue ! fakesink");
  p.eos("in");
  auto r = p.run();
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("d: got EOS before any output pad was created"), std::string::npos)
      << r.error_text;
}

// Src pads are removed on PAUSED->READY (as upstream), so the test links them on pad-added
// every cycle instead of relying on gst_parse_launch's one-shot delayed links. Odd cycles end
// with EOS, even ones stop while data flows; nothing may be left alive after any of them.
TEST(TensorDemux, HundredPlayingNullCyclesNoHangNoLeak) {
  Pipe q(appsrc("in", kThree) +
         "! tensor_demux name=d queue name=q0 ! fakesink name=f0 "
         "queue name=q1 ! fakesink name=f1 queue name=q2 ! fakesink name=f2");
  g_signal_connect(q.get("d"), "pad-added",
                   G_CALLBACK(+[](GstElement *, GstPad *pad, gpointer bin) {
                     std::string qn = "q" + std::string(GST_PAD_NAME(pad)).substr(4);
                     GstElement *qe = gst_bin_get_by_name(GST_BIN(bin), qn.c_str());
                     GstPad *sink = gst_element_get_static_pad(qe, "sink");
                     gst_pad_link(pad, sink);
                     gst_object_unref(sink);
                     gst_object_unref(qe);
                   }),
                   q.pipeline());
  state_cycles(q.pipeline(), 100, [&](int i, LiveObjects &live) {
    std::size_t before = live.delivered("f2");
    q.push("in", three(1));
    q.push("in", three(2));
    if (i % 2) {
      q.eos("in");
      std::string err;
      EXPECT_TRUE(wait_eos(q.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
    }
    for (const char *f : {"f0", "f1", "f2"})
      EXPECT_TRUE(live.wait_delivered(f, before + 2)) << f << " cycle " << i;
  });
}

}  // namespace
}  // namespace nns::test

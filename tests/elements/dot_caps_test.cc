// SPDX-License-Identifier: LGPL-2.1-only
// Several tensors' caps spelled with '.' between tensors (types=uint8.float32,
// dimensions=3:8:6:1.1:4:2:1), as upstream's tests and gst-launch lines write them: a capsfilter
// so written after our elements negotiates the same config; one that says other dimensions still
// fails naming both. (tensor_src_grpc: tests/grpc, edgesrc: tests/edge.)
#include <gtest/gtest.h>

#include <fstream>
#include <string>

#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"
#include "support/harness.h"

namespace {

using nns::test::run_pipeline;

// 3:8:6:1 uint8 (RGB 8x6) and 1:4:2:1 float32 (GRAY8 4x2, typecast), muxed, 2 frames at 30/1.
const std::string kTwo =
    "videotestsrc num-buffers=2 ! video/x-raw,format=RGB,width=8,height=6,framerate=30/1 ! "
    "tensor_converter ! mux.sink_0 "
    "videotestsrc num-buffers=2 ! video/x-raw,format=GRAY8,width=4,height=2,framerate=30/1 ! "
    "tensor_converter ! tensor_transform mode=typecast option=float32 ! mux.sink_1 "
    "tensor_mux name=mux ";
const char *kOurs =
    "other/tensors,format=static,num_tensors=2,types=(string)\"uint8,float32\","
    "dimensions=(string)\"3:8:6:1,1:4:2:1\",framerate=(fraction)30/1";
const std::string kDot =
    "other/tensors,format=static,num_tensors=2,types=uint8.float32,"
    "dimensions=3:8:6:1.1:4:2:1,framerate=30/1";

struct Seen {
  int buffers = 0;
  std::string caps;  // caps of the first buffer at the sink
};

void on_handoff(GstElement *, GstBuffer *, GstPad *pad, gpointer data) {
  auto *seen = static_cast<Seen *>(data);
  if (seen->buffers++ == 0) {
    nns::gst::CapsPtr c(gst_pad_get_current_caps(pad));
    seen->caps = nns::gst::caps_to_string(c.get());
  }
}

// Runs `desc` ending in "fakesink name=out"; counts buffers and keeps the first one's caps.
nns::test::RunResult run_seen(const std::string &desc, Seen *seen) {
  GError *err = nullptr;
  GstElement *pipe = gst_parse_launch(desc.c_str(), &err);
  if (err) {
    ADD_FAILURE() << err->message;
    g_error_free(err);
  }
  if (!pipe) return {};
  GstElement *out = gst_bin_get_by_name(GST_BIN(pipe), "out");
  g_object_set(out, "signal-handoffs", TRUE, nullptr);
  g_signal_connect(out, "handoff", G_CALLBACK(on_handoff), seen);
  gst_object_unref(out);
  auto r = run_pipeline(pipe);
  gst_object_unref(pipe);
  return r;
}

// The caps `got` describe the same tensors and rate as `want`.
void expect_config(const std::string &got, const std::string &want) {
  nns::gst::CapsPtr g(gst_caps_from_string(got.c_str()));
  nns::gst::CapsPtr w(gst_caps_from_string(want.c_str()));
  ASSERT_TRUE(g) << got;
  auto gc = nns::gst::config_from_caps(g.get());
  auto wc = nns::gst::config_from_caps(w.get());
  EXPECT_TRUE(gc.same_as(wc)) << got << " vs " << want;
  EXPECT_EQ(gc.rate_n, wc.rate_n);
  EXPECT_EQ(gc.rate_d, wc.rate_d);
}

void expect_negotiates(const std::string &upstream, const std::string &filter,
                       const std::string &want_config, int buffers) {
  Seen seen;
  auto r = run_seen(upstream + "! " + filter + " ! fakesink name=out", &seen);
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(seen.buffers, buffers);
  expect_config(seen.caps, want_config);
}

}  // namespace

TEST(DotCaps, ConfigFromCapsReadsBothSpellings) {
  nns::gst::CapsPtr dot(gst_caps_from_string(kDot.c_str()));
  nns::gst::CapsPtr ours(gst_caps_from_string(kOurs));
  auto d = nns::gst::config_from_caps(dot.get());
  EXPECT_TRUE(d.same_as(nns::gst::config_from_caps(ours.get())));
  EXPECT_EQ(d.info.dims_string(), "3:8:6:1,1:4:2:1");
  EXPECT_EQ(d.info.types_string(), "uint8,float32");
}

TEST(DotCaps, VariantCapsOfferTheDotSpellingsOursFirst) {
  nns::gst::CapsPtr ours(gst_caps_from_string(kOurs));
  nns::gst::CapsPtr v(nns::gst::caps_from_config(nns::gst::config_from_caps(ours.get()), true));
  nns::gst::CapsPtr dot(gst_caps_from_string(kDot.c_str()));
  EXPECT_TRUE(gst_caps_can_intersect(v.get(), dot.get())) << nns::gst::caps_to_string(v.get());
  // Without a peer preference, fixation gives our own spelling.
  nns::gst::CapsPtr fixed(gst_caps_fixate(gst_caps_copy(v.get())));
  EXPECT_TRUE(gst_caps_is_equal(fixed.get(), ours.get())) << nns::gst::caps_to_string(fixed.get());
  // Other dimensions spelled with '.' do not intersect.
  nns::gst::CapsPtr other(gst_caps_from_string(
      "other/tensors,format=static,num_tensors=2,types=uint8.float32,dimensions=3:8:6:1.1:4:3:1"));
  EXPECT_FALSE(gst_caps_can_intersect(v.get(), other.get()));
  // A single tensor gets no '.' spellings.
  nns::gst::CapsPtr one(gst_caps_from_string(
      "other/tensors,format=static,num_tensors=1,types=uint8,dimensions=3:4,framerate=0/1"));
  nns::gst::CapsPtr v1(nns::gst::caps_from_config(nns::gst::config_from_caps(one.get()), true));
  EXPECT_EQ(nns::gst::caps_to_string(v1.get()).find('.'), std::string::npos)
      << nns::gst::caps_to_string(v1.get());
}

TEST(DotCaps, TensorMux) {
  expect_negotiates(kTwo, kDot, kOurs, 2);
  // Trailing :1 dropped in the '.' spelling too.
  expect_negotiates(kTwo,
                    "other/tensors,format=static,num_tensors=2,types=uint8.float32,"
                    "dimensions=3:8:6.1:4:2",
                    kOurs, 2);
  // Without a filter our own spelling goes downstream.
  Seen seen;
  auto r = run_seen(kTwo + "! fakesink name=out", &seen);
  EXPECT_TRUE(r.eos) << r.error_text;
  nns::gst::CapsPtr got(gst_caps_from_string(seen.caps.c_str()));
  nns::gst::CapsPtr ours(gst_caps_from_string(kOurs));
  EXPECT_TRUE(gst_caps_is_equal(got.get(), ours.get())) << seen.caps;
}

TEST(DotCaps, TensorMuxOtherDimensionsFailNamingBoth) {
  auto r = run_pipeline(kTwo +
                        "! other/tensors,format=static,num_tensors=2,types=uint8.float32,"
                        "dimensions=3:8:6:1.1:4:3:1 ! fakesink");
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_EQ(r.error_source, "mux") << r.error_text;
  EXPECT_NE(r.error_text.find("\"3:8:6:1\\,1:4:2:1\""), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("3:8:6:1.1:4:3:1"), std::string::npos) << r.error_text;
}

TEST(DotCaps, TensorTransform) {
  expect_negotiates(kTwo + "! tensor_transform mode=typecast option=float32 ",
                    "other/tensors,num_tensors=2,types=float32.float32,dimensions=3:8:6:1.1:4:2:1",
                    "other/tensors,format=static,num_tensors=2,types=(string)\"float32,float32\","
                    "dimensions=(string)\"3:8:6:1,1:4:2:1\",framerate=(fraction)30/1",
                    2);
}

TEST(DotCaps, TensorDemux) {
  // Three tensors in, tensors 0 and 1 out of src_0 (a pad added while playing).
  const std::string three =
      kTwo +
      "videotestsrc num-buffers=2 ! "
      "video/x-raw,format=GRAY8,width=4,height=4,framerate=30/1 ! tensor_converter ! "
      "mux.sink_2 ";
  expect_negotiates(
      three + "mux. ! tensor_demux name=d tensorpick=0:1,2 d.src_1 ! fakesink d.src_0 ! queue ",
      kDot, kOurs, 2);
  // A filter with another dimension does not link (gst-parse leaves src_0 unlinked): see
  // VariantCapsOfferTheDotSpellingsOursFirst for the caps that do not intersect.
}

TEST(DotCaps, TensorConverterOctetStream) {
  const std::string dir = nns::test::make_temp_dir();
  const std::string file = dir + "/two.bin";
  std::ofstream(file) << std::string(2 * 176, 'x');  // 144 uint8 + 8 float32, twice
  expect_negotiates("filesrc location=" + file +
                        " blocksize=176 ! application/octet-stream,framerate=30/1 ! "
                        "tensor_converter input-dim=3:8:6:1,1:4:2:1 input-type=uint8,float32 ",
                    kDot, kOurs, 2);
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder properties as NNStreamer's tests/nnstreamer_sink tensorDecoderProperty1/2_n
// check them: option1..9 read back as given (also options the mode does not use), mode and
// silent, the sub-plugins list, unknown properties, and the stream still runs to the end.
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <atomic>
#include <string>

#include "gst/decoder_registry.h"
#include "support/harness.h"

namespace {

std::string get_string(GstElement *e, const char *prop) {
  gchar *s = nullptr;
  g_object_get(e, prop, &s, nullptr);
  std::string out = s ? s : "<NULL>";
  g_free(s);
  return out;
}

void count_data(GstElement *, GstBuffer *b, gpointer user) {
  auto *n = static_cast<std::atomic<int> *>(user);
  if (gst_buffer_get_size(b) == 64 && gst_buffer_n_memory(b) == 1) ++*n;
}

TEST(TensorDecoderUpstream, OptionsReadBackAsGiven) {
  GError *err = nullptr;
  GstElement *p = gst_parse_launch(
      "videotestsrc pattern=snow num-buffers=5 ! "
      "video/x-raw,format=BGRx,height=4,width=4,framerate=10/1 ! tensor_converter ! "
      "tensor_decoder mode=direct_video name=decoder option1=whatthehell option2=isgoingon "
      "option3=nothing option4=iswrong option5=keepcalm option6=\"and have a break\" "
      "option7=\"iwill=not\" option8=\"break=your\" option9=\"system=1234\" ! "
      "video/x-raw,format=BGRx ! tensor_converter ! tensor_sink name=test_sink",
      &err);
  ASSERT_TRUE(p) << (err ? err->message : "");
  GstElement *dec = gst_bin_get_by_name(GST_BIN(p), "decoder");
  ASSERT_TRUE(dec);
  EXPECT_EQ(get_string(dec, "mode"), "direct_video");
  gboolean silent = FALSE;
  g_object_get(dec, "silent", &silent, nullptr);
  EXPECT_TRUE(silent);
  g_object_set(dec, "silent", !silent, nullptr);
  gboolean res = silent;
  g_object_get(dec, "silent", &res, nullptr);
  EXPECT_EQ(res, !silent);
  const char *expected[9] = {"whatthehell", "isgoingon",  "nothing",
                             "iswrong",     "keepcalm",   "and have a break",
                             "iwill=not",   "break=your", "system=1234"};
  for (int i = 0; i < 9; ++i) {
    std::string prop = "option" + std::to_string(i + 1);
    EXPECT_EQ(get_string(dec, prop.c_str()), expected[i]) << prop;
  }
  std::string subs = get_string(dec, "sub-plugins");
  EXPECT_NE(subs.find("direct_video"), std::string::npos) << subs;
  EXPECT_NE(subs.find("bounding_boxes"), std::string::npos) << subs;
  // An unknown property: set is ignored (GLib warns), nothing to read.
  EXPECT_EQ(g_object_class_find_property(G_OBJECT_GET_CLASS(dec), "invalid_prop"), nullptr);
  gst_object_unref(dec);

  std::atomic<int> received{0};
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "test_sink");
  g_signal_connect(sink, "new-data", G_CALLBACK(count_data), &received);
  gst_object_unref(sink);
  auto r = nns::test::run_pipeline(p);
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(received, 5);  // uint8 4:4:4:1 each
  gst_object_unref(p);
}

TEST(TensorDecoderUpstream, UnsetOptionsReadBackNull) {
  GstElement *dec = gst_element_factory_make("tensor_decoder", nullptr);
  ASSERT_TRUE(dec);
  for (int i = 1; i <= 9; ++i) {
    std::string prop = "option" + std::to_string(i);
    EXPECT_EQ(get_string(dec, prop.c_str()), "<NULL>") << prop;
  }
  g_object_set(dec, "option3", "x", nullptr);
  EXPECT_EQ(get_string(dec, "option3"), "x");
  gst_object_unref(dec);
}

// --- sub-plugin registration (tests/nnstreamer_decoder: subplugin*, probeSubplug*) ----------

int dec_init(void **) {
  return TRUE;
}
GstCaps *dec_caps(void **, const GstTensorsConfig *) {
  return gst_caps_new_any();
}
GstFlowReturn dec_decode(void **, const GstTensorsConfig *, const GstTensorMemory *, GstBuffer *) {
  return GST_FLOW_OK;
}

GstTensorDecoderDef make_def(const char *name) {
  GstTensorDecoderDef def{};
  def.modename = const_cast<char *>(name);
  def.init = dec_init;
  def.getOutCaps = dec_caps;
  def.decode = dec_decode;
  return def;
}

TEST(TensorDecoderUpstream, ProbeRefusesInvalidSubplugins) {
  auto ok = make_def("upstream_test_mode");
  EXPECT_TRUE(nnstreamer_decoder_probe(&ok));
  EXPECT_EQ(nnstreamer_decoder_find("upstream_test_mode"), &ok);
  nnstreamer_decoder_exit("upstream_test_mode");
  auto no_name = make_def(nullptr);
  EXPECT_FALSE(nnstreamer_decoder_probe(&no_name));
  auto no_init = make_def("upstream_test_mode");
  no_init.init = nullptr;
  EXPECT_FALSE(nnstreamer_decoder_probe(&no_init));
  auto no_caps = make_def("upstream_test_mode");
  no_caps.getOutCaps = nullptr;
  EXPECT_FALSE(nnstreamer_decoder_probe(&no_caps));
  auto no_decode = make_def("upstream_test_mode");
  no_decode.decode = nullptr;
  EXPECT_FALSE(nnstreamer_decoder_probe(&no_decode));
  auto any = make_def("any");
  EXPECT_FALSE(nnstreamer_decoder_probe(&any));
  EXPECT_FALSE(nnstreamer_decoder_probe(nullptr));
  EXPECT_EQ(nnstreamer_decoder_find(nullptr), nullptr);
}

// subpluginNullDesc_n: a property given with a NULL description is refused (nothing is kept);
// a described one is kept until the sub-plugin exits.
TEST(TensorDecoderUpstream, CustomPropertyWithNullDescriptionIsRefused) {
  auto &reg = nns::gst::DecoderRegistry::instance();
  auto def = make_def("upstream_desc_mode");
  ASSERT_TRUE(nnstreamer_decoder_probe(&def));
  nnstreamer_decoder_set_custom_property_desc("upstream_desc_mode", "Desc1", nullptr);
  EXPECT_FALSE(reg.property_descs("upstream_desc_mode"));
  nnstreamer_decoder_set_custom_property_desc("upstream_desc_mode", "Desc2",
                                              "decoder subplugin for test", nullptr);
  auto descs = reg.property_descs("upstream_desc_mode");
  ASSERT_TRUE(descs);
  ASSERT_EQ(descs->size(), 1u);
  EXPECT_EQ((*descs)[0].first, "Desc2");
  EXPECT_EQ((*descs)[0].second, "decoder subplugin for test");
  // Set again: replaces; a key without description ends the list (earlier pairs stay).
  nnstreamer_decoder_set_custom_property_desc("upstream_desc_mode", "A", "a", "B", nullptr);
  descs = reg.property_descs("upstream_desc_mode");
  ASSERT_TRUE(descs);
  ASSERT_EQ(descs->size(), 1u);
  EXPECT_EQ((*descs)[0].first, "A");
  // Not registered: nothing kept.
  nnstreamer_decoder_set_custom_property_desc("upstream_not_registered", "X", "x", nullptr);
  EXPECT_FALSE(reg.property_descs("upstream_not_registered"));
  nnstreamer_decoder_exit("upstream_desc_mode");
  EXPECT_FALSE(reg.property_descs("upstream_desc_mode"));
}

}  // namespace

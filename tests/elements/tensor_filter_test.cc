// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter: loading back ends, built-in custom / custom-easy filters, shape checks and
// their error messages.
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>

#include "elements/filter_test_util.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

using namespace nns::test;

namespace {

std::atomic<const void *> g_seen_ptr{nullptr};
std::atomic<int> g_easy_calls{0};

int easy_copy(void *data, const GstTensorFilterProperties *prop, const GstTensorMemory *in,
              GstTensorMemory *out) {
  (void)prop;
  g_seen_ptr = in[0].data;
  g_easy_calls++;
  const int add = data ? *static_cast<int *>(data) : 0;
  for (size_t i = 0; i < in[0].size; ++i)
    static_cast<uint8_t *>(out[0].data)[i] = static_cast<const uint8_t *>(in[0].data)[i] + add;
  return 0;
}

int easy_fail(void *, const GstTensorFilterProperties *, const GstTensorMemory *,
              GstTensorMemory *) {
  return -5;
}

class EasyModel {
 public:
  EasyModel(const char *name, NNS_custom_invoke f, void *data, tensor_type t,
            std::initializer_list<uint32_t> in, std::initializer_list<uint32_t> out)
      : name_(name) {
    GstTensorsInfo i = gst_info(t, in), o = gst_info(t, out);
    EXPECT_EQ(NNS_custom_easy_register(name, f, data, &i, &o), 0);
  }
  ~EasyModel() { EXPECT_EQ(NNS_custom_easy_unregister(name_), 0); }

 private:
  const char *name_;
};

}  // namespace

TEST(TensorFilter, DefaultsMatchUpstream) {
  GstElement *f = gst_element_factory_make("tensor_filter", nullptr);
  ASSERT_NE(f, nullptr);
  gchar *fw = nullptr, *sub = nullptr, *model = nullptr;
  gint latency = 0, throughput = 0;
  guint suspend = 9;
  gboolean silent = FALSE, dyn = TRUE, upd = TRUE, rep = TRUE, async = TRUE;
  g_object_get(f, "framework", &fw, "sub-plugins", &sub, "model", &model, "latency", &latency,
               "throughput", &throughput, "suspend", &suspend, "silent", &silent, "invoke-dynamic",
               &dyn, "is-updatable", &upd, "latency-report", &rep, "invoke-async", &async, nullptr);
  EXPECT_STREQ(fw, "auto");
  EXPECT_STREQ(model, "");
  EXPECT_NE(std::string(sub).find("custom,custom-easy,cpp"), std::string::npos) << sub;
  EXPECT_EQ(latency, -1);
  EXPECT_EQ(throughput, -1);
  EXPECT_EQ(suspend, 0u);
  EXPECT_TRUE(silent);
  EXPECT_FALSE(dyn);
  EXPECT_FALSE(upd);
  EXPECT_FALSE(rep);
  EXPECT_FALSE(async);
  g_free(fw);
  g_free(sub);
  g_free(model);
  GParamSpec *ps = g_object_class_find_property(G_OBJECT_GET_CLASS(f), "inputranks");
  ASSERT_NE(ps, nullptr);
  EXPECT_FALSE(ps->flags & G_PARAM_WRITABLE);
  ps = g_object_class_find_property(G_OBJECT_GET_CLASS(f), "latency");
  EXPECT_EQ(G_PARAM_SPEC_VALUE_TYPE(ps), G_TYPE_INT);
  gst_object_unref(f);
}

TEST(TensorFilter, CustomEasyPassesInputPointerUnchanged) {
  int add = 1;
  EasyModel m("tf_easy_copy", easy_copy, &add, _NNS_UINT8, {4, 1, 1, 1}, {4, 1, 1, 1});
  FilterHarness fh("tensor_filter framework=custom-easy model=tf_easy_copy",
                   tensors_caps("uint8", "4:1:1:1"));
  GstBuffer *in = tensor_buffer({{1, 2, 3, 4}});
  const void *upstream_ptr;
  {
    GstMapInfo map;
    gst_memory_map(gst_buffer_peek_memory(in, 0), &map, GST_MAP_READ);
    upstream_ptr = map.data;
    gst_memory_unmap(gst_buffer_peek_memory(in, 0), &map);
  }
  gst_buffer_ref(in);  // keep it alive to compare after the push
  ASSERT_EQ(gst_harness_push(fh.h.get(), in), GST_FLOW_OK) << fh.error_text();
  EXPECT_EQ(g_seen_ptr.load(), upstream_ptr) << "input was copied before invoke";
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(memory_bytes(out, 0), (std::vector<uint8_t>{2, 3, 4, 5}));
  EXPECT_EQ(GST_BUFFER_PTS(out), GST_BUFFER_PTS(in));
  gst_buffer_unref(out);
  gst_buffer_unref(in);
  GstCaps *caps = gst_pad_get_current_caps(fh.h->sinkpad);
  ASSERT_NE(caps, nullptr);
  gchar *cs = gst_caps_to_string(caps);
  std::string s = cs;
  g_free(cs);
  EXPECT_NE(s.find("uint8"), std::string::npos) << s;
  gst_caps_unref(caps);
}

TEST(TensorFilter, CustomEasyRunsInPipeline) {
  EasyModel m("tf_easy_pipe", easy_copy, nullptr, _NNS_UINT8, {4}, {4});
  g_easy_calls = 0;
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=custom-easy model=tf_easy_pipe ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(g_easy_calls.load(), 3);
}

TEST(TensorFilter, CustomEasyUnknownModelIsAnError) {
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=custom-easy model=no_such_easy ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("custom-easy model 'no_such_easy' is not registered"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorFilter, CustomEasyUnregisterWhileInUseIsBusy) {
  EasyModel m("tf_easy_busy", easy_copy, nullptr, _NNS_UINT8, {4}, {4});
  FilterHarness fh("tensor_filter framework=custom-easy model=tf_easy_busy",
                   tensors_caps("uint8", "4"));
  EXPECT_EQ(NNS_custom_easy_unregister("tf_easy_busy"), -EBUSY);
  GstTensorsInfo i = gst_info(_NNS_UINT8, {4});
  EXPECT_EQ(NNS_custom_easy_register("tf_easy_busy", easy_copy, nullptr, &i, &i), -EEXIST);
  EXPECT_EQ(NNS_custom_easy_register(nullptr, easy_copy, nullptr, &i, &i), -EINVAL);
}

TEST(TensorFilter, InvokeErrorNamesModelAndCause) {
  EasyModel m("tf_easy_fail", easy_fail, nullptr, _NNS_UINT8, {4}, {4});
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=custom-easy model=tf_easy_fail ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("tf_easy_fail"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("invoke failed"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("returned -5"), std::string::npos) << r.error_text;
}

TEST(TensorFilter, CustomSharedObjectPassthrough) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  FilterHarness fh("tensor_filter framework=custom model=" + so,
                   tensors_caps("float32", "10:1:1:1"));
  std::vector<uint8_t> bytes(40);
  for (std::size_t i = 0; i < bytes.size(); ++i) bytes[i] = static_cast<uint8_t>(i);
  ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({bytes})), GST_FLOW_OK) << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(memory_bytes(out, 0), bytes);
  gst_buffer_unref(out);
  gchar *in_dims = nullptr, *ranks = nullptr;
  g_object_get(fh.element(), "input", &in_dims, "inputranks", &ranks, nullptr);
  EXPECT_STREQ(in_dims, "10:1:1:1");
  EXPECT_STREQ(ranks, "4");
  g_free(in_dims);
  g_free(ranks);
}

TEST(TensorFilter, CustomAutoDetectedFromSoExtension) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  auto r = run_pipeline(fake_source(40, tensors_caps("float32", "10:1:1:1")) +
                        "tensor_filter model=" + so + " ! fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
}

TEST(TensorFilter, CustomScalerUsesSetInputDimAndCustomProperty) {
  std::string so = filter_dir() + "/libcustom_scaler.so";
  FilterHarness fh("tensor_filter framework=custom model=" + so + " custom=2x1",
                   tensors_caps("uint8", "1:4:2:1"));
  ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{1, 2, 3, 4, 5, 6, 7, 8}})), GST_FLOW_OK)
      << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(memory_bytes(out, 0), (std::vector<uint8_t>{1, 3}));
  gst_buffer_unref(out);
  gchar *o = nullptr;
  g_object_get(fh.element(), "output", &o, nullptr);
  EXPECT_STREQ(o, "1:2:1:1");
  g_free(o);
}

TEST(TensorFilter, CustomWithoutSymbolIsAnError) {
  std::string so = filter_dir() + "/libcustom_nosym.so";
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=custom model=" + so + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("does not export the symbol NNStreamer_custom"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find(so), std::string::npos) << r.error_text;
}

TEST(TensorFilter, MissingModelFileIsAnError) {
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=custom model=/nonexistent/libx.so ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("model file '/nonexistent/libx.so' does not exist"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorFilter, UnknownFrameworkNamesTheMissingFileAndFolders) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=nosuchfw model=/etc/hostname ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("framework 'nosuchfw' is not available: no "
                              "libnnstreamer_filter_nosuchfw.so in " +
                              filter_dir()),
            std::string::npos)
      << r.error_text;
}

TEST(TensorFilter, ApiVersionMismatchNamesBothVersionsAndFile) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=badversion model=/etc/hostname ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find(filter_dir() + "/libnnstreamer_filter_badversion.so"),
            std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("API version 99"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("needs version 1"), std::string::npos) << r.error_text;
}

TEST(TensorFilter, BackendWithoutEntryPointIsAnError) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=noentry model=/etc/hostname ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("does not export nns_filter_backend_entry"), std::string::npos)
      << r.error_text;
}

TEST(TensorFilter, LoadsBackendFromConfiguredFolder) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  std::string model = write_temp("m.echo", "echo");
  FilterHarness fh("tensor_filter framework=testecho model=" + model, tensors_caps("uint8", "3:2"));
  ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({{9, 8, 7, 6, 5, 4}})), GST_FLOW_OK)
      << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(memory_bytes(out, 0), (std::vector<uint8_t>{9, 8, 7, 6, 5, 4}));
  gst_buffer_unref(out);
}

TEST(TensorFilter, BackendOpenErrorCarriesBackendMessage) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  std::string model = write_temp("m.echo", "echo");
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter framework=testecho custom=fail_open:1 model=" + model +
                        " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("could not open model '" + model + "'"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("testecho refuses to open"), std::string::npos) << r.error_text;
}

TEST(TensorFilter, PropertyShapeContradictingModelShowsBoth) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  auto r = run_pipeline(fake_source(20, tensors_caps("float32", "5")) +
                        "tensor_filter framework=custom model=" + so +
                        " input=5 inputtype=float32 ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("float32 5"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("float32 10:1:1:1"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("the model's input"), std::string::npos) << r.error_text;
}

TEST(TensorFilter, CapsContradictingModelShowsBoth) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  auto r = run_pipeline(fake_source(4, tensors_caps("uint8", "4")) +
                        "tensor_filter name=tf framework=custom model=" + so + " ! fakesink");
  ASSERT_TRUE(r.error);
  // The filter's own message (posted before the source's not-negotiated): the stream's shape,
  // the model's shape and the model.
  EXPECT_EQ(r.error_source, "tf") << r.error_text;
  EXPECT_NE(r.error_text.find("the input stream has 1 tensor(s): [0] uint8 4,"), std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("the model's input is 1 tensor(s): [0] float32 10:1:1:1"),
            std::string::npos)
      << r.error_text;
  EXPECT_NE(r.error_text.find("model '" + so + "'"), std::string::npos) << r.error_text;
}

TEST(TensorFilter, DirectoryAsModelIsAnError) {
  std::string dir = make_temp_dir();
  auto r = run_pipeline(fake_source(40, tensors_caps("float32", "10")) +
                        "tensor_filter framework=custom model=" + dir + " ! fakesink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("model file '" + dir + "' is a directory, not a model file"),
            std::string::npos)
      << r.error_text;
  rmdir(dir.c_str());
}

TEST(TensorFilter, UnreadableModelIsAnError) {
  if (geteuid() == 0)
    GTEST_SKIP() << "running as root: a mode-000 file stays readable, so this cannot fail";
  std::string model = write_temp("unreadable.so", "x");
  ASSERT_EQ(chmod(model.c_str(), 0), 0);
  auto r = run_pipeline(fake_source(40, tensors_caps("float32", "10")) +
                        "tensor_filter framework=custom model=" + model + " ! fakesink");
  chmod(model.c_str(), 0600);
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("model file '" + model + "' is not readable (Permission denied)"),
            std::string::npos)
      << r.error_text;
}

// Back ends that do not pick tensors by name get no names-only description; the user is told.
TEST(TensorFilter, NamesIgnoredByBackendWithoutNamesAreAWarning) {
  std::string so = filter_dir() + "/libcustom_passthrough.so";
  FilterHarness fh("tensor_filter framework=custom model=" + so + " inputname=pixels",
                   tensors_caps("float32", "10:1:1:1"));
  std::vector<uint8_t> bytes(40, 7);
  ASSERT_EQ(gst_harness_push(fh.h.get(), tensor_buffer({bytes})), GST_FLOW_OK) << fh.error_text();
  GstBuffer *out = gst_harness_pull(fh.h.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(memory_bytes(out, 0), bytes);
  gst_buffer_unref(out);
  EXPECT_NE(fh.warning_text().find(
                "inputname='pixels' is ignored: framework 'custom' does not pick tensors by name"),
            std::string::npos);
  EXPECT_EQ(fh.error_text(), "");
}

TEST(TensorFilter, AfterTensorConverter) {
  EasyModel m("tf_easy_video", easy_copy, nullptr, _NNS_UINT8, {3, 4, 4, 1}, {3, 4, 4, 1});
  g_easy_calls = 0;
  auto r = run_pipeline(
      "videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=4,height=4,framerate=30/1 ! "
      "tensor_converter ! tensor_filter framework=custom-easy model=tf_easy_video ! tensor_sink");
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(g_easy_calls.load(), 3);
  r = run_pipeline(
      "videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=8,height=4,framerate=30/1 ! "
      "tensor_converter ! tensor_filter framework=custom-easy model=tf_easy_video ! tensor_sink");
  ASSERT_TRUE(r.error);
  EXPECT_NE(r.error_text.find("uint8 3:8:4:1"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("the model's input is 1 tensor(s): [0] uint8 3:4:4:1"),
            std::string::npos)
      << r.error_text;
}

TEST(TensorFilter, CustomModelRelativeToWorkingDirectory) {
  char old[4096];
  ASSERT_NE(getcwd(old, sizeof old), nullptr);
  ASSERT_EQ(chdir(filter_dir().c_str()), 0);
  auto r = run_pipeline(fake_source(40, tensors_caps("float32", "10")) +
                        "tensor_filter framework=custom model=libcustom_passthrough.so ! fakesink");
  ASSERT_EQ(chdir(old), 0);
  EXPECT_TRUE(r.eos) << r.error_text;
}

// tensor_filter answers the caps query from upstream with the model's input, so the elements
// before it negotiate to the model: videoscale scales to 280x40 for a 3:280:40:1 uint8 model.
TEST(TensorFilter, UpstreamNegotiatesToTheModelInput) {
  EasyModel m("tf_easy_280x40", easy_copy, nullptr, _NNS_UINT8, {3, 280, 40, 1}, {3, 280, 40, 1});
  g_easy_calls = 0;
  GError *err = nullptr;
  nns::gst::ElementPtr pipe(gst_parse_launch(
      "videotestsrc num-buffers=2 ! videoscale ! video/x-raw,format=RGB ! tensor_converter ! "
      "tensor_filter name=tf framework=custom-easy model=tf_easy_280x40 ! fakesink",
      &err));
  ASSERT_EQ(err, nullptr) << err->message;
  GstElement *tf = gst_bin_get_by_name(GST_BIN(pipe.get()), "tf");
  std::string caps;
  GstPad *sink = gst_element_get_static_pad(tf, "sink");
  gulong id = gst_pad_add_probe(
      sink, GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM,
      [](GstPad *, GstPadProbeInfo *info, gpointer user) {
        GstEvent *ev = GST_PAD_PROBE_INFO_EVENT(info);
        if (GST_EVENT_TYPE(ev) == GST_EVENT_CAPS) {
          GstCaps *c = nullptr;
          gst_event_parse_caps(ev, &c);
          *static_cast<std::string *>(user) = nns::gst::caps_to_string(c);
        }
        return GST_PAD_PROBE_OK;
      },
      &caps, nullptr);
  auto r = run_pipeline(pipe.get());
  gst_pad_remove_probe(sink, id);
  gst_object_unref(sink);
  gst_object_unref(tf);
  EXPECT_TRUE(r.eos) << r.error_text;
  EXPECT_EQ(g_easy_calls.load(), 2);
  EXPECT_NE(caps.find("3:280:40:1"), std::string::npos) << caps;
}

// Caps honesty: a capsfilter asking for another type than the model produces does not get a
// flexible stream whose caps say so; negotiation fails naming both types.
TEST(TensorFilter, CapsfilterAskingAnotherTypeFailsNamingBoth) {
  EasyModel m("tf_easy_types", easy_copy, nullptr, _NNS_UINT8, {3, 4, 4, 1}, {3, 4, 4, 1});
  auto r = run_pipeline(
      "videotestsrc num-buffers=1 ! video/x-raw,format=RGB,width=4,height=4 ! tensor_converter ! "
      "tensor_filter name=tf framework=custom-easy model=tf_easy_types ! "
      "other/tensors,types=float32 ! fakesink");
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_EQ(r.error_source, "tf") << r.error_text;
  EXPECT_NE(r.error_text.find("say types=float32"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("produces uint8"), std::string::npos) << r.error_text;
}

// Several tensors spelled with '.' between them (upstream's tests and gst-launch lines) in
// capsfilters before and after the filter negotiate; other dimensions fail naming both.
TEST(TensorFilter, DotSpelledCapsfiltersAroundTwoTensors) {
  ScopedEnv conf("NNSTREAMER_CONF", test_ini());
  const std::string model = write_temp("m.echo", "echo");
  const std::string two =
      "videotestsrc num-buffers=2 ! video/x-raw,format=RGB,width=8,height=6,framerate=30/1 ! "
      "tensor_converter ! mux.sink_0 "
      "videotestsrc num-buffers=2 ! video/x-raw,format=GRAY8,width=4,height=2,framerate=30/1 ! "
      "tensor_converter ! tensor_transform mode=typecast option=float32 ! mux.sink_1 "
      "tensor_mux name=mux ! ";
  const std::string dot =
      "other/tensors,num_tensors=2,types=uint8.float32,dimensions=3:8:6:1.1:4:2:1 ! ";
  auto r = run_pipeline(two + dot + "tensor_filter framework=testecho model=" + model + " ! " +
                        dot + "fakesink");
  EXPECT_TRUE(r.eos) << r.error_text;
  r = run_pipeline(two + "tensor_filter name=f framework=testecho model=" + model +
                   " ! other/tensors,types=uint8.float32,dimensions=3:8:6:1.1:4:3:1 ! fakesink");
  ASSERT_TRUE(r.error) << "negotiated";
  EXPECT_NE(r.error_text.find("3:8:6:1.1:4:3:1"), std::string::npos) << r.error_text;
  EXPECT_NE(r.error_text.find("1:4:2:1"), std::string::npos) << r.error_text;
}

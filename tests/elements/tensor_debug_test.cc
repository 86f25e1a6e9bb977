// SPDX-License-Identifier: LGPL-2.1-only
// tensor_debug: what each capability mode and metadata flag logs, where each output-method
// sends it (stdout, stderr, GStreamer debug log), passthrough of the data, enum/flag types.
#include <gtest/gtest.h>

#include <mutex>

#include "core/meta_header.h"
#include "elements/cycle_check.h"
#include "elements/flow_harness.h"

namespace {

using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::Frame;
using nns::test::static_caps;

std::mutex g_m;
std::vector<std::string> g_out, g_err, g_gst;

void on_print(const gchar *s) {
  std::lock_guard<std::mutex> l(g_m);
  g_out.emplace_back(s);
}
void on_printerr(const gchar *s) {
  std::lock_guard<std::mutex> l(g_m);
  g_err.emplace_back(s);
}
void on_log(GstDebugCategory *cat, GstDebugLevel level, const gchar *, const gchar *, gint,
            GObject *, GstDebugMessage *msg, gpointer) {
  if (std::string(gst_debug_category_get_name(cat)) != "tensor_debug") return;
  std::lock_guard<std::mutex> l(g_m);
  // level names are padded ("INFO "): trim them
  std::string name = gst_debug_level_get_name(level);
  name.erase(name.find_last_not_of(' ') + 1);
  g_gst.push_back(name + " " + gst_debug_message_get(msg));
}

struct Captured {
  std::vector<std::string> out, err, gst;
  std::vector<Frame> frames;
  nns::test::RunResult r;
};

std::vector<Frame> static_frames() {
  std::vector<Frame> f;
  for (int i = 0; i < 3; ++i)
    f.push_back(Frame({Bytes{1, 2, 3, static_cast<uint8_t>(i)},
                       nns::test::bytes_of(std::vector<float>{0.5f, float(i)})},
                      static_cast<GstClockTime>(i + 1) * 10 * GST_MSECOND, 10 * GST_MSECOND));
  return f;
}

Captured run_debug(const std::string &props, const std::string &caps,
                   const std::vector<Frame> &frames) {
  {
    std::lock_guard<std::mutex> l(g_m);
    g_out.clear();
    g_err.clear();
    g_gst.clear();
  }
  GPrintFunc old_print = g_set_print_handler(on_print);
  GPrintFunc old_err = g_set_printerr_handler(on_printerr);
  gst_debug_set_active(TRUE);
  gst_debug_set_threshold_for_name("tensor_debug", GST_LEVEL_INFO);
  gst_debug_add_log_function(on_log, nullptr, nullptr);
  Captured c;
  {
    AppPipeline p("appsrc name=src ! tensor_debug name=dbg " + props + " ! appsink name=out");
    p.set_caps("src", caps);
    for (const auto &f : frames) p.push("src", f);
    p.eos("src");
    c.r = p.run(10);
    c.frames = p.frames("out");
  }
  gst_debug_remove_log_function(on_log);
  gst_debug_set_threshold_for_name("tensor_debug", GST_LEVEL_NONE);
  g_set_print_handler(old_print);
  g_set_printerr_handler(old_err);
  std::lock_guard<std::mutex> l(g_m);
  c.out = g_out;
  c.err = g_err;
  c.gst = g_gst;
  return c;
}

int count_with(const std::vector<std::string> &v, const std::string &s) {
  int n = 0;
  for (const auto &x : v) n += x.find(s) != std::string::npos;
  return n;
}

const std::string kCaps = static_caps("4,2", "uint8,float32", "100/1");

TEST(TensorDebug, DefaultLogsCapsOnceToStdoutAndPassesDataThrough) {
  auto c = run_debug("", kCaps, static_frames());
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(c.out.size(), 1u);
  EXPECT_EQ(c.out[0].rfind("[dbg] caps: other/tensors", 0), 0u) << c.out[0];
  EXPECT_NE(c.out[0].find("| static, 2 tensor(s): [0] uint8 4, [1] float32 2\n"), std::string::npos)
      << c.out[0];
  EXPECT_TRUE(c.err.empty());
  auto in = static_frames();
  ASSERT_EQ(c.frames.size(), 3u);
  for (int i = 0; i < 3; ++i) {
    EXPECT_EQ(c.frames[i].mems, in[i].mems);
    EXPECT_EQ(c.frames[i].pts, in[i].pts);
  }
}

TEST(TensorDebug, CapabilityModes) {
  auto c = run_debug("capability=always", kCaps, static_frames());
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  EXPECT_EQ(count_with(c.out, "caps: other/tensors"), 4);  // negotiation + every frame
  c = run_debug("capability=updates", kCaps, static_frames());
  EXPECT_EQ(count_with(c.out, "caps: "), 1);
  c = run_debug("capability=disabled", kCaps, static_frames());
  EXPECT_TRUE(c.out.empty());
}

TEST(TensorDebug, TimestampMetadata) {
  auto c = run_debug("capability=disabled metadata=timestamp", kCaps, static_frames());
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(c.out.size(), 3u);
  EXPECT_EQ(c.out[1],
            "[dbg] meta: pts 0:00:00.020000000, dts none, duration 0:00:00.010000000, offset "
            "none\n");
  c = run_debug("capability=disabled metadata=timestamp+queryserver", kCaps, static_frames());
  EXPECT_EQ(count_with(c.out, "meta: queryserver"), 3);
}

Bytes flex_mem(std::initializer_list<uint32_t> dims) {
  nns::MetaHeader h;
  h.type = nns::TensorType::kUInt8;
  h.dims = nns::make_dims(dims);
  h.format = nns::TensorFormat::kFlexible;
  Bytes b(nns::kMetaHeaderSize + h.payload_size(), 7);
  nns::write_meta_header(h, b.data());
  return b;
}

TEST(TensorDebug, UpdatesFullLogsFlexibleDimensionChanges) {
  std::vector<Frame> f{Frame({flex_mem({4})}, 0), Frame({flex_mem({4})}, GST_MSECOND),
                       Frame({flex_mem({2, 3})}, 2 * GST_MSECOND)};
  auto c = run_debug("capability=updates-full", "other/tensors,format=flexible,framerate=0/1", f);
  ASSERT_TRUE(c.r.eos) << c.r.error_text;
  ASSERT_EQ(count_with(c.out, "tensors: flexible, 1 tensor(s): [0] uint8 4\n"), 1);
  ASSERT_EQ(count_with(c.out, "tensors: flexible, 1 tensor(s): [0] uint8 2:3\n"), 1);
  c = run_debug("capability=updates", "other/tensors,format=flexible,framerate=0/1", f);
  EXPECT_EQ(count_with(c.out, "tensors: "), 0);
}

TEST(TensorDebug, OutputMethods) {
  auto c = run_debug("output-method=console-warn", kCaps, static_frames());
  EXPECT_TRUE(c.out.empty());
  ASSERT_EQ(c.err.size(), 1u);
  EXPECT_EQ(c.err[0].rfind("[dbg] WARNING: caps: ", 0), 0u) << c.err[0];
  c = run_debug("output-method=console-error", kCaps, static_frames());
  ASSERT_EQ(c.err.size(), 1u);
  EXPECT_EQ(c.err[0].rfind("[dbg] ERROR: caps: ", 0), 0u) << c.err[0];
  c = run_debug("output-method=gstdebug-info", kCaps, static_frames());
  EXPECT_TRUE(c.out.empty());
  EXPECT_TRUE(c.err.empty());
  ASSERT_EQ(count_with(c.gst, "INFO caps: other/tensors"), 1);
  c = run_debug("output-method=gstdebug-warn+console-info", kCaps, static_frames());
  EXPECT_EQ(count_with(c.gst, "WARN caps: "), 1);
  EXPECT_EQ(count_with(c.out, "caps: "), 1);
  c = run_debug("output-method=disabled capability=always metadata=timestamp", kCaps,
                static_frames());
  EXPECT_TRUE(c.out.empty() && c.err.empty() && c.gst.empty());
  EXPECT_EQ(c.frames.size(), 3u);
}

// 100 PLAYING<->NULL cycles logging caps and timestamps of every frame (to the GStreamer
// debug log, below its threshold); odd cycles end with EOS. No hang, nothing left alive.
TEST(TensorDebug, HundredPlayingNullCyclesNoHangNoLeak) {
  AppPipeline p(
      "appsrc name=src ! tensor_debug name=dbg capability=always metadata=timestamp "
      "output-method=gstdebug-info ! fakesink name=out");
  p.set_caps("src", kCaps);
  auto in = static_frames();
  nns::test::state_cycles(p.pipeline(), 100, [&](int i, nns::test::LiveObjects &live) {
    std::size_t before = live.delivered("out");
    for (const auto &f : in) p.push("src", f);
    if (i % 2) {
      p.eos("src");
      std::string err;
      EXPECT_TRUE(nns::test::wait_eos(p.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
    }
    EXPECT_TRUE(live.wait_delivered("out", before + in.size())) << "cycle " << i;
  });
}

TEST(TensorDebug, FlagAndEnumTypesAsUpstream) {
  GstElement *e = gst_element_factory_make("tensor_debug", nullptr);
  ASSERT_NE(e, nullptr);
  auto *cls = G_OBJECT_GET_CLASS(e);
  auto *out = G_PARAM_SPEC_FLAGS(g_object_class_find_property(cls, "output-method"));
  EXPECT_STREQ(g_type_name(G_PARAM_SPEC_VALUE_TYPE(out)), "gtd_output");
  EXPECT_EQ(out->default_value, 0x11u);
  struct {
    const char *nick;
    guint value;
  } flags[] = {{"disabled", 0},          {"console-info", 0x11},  {"console-warn", 0x12},
               {"console-error", 0x13},  {"gstdebug-info", 0x24}, {"gstdebug-warn", 0x28},
               {"gstdebug-error", 0x2C}, {"circularbuf", 0x100},  {"filewrite", 0x200}};
  for (const auto &f : flags) {
    GFlagsValue *v = g_flags_get_value_by_nick(out->flags_class, f.nick);
    ASSERT_NE(v, nullptr) << f.nick;
    EXPECT_EQ(v->value, f.value) << f.nick;
  }
  auto *cap = G_PARAM_SPEC_ENUM(g_object_class_find_property(cls, "capability"));
  EXPECT_STREQ(g_type_name(G_PARAM_SPEC_VALUE_TYPE(cap)), "gtd_cap");
  EXPECT_EQ(cap->default_value, 2);
  EXPECT_EQ(g_enum_get_value_by_name(cap->enum_class, "always")->value, 3);
  auto *meta = G_PARAM_SPEC_FLAGS(g_object_class_find_property(cls, "metadata"));
  EXPECT_STREQ(g_type_name(G_PARAM_SPEC_VALUE_TYPE(meta)), "gtd_meta");
  EXPECT_EQ(g_flags_get_value_by_nick(meta->flags_class, "queryserver")->value, 2u);
  gst_object_unref(e);
}

}  // namespace

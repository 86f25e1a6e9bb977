// SPDX-License-Identifier: LGPL-2.1-only
// tensor_if: every operator by name and by upstream nick, A_VALUE / TENSOR_AVERAGE_VALUE /
// CUSTOM, PASSTHROUGH / SKIP / TENSORPICK on both branches, enum/property compatibility and
// bus errors for options that disagree with the input.
#include <gtest/gtest.h>

#include "elements/cycle_check.h"
#include "elements/flow_harness.h"
#include "tensor_if.h"

namespace {

using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::Frame;
using nns::test::static_caps;

// Frames 0..9: tensor 0 = uint8[4] {i, 2i, 0, 1}, tensor 1 = float32[2] {i/2, -i}.
std::vector<Frame> frames() {
  std::vector<Frame> f;
  for (int i = 0; i < 10; ++i) {
    Bytes a{static_cast<uint8_t>(i), static_cast<uint8_t>(2 * i), 0, 1};
    Bytes b = nns::test::bytes_of(std::vector<float>{i / 2.0f, float(-i)});
    f.push_back(Frame({a, b}, static_cast<GstClockTime>(i) * 10 * GST_MSECOND));
  }
  return f;
}

struct Routed {
  nns::test::RunResult r;
  std::vector<Frame> then_out, else_out;
};

// Runs the frames through tensor_if with `props`; `branches` 0b01 links src_0, 0b10 src_1.
Routed route(const std::string &props, int branches = 3) {
  std::string desc = "appsrc name=src ! tensor_if name=tif " + props;
  if (branches & 1) desc += " tif.src_0 ! queue ! appsink name=then";
  if (branches & 2) desc += " tif.src_1 ! queue ! appsink name=else";
  AppPipeline p(desc);
  Routed out;
  if (!p.pipeline()) return out;
  p.set_caps("src", static_caps("4,2", "uint8,float32", "10/1"));
  for (const auto &f : frames()) p.push("src", f);
  p.eos("src");
  out.r = p.run(10);
  out.then_out = p.frames("then");
  out.else_out = p.frames("else");
  return out;
}

// Indices (value of tensor 0 element 0) of the frames in `fs`.
std::vector<int> ids(const std::vector<Frame> &fs) {
  std::vector<int> v;
  for (const auto &f : fs) v.push_back(f.mems.empty() ? -1 : f.mems[0][0]);
  return v;
}

struct OpCase {
  const char *name, *nick, *sv;
  std::vector<int> then_ids;
};

TEST(TensorIf, EveryOperatorByNameAndNick) {
  const OpCase cases[] = {
      {"EQ", "eqaual", "3", {3}},
      {"NE", "not_eqaual", "3", {0, 1, 2, 4, 5, 6, 7, 8, 9}},
      {"GT", "greater_than", "6", {7, 8, 9}},
      {"GE", "greater_or_equal", "6", {6, 7, 8, 9}},
      {"LT", "less_than", "2", {0, 1}},
      {"LE", "less_or_equal", "2", {0, 1, 2}},
      {"RANGE_INCLUSIVE", "range inclusive", "3,5", {3, 4, 5}},
      {"RANGE_EXCLUSIVE", "range exclusive", "3,5", {4}},
      {"NOT_IN_RANGE_INCLUSIVE", "not in range inclusive", "3,5", {0, 1, 2, 6, 7, 8, 9}},
      {"NOT_IN_RANGE_EXCLUSIVE", "not in range exclusive", "3,5", {0, 1, 2, 3, 5, 6, 7, 8, 9}},
  };
  for (const auto &c : cases) {
    for (std::string op : {std::string(c.name), "\"" + std::string(c.nick) + "\""}) {
      auto res = route("compared-value=A_VALUE compared-value-option=0:0:0:0,0 operator=" + op +
                       " supplied-value=" + c.sv + " then=PASSTHROUGH else=PASSTHROUGH");
      ASSERT_TRUE(res.r.eos) << op << ": " << res.r.error_text;
      EXPECT_EQ(ids(res.then_out), c.then_ids) << op;
      EXPECT_EQ(res.then_out.size() + res.else_out.size(), 10u) << op;
    }
  }
}

TEST(TensorIf, PassthroughKeepsFrameAndTimestamps) {
  auto res = route("compared-value-option=1:0:0:0,0 operator=GE supplied-value=10");
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  ASSERT_EQ(ids(res.then_out), (std::vector<int>{5, 6, 7, 8, 9}));
  auto in = frames();
  for (const auto &f : res.then_out) {
    int i = f.mems[0][0];
    EXPECT_EQ(f.mems, in[i].mems);
    EXPECT_EQ(f.pts, in[i].pts);
  }
  EXPECT_NE(res.then_out[0].caps.find("num_tensors=(int)2"), std::string::npos)
      << res.then_out[0].caps;
}

TEST(TensorIf, FloatElementOfSecondTensor) {
  // tensor 1 element 0 = i/2 > 2.2 -> i >= 5
  auto res = route("compared-value-option=0,1 operator=GT supplied-value=2.2");
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  EXPECT_EQ(ids(res.then_out), (std::vector<int>{5, 6, 7, 8, 9}));
  // element 1 = -i: in [-7,-4] for i in 4..7
  res = route("compared-value-option=1,1 operator=RANGE_INCLUSIVE supplied-value=-7,-4");
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  EXPECT_EQ(ids(res.then_out), (std::vector<int>{4, 5, 6, 7}));
}

TEST(TensorIf, TensorAverageValue) {
  // average of uint8 {i, 2i, 0, 1} = (3i+1)/4, cast to uint8: >= 4 when 3i+1 >= 16 -> i >= 5
  auto res = route(
      "compared-value=TENSOR_AVERAGE_VALUE compared-value-option=0 operator=GE "
      "supplied-value=4");
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  EXPECT_EQ(ids(res.then_out), (std::vector<int>{5, 6, 7, 8, 9}));
  // float average of {i/2, -i} = -i/4 < -1.5 -> i > 6
  res = route(
      "compared-value=TENSOR_AVERAGE_VALUE compared-value-option=1 operator=LT "
      "supplied-value=-1.5");
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  EXPECT_EQ(ids(res.then_out), (std::vector<int>{7, 8, 9}));
}

TEST(TensorIf, SkipAndTensorPick) {
  auto res = route(
      "compared-value-option=0,0 operator=LT supplied-value=3 then=TENSORPICK "
      "then-option=1 else=SKIP",
      1);
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  ASSERT_EQ(res.then_out.size(), 3u);
  auto in = frames();
  for (int i = 0; i < 3; ++i) {
    ASSERT_EQ(res.then_out[i].mems.size(), 1u);
    EXPECT_EQ(res.then_out[i].mems[0], in[i].mems[1]);
    EXPECT_EQ(res.then_out[i].pts, in[i].pts);
  }
  EXPECT_NE(res.then_out[0].caps.find("types=(string)float32"), std::string::npos)
      << res.then_out[0].caps;
  // else branch picks tensors 1 then 0 (order kept, duplicates allowed)
  res = route(
      "compared-value-option=0,0 operator=LT supplied-value=3 then=SKIP "
      "else=TENSORPICK else-option=1,0",
      2);
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  ASSERT_EQ(res.else_out.size(), 7u);
  EXPECT_EQ(res.else_out[0].mems[0], in[3].mems[1]);
  EXPECT_EQ(res.else_out[0].mems[1], in[3].mems[0]);
}

gboolean odd_first(const GstTensorsInfo *info, const GstTensorMemory *input, void *data,
                   gboolean *result) {
  auto *calls = static_cast<int *>(data);
  ++*calls;
  if (info->num_tensors != 2 || input[0].size != 4 || input[1].size != 8) return FALSE;
  *result = (static_cast<const uint8_t *>(input[0].data)[0] % 2) == 1;
  return TRUE;
}

gboolean failing(const GstTensorsInfo *, const GstTensorMemory *, void *, gboolean *) {
  return FALSE;
}

TEST(TensorIf, CustomCondition) {
  int calls = 0;
  ASSERT_EQ(nnstreamer_if_custom_register("odd_first", odd_first, &calls), 0);
  EXPECT_EQ(nnstreamer_if_custom_register("odd_first", odd_first, &calls), -EINVAL);
  EXPECT_EQ(nnstreamer_if_custom_register("", odd_first, &calls), -EINVAL);
  EXPECT_EQ(nnstreamer_if_custom_register("x", nullptr, &calls), -EINVAL);
  auto res = route("compared-value=CUSTOM compared-value-option=odd_first");
  ASSERT_TRUE(res.r.eos) << res.r.error_text;
  EXPECT_EQ(ids(res.then_out), (std::vector<int>{1, 3, 5, 7, 9}));
  EXPECT_EQ(ids(res.else_out), (std::vector<int>{0, 2, 4, 6, 8}));
  EXPECT_EQ(calls, 10);
  EXPECT_EQ(nnstreamer_if_custom_unregister("odd_first"), 0);
  EXPECT_EQ(nnstreamer_if_custom_unregister("odd_first"), -EINVAL);

  res = route("compared-value=CUSTOM compared-value-option=odd_first");
  ASSERT_TRUE(res.r.error);
  EXPECT_NE(res.r.error_text.find(
                "tif: compared-value-option: no custom condition is registered as 'odd_first'"),
            std::string::npos)
      << res.r.error_text;

  ASSERT_EQ(nnstreamer_if_custom_register("failing", failing, nullptr), 0);
  res = route("compared-value=CUSTOM compared-value-option=failing");
  ASSERT_TRUE(res.r.error);
  EXPECT_NE(res.r.error_text.find("custom condition 'failing' returned an error"),
            std::string::npos)
      << res.r.error_text;
  nnstreamer_if_custom_unregister("failing");
}

TEST(TensorIf, OptionsThatDisagreeWithTheInputAreBusErrors) {
  struct Case {
    const char *props, *text;
  } cases[] = {
      {"compared-value-option=0,2 supplied-value=1",
       "tif: compared-value-option='0,2' names tensor 2 but the input has 2 tensor(s)"},
      {"compared-value-option=4,0 supplied-value=1",
       "index 4 of dimension 0 is outside tensor 0 (uint8 4)"},
      {"compared-value=TENSOR_AVERAGE_VALUE compared-value-option=3 supplied-value=1",
       "compared-value-option='3' names tensor 3 but the input has 2 tensor(s)"},
      {"compared-value-option=0,0 supplied-value=1 then=TENSORPICK then-option=0,5",
       "tif: then-option picks tensor 5 but the input has 2 tensor(s)"},
      {"compared-value-option=0,0 supplied-value=1 else=TENSORPICK else-option=7",
       "tif: else-option picks tensor 7 but the input has 2 tensor(s)"},
      {"compared-value-option=0,0 supplied-value=1 operator=RANGE_INCLUSIVE",
       "operator RANGE_INCLUSIVE needs two supplied values"},
      {"compared-value-option=0,0", "supplied-value is not set"},
      {"compared-value-option=0,0 supplied-value=abc", "supplied-value: 'abc'"},
      {"compared-value-option=0:0:0:0 supplied-value=1", "compared-value-option: '0:0:0:0'"},
  };
  for (const auto &c : cases) {
    auto res = route(c.props, 1);
    ASSERT_TRUE(res.r.error) << c.props;
    EXPECT_NE(res.r.error_text.find(c.text), std::string::npos)
        << c.props << " -> " << res.r.error_text;
  }
}

TEST(TensorIf, EnumsAndDefaultsAsUpstream) {
  GstElement *e = gst_element_factory_make("tensor_if", nullptr);
  ASSERT_NE(e, nullptr);
  auto enum_of = [&](const char *prop) {
    return G_PARAM_SPEC_ENUM(g_object_class_find_property(G_OBJECT_GET_CLASS(e), prop));
  };
  GEnumClass *cv = enum_of("compared-value")->enum_class;
  EXPECT_STREQ(g_type_name(G_TYPE_FROM_CLASS(cv)), "tensor_if_compared_value");
  EXPECT_EQ(g_enum_get_value_by_name(cv, "A_VALUE")->value, 0);
  EXPECT_EQ(g_enum_get_value_by_name(cv, "TENSOR_AVERAGE_VALUE")->value, 3);
  EXPECT_EQ(g_enum_get_value_by_name(cv, "CUSTOM")->value, 5);
  GEnumClass *op = enum_of("operator")->enum_class;
  EXPECT_STREQ(g_type_name(G_TYPE_FROM_CLASS(op)), "tensor_if_operator");
  EXPECT_EQ(g_enum_get_value_by_nick(op, "not_eqaual")->value, 1);
  EXPECT_EQ(g_enum_get_value_by_name(op, "NOT_IN_RANGE_EXCLUSIVE")->value, 9);
  GEnumClass *act = enum_of("then")->enum_class;
  EXPECT_STREQ(g_type_name(G_TYPE_FROM_CLASS(act)), "tensor_if_behavior");
  EXPECT_EQ(g_enum_get_value_by_name(act, "TENSORPICK")->value, 7);
  EXPECT_EQ(g_enum_get_value_by_nick(act, "skip")->value, 1);
  gint then_v, else_v, op_v, cv_v;
  gboolean silent;
  gchar *cvo, *sv;
  g_object_get(e, "then", &then_v, "else", &else_v, "operator", &op_v, "compared-value", &cv_v,
               "silent", &silent, "compared-value-option", &cvo, "supplied-value", &sv, nullptr);
  EXPECT_EQ(then_v, 0);
  EXPECT_EQ(else_v, 0);
  EXPECT_EQ(op_v, 0);
  EXPECT_EQ(cv_v, 0);
  EXPECT_TRUE(silent);
  EXPECT_STREQ(cvo, "");
  EXPECT_STREQ(sv, "");
  g_free(cvo);
  g_free(sv);
  GstPadTemplate *t = gst_element_class_get_pad_template(GST_ELEMENT_GET_CLASS(e), "src");
  ASSERT_NE(t, nullptr);
  EXPECT_EQ(GST_PAD_TEMPLATE_PRESENCE(t), GST_PAD_SOMETIMES);
  gst_object_unref(e);
}

}  // namespace

namespace {

// Every frame goes to src_1: the sink on src_0 prerolls on the GAP events and the pipeline
// still ends (clock-synced sinks, no hang).
TEST(TensorIf, BranchWithoutDataDoesNotBlockPrerollOrEos) {
  auto r = nns::test::run_pipeline(
      "videotestsrc num-buffers=6 ! video/x-raw,format=GRAY8,width=4,height=4,framerate=60/1 ! "
      "tensor_converter ! tensor_if name=tif compared-value-option=0:0:0:0,0 operator=GT "
      "supplied-value=1000 tif.src_0 ! queue ! fakesink sync=true "
      "tif.src_1 ! queue ! fakesink sync=true",
      10);
  EXPECT_TRUE(r.eos) << r.error_text << (r.timed_out ? " (timed out)" : "");
}

// 100 PLAYING<->NULL cycles with a frame for each branch (then passes it through, else picks
// tensor 1); odd cycles end with EOS. No hang, nothing left alive.
TEST(TensorIf, HundredPlayingNullCyclesNoHangNoLeak) {
  AppPipeline p(
      "appsrc name=src ! tensor_if name=tif compared-value-option=0:0:0:0,0 operator=LT "
      "supplied-value=3 then=PASSTHROUGH else=TENSORPICK else-option=1 "
      "tif.src_0 ! queue ! fakesink name=then tif.src_1 ! queue ! fakesink name=else");
  p.set_caps("src", static_caps("4,2", "uint8,float32", "10/1"));
  auto in = frames();
  nns::test::state_cycles(p.pipeline(), 100, [&](int i, nns::test::LiveObjects &live) {
    std::size_t t = live.delivered("then"), e = live.delivered("else");
    p.push("src", in[1]);
    p.push("src", in[7]);
    if (i % 2) {
      p.eos("src");
      std::string err;
      EXPECT_TRUE(nns::test::wait_eos(p.pipeline(), 10, &err)) << "cycle " << i << ": " << err;
    }
    EXPECT_TRUE(live.wait_delivered("then", t + 1)) << "cycle " << i;
    EXPECT_TRUE(live.wait_delivered("else", e + 1)) << "cycle " << i;
  });
}

}  // namespace

// SPDX-License-Identifier: LGPL-2.1-only
// Pipeline API: construct/start/stop/flush/destroy with state callbacks, sinks (tensor_sink and
// appsink) and sources (appsrc) with exact data through a custom-easy filter, buffer policies,
// and the error codes and ml_error() texts of wrong arguments.
#include <atomic>
#include <mutex>

#include "api/ml_pipeline_test_util.h"

using namespace capi_test;

namespace {

// out[i] = 2 * in[i] + 1 (uint8[4] -> float32[4]).
int double_plus_one(const ml_tensors_data_h in, ml_tensors_data_h out, void *user) {
  void *ip = nullptr, *op = nullptr;
  size_t is = 0, os = 0;
  if (ml_tensors_data_get_tensor_data(in, 0, &ip, &is) != ML_ERROR_NONE) return -1;
  if (ml_tensors_data_get_tensor_data(out, 0, &op, &os) != ML_ERROR_NONE) return -1;
  if (is != 4 || os != 16) return -1;
  for (int i = 0; i < 4; ++i)
    static_cast<float *>(op)[i] = 2.0f * static_cast<uint8_t *>(ip)[i] + 1.0f;
  if (user) ++*static_cast<std::atomic<int> *>(user);
  return 0;
}

struct States {
  std::mutex m;
  std::vector<ml_pipeline_state_e> seen;
  static void cb(ml_pipeline_state_e s, void *user) {
    auto *st = static_cast<States *>(user);
    std::lock_guard lk(st->m);
    st->seen.push_back(s);
  }
  bool saw(ml_pipeline_state_e s) {
    std::lock_guard lk(m);
    for (auto x : seen)
      if (x == s) return true;
    return false;
  }
};

bool wait_state(ml_pipeline_h p, ml_pipeline_state_e want, double seconds = 5) {
  auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (std::chrono::steady_clock::now() < end) {
    ml_pipeline_state_e s = ML_PIPELINE_STATE_UNKNOWN;
    if (ml_pipeline_get_state(p, &s) == ML_ERROR_NONE && s == want) return true;
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  }
  return false;
}

// appsrc (uint8[4]) -> custom-easy "capi_dpo" -> sink `sink_desc`.
class CustomEasyPipe : public ::testing::Test {
 protected:
  void SetUp() override {
    in_ = make_info({{ML_TENSOR_TYPE_UINT8, {4}}});
    out_ = make_info({{ML_TENSOR_TYPE_FLOAT32, {4}}});
    ASSERT_EQ(ml_pipeline_custom_easy_filter_register("capi_dpo", in_, out_, double_plus_one,
                                                      &calls_, &custom_),
              ML_ERROR_NONE)
        << ml_error();
  }
  void TearDown() override {
    if (pipe_) {
      EXPECT_EQ(ml_pipeline_destroy(pipe_), ML_ERROR_NONE) << ml_error();
    }
    EXPECT_EQ(ml_pipeline_custom_easy_filter_unregister(custom_), ML_ERROR_NONE) << ml_error();
    ml_tensors_info_destroy(in_);
    ml_tensors_info_destroy(out_);
  }
  void build(const std::string &sink = "tensor_sink name=sink async=false") {
    std::string d = "appsrc name=src caps=" + tensor_caps("4:1:1:1", "uint8") +
                    " ! tensor_filter framework=custom-easy model=capi_dpo ! " + sink;
    ASSERT_EQ(ml_pipeline_construct(d.c_str(), States::cb, &states_, &pipe_), ML_ERROR_NONE)
        << ml_error();
  }
  void push(ml_pipeline_src_h src, uint8_t base) {
    ml_tensors_data_h d =
        make_data(in_, {{base, uint8_t(base + 1), uint8_t(base + 2), uint8_t(base + 3)}});
    ASSERT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_AUTO_FREE), ML_ERROR_NONE)
        << ml_error();
  }
  static std::vector<float> expect(uint8_t base) {
    return {2.f * base + 1, 2.f * (base + 1) + 1, 2.f * (base + 2) + 1, 2.f * (base + 3) + 1};
  }

  ml_tensors_info_h in_ = nullptr, out_ = nullptr;
  ml_custom_easy_filter_h custom_ = nullptr;
  ml_pipeline_h pipe_ = nullptr;
  std::atomic<int> calls_{0};
  States states_;
};

}  // namespace

TEST(MlPipeline, ConstructStartStopDestroyWithStateCallback) {
  States st;
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct("videotestsrc is-live=true ! video/x-raw,format=RGB,width=4,"
                                  "height=4,framerate=60/1 ! tensor_converter ! "
                                  "tensor_sink name=sink",
                                  States::cb, &st, &p),
            ML_ERROR_NONE)
      << ml_error();
  EXPECT_TRUE(st.saw(ML_PIPELINE_STATE_READY));
  Collector c;
  ml_pipeline_sink_h s = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", Collector::cb, &c, &s), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE) << ml_error();
  EXPECT_TRUE(wait_state(p, ML_PIPELINE_STATE_PLAYING));
  EXPECT_TRUE(st.saw(ML_PIPELINE_STATE_PLAYING));
  ASSERT_TRUE(c.wait_for(3));
  {
    std::lock_guard lk(c.m);
    ASSERT_EQ(c.frames[0].tensors.size(), 1u);
    EXPECT_EQ(c.frames[0].tensors[0].size(), 48u);
    EXPECT_EQ(c.frames[0].types[0], ML_TENSOR_TYPE_UINT8);
    EXPECT_EQ(c.frames[0].dims[0], (std::vector<unsigned>{3, 4, 4, 1}));
  }
  ASSERT_EQ(ml_pipeline_stop(p), ML_ERROR_NONE) << ml_error();
  EXPECT_TRUE(wait_state(p, ML_PIPELINE_STATE_PAUSED));
  ASSERT_EQ(ml_pipeline_flush(p, true), ML_ERROR_NONE) << ml_error();
  EXPECT_TRUE(wait_state(p, ML_PIPELINE_STATE_PLAYING));
  EXPECT_EQ(ml_pipeline_sink_unregister(s), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE) << ml_error();
  // The handle is gone: a second destroy says so.
  EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("not a live pipeline"), std::string::npos) << ml_error();
}

TEST(MlPipeline, ConstructEndsPausedWhenThePipelinePrerolls) {
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct("videotestsrc num-buffers=3 ! video/x-raw,format=GRAY8,width=4,"
                                  "height=4 ! tensor_converter ! tensor_sink name=sink",
                                  nullptr, nullptr, &p),
            ML_ERROR_NONE);
  ml_pipeline_state_e s = ML_PIPELINE_STATE_UNKNOWN;
  EXPECT_EQ(ml_pipeline_get_state(p, &s), ML_ERROR_NONE);
  EXPECT_EQ(s, ML_PIPELINE_STATE_PAUSED);
  EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE);
}

TEST(MlPipeline, UnknownElementIsNamed) {
  ml_pipeline_h p = reinterpret_cast<ml_pipeline_h>(0x1);
  EXPECT_EQ(ml_pipeline_construct("videotestsrc ! tensor_fitler ! fakesink", nullptr, nullptr, &p),
            ML_ERROR_STREAMS_PIPE);
  EXPECT_EQ(p, nullptr);
  std::string e = ml_error();
  EXPECT_NE(e.find("tensor_fitler"), std::string::npos) << e;
  EXPECT_NE(e.find("unknown element"), std::string::npos) << e;
}

TEST(MlPipeline, FailureToPauseCarriesTheElementError) {
  ml_pipeline_h p = nullptr;
  EXPECT_EQ(ml_pipeline_construct("filesrc name=fsrc location=/nonexistent/capi.bin ! fakesink",
                                  nullptr, nullptr, &p),
            ML_ERROR_STREAMS_PIPE);
  EXPECT_EQ(p, nullptr);
  std::string e = ml_error();
  EXPECT_NE(e.find("cannot go to PAUSED: fsrc: "), std::string::npos) << e;
  EXPECT_NE(e.find("/nonexistent/capi.bin"), std::string::npos) << e;
}

TEST(MlPipeline, NullArguments) {
  ml_pipeline_h p = nullptr;
  EXPECT_EQ(ml_pipeline_construct(nullptr, nullptr, nullptr, &p), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_construct("fakesrc ! fakesink", nullptr, nullptr, nullptr),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_destroy(nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_start(nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_stop(nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_flush(nullptr, false), ML_ERROR_INVALID_PARAMETER);
  ml_pipeline_state_e s;
  EXPECT_EQ(ml_pipeline_get_state(nullptr, &s), ML_ERROR_INVALID_PARAMETER);
  ASSERT_EQ(ml_pipeline_construct("appsrc name=src ! tensor_sink name=sink", nullptr, nullptr, &p),
            ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_get_state(p, nullptr), ML_ERROR_INVALID_PARAMETER);
  ml_pipeline_sink_h sh;
  EXPECT_EQ(ml_pipeline_sink_register(p, nullptr, Collector::cb, nullptr, &sh),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_sink_register(p, "sink", nullptr, nullptr, &sh),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_sink_register(p, "sink", Collector::cb, nullptr, nullptr),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_sink_unregister(nullptr), ML_ERROR_INVALID_PARAMETER);
  ml_pipeline_src_h src;
  EXPECT_EQ(ml_pipeline_src_get_handle(p, nullptr, &src), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_src_get_handle(p, "src", nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_src_release_handle(nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_src_input_data(nullptr, nullptr, ML_PIPELINE_BUF_POLICY_AUTO_FREE),
            ML_ERROR_INVALID_PARAMETER);
  ASSERT_EQ(ml_pipeline_src_get_handle(p, "src", &src), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_src_input_data(src, nullptr, ML_PIPELINE_BUF_POLICY_AUTO_FREE),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_src_set_event_cb(src, nullptr, nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_src_get_tensors_info(src, nullptr), ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_src_release_handle(src), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE);
}

TEST(MlPipeline, WrongElementKindsAreNamed) {
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct("appsrc name=src ! queue name=q ! tensor_sink name=sink", nullptr,
                                  nullptr, &p),
            ML_ERROR_NONE);
  ml_pipeline_sink_h sh = nullptr;
  EXPECT_EQ(ml_pipeline_sink_register(p, "q", Collector::cb, nullptr, &sh),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("'q' is a queue, not a tensor_sink or appsink"),
            std::string::npos)
      << ml_error();
  EXPECT_EQ(ml_pipeline_sink_register(p, "nope", Collector::cb, nullptr, &sh),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("no element named 'nope'"), std::string::npos)
      << ml_error();
  EXPECT_NE(std::string(ml_error()).find("its sinks: 'sink'"), std::string::npos) << ml_error();
  ml_pipeline_src_h src = nullptr;
  EXPECT_EQ(ml_pipeline_src_get_handle(p, "sink", &src), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("'sink' is a tensor_sink, not an appsrc"),
            std::string::npos)
      << ml_error();
  EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE);
}

TEST_F(CustomEasyPipe, ExactDataThroughSinkCallback) {
  build();
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(pipe_, "src", &src), ML_ERROR_NONE) << ml_error();
  ml_tensors_info_h got = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_tensors_info(src, &got), ML_ERROR_NONE) << ml_error();
  unsigned n = 0;
  ml_tensor_type_e t;
  ml_tensor_dimension dim{};
  ml_tensors_info_get_count(got, &n);
  ml_tensors_info_get_tensor_type(got, 0, &t);
  ml_tensors_info_get_tensor_dimension(got, 0, dim);
  EXPECT_EQ(n, 1u);
  EXPECT_EQ(t, ML_TENSOR_TYPE_UINT8);
  EXPECT_EQ(dim[0], 4u);
  EXPECT_EQ(dim[1], 1u);
  ml_tensors_info_destroy(got);

  Collector c;
  ml_pipeline_sink_h sink = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(pipe_, "sink", Collector::cb, &c, &sink), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(pipe_), ML_ERROR_NONE) << ml_error();
  for (uint8_t b = 0; b < 50; b += 10) push(src, b);
  ASSERT_TRUE(c.wait_for(5));
  std::lock_guard lk(c.m);
  ASSERT_EQ(c.frames.size(), 5u);
  for (int i = 0; i < 5; ++i) {
    ASSERT_EQ(c.frames[i].tensors.size(), 1u);
    EXPECT_EQ(c.frames[i].types[0], ML_TENSOR_TYPE_FLOAT32);
    EXPECT_EQ(c.frames[i].dims[0], (std::vector<unsigned>{4, 1, 1, 1}));
    EXPECT_EQ(as_f32(c.frames[i].tensors[0]), expect(uint8_t(10 * i)));
    EXPECT_NE(c.threads[i], std::this_thread::get_id());  // streaming thread
  }
  EXPECT_EQ(calls_.load(), 5);
  EXPECT_EQ(ml_pipeline_sink_unregister(sink), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_src_release_handle(src), ML_ERROR_NONE);
}

TEST_F(CustomEasyPipe, AppsinkGetsTheSameData) {
  build("appsink name=out sync=false");
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(pipe_, "src", &src), ML_ERROR_NONE);
  Collector c;
  ml_pipeline_sink_h sink = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(pipe_, "out", Collector::cb, &c, &sink), ML_ERROR_NONE)
      << ml_error();
  ASSERT_EQ(ml_pipeline_start(pipe_), ML_ERROR_NONE);
  push(src, 7);
  push(src, 100);
  ASSERT_TRUE(c.wait_for(2));
  std::lock_guard lk(c.m);
  EXPECT_EQ(as_f32(c.frames[0].tensors[0]), expect(7));
  EXPECT_EQ(as_f32(c.frames[1].tensors[0]), expect(100));
  EXPECT_EQ(c.frames[1].types[0], ML_TENSOR_TYPE_FLOAT32);
}

TEST_F(CustomEasyPipe, WrongInputSizeNamesExpectedAndReceived) {
  build();
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(pipe_, "src", &src), ML_ERROR_NONE);
  ml_tensors_info_h three = make_info({{ML_TENSOR_TYPE_UINT8, {3}}});
  ml_tensors_data_h d = make_data(three, {{1, 2, 3}});
  EXPECT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_AUTO_FREE),
            ML_ERROR_INVALID_PARAMETER);
  std::string e = ml_error();
  EXPECT_NE(e.find("tensor 0 of the data has 3 bytes but appsrc 'src' expects 4 bytes"),
            std::string::npos)
      << e;
  // Not taken on failure: the caller still owns it.
  EXPECT_EQ(ml_tensors_data_destroy(d), ML_ERROR_NONE);
  ml_tensors_info_h two = make_info({{ML_TENSOR_TYPE_UINT8, {4}}, {ML_TENSOR_TYPE_UINT8, {4}}});
  d = make_data(two, {{1, 2, 3, 4}, {5, 6, 7, 8}});
  EXPECT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_AUTO_FREE),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("expects 1 tensor(s)"), std::string::npos) << ml_error();
  EXPECT_NE(std::string(ml_error()).find("the data has 2"), std::string::npos) << ml_error();
  ml_tensors_data_destroy(d);
  EXPECT_EQ(ml_pipeline_src_input_data(src, d, static_cast<ml_pipeline_buf_policy_e>(7)),
            ML_ERROR_INVALID_PARAMETER);
  ml_tensors_info_destroy(three);
  ml_tensors_info_destroy(two);
}

TEST_F(CustomEasyPipe, DoNotFreeKeepsTheCallersBuffer) {
  build();
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(pipe_, "src", &src), ML_ERROR_NONE);
  Collector c;
  ml_pipeline_sink_h sink = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(pipe_, "sink", Collector::cb, &c, &sink), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(pipe_), ML_ERROR_NONE);
  ml_tensors_data_h d = make_data(in_, {{9, 8, 7, 6}});
  ASSERT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_DO_NOT_FREE), ML_ERROR_NONE);
  ASSERT_TRUE(c.wait_for(1));
  // Still ours: readable and pushable again.
  void *raw = nullptr;
  size_t size = 0;
  ASSERT_EQ(ml_tensors_data_get_tensor_data(d, 0, &raw, &size), ML_ERROR_NONE);
  EXPECT_EQ(static_cast<uint8_t *>(raw)[0], 9);
  ASSERT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_DO_NOT_FREE), ML_ERROR_NONE);
  ASSERT_TRUE(c.wait_for(2));
  {
    std::lock_guard lk(c.m);
    EXPECT_EQ(as_f32(c.frames[1].tensors[0]), (std::vector<float>{19, 17, 15, 13}));
  }
  EXPECT_EQ(ml_pipeline_sink_unregister(sink), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_destroy(pipe_), ML_ERROR_NONE);
  pipe_ = nullptr;
  EXPECT_EQ(ml_tensors_data_destroy(d), ML_ERROR_NONE);
}

TEST_F(CustomEasyPipe, EndOfStreamPolicy) {
  build();
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(pipe_, "src", &src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(pipe_), ML_ERROR_NONE);
  push(src, 1);
  EXPECT_EQ(ml_pipeline_src_input_data(src, nullptr, ML_PIPELINE_BUF_SRC_EVENT_EOS), ML_ERROR_NONE);
  ml_tensors_data_h d = make_data(in_, {{1, 2, 3, 4}});
  EXPECT_EQ(ml_pipeline_src_input_data(src, d, ML_PIPELINE_BUF_POLICY_AUTO_FREE),
            ML_ERROR_STREAMS_PIPE);
  EXPECT_NE(std::string(ml_error()).find("end-of-stream"), std::string::npos) << ml_error();
}

TEST_F(CustomEasyPipe, TwoSinkCallbacksAndUnregister) {
  build();
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(pipe_, "src", &src), ML_ERROR_NONE);
  Collector a, b;
  ml_pipeline_sink_h ha = nullptr, hb = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(pipe_, "sink", Collector::cb, &a, &ha), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_sink_register(pipe_, "sink", Collector::cb, &b, &hb), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(pipe_), ML_ERROR_NONE);
  push(src, 1);
  ASSERT_TRUE(a.wait_for(1));
  ASSERT_TRUE(b.wait_for(1));
  ASSERT_EQ(ml_pipeline_sink_unregister(ha), ML_ERROR_NONE);
  EXPECT_EQ(ml_pipeline_sink_unregister(ha), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("not a live handle"), std::string::npos) << ml_error();
  push(src, 2);
  ASSERT_TRUE(b.wait_for(2));
  EXPECT_EQ(a.count(), 1u);
  std::lock_guard lk(b.m);
  EXPECT_EQ(as_f32(b.frames[1].tensors[0]), expect(2));
}

TEST_F(CustomEasyPipe, SrcEventCallbacks) {
  build();
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(pipe_, "src", &src), ML_ERROR_NONE);
  static std::atomic<int> need{0};
  need = 0;
  ml_pipeline_src_callbacks_s cbs{};
  cbs.need_data = [](ml_pipeline_src_h, unsigned int, void *u) {
    ++*static_cast<std::atomic<int> *>(u);
  };
  ASSERT_EQ(ml_pipeline_src_set_event_cb(src, &cbs, &need), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(pipe_), ML_ERROR_NONE);
  // need-data comes when the queue runs empty after this frame is taken.
  push(src, 3);
  for (int i = 0; i < 200 && need.load() == 0; ++i)
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
  EXPECT_GT(need.load(), 0);
  EXPECT_EQ(ml_pipeline_src_release_handle(src), ML_ERROR_NONE);
}

TEST_F(CustomEasyPipe, UnregisterWhileUsedIsRefused) {
  build();
  ml_custom_easy_filter_h dup = nullptr;
  EXPECT_EQ(ml_pipeline_custom_easy_filter_register("capi_dpo", in_, out_, double_plus_one, nullptr,
                                                    &dup),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("already registered"), std::string::npos) << ml_error();
  EXPECT_EQ(ml_pipeline_custom_easy_filter_unregister(custom_), ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("is used by 1 pipeline(s)"), std::string::npos)
      << ml_error();
  // TearDown destroys the pipeline first, then unregisters successfully.
}

TEST(MlPipeline, CustomEasyArguments) {
  ml_tensors_info_h ok = make_info({{ML_TENSOR_TYPE_UINT8, {4}}});
  ml_tensors_info_h empty = nullptr;
  ml_tensors_info_create(&empty);
  ml_custom_easy_filter_h h = nullptr;
  EXPECT_EQ(ml_pipeline_custom_easy_filter_register(nullptr, ok, ok, double_plus_one, nullptr, &h),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_custom_easy_filter_register("x", ok, ok, nullptr, nullptr, &h),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_custom_easy_filter_register("x", ok, ok, double_plus_one, nullptr, nullptr),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_EQ(ml_pipeline_custom_easy_filter_register("x", empty, ok, double_plus_one, nullptr, &h),
            ML_ERROR_INVALID_PARAMETER);
  EXPECT_NE(std::string(ml_error()).find("in is not a valid tensors-info"), std::string::npos);
  EXPECT_EQ(ml_pipeline_custom_easy_filter_unregister(nullptr), ML_ERROR_INVALID_PARAMETER);
  ml_tensors_info_destroy(ok);
  ml_tensors_info_destroy(empty);
}

TEST(MlPipeline, FlexibleTensorsCarryTheirOwnInfo) {
  // appsrc with flexible caps: input_data adds each tensor's header; the sink callback gets the
  // payload and the info from the headers, so frames of different shapes pass.
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(
      ml_pipeline_construct("appsrc name=src caps=other/tensors,format=flexible,framerate=0/1 "
                            "! tensor_sink name=sink async=false",
                            nullptr, nullptr, &p),
      ML_ERROR_NONE)
      << ml_error();
  Collector c;
  ml_pipeline_sink_h s = nullptr;
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", Collector::cb, &c, &s), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_src_get_handle(p, "src", &src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ml_tensors_info_h a = make_info({{ML_TENSOR_TYPE_INT16, {3, 2}}});
  ml_tensors_info_h b = make_info({{ML_TENSOR_TYPE_FLOAT32, {2}}, {ML_TENSOR_TYPE_UINT8, {5}}});
  ASSERT_EQ(ml_pipeline_src_input_data(src, make_data(a, {Bytes(12, 7)}),
                                       ML_PIPELINE_BUF_POLICY_AUTO_FREE),
            ML_ERROR_NONE)
      << ml_error();
  ASSERT_EQ(
      ml_pipeline_src_input_data(src, make_data(b, {f32_bytes({1.5f, -2}), Bytes{1, 2, 3, 4, 5}}),
                                 ML_PIPELINE_BUF_POLICY_AUTO_FREE),
      ML_ERROR_NONE)
      << ml_error();
  ASSERT_TRUE(c.wait_for(2));
  {
    std::lock_guard lk(c.m);
    ASSERT_EQ(c.frames[0].tensors.size(), 1u);
    EXPECT_EQ(c.frames[0].types[0], ML_TENSOR_TYPE_INT16);
    EXPECT_EQ(c.frames[0].dims[0], (std::vector<unsigned>{3, 2, 1, 1}));
    EXPECT_EQ(c.frames[0].tensors[0], Bytes(12, 7));
    ASSERT_EQ(c.frames[1].tensors.size(), 2u);
    EXPECT_EQ(c.frames[1].types[0], ML_TENSOR_TYPE_FLOAT32);
    EXPECT_EQ(c.frames[1].types[1], ML_TENSOR_TYPE_UINT8);
    EXPECT_EQ(as_f32(c.frames[1].tensors[0]), (std::vector<float>{1.5f, -2}));
    EXPECT_EQ(c.frames[1].tensors[1], (Bytes{1, 2, 3, 4, 5}));
  }
  ml_tensors_info_destroy(a);
  ml_tensors_info_destroy(b);
  EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE);
}

// SPDX-License-Identifier: LGPL-2.1-only
// Pipeline API thread-safety as NNStreamer documents it: callbacks run on streaming threads,
// destroy works from any thread and waits for a running callback, no callback starts after
// unregister returns, a callback may unregister itself, and several threads may push at once.
// Every step that could deadlock runs under finish_within.
#include <atomic>

#include "api/ml_pipeline_test_util.h"
#include "deadline.h"

using namespace capi_test;
using nns::test::finish_within;

namespace {

// A live 4x4 GRAY8 stream at 200 frames/s into tensor_sink "sink".
const char *kLive =
    "videotestsrc is-live=true ! video/x-raw,format=GRAY8,width=4,height=4,framerate=200/1 ! "
    "tensor_converter ! tensor_sink name=sink";

struct Slow {
  std::atomic<int> calls{0};
  std::atomic<bool> inside{false};
  std::atomic<bool> finished_after_return{false};
  int ms = 0;
  static void cb(const ml_tensors_data_h, const ml_tensors_info_h, void *u) {
    auto *s = static_cast<Slow *>(u);
    s->inside = true;
    ++s->calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(s->ms));
    s->inside = false;
  }
};

bool wait_until(const std::function<bool()> &f, double seconds = 10) {
  auto end = std::chrono::steady_clock::now() + std::chrono::duration<double>(seconds);
  while (!f()) {
    if (std::chrono::steady_clock::now() > end) return false;
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

}  // namespace

TEST(MlPipelineThreads, DestroyFromAnotherThreadWaitsForRunningCallback) {
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct(kLive, nullptr, nullptr, &p), ML_ERROR_NONE) << ml_error();
  Slow s;
  s.ms = 200;
  ml_pipeline_sink_h h = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", Slow::cb, &s, &h), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ASSERT_TRUE(wait_until([&] { return s.inside.load(); }));
  int rc = -1;
  bool inside_at_return = true;
  finish_within(10, "ml_pipeline_destroy during a callback", [&] {
    std::thread t([&] {
      rc = ml_pipeline_destroy(p);
      inside_at_return = s.inside.load();
    });
    t.join();
  });
  EXPECT_EQ(rc, ML_ERROR_NONE);
  EXPECT_FALSE(inside_at_return);  // the running callback had finished
  int after = s.calls.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(s.calls.load(), after);
}

TEST(MlPipelineThreads, NoCallbackAfterUnregisterReturns) {
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct(kLive, nullptr, nullptr, &p), ML_ERROR_NONE);
  Slow s;
  s.ms = 20;
  ml_pipeline_sink_h h = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", Slow::cb, &s, &h), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ASSERT_TRUE(wait_until([&] { return s.calls.load() >= 3 && s.inside.load(); }));
  bool inside_at_return = true;
  finish_within(10, "ml_pipeline_sink_unregister during a callback", [&] {
    EXPECT_EQ(ml_pipeline_sink_unregister(h), ML_ERROR_NONE);
    inside_at_return = s.inside.load();
  });
  EXPECT_FALSE(inside_at_return);
  int after = s.calls.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(150));  // ~30 more frames flow
  EXPECT_EQ(s.calls.load(), after);
  finish_within(10, "ml_pipeline_destroy",
                [&] { EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE); });
}

namespace {

struct SelfRemover {
  std::atomic<int> calls{0};
  std::atomic<int> rc{1};
  ml_pipeline_sink_h h = nullptr;
  std::atomic<bool> ready{false};
  static void cb(const ml_tensors_data_h, const ml_tensors_info_h, void *u) {
    auto *s = static_cast<SelfRemover *>(u);
    ++s->calls;
    if (s->ready.exchange(false)) s->rc = ml_pipeline_sink_unregister(s->h);
  }
};

struct DestroyInCallback {
  ml_pipeline_h p = nullptr;
  std::atomic<int> rc{1};
  std::string text;
  std::atomic<bool> done{false};
  static void cb(const ml_tensors_data_h, const ml_tensors_info_h, void *u) {
    auto *s = static_cast<DestroyInCallback *>(u);
    if (s->done) return;
    s->rc = ml_pipeline_destroy(s->p);
    s->text = ml_error();  // per thread: this streaming thread's error
    s->done = true;
  }
};

}  // namespace

TEST(MlPipelineThreads, CallbackMayUnregisterItself) {
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct(kLive, nullptr, nullptr, &p), ML_ERROR_NONE);
  SelfRemover s;
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", SelfRemover::cb, &s, &s.h), ML_ERROR_NONE);
  s.ready = true;
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ASSERT_TRUE(wait_until([&] { return s.rc.load() != 1; }));
  EXPECT_EQ(s.rc.load(), ML_ERROR_NONE);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  EXPECT_EQ(s.calls.load(), 1);
  finish_within(10, "ml_pipeline_destroy",
                [&] { EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE); });
}

TEST(MlPipelineThreads, DestroyInsideItsOwnCallbackIsRefused) {
  DestroyInCallback s;
  ASSERT_EQ(ml_pipeline_construct(kLive, nullptr, nullptr, &s.p), ML_ERROR_NONE);
  ml_pipeline_sink_h h = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(s.p, "sink", DestroyInCallback::cb, &s, &h), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(s.p), ML_ERROR_NONE);
  ASSERT_TRUE(wait_until([&] { return s.done.load(); }));
  EXPECT_EQ(s.rc.load(), ML_ERROR_STREAMS_PIPE);
  EXPECT_NE(s.text.find("cannot be destroyed from its own sink callback"), std::string::npos)
      << s.text;
  finish_within(10, "ml_pipeline_destroy",
                [&] { EXPECT_EQ(ml_pipeline_destroy(s.p), ML_ERROR_NONE); });
}

TEST(MlPipelineThreads, ConcurrentPushesAllArrive) {
  ml_pipeline_h p = nullptr;
  std::string d = "appsrc name=src caps=" + tensor_caps("4:1:1:1", "int32") +
                  " ! queue ! tensor_sink name=sink async=false";
  ASSERT_EQ(ml_pipeline_construct(d.c_str(), nullptr, nullptr, &p), ML_ERROR_NONE);
  Collector c;
  ml_pipeline_sink_h h = nullptr;
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", Collector::cb, &c, &h), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_src_get_handle(p, "src", &src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ml_tensors_info_h info = make_info({{ML_TENSOR_TYPE_INT32, {4}}});
  std::atomic<int> failures{0};
  finish_within(20, "4 threads x 50 pushes", [&] {
    std::vector<std::thread> ts;
    for (int t = 0; t < 4; ++t)
      ts.emplace_back([&, t] {
        for (int i = 0; i < 50; ++i) {
          int32_t v[4] = {t, i, t * 1000 + i, -1};
          ml_tensors_data_h dh = nullptr;
          ml_tensors_data_create(info, &dh);
          ml_tensors_data_set_tensor_data(dh, 0, v, sizeof v);
          if (ml_pipeline_src_input_data(src, dh, ML_PIPELINE_BUF_POLICY_AUTO_FREE) !=
              ML_ERROR_NONE)
            ++failures;
        }
      });
    for (auto &t : ts) t.join();
  });
  EXPECT_EQ(failures.load(), 0);
  ASSERT_TRUE(c.wait_for(200));
  std::vector<int> per_thread(4, 0);
  {
    std::lock_guard lk(c.m);
    for (auto &f : c.frames) {
      int32_t v[4];
      std::memcpy(v, f.tensors[0].data(), 16);
      ASSERT_EQ(v[2], v[0] * 1000 + v[1]);
      // Each thread's frames arrive in its own order.
      EXPECT_EQ(v[1], per_thread[v[0]]++);
    }
  }
  ml_tensors_info_destroy(info);
  finish_within(10, "ml_pipeline_destroy",
                [&] { EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE); });
}

TEST(MlPipelineThreads, StateCallbackOnChangeAndErrorPerThread) {
  std::atomic<int> playing{0};
  auto cb = [](ml_pipeline_state_e s, void *u) {
    if (s == ML_PIPELINE_STATE_PLAYING) ++*static_cast<std::atomic<int> *>(u);
  };
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct(kLive, cb, &playing, &p), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ASSERT_TRUE(wait_until([&] { return playing.load() == 1; }));
  // An error on another thread does not change this thread's ml_error().
  EXPECT_EQ(ml_pipeline_start(nullptr), ML_ERROR_INVALID_PARAMETER);
  std::string mine = ml_error();
  std::thread([] { ml_pipeline_sink_unregister(nullptr); }).join();
  EXPECT_EQ(std::string(ml_error()), mine);
  finish_within(10, "ml_pipeline_destroy from another thread", [&] {
    std::thread([&] { EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE); }).join();
  });
  EXPECT_EQ(playing.load(), 1);
}

namespace {

// Sink callback that calls the API (pushes into another branch's appsrc) while it runs.
struct Forwarder {
  ml_pipeline_src_h src = nullptr;
  ml_tensors_info_h info = nullptr;
  std::atomic<bool> inside{false};
  std::atomic<int> calls{0}, push_errors{0};
  static void cb(const ml_tensors_data_h, const ml_tensors_info_h, void *u) {
    auto *f = static_cast<Forwarder *>(u);
    f->inside = true;
    ++f->calls;
    std::this_thread::sleep_for(std::chrono::milliseconds(30));
    ml_tensors_data_h d = nullptr;
    ml_tensors_data_create(f->info, &d);
    if (ml_pipeline_src_input_data(f->src, d, ML_PIPELINE_BUF_POLICY_AUTO_FREE) != ML_ERROR_NONE) {
      ml_tensors_data_destroy(d);
      ++f->push_errors;
    }
    f->inside = false;
  }
};

}  // namespace

TEST(MlPipelineThreads, UnregisterAndReleaseWhileCallbacksCallTheApi) {
  std::string d = std::string(kLive) + " appsrc name=src caps=" + tensor_caps("2:1:1:1", "uint8") +
                  " ! tensor_sink name=out async=false";
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct(d.c_str(), nullptr, nullptr, &p), ML_ERROR_NONE) << ml_error();
  Forwarder f;
  f.info = make_info({{ML_TENSOR_TYPE_UINT8, {2}}});
  Collector out;
  ml_pipeline_sink_h hs = nullptr, ho = nullptr;
  ASSERT_EQ(ml_pipeline_src_get_handle(p, "src", &f.src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_sink_register(p, "out", Collector::cb, &out, &ho), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", Forwarder::cb, &f, &hs), ML_ERROR_NONE);
  // need_data also calls the API (a state query) from the appsrc thread.
  static std::atomic<int> need{0};
  need = 0;
  ml_pipeline_src_callbacks_s cbs{};
  cbs.need_data = [](ml_pipeline_src_h, unsigned int, void *u) {
    ml_pipeline_state_e s;
    ml_pipeline_get_state(u, &s);
    ++need;
  };
  ASSERT_EQ(ml_pipeline_src_set_event_cb(f.src, &cbs, p), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ASSERT_TRUE(wait_until([&] { return f.calls.load() >= 2 && f.inside.load(); }));
  ASSERT_TRUE(out.wait_for(1));
  finish_within(10, "unregister while the callback pushes into an appsrc",
                [&] { EXPECT_EQ(ml_pipeline_sink_unregister(hs), ML_ERROR_NONE); });
  EXPECT_FALSE(f.inside.load());
  finish_within(10, "src release while need-data callbacks call the API",
                [&] { EXPECT_EQ(ml_pipeline_src_release_handle(f.src), ML_ERROR_NONE); });
  int n = need.load();
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(need.load(), n);  // no event callback after release returned
  EXPECT_EQ(f.push_errors.load(), 0);
  finish_within(10, "ml_pipeline_destroy",
                [&] { EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE); });
  ml_tensors_info_destroy(f.info);
}

TEST(MlPipelineThreads, DestroyUnblocksAPushWaitingOnAFullAppsrc) {
  // block=true max-buffers=1 and a slow sink: the pushing thread waits inside
  // ml_pipeline_src_input_data when destroy comes; destroy ends it and waits for it.
  std::string d =
      "appsrc name=src block=true max-buffers=1 caps=" + tensor_caps("4:1:1:1", "uint8") +
      " ! tensor_sink name=sink async=false";
  ml_pipeline_h p = nullptr;
  ASSERT_EQ(ml_pipeline_construct(d.c_str(), nullptr, nullptr, &p), ML_ERROR_NONE) << ml_error();
  Slow s;
  s.ms = 200;
  ml_pipeline_sink_h h = nullptr;
  ml_pipeline_src_h src = nullptr;
  ASSERT_EQ(ml_pipeline_sink_register(p, "sink", Slow::cb, &s, &h), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_src_get_handle(p, "src", &src), ML_ERROR_NONE);
  ASSERT_EQ(ml_pipeline_start(p), ML_ERROR_NONE);
  ml_tensors_info_h info = make_info({{ML_TENSOR_TYPE_UINT8, {4}}});
  std::atomic<int> pushed{0}, last_rc{0};
  std::thread pusher([&] {
    for (int i = 0; i < 20; ++i) {
      ml_tensors_data_h dh = make_data(info, {{1, 2, 3, 4}});
      int rc = ml_pipeline_src_input_data(src, dh, ML_PIPELINE_BUF_POLICY_AUTO_FREE);
      last_rc = rc;
      // Refused before the push (the handle died with the pipeline): the data is still ours.
      // Refused by the appsrc (flushing): it was taken, as with a successful push.
      if (rc == ML_ERROR_INVALID_PARAMETER) ml_tensors_data_destroy(dh);
      if (rc != ML_ERROR_NONE) break;  // the pipeline is going away
      ++pushed;
    }
  });
  ASSERT_TRUE(wait_until([&] { return s.inside.load() && pushed.load() >= 2; }));
  finish_within(10, "destroy while a push waits on a full appsrc", [&] {
    EXPECT_EQ(ml_pipeline_destroy(p), ML_ERROR_NONE);
    pusher.join();
  });
  EXPECT_LT(pushed.load(), 20);
  EXPECT_NE(last_rc.load(), ML_ERROR_NONE);  // the next push after destroy is refused
  ml_tensors_info_destroy(info);
}

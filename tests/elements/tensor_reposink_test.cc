// SPDX-License-Identifier: LGPL-2.1-only
// tensor_reposink (and tensor_reposrc) under state changes: a writer waiting on a full slot
// never blocks a state change (200 NULL->PLAYING->NULL cycles with buffers queued before
// PLAYING), pausing and resuming loses no buffer, `signal-rate` drops hand-offs that come too
// soon, and a slot-index change moves a waiting writer or reader to the new slot.
#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <mutex>
#include <thread>
#include <vector>

#include "elements/flow_harness.h"
#include "gst/tensor_repo.h"
#include "support/deadline.h"

namespace {

using nns::gst::TensorRepo;
using nns::test::AppPipeline;
using nns::test::Bytes;
using nns::test::finish_within;
using nns::test::Frame;
using Clock = std::chrono::steady_clock;

const char *kF4Caps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=(string)float32,"
    "framerate=(fraction)0/1";

// Frame number `v`: 16 bytes of value v.
Frame numbered(int v) {
  return Frame({Bytes(16, static_cast<uint8_t>(v))}, static_cast<GstClockTime>(v) * GST_MSECOND);
}

std::vector<int> iota(int from, int to) {
  std::vector<int> v;
  for (int i = from; i <= to; ++i) v.push_back(i);
  return v;
}

// Waits (polling) up to `seconds` for `cond`; returns it.
template <typename F>
bool eventually(double seconds, F cond) {
  auto end = Clock::now() + std::chrono::duration<double>(seconds);
  while (!cond()) {
    if (Clock::now() > end) return cond();
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return true;
}

// The test as the reader of a slot (what tensor_reposrc does): pops on its own thread until the
// slot ends, recording each buffer's number (its first byte).
class SlotReader {
 public:
  explicit SlotReader(uint32_t slot) : slot_(slot), thread_([this] { run(); }) {}
  ~SlotReader() { stop(); }
  void stop() {
    if (!thread_.joinable()) return;
    stop_ = true;
    TensorRepo::instance().wake(slot_);
    thread_.join();
  }
  // Waits up to `seconds` until `n` buffers were taken or the slot ended.
  void wait_for(std::size_t n, double seconds) {
    std::unique_lock<std::mutex> l(m_);
    cv_.wait_for(l, std::chrono::duration<double>(seconds),
                 [&] { return values_.size() >= n || done_; });
  }
  // Waits up to `seconds` for the slot's EOS; false on time-out.
  bool wait_eos(double seconds) {
    std::unique_lock<std::mutex> l(m_);
    return cv_.wait_for(l, std::chrono::duration<double>(seconds), [&] { return eos_; });
  }
  std::vector<int> values() {
    std::lock_guard<std::mutex> l(m_);
    return values_;
  }

 private:
  void run() {
    for (;;) {
      GstBuffer *buf = nullptr;
      GstCaps *caps = nullptr;
      auto st = TensorRepo::instance().pop(slot_, &buf, &caps, [this] { return stop_.load(); });
      int v = -1;
      if (st == TensorRepo::Status::kOk) {
        GstMapInfo map;
        if (gst_buffer_map(buf, &map, GST_MAP_READ)) {
          v = map.size ? map.data[0] : -1;
          gst_buffer_unmap(buf, &map);
        }
        gst_buffer_unref(buf);
        if (caps) gst_caps_unref(caps);
      }
      std::lock_guard<std::mutex> l(m_);
      if (st != TensorRepo::Status::kOk) {
        eos_ = st == TensorRepo::Status::kEos;
        done_ = true;
        cv_.notify_all();
        return;
      }
      values_.push_back(v);
      cv_.notify_all();
    }
  }

  const uint32_t slot_;
  std::atomic<bool> stop_{false};
  std::mutex m_;
  std::condition_variable cv_;
  std::vector<int> values_;
  bool eos_ = false, done_ = false;
  std::thread thread_;  // last: starts after the members above exist
};

// Sets the pipeline's state and waits (up to 10 s) until it is reached.
void go(GstElement *pipe, GstState state) {
  EXPECT_NE(gst_element_set_state(pipe, state), GST_STATE_CHANGE_FAILURE)
      << gst_element_state_get_name(state);
  GstState now = GST_STATE_VOID_PENDING;
  EXPECT_EQ(gst_element_get_state(pipe, &now, nullptr, 10 * GST_SECOND), GST_STATE_CHANGE_SUCCESS)
      << gst_element_state_get_name(state);
  EXPECT_EQ(now, state);
}

// The bus message ending the run (EOS or ERROR), "" on time-out.
std::string end_message(GstElement *pipe, double seconds) {
  GstMessage *m = gst_bus_timed_pop_filtered(
      GST_ELEMENT_BUS(pipe), static_cast<GstClockTime>(seconds * GST_SECOND),
      static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  if (!m) return "";
  std::string what = GST_MESSAGE_TYPE_NAME(m);
  if (GST_MESSAGE_TYPE(m) == GST_MESSAGE_ERROR) {
    GError *err = nullptr;
    gst_message_parse_error(m, &err, nullptr);
    what += std::string(": ") + (err ? err->message : "");
    if (err) g_error_free(err);
  }
  gst_message_unref(m);
  return what;
}

// Opens the race window of the PAUSED->PLAYING deadlock on purpose: a tracer hook runs in
// gst_element_change_state after the sink's pending state became PLAYING and before its
// change_state takes the preroll lock; it lets the held first buffer go and sleeps, so the
// streaming thread commits PLAYING itself and renders the second buffer into the full slot
// while the state change still wants the preroll lock.
struct RaceWindow {
  std::mutex m;
  std::condition_variable cv;
  std::atomic<GstElement *> sink{nullptr};  // whose PAUSED->PLAYING is delayed (null: none)
  bool open = false;
};
RaceWindow g_window;

struct TestTracer {
  GstTracer parent;
};
struct TestTracerClass {
  GstTracerClass parent_class;
};
G_DEFINE_TYPE(TestTracer, test_tracer, GST_TYPE_TRACER)
void test_tracer_class_init(TestTracerClass *) {}
void test_tracer_init(TestTracer *) {}

void on_change_state_pre(GObject *, GstClockTime, GstElement *element, GstStateChange change) {
  if (element != g_window.sink || change != GST_STATE_CHANGE_PAUSED_TO_PLAYING) return;
  {
    std::lock_guard<std::mutex> l(g_window.m);
    g_window.open = true;
    g_window.cv.notify_all();
  }
  std::this_thread::sleep_for(std::chrono::milliseconds(20));
}

// Kept for the process (the tracing registry uses it, without a reference of its own, and
// gst_deinit forgets it).
GstTracer *g_tracer = nullptr;

void install_race_hook() {
  if (g_tracer) return;
  g_tracer = static_cast<GstTracer *>(g_object_new(test_tracer_get_type(), nullptr));
  gst_tracing_register_hook(g_tracer, "element-change-state-pre", G_CALLBACK(on_change_state_pre));
}

// Holds the first buffer until the sink's PAUSED->PLAYING has begun (at most 5 s).
GstPadProbeReturn hold_first_buffer(GstPad *, GstPadProbeInfo *, gpointer) {
  std::unique_lock<std::mutex> l(g_window.m);
  g_window.cv.wait_for(l, std::chrono::seconds(5), [] { return g_window.open; });
  return GST_PAD_PROBE_REMOVE;
}

TEST(TensorRepoSink, TwoHundredNullPlayingNullCyclesWithAFullSlotNeverHang) {
  // Nobody reads slot 61: the first buffer fills it and the writer waits with the second. The
  // buffers are queued before PLAYING. In cycles 0, 2 mod 4 the first buffer reaches the sink
  // while the bin moves it PAUSED->PLAYING (see RaceWindow), in the others whenever it does;
  // cycles 0, 1 mod 4 wait for the slot to fill before going to NULL, the others stop at once.
  // The sink is the same element throughout; each cycle gets a new appsrc (a stopped appsrc
  // refuses buffers until it starts again).
  install_race_hook();
  GstElement *pipe = gst_pipeline_new("cycles");
  GstElement *sink = gst_element_factory_make("tensor_reposink", "rsink");
  ASSERT_TRUE(pipe && sink);
  g_object_set(sink, "slot-index", 61u, nullptr);
  gst_bin_add(GST_BIN(pipe), sink);
  GstCaps *caps = gst_caps_from_string(kF4Caps);
  int filled = 0;
  bool hooks_work = true;
  finish_within(240, "200 NULL->PLAYING->NULL cycles", [&] {
    for (int i = 0; i < 200; ++i) {
      GstElement *src = gst_element_factory_make("appsrc", nullptr);
      g_object_set(src, "caps", caps, "format", GST_FORMAT_TIME, nullptr);
      gst_bin_add(GST_BIN(pipe), src);
      ASSERT_TRUE(gst_element_link(src, sink));
      for (int k = 1; k <= 3; ++k)
        ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(src), nns::test::make_buffer(numbered(k))),
                  GST_FLOW_OK);
      bool race = i % 2 == 0 && hooks_work, wait = i % 4 < 2;
      if (race) {
        {
          std::lock_guard<std::mutex> l(g_window.m);
          g_window.open = false;
        }
        g_window.sink = sink;
        GstPad *pad = gst_element_get_static_pad(src, "src");
        gst_pad_add_probe(pad, GST_PAD_PROBE_TYPE_BUFFER, hold_first_buffer, nullptr, nullptr);
        gst_object_unref(pad);
      }
      finish_within(30, "cycle " + std::to_string(i), [&] {
        ASSERT_NE(gst_element_set_state(pipe, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
        g_window.sink = nullptr;
        if (race) {
          std::lock_guard<std::mutex> l(g_window.m);
          if (!g_window.open) {  // a GStreamer built without tracer hooks
            std::printf("tracer hooks do not run: the race window is left to chance\n");
            hooks_work = false;
          }
        }
        if (wait) {
          bool full = eventually(10, [] { return TensorRepo::instance().has_buffer(61); });
          EXPECT_TRUE(full) << "cycle " << i << ": the slot was never filled";
          filled += full;
        }
        EXPECT_EQ(gst_element_set_state(pipe, GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS);
      });
      gst_bin_remove(GST_BIN(pipe), src);
      if (HasFailure()) break;
    }
  });
  EXPECT_EQ(filled, 100);
  gst_caps_unref(caps);
  gst_object_unref(pipe);
}

TEST(TensorRepoSink, PauseAndResumeWithAFullSlotLoseNoBuffer) {
  // Before: PLAYING->PAUSED unlocked the waiting writer, render returned FLUSHING, the buffer
  // was dropped and appsrc's task stopped for good. Now the writer waits for PLAYING and
  // stores the same buffer; nothing is stored while PAUSED.
  TensorRepo::instance().reset(62);
  AppPipeline p("appsrc name=in ! tensor_reposink slot-index=62");
  p.set_caps("in", kF4Caps);
  for (int v = 1; v <= 8; ++v) p.push("in", numbered(v));
  p.eos("in");
  GstElement *pipe = p.pipeline();
  finish_within(30, "NULL->PLAYING", [&] {
    go(pipe, GST_STATE_PLAYING);
    EXPECT_TRUE(eventually(10, [] { return TensorRepo::instance().has_buffer(62); }));
  });
  finish_within(30, "PLAYING->PAUSED with the writer waiting", [&] { go(pipe, GST_STATE_PAUSED); });
  SlotReader reader(62);
  reader.wait_for(1, 10);
  EXPECT_EQ(reader.values(), std::vector<int>{1});
  // Given time, a writer that ignored PAUSED would store buffer 2 now.
  std::this_thread::sleep_for(std::chrono::milliseconds(200));
  EXPECT_FALSE(TensorRepo::instance().has_buffer(62)) << "a buffer was stored while PAUSED";
  EXPECT_EQ(reader.values(), std::vector<int>{1});
  finish_within(30, "PAUSED->PLAYING", [&] { go(pipe, GST_STATE_PLAYING); });
  // More pauses while the rest flows: whatever the writer is doing then, nothing is lost.
  for (int i = 0; i < 10; ++i)
    finish_within(30, "pause/resume " + std::to_string(i), [&] {
      go(pipe, GST_STATE_PAUSED);
      go(pipe, GST_STATE_PLAYING);
    });
  EXPECT_TRUE(reader.wait_eos(20)) << "the slot did not end; got " << reader.values().size();
  EXPECT_EQ(reader.values(), iota(1, 8));
  EXPECT_EQ(end_message(pipe, 10), "eos");
  finish_within(30, "PLAYING->NULL", [&] { gst_element_set_state(pipe, GST_STATE_NULL); });
}

TEST(TensorRepoSink, PauseAndResumeWhileTheReaderWaits) {
  // tensor_reposrc waits in create for an empty slot: pausing and resuming must not wait for
  // it, and it outputs what arrives after resuming. (appsink async=false: with nothing to
  // preroll, an async sink would keep PAUSED pending.)
  auto &repo = TensorRepo::instance();
  repo.reset(70);
  AppPipeline p(std::string("tensor_reposrc slot-index=70 caps=\"") + kF4Caps +
                "\" ! appsink name=out async=false");
  finish_within(30, "NULL->PLAYING", [&] {
    go(p.pipeline(), GST_STATE_PLAYING);
    EXPECT_TRUE(eventually(10, [&] { return p.frames("out").size() == 1; }));  // zero frame
  });
  for (int i = 0; i < 5; ++i)
    finish_within(30, "pause/resume " + std::to_string(i), [&] {
      go(p.pipeline(), GST_STATE_PAUSED);
      go(p.pipeline(), GST_STATE_PLAYING);
    });
  GstCaps *caps = gst_caps_from_string(kF4Caps);
  GstBuffer *buf = nns::test::make_buffer(numbered(9));
  EXPECT_EQ(repo.try_push(70, buf, caps), TensorRepo::Status::kOk);
  gst_buffer_unref(buf);
  gst_caps_unref(caps);
  EXPECT_TRUE(eventually(10, [&] { return p.frames("out").size() == 2; }));
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[1].mems, std::vector<Bytes>{Bytes(16, 9)});
  finish_within(30, "PLAYING->NULL", [&] { gst_element_set_state(p.pipeline(), GST_STATE_NULL); });
}

// Pushes `frames` into a reposink with `signal-rate=rate` writing `slot`; the test reads the
// slot. Returns the numbers read and the seconds from PLAYING to the slot's EOS.
std::vector<int> burst(uint32_t slot, guint rate, int frames, double *seconds) {
  TensorRepo::instance().reset(slot);
  AppPipeline p("appsrc name=in ! tensor_reposink slot-index=" + std::to_string(slot) +
                " signal-rate=" + std::to_string(rate));
  p.set_caps("in", kF4Caps);
  for (int v = 1; v <= frames; ++v) p.push("in", numbered(v));
  p.eos("in");
  SlotReader reader(slot);
  auto t0 = Clock::now();
  finish_within(30, "the burst", [&] {
    gst_element_set_state(p.pipeline(), GST_STATE_PLAYING);
    EXPECT_TRUE(reader.wait_eos(20));
  });
  *seconds = std::chrono::duration<double>(Clock::now() - t0).count();
  EXPECT_EQ(end_message(p.pipeline(), 10), "eos");
  finish_within(30, "PLAYING->NULL", [&] { gst_element_set_state(p.pipeline(), GST_STATE_NULL); });
  return reader.values();
}

TEST(TensorRepoSink, SignalRateDropsHandOffsThatComeTooSoon) {
  // signal-rate=2: at most one hand-off per 500 ms, the first always. Five buffers pushed at
  // once: the later ones come within microseconds and are dropped (render returns at once,
  // without waiting for the reader). On a machine so loaded that the burst took longer, at most
  // one more buffer per 500 ms may pass, still in order.
  double seconds = 0;
  auto got = burst(63, 2, 5, &seconds);
  ASSERT_FALSE(got.empty());
  EXPECT_EQ(got[0], 1);
  if (seconds < 0.5) {
    EXPECT_EQ(got, std::vector<int>{1}) << "run took " << seconds << " s";
  } else {
    EXPECT_LE(got.size(), 1 + static_cast<std::size_t>(seconds / 0.5)) << seconds << " s";
    for (std::size_t i = 1; i < got.size(); ++i) EXPECT_GT(got[i], got[i - 1]);
  }
  // signal-rate=0 (the default): every buffer, in order (the writer waits for the reader).
  got = burst(65, 0, 5, &seconds);
  EXPECT_EQ(got, iota(1, 5));
}

TEST(TensorRepoSink, SignalRatePassesHandOffsSpacedByTheInterval) {
  // signal-rate=10 (100 ms): each buffer is pushed 150 ms after the reader took the previous
  // one, so its render starts at least 150 ms after the previous hand-off: all pass.
  TensorRepo::instance().reset(64);
  AppPipeline p("appsrc name=in ! tensor_reposink slot-index=64 signal-rate=10");
  p.set_caps("in", kF4Caps);
  SlotReader reader(64);
  finish_within(60, "spaced hand-offs", [&] {
    go(p.pipeline(), GST_STATE_PLAYING);
    for (int v = 1; v <= 4; ++v) {
      p.push("in", numbered(v));
      reader.wait_for(v, 10);
      ASSERT_EQ(reader.values().size(), static_cast<std::size_t>(v)) << "buffer " << v;
      std::this_thread::sleep_for(std::chrono::milliseconds(150));
    }
    p.eos("in");
    EXPECT_TRUE(reader.wait_eos(10));
    gst_element_set_state(p.pipeline(), GST_STATE_NULL);
  });
  EXPECT_EQ(reader.values(), iota(1, 4));
}

TEST(TensorRepoSink, SlotIndexChangeMovesAWaitingWriter) {
  auto &repo = TensorRepo::instance();
  repo.reset(66);
  repo.reset(67);
  AppPipeline p("appsrc name=in ! tensor_reposink name=rsink slot-index=66");
  p.set_caps("in", kF4Caps);
  p.push("in", numbered(1));
  p.push("in", numbered(2));
  GstElement *sink = p.get("rsink");
  finish_within(30, "the writer filling slot 66", [&] {
    go(p.pipeline(), GST_STATE_PLAYING);
    EXPECT_TRUE(eventually(10, [&] { return repo.has_buffer(66); }));
  });
  // Buffer 2 waits on the full slot 66 (or is about to): it goes to 67 instead.
  g_object_set(sink, "slot-index", 67u, nullptr);
  EXPECT_TRUE(eventually(10, [&] { return repo.has_buffer(67); }));
  auto take = [&](uint32_t slot) {  // the slot holds a buffer: pop does not wait
    GstBuffer *buf = nullptr;
    GstCaps *caps = nullptr;
    if (repo.pop(slot, &buf, &caps, [] { return false; }) != TensorRepo::Status::kOk) return -1;
    auto f = nns::test::frame_of(buf);
    gst_buffer_unref(buf);
    if (caps) gst_caps_unref(caps);
    return f.mems.empty() || f.mems[0].empty() ? -1 : static_cast<int>(f.mems[0][0]);
  };
  ASSERT_TRUE(repo.has_buffer(66) && repo.has_buffer(67));
  EXPECT_EQ(take(66), 1);
  EXPECT_EQ(take(67), 2);
  finish_within(30, "PLAYING->NULL", [&] { gst_element_set_state(p.pipeline(), GST_STATE_NULL); });
  guint slot = 0;
  g_object_get(sink, "slot-index", &slot, nullptr);
  EXPECT_EQ(slot, 67u);
  gst_object_unref(sink);
}

TEST(TensorRepoSink, SlotIndexChangeMovesAWaitingReader) {
  auto &repo = TensorRepo::instance();
  repo.reset(68);
  repo.reset(69);
  AppPipeline p(std::string("tensor_reposrc name=rsrc slot-index=68 caps=\"") + kF4Caps +
                "\" ! appsink name=out");
  GstElement *src = p.get("rsrc");
  finish_within(30, "the reader's first frame", [&] {
    go(p.pipeline(), GST_STATE_PLAYING);
    EXPECT_TRUE(eventually(10, [&] { return p.frames("out").size() == 1; }));  // zero frame
  });
  // The reader waits on the empty slot 68; slot 69 holds frame 7.
  GstCaps *caps = gst_caps_from_string(kF4Caps);
  GstBuffer *buf = nns::test::make_buffer(numbered(7));
  EXPECT_EQ(repo.try_push(69, buf, caps), TensorRepo::Status::kOk);
  gst_buffer_unref(buf);
  gst_caps_unref(caps);
  std::this_thread::sleep_for(std::chrono::milliseconds(50));
  EXPECT_EQ(p.frames("out").size(), 1u);
  g_object_set(src, "slot-index", 69u, nullptr);
  EXPECT_TRUE(eventually(10, [&] { return p.frames("out").size() == 2; }));
  auto out = p.frames("out");
  ASSERT_EQ(out.size(), 2u);
  EXPECT_EQ(out[0].mems, std::vector<Bytes>{Bytes(16, 0)});
  EXPECT_EQ(out[1].mems, std::vector<Bytes>{Bytes(16, 7)});
  EXPECT_FALSE(repo.has_buffer(69));
  finish_within(30, "PLAYING->NULL", [&] { gst_element_set_state(p.pipeline(), GST_STATE_NULL); });
  gst_object_unref(src);
}

}  // namespace

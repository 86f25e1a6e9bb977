// SPDX-License-Identifier: LGPL-2.1-only
// Leak and hang checks for the stream-composition element tests.
//
// LiveObjects puts a probe on every pad of a pipeline (pads added later too) and a
// GstMiniObject weak reference on every buffer, buffer memory and event (either direction)
// that crosses one, so it knows which of them have not been freed. After the pipeline is set
// to NULL nothing it saw may still be alive: an element that keeps (or forgets to unref) a
// buffer, a memory or an event shows up there, with where it was seen. No tracer is needed, so the
// check runs in every build. LiveObjects.CountsWhatAnElementKeeps (cycle_check_test.cc) shows it
// can fail.
//
// End such pipelines in fakesink: appsink (GStreamer 1.22) keeps the buffer of the last sample
// pulled from it after NULL (until the next sample or its disposal), which would be reported.
//
// state_cycles() drives PLAYING -> (feed) -> NULL cycles and checks after every NULL that no
// object is alive; a cycle that does not finish within the timeout aborts the test binary with
// the cycle number (a hang would otherwise only end at the ctest timeout).
#pragma once

#include <gst/gst.h>
#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdio>
#include <cstdlib>
#include <functional>
#include <map>
#include <memory>
#include <mutex>
#include <sstream>
#include <string>
#include <thread>

namespace nns::test {

class LiveObjects {
 public:
  explicit LiveObjects(GstElement *pipeline) : st_(std::make_shared<State>()) {
    GstIterator *it = gst_bin_iterate_recurse(GST_BIN(pipeline));
    GValue v = G_VALUE_INIT;
    while (gst_iterator_next(it, &v) == GST_ITERATOR_OK) {
      watch_element(GST_ELEMENT(g_value_get_object(&v)));
      g_value_reset(&v);
    }
    g_value_unset(&v);
    gst_iterator_free(it);
  }
  ~LiveObjects() {
    // The probes keep the state alive; the pipeline is expected to be in NULL by now.
    std::lock_guard<std::mutex> l(st_->m);
    st_->closed = true;
  }
  LiveObjects(const LiveObjects &) = delete;
  LiveObjects &operator=(const LiveObjects &) = delete;

  // Tracked objects not freed yet.
  std::size_t alive() const {
    std::lock_guard<std::mutex> l(st_->m);
    return st_->alive.size();
  }
  // Objects tracked since the start (shows the check saw the data at all).
  std::size_t tracked() const {
    std::lock_guard<std::mutex> l(st_->m);
    return st_->tracked;
  }
  // What is still alive, one line per object.
  std::string describe() const {
    std::lock_guard<std::mutex> l(st_->m);
    std::ostringstream os;
    for (const auto &[obj, what] : st_->alive)
      os << "  " << what << " (refcount " << GST_MINI_OBJECT_REFCOUNT_VALUE(obj) << ")\n";
    return os.str();
  }
  // Buffers that entered a sink pad of `element` since the start.
  std::size_t delivered(const std::string &element) const {
    std::lock_guard<std::mutex> l(st_->m);
    auto it = st_->delivered.find(element);
    return it == st_->delivered.end() ? 0 : it->second;
  }
  // Waits until delivered(element) >= n; false after `timeout_s`.
  bool wait_delivered(const std::string &element, std::size_t n, double timeout_s = 10) const {
    std::unique_lock<std::mutex> l(st_->m);
    return st_->cv.wait_for(l, std::chrono::duration<double>(timeout_s), [&] {
      auto it = st_->delivered.find(element);
      return it != st_->delivered.end() && it->second >= n;
    });
  }

 private:
  struct State {
    mutable std::mutex m;
    std::condition_variable cv;
    std::map<GstMiniObject *, std::string> alive;
    std::map<std::string, std::size_t> delivered;
    std::size_t tracked = 0;
    bool closed = false;
    ~State() {
      // Objects still alive (a leak already reported) must not call back into freed state.
      for (auto &[obj, what] : alive) gst_mini_object_weak_unref(obj, gone, this);
    }
  };
  using StatePtr = std::shared_ptr<State>;

  static void gone(gpointer user, GstMiniObject *obj) {
    auto *st = static_cast<State *>(user);
    std::lock_guard<std::mutex> l(st->m);
    st->alive.erase(obj);
  }
  static void track(State *st, GstMiniObject *obj, const std::string &what) {
    if (st->alive.count(obj)) return;
    st->alive.emplace(obj, what);
    st->tracked++;
    gst_mini_object_weak_ref(obj, gone, st);
  }
  static void track_buffer(State *st, GstBuffer *b, const std::string &where) {
    std::ostringstream os;
    os << "buffer pts=" << GST_BUFFER_PTS(b) << " size=" << gst_buffer_get_size(b) << " at "
       << where;
    track(st, GST_MINI_OBJECT_CAST(b), os.str());
    for (guint i = 0; i < gst_buffer_n_memory(b); ++i)
      track(st, GST_MINI_OBJECT_CAST(gst_buffer_peek_memory(b, i)),
            "memory " + std::to_string(i) + " of " + os.str());
  }
  static GstPadProbeReturn probe(GstPad *pad, GstPadProbeInfo *info, gpointer user) {
    State *st = static_cast<StatePtr *>(user)->get();
    GstElement *parent = GST_PAD_PARENT(pad);
    std::string where =
        std::string(parent ? GST_ELEMENT_NAME(parent) : "(none)") + ":" + GST_PAD_NAME(pad);
    std::lock_guard<std::mutex> l(st->m);
    if (st->closed) return GST_PAD_PROBE_OK;
    std::size_t buffers = 0;
    if (info->type & GST_PAD_PROBE_TYPE_BUFFER) {
      track_buffer(st, GST_PAD_PROBE_INFO_BUFFER(info), where);
      buffers = 1;
    } else if (info->type & GST_PAD_PROBE_TYPE_BUFFER_LIST) {
      GstBufferList *list = GST_PAD_PROBE_INFO_BUFFER_LIST(info);
      track(st, GST_MINI_OBJECT_CAST(list), "buffer list at " + where);
      buffers = gst_buffer_list_length(list);
      for (guint i = 0; i < buffers; ++i) track_buffer(st, gst_buffer_list_get(list, i), where);
    } else if (info->type & GST_PAD_PROBE_TYPE_EVENT_BOTH) {
      GstEvent *ev = GST_PAD_PROBE_INFO_EVENT(info);
      track(st, GST_MINI_OBJECT_CAST(ev),
            std::string(GST_EVENT_TYPE_NAME(ev)) + " event at " + where);
    }
    if (buffers && parent && GST_PAD_IS_SINK(pad)) {
      st->delivered[GST_ELEMENT_NAME(parent)] += buffers;
      st->cv.notify_all();
    }
    return GST_PAD_PROBE_OK;
  }
  static void watch_pad(const StatePtr &st, GstPad *pad) {
    gst_pad_add_probe(
        pad,
        static_cast<GstPadProbeType>(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_BUFFER_LIST |
                                     GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM),
        probe, new StatePtr(st), [](gpointer p) { delete static_cast<StatePtr *>(p); });
  }
  void watch_element(GstElement *e) {
    GstIterator *it = gst_element_iterate_pads(e);
    GValue v = G_VALUE_INIT;
    while (gst_iterator_next(it, &v) == GST_ITERATOR_OK) {
      watch_pad(st_, GST_PAD(g_value_get_object(&v)));
      g_value_reset(&v);
    }
    g_value_unset(&v);
    gst_iterator_free(it);
    g_signal_connect_data(
        e, "pad-added", G_CALLBACK(+[](GstElement *, GstPad *pad, gpointer user) {
          watch_pad(*static_cast<StatePtr *>(user), pad);
        }),
        new StatePtr(st_), [](gpointer p, GClosure *) { delete static_cast<StatePtr *>(p); },
        static_cast<GConnectFlags>(0));
  }

  StatePtr st_;
};

// Aborts the test binary when not disarmed within `timeout_s` (a hang).
class Watchdog {
 public:
  Watchdog(double timeout_s, std::string what) : what_(std::move(what)) {
    t_ = std::thread([this, timeout_s] {
      std::unique_lock<std::mutex> l(m_);
      if (!cv_.wait_for(l, std::chrono::duration<double>(timeout_s), [&] { return done_; })) {
        std::fprintf(stderr, "HANG: %s did not finish within %g s\n", what_.c_str(), timeout_s);
        std::fflush(stderr);
        std::abort();
      }
    });
  }
  ~Watchdog() {
    {
      std::lock_guard<std::mutex> l(m_);
      done_ = true;
    }
    cv_.notify_all();
    t_.join();
  }
  Watchdog(const Watchdog &) = delete;
  Watchdog &operator=(const Watchdog &) = delete;

 private:
  std::string what_;
  std::mutex m_;
  std::condition_variable cv_;
  bool done_ = false;
  std::thread t_;
};

// Waits for EOS (true) or an error (false, with the error in `*error` when given) on the
// pipeline's bus.
inline bool wait_eos(GstElement *pipeline, double timeout_s = 10, std::string *error = nullptr) {
  GstBus *bus = gst_element_get_bus(pipeline);
  GstMessage *m =
      gst_bus_timed_pop_filtered(bus, static_cast<GstClockTime>(timeout_s * GST_SECOND),
                                 static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  gst_object_unref(bus);
  if (!m) {
    if (error) *error = "timed out";
    return false;
  }
  bool eos = GST_MESSAGE_TYPE(m) == GST_MESSAGE_EOS;
  if (!eos && error) {
    GError *err = nullptr;
    gst_message_parse_error(m, &err, nullptr);
    *error = err ? err->message : "error";
    if (err) g_error_free(err);
  }
  gst_message_unref(m);
  return eos;
}

// `cycles` times: PLAYING, feed(cycle, live) (pushes data and waits for what the cycle needs,
// with gtest EXPECTs), NULL; then no object the pipeline's pads saw may be alive. A cycle
// longer than `timeout_s` aborts (hang). At least one object must have been tracked.
inline void state_cycles(GstElement *pipeline, int cycles,
                         const std::function<void(int, LiveObjects &)> &feed,
                         double timeout_s = 30) {
  LiveObjects live(pipeline);
  for (int i = 0; i < cycles; ++i) {
    {
      Watchdog dog(timeout_s, "PLAYING<->NULL cycle " + std::to_string(i));
      ASSERT_NE(gst_element_set_state(pipeline, GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE)
          << "cycle " << i;
      feed(i, live);
      if (::testing::Test::HasFatalFailure()) {
        gst_element_set_state(pipeline, GST_STATE_NULL);
        return;
      }
      ASSERT_EQ(gst_element_set_state(pipeline, GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS)
          << "cycle " << i;
    }
    ASSERT_EQ(live.alive(), 0u) << "after cycle " << i << ", still alive:\n" << live.describe();
  }
  EXPECT_GT(live.tracked(), 0u) << "no buffer or event crossed a pad";
}

}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// The data path shared by tensor_mux and tensor_merge (src/gst/tensor_sync.cc): per-pad
// queues, producers that wait for room and are woken, flushing, shutdown while a producer
// waits, latency queries, serialized events kept in order, and a tee feeding two pads of the
// same element from one thread.
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include <chrono>
#include <thread>

#include "elements/stream_util.h"
#include "support/deadline.h"

namespace nns::test {
namespace {

constexpr GstClockTime k30 = 33333333;
const char *kCaps =
    "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8,framerate=30/1";

// Two harnesses on one tensor_mux (sink_0 carries the src side).
struct TwoPads {
  HarnessPtr h0, h1;
  explicit TwoPads(const char *mode) {
    GstElement *mux = gst_element_factory_make("tensor_mux", nullptr);
    g_object_set(mux, "sync-mode", mode, nullptr);
    h0.reset(gst_harness_new_with_element(mux, "sink_0", "src"));
    gst_object_unref(mux);
    h1.reset(gst_harness_new_with_element(h0->element, "sink_1", nullptr));
    gst_harness_set_src_caps_str(h0.get(), kCaps);
    gst_harness_set_src_caps_str(h1.get(), kCaps);
  }
};

// Events the harness's sink got, by type, dropping them.
int count_events(GstHarness *h, GstEventType type) {
  int n = 0;
  while (GstEvent *ev = gst_harness_try_pull_event(h)) {
    if (GST_EVENT_TYPE(ev) == type) ++n;
    gst_event_unref(ev);
  }
  return n;
}

TEST(TensorSyncFlow, FlushDropsQueuedBuffersAndGoesDownstreamOnce) {
  TwoPads t("nosync");
  // GstHarness's source says it is live, so sink_0 queues two buffers at most.
  for (uint8_t i = 0; i < 2; ++i)
    ASSERT_EQ(gst_harness_push(t.h0.get(), make_buffer({{0, i, 0, 0}}, i * k30)), GST_FLOW_OK);
  EXPECT_EQ(gst_harness_buffers_in_queue(t.h0.get()), 0u) << "sink_1 has no data yet";
  count_events(t.h0.get(), GST_EVENT_EOS);  // drop stream-start etc.

  ASSERT_TRUE(gst_harness_push_event(t.h0.get(), gst_event_new_flush_start()));
  ASSERT_TRUE(gst_harness_push_event(t.h1.get(), gst_event_new_flush_start()));
  EXPECT_EQ(count_events(t.h0.get(), GST_EVENT_FLUSH_START), 1);
  ASSERT_TRUE(gst_harness_push_event(t.h0.get(), gst_event_new_flush_stop(TRUE)));
  EXPECT_EQ(count_events(t.h0.get(), GST_EVENT_FLUSH_STOP), 0) << "sink_1 still flushing";
  ASSERT_TRUE(gst_harness_push_event(t.h1.get(), gst_event_new_flush_stop(TRUE)));
  EXPECT_EQ(count_events(t.h0.get(), GST_EVENT_FLUSH_STOP), 1);

  GstSegment seg;
  gst_segment_init(&seg, GST_FORMAT_TIME);
  for (auto *h : {t.h0.get(), t.h1.get()})
    ASSERT_TRUE(gst_harness_push_event(h, gst_event_new_segment(&seg)));
  ASSERT_EQ(gst_harness_push(t.h0.get(), make_buffer({{0, 9, 0, 0}}, 0)), GST_FLOW_OK);
  ASSERT_EQ(gst_harness_push(t.h1.get(), make_buffer({{1, 7, 0, 0}}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(t.h0.get());
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(tensor_bytes(out, 0)[1], 9) << "the buffers queued before the flush are gone";
  EXPECT_EQ(tensor_bytes(out, 1)[1], 7);
  gst_buffer_unref(out);
  EXPECT_EQ(gst_harness_buffers_in_queue(t.h0.get()), 0u);
}

TEST(TensorSyncFlow, BufferOnAFlushingPadIsRefused) {
  TwoPads t("nosync");
  ASSERT_TRUE(gst_harness_push_event(t.h1.get(), gst_event_new_flush_start()));
  // The harness's own src pad is flushing too now; call the mux's chain function directly.
  GstPad *sink1 = gst_element_get_static_pad(t.h0->element, "sink_1");
  ASSERT_NE(sink1, nullptr);
  EXPECT_EQ(gst_pad_chain(sink1, make_buffer({{1, 0, 0, 0}}, 0)), GST_FLOW_FLUSHING);
  gst_object_unref(sink1);
}

// A serialized event waits behind the buffers queued before it on its pad.
TEST(TensorSyncFlow, SerializedEventKeepsItsPlaceBehindQueuedBuffers) {
  TwoPads t("nosync");
  count_events(t.h0.get(), GST_EVENT_EOS);
  ASSERT_EQ(gst_harness_push(t.h0.get(), make_buffer({{0, 1, 0, 0}}, 0)), GST_FLOW_OK);
  GstStructure *s = gst_structure_new_empty("nns-test-marker");
  ASSERT_TRUE(
      gst_harness_push_event(t.h0.get(), gst_event_new_custom(GST_EVENT_CUSTOM_DOWNSTREAM, s)));
  EXPECT_EQ(count_events(t.h0.get(), GST_EVENT_CUSTOM_DOWNSTREAM), 0)
      << "the event went past the buffer still waiting for sink_1";
  ASSERT_EQ(gst_harness_push(t.h1.get(), make_buffer({{1, 1, 0, 0}}, 0)), GST_FLOW_OK);
  GstBuffer *out = gst_harness_pull(t.h0.get());
  ASSERT_NE(out, nullptr);
  gst_buffer_unref(out);
  EXPECT_EQ(count_events(t.h0.get(), GST_EVENT_CUSTOM_DOWNSTREAM), 1);
}

// Releasing the pad that was missing lets the data already queued on the others go out.
TEST(TensorSyncFlow, ReleasingTheMissingPadCompletesTheSet) {
  GstHarness *h0 = gst_harness_new_with_padnames("tensor_mux", "sink_0", "src");
  HarnessPtr hp0(h0);
  GstPad *extra = gst_element_request_pad_simple(h0->element, "sink_%u");
  ASSERT_NE(extra, nullptr);
  gst_harness_set_src_caps_str(h0, kCaps);
  ASSERT_EQ(gst_harness_push(h0, make_buffer({{1, 2, 3, 4}}, 0)), GST_FLOW_OK);
  EXPECT_EQ(gst_harness_buffers_in_queue(h0), 0u);
  gst_element_release_request_pad(h0->element, extra);
  gst_object_unref(extra);
  GstBuffer *out = gst_harness_try_pull(h0);
  ASSERT_NE(out, nullptr);
  EXPECT_EQ(gst_buffer_n_memory(out), 1u);
  gst_buffer_unref(out);
}

std::string two_appsrc_mux(const std::string &mode, const std::string &src_extra = "") {
  return appsrc("a0", kCaps) + src_extra + "! mux.sink_0 " + appsrc("a1", kCaps) + src_extra +
         "! mux.sink_1 tensor_mux name=mux sync-mode=" + mode + " ! appsink name=out sync=false";
}

// sink_0's producer fills its queue long before sink_1 has data, waits for room, and is
// woken as outputs drain it: every frame comes out, paired with its partner.
TEST(TensorSyncFlow, ProducerWaitsForRoomAndIsWoken) {
  constexpr int kFrames = 300;  // several times the queue depth
  Pipe p(two_appsrc_mux("nosync", "max-buffers=0 "));
  p.collect("out");
  for (int i = 0; i < kFrames; ++i)
    p.push("a0", make_buffer({{0, static_cast<uint8_t>(i), 0, 0}}, i * k30));
  p.eos("a0");
  std::thread late([&] {
    std::this_thread::sleep_for(std::chrono::milliseconds(150));
    for (int i = 0; i < kFrames; ++i)
      p.push("a1", make_buffer({{1, static_cast<uint8_t>(i), 0, 0}}, i * k30));
    p.eos("a1");
  });
  auto r = p.run(20);
  late.join();
  ASSERT_TRUE(r.eos) << (r.timed_out ? "timed out" : r.error_text);
  ASSERT_EQ(p.out().size(), static_cast<std::size_t>(kFrames));
  for (int i = 0; i < kFrames; ++i) {
    EXPECT_EQ(tensor_bytes(p.out()[i], 0)[1], static_cast<uint8_t>(i));
    EXPECT_EQ(tensor_bytes(p.out()[i], 1)[1], static_cast<uint8_t>(i));
    EXPECT_EQ(GST_BUFFER_PTS(p.out()[i]), i * k30);
  }
}

// A live input is held back after two queued buffers (upstream's CollectPads holds one), so
// it is not paired with frames from long ago; a non-live one queues many.
TEST(TensorSyncFlow, LiveInputsQueueLittle) {
  for (bool live : {true, false}) {
    Pipe p(two_appsrc_mux("nosync",
                          std::string("max-buffers=0 is-live=") + (live ? "true" : "false") + " "));
    for (int i = 0; i < 20; ++i) p.push("a0", make_buffer({{0, 0, 0, 0}}, i * k30));
    ASSERT_NE(gst_element_set_state(p.pipeline(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
    guint64 left = 0;
    g_object_get(p.get("a0"), "current-level-buffers", &left, nullptr);
    // appsrc's thread holds one more buffer while it waits in the mux.
    if (live)
      EXPECT_EQ(left, 20u - 3u);
    else
      EXPECT_EQ(left, 0u);
  }
}

// Going to NULL while a producer waits for room in a full queue must not hang.
TEST(TensorSyncFlow, StopWhileAProducerWaitsForRoom) {
  Pipe p(two_appsrc_mux("slowest", "max-buffers=0 "));
  for (int i = 0; i < 200; ++i) p.push("a0", make_buffer({{0, 0, 0, 0}}, i * k30));
  ASSERT_NE(gst_element_set_state(p.pipeline(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  std::this_thread::sleep_for(std::chrono::milliseconds(100));
  finish_within(5, "PLAYING->NULL while a producer waits for room",
                [&] { gst_element_set_state(p.pipeline(), GST_STATE_NULL); });
}

// A tee pushing to two pads of one mux from a single thread (no queues): the first pad's
// buffer waits in its queue while the thread goes on to the second pad.
TEST(TensorSyncFlow, TeeIntoTwoPadsWithoutQueues) {
  Pipe p(appsrc("a0", kCaps) +
         "! tee name=t t. ! mux.sink_0 t. ! mux.sink_1 "
         "tensor_mux name=mux sync-mode=nosync ! appsink name=out sync=false");
  p.collect("out");
  for (uint8_t i = 0; i < 5; ++i) p.push("a0", make_buffer({{0, i, 0, 0}}, i * k30));
  p.eos("a0");
  auto r = p.run(10);
  ASSERT_TRUE(r.eos) << (r.timed_out ? "timed out" : r.error_text);
  ASSERT_EQ(p.out().size(), 5u);
  for (uint8_t i = 0; i < 5; ++i) {
    EXPECT_EQ(gst_buffer_n_memory(p.out()[i]), 2u);
    EXPECT_EQ(gst_buffer_peek_memory(p.out()[i], 0), gst_buffer_peek_memory(p.out()[i], 1))
        << "both tensors are the one tee'd memory";
    EXPECT_EQ(tensor_bytes(p.out()[i], 1)[1], i);
  }
}

// LATENCY: live when any input is live; min = the largest minimum, max = the smallest maximum.
TEST(TensorSyncFlow, LatencyQueryCombinesTheInputs) {
  Pipe p(appsrc("a0", kCaps) + "is-live=true min-latency=20000000 max-latency=100000000 " +
         "! mux.sink_0 " + appsrc("a1", kCaps) +
         "is-live=true min-latency=50000000 max-latency=80000000 ! mux.sink_1 " +
         appsrc("a2", kCaps) + "! mux.sink_2 tensor_mux name=mux ! fakesink sync=false");
  ASSERT_NE(gst_element_set_state(p.pipeline(), GST_STATE_PAUSED), GST_STATE_CHANGE_FAILURE);
  GstPad *src = gst_element_get_static_pad(p.get("mux"), "src");
  GstQuery *q = gst_query_new_latency();
  ASSERT_TRUE(gst_pad_query(src, q));
  gboolean live = FALSE;
  GstClockTime min = 0, max = 0;
  gst_query_parse_latency(q, &live, &min, &max);
  EXPECT_TRUE(live);
  EXPECT_EQ(min, 50 * GST_MSECOND);
  EXPECT_EQ(max, 80 * GST_MSECOND);
  gst_query_unref(q);
  gst_object_unref(src);
}

TEST(TensorSyncFlow, LatencyQueryWithoutLiveInputs) {
  Pipe p(two_appsrc_mux("nosync"));
  ASSERT_NE(gst_element_set_state(p.pipeline(), GST_STATE_PAUSED), GST_STATE_CHANGE_FAILURE);
  GstPad *src = gst_element_get_static_pad(p.get("mux"), "src");
  GstQuery *q = gst_query_new_latency();
  ASSERT_TRUE(gst_pad_query(src, q));
  gboolean live = TRUE;
  gst_query_parse_latency(q, &live, nullptr, nullptr);
  EXPECT_FALSE(live);
  gst_query_unref(q);
  gst_object_unref(src);
}

// The element answers caps queries from its templates, and its pads are in request order.
TEST(TensorSyncFlow, PadsAndCapsQueries) {
  GstElement *merge = gst_element_factory_make("tensor_merge", nullptr);
  ASSERT_NE(merge, nullptr);
  GstPad *s3 = gst_element_request_pad_simple(merge, "sink_3");
  GstPad *any = gst_element_request_pad_simple(merge, "sink_%u");
  ASSERT_TRUE(s3 && any);
  EXPECT_STREQ(GST_PAD_NAME(s3), "sink_3");
  EXPECT_STREQ(GST_PAD_NAME(any), "sink_4") << "serials continue after the highest";
  GstCaps *c = gst_pad_query_caps(s3, nullptr);
  GstCaps *ok = gst_caps_from_string(
      "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8,"
      "framerate=30/1");
  GstCaps *bad = gst_caps_from_string("other/tensors,format=flexible,framerate=30/1");
  EXPECT_TRUE(gst_caps_can_intersect(c, ok));
  EXPECT_TRUE(gst_pad_query_accept_caps(s3, ok));
  EXPECT_FALSE(gst_pad_query_accept_caps(s3, bad)) << "tensor_merge takes static tensors only";
  gst_caps_unref(c);
  gst_caps_unref(ok);
  gst_caps_unref(bad);
  gst_element_release_request_pad(merge, s3);
  gst_element_release_request_pad(merge, any);
  gst_object_unref(s3);
  gst_object_unref(any);
  gst_object_unref(merge);
}

}  // namespace
}  // namespace nns::test

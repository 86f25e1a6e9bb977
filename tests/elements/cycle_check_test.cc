// SPDX-License-Identifier: LGPL-2.1-only
// The leak and hang checks of cycle_check.h can fail: an element that keeps a buffer or an
// event is reported (with where the object was seen), and a cycle that hangs aborts.
#include <gtest/gtest.h>

#include "elements/cycle_check.h"
#include "elements/stream_util.h"

namespace nns::test {
namespace {

const char *kCaps = "other/tensors,format=static,num_tensors=1,dimensions=(string)4,types=uint8";

struct Kept {
  GstBuffer *buffer = nullptr;
  GstEvent *event = nullptr;
};

// A "leaky element": a probe on identity's src pad that keeps the second buffer and the
// SEGMENT event it sees.
GstPadProbeReturn keep(GstPad *, GstPadProbeInfo *info, gpointer user) {
  auto *k = static_cast<Kept *>(user);
  if (info->type & GST_PAD_PROBE_TYPE_BUFFER) {
    GstBuffer *b = GST_PAD_PROBE_INFO_BUFFER(info);
    if (GST_BUFFER_PTS(b) == 1 && !k->buffer) k->buffer = gst_buffer_ref(b);
  } else if (info->type & GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM) {
    GstEvent *ev = GST_PAD_PROBE_INFO_EVENT(info);
    if (GST_EVENT_TYPE(ev) == GST_EVENT_SEGMENT && !k->event) k->event = gst_event_ref(ev);
  }
  return GST_PAD_PROBE_OK;
}

TEST(LiveObjects, CountsWhatAnElementKeeps) {
  Pipe p(appsrc("in", kCaps) + "! identity name=leaky ! fakesink name=out sync=false");
  Kept k;
  GstPad *src = gst_element_get_static_pad(p.get("leaky"), "src");
  gst_pad_add_probe(
      src,
      static_cast<GstPadProbeType>(GST_PAD_PROBE_TYPE_BUFFER | GST_PAD_PROBE_TYPE_EVENT_DOWNSTREAM),
      keep, &k, nullptr);
  gst_object_unref(src);
  LiveObjects live(p.pipeline());
  ASSERT_NE(gst_element_set_state(p.pipeline(), GST_STATE_PLAYING), GST_STATE_CHANGE_FAILURE);
  for (GstClockTime t = 0; t < 3; ++t) p.push("in", make_buffer({{1, 2, 3, 4}}, t));
  ASSERT_TRUE(live.wait_delivered("out", 3));
  EXPECT_EQ(live.delivered("leaky"), 3u);
  ASSERT_EQ(gst_element_set_state(p.pipeline(), GST_STATE_NULL), GST_STATE_CHANGE_SUCCESS);
  ASSERT_NE(k.buffer, nullptr);
  ASSERT_NE(k.event, nullptr);
  // The kept buffer, its memory and the segment event.
  EXPECT_EQ(live.alive(), 3u) << live.describe();
  std::string d = live.describe();
  EXPECT_NE(d.find("buffer pts=1 size=4 at in:src"), std::string::npos) << d;
  EXPECT_NE(d.find("memory 0 of buffer pts=1"), std::string::npos) << d;
  EXPECT_NE(d.find("segment event at in:src"), std::string::npos) << d;
  gst_buffer_unref(k.buffer);
  gst_event_unref(k.event);
  EXPECT_EQ(live.alive(), 0u) << live.describe();
  EXPECT_GE(live.tracked(), 8u);  // 3 buffers, 3 memories, stream-start, caps, segment
}

TEST(LiveObjects, StateCyclesPassWhenNothingIsKept) {
  Pipe p(appsrc("in", kCaps) + "! identity ! fakesink name=out sync=false");
  state_cycles(p.pipeline(), 5, [&](int i, LiveObjects &live) {
    std::size_t before = live.delivered("out");
    p.push("in", make_buffer({{1, 2, 3, 4}}, i));
    EXPECT_TRUE(live.wait_delivered("out", before + 1)) << "cycle " << i;
  });
}

TEST(LiveObjectsDeathTest, HangingCycleAborts) {
  GTEST_FLAG_SET(death_test_style, "threadsafe");
  EXPECT_DEATH(
      {
        Watchdog dog(0.2, "cycle 7");
        std::this_thread::sleep_for(std::chrono::seconds(5));
      },
      "HANG: cycle 7 did not finish within 0.2 s");
}

}  // namespace
}  // namespace nns::test

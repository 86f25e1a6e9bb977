// SPDX-License-Identifier: LGPL-2.1-only
// nns::gst::MemoryRecycler (src/gst/memory_recycler.h): a memory is handed out again only
// once nothing but the recycler holds it; tensor_transform reuses its output memories.
#include <gst/check/gstharness.h>
#include <gtest/gtest.h>

#include <cstring>
#include <vector>

#include "gst/gst_ptr.h"
#include "gst/memory_recycler.h"
#include "support/harness.h"

using nns::gst::MemoryRecycler;

TEST(MemoryRecycler, ReusesOnlyWhatNothingElseHolds) {
  MemoryRecycler r(2);
  GstMemory *a = r.alloc(1000);
  ASSERT_NE(a, nullptr);
  GstBuffer *buf = gst_buffer_new();
  gst_buffer_append_memory(buf, a);  // the buffer holds a
  EXPECT_TRUE(gst_buffer_is_writable(buf));
  GstMapInfo mi;
  ASSERT_TRUE(gst_buffer_map(buf, &mi, GST_MAP_WRITE)) << "the recycler's ref must not lock it";
  gst_buffer_unmap(buf, &mi);
  GstMemory *b = r.alloc(1000);
  EXPECT_NE(b, a) << "a is still in a buffer";
  GstMemory *part = gst_memory_share(a, 10, 20);  // a sub-memory keeps a alive
  gst_buffer_unref(buf);
  gst_memory_unref(b);
  GstMemory *c = r.alloc(1000);
  EXPECT_EQ(c, b) << "b was let go: reused";
  GstMemory *d = r.alloc(1000);
  EXPECT_NE(d, a) << "a is still shared by a sub-memory";
  gst_memory_unref(part);
  gst_memory_unref(c);
  gst_memory_unref(d);
  GstMemory *f = r.alloc(1000);  // marked read-only by its user: never handed out again
  GST_MINI_OBJECT_FLAG_SET(f, GST_MEMORY_FLAG_READONLY);
  gst_memory_unref(f);
  GstMemory *g = r.alloc(1000);
  EXPECT_NE(g, f);
  gst_memory_unref(g);
  GstMemory *e = r.alloc(999);  // another size: a new one (keep=2 drops the oldest kept)
  gsize size = gst_memory_get_sizes(e, nullptr, nullptr);
  EXPECT_EQ(size, 999u);
  gst_memory_unref(e);
  r.clear();
}

// tensor_transform: the second output reuses the first's memory once it was let go, with the
// right bytes.
TEST(MemoryRecycler, TensorTransformReusesItsOutputMemory) {
  GstHarness *h = gst_harness_new_parse("tensor_transform mode=arithmetic option=add:1");
  gst_harness_set_src_caps_str(h,
                               "other/tensors,format=static,num_tensors=1,dimensions=(string)"
                               "1024:1,types=(string)uint8,framerate=(fraction)0/1");
  auto push = [&](uint8_t v) {
    GstBuffer *in = gst_buffer_new_allocate(nullptr, 1024, nullptr);
    gst_buffer_memset(in, 0, v, 1024);
    EXPECT_EQ(gst_harness_push(h, in), GST_FLOW_OK);
    return gst_harness_pull(h);
  };
  GstBuffer *o1 = push(1);
  ASSERT_NE(o1, nullptr);
  const GstMemory *m1 = gst_buffer_peek_memory(o1, 0);
  gst_buffer_unref(o1);
  GstBuffer *o2 = push(7);
  ASSERT_NE(o2, nullptr);
  EXPECT_EQ(gst_buffer_peek_memory(o2, 0), m1);
  GstMapInfo mi;
  ASSERT_TRUE(gst_buffer_map(o2, &mi, GST_MAP_READ));
  std::vector<uint8_t> want(1024, 8);
  EXPECT_EQ(0, memcmp(mi.data, want.data(), 1024));
  gst_buffer_unmap(o2, &mi);
  GstBuffer *o3 = push(9);  // o2 still held: another memory
  EXPECT_NE(gst_buffer_peek_memory(o3, 0), gst_buffer_peek_memory(o2, 0));
  gst_buffer_unref(o2);
  gst_buffer_unref(o3);
  gst_harness_teardown(h);
}

// SPDX-License-Identifier: LGPL-2.1-only
// Test helper for the flow-control elements: a gst-launch description whose sources are
// `appsrc name=<x>` (frames queued before running) and whose sinks are `appsink name=<y>`
// (every sample recorded: tensor memories, timestamps, flags and the caps in force).
#pragma once

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "support/harness.h"

namespace nns::test {

using Bytes = std::vector<uint8_t>;

struct Frame {
  Frame() = default;
  Frame(std::vector<Bytes> m, GstClockTime p = GST_CLOCK_TIME_NONE,
        GstClockTime d = GST_CLOCK_TIME_NONE)
      : mems(std::move(m)), pts(p), duration(d) {}
  std::vector<Bytes> mems;
  GstClockTime pts = GST_CLOCK_TIME_NONE;
  GstClockTime duration = GST_CLOCK_TIME_NONE;
  bool gap = false;
  std::string caps;  // caps of the sample (output side)
};

template <typename T>
Bytes bytes_of(const std::vector<T> &v) {
  Bytes b(v.size() * sizeof(T));
  std::memcpy(b.data(), v.data(), b.size());
  return b;
}

template <typename T>
std::vector<T> values_of(const Bytes &b) {
  std::vector<T> v(b.size() / sizeof(T));
  std::memcpy(v.data(), b.data(), v.size() * sizeof(T));
  return v;
}

inline GstBuffer *make_buffer(const Frame &f) {
  GstBuffer *buf = gst_buffer_new();
  for (const auto &m : f.mems) {
    gpointer data = g_memdup2(m.data(), m.size());
    gst_buffer_append_memory(buf, gst_memory_new_wrapped(static_cast<GstMemoryFlags>(0), data,
                                                         m.size(), 0, m.size(), data, g_free));
  }
  GST_BUFFER_PTS(buf) = f.pts;
  GST_BUFFER_DURATION(buf) = f.duration;
  return buf;
}

inline Frame frame_of(GstBuffer *buf) {
  Frame f;
  for (guint i = 0; i < gst_buffer_n_memory(buf); ++i) {
    GstMemory *mem = gst_buffer_peek_memory(buf, i);
    GstMapInfo map;
    if (!gst_memory_map(mem, &map, GST_MAP_READ)) continue;
    f.mems.emplace_back(map.data, map.data + map.size);
    gst_memory_unmap(mem, &map);
  }
  f.pts = GST_BUFFER_PTS(buf);
  f.duration = GST_BUFFER_DURATION(buf);
  f.gap = GST_BUFFER_FLAG_IS_SET(buf, GST_BUFFER_FLAG_GAP);
  return f;
}

class AppPipeline {
 public:
  explicit AppPipeline(const std::string &desc) : desc_(desc) {
    GError *err = nullptr;
    pipeline_ = gst_parse_launch(desc.c_str(), &err);
    EXPECT_EQ(err, nullptr) << desc << ": " << (err ? err->message : "");
    if (err) g_error_free(err);
    if (!pipeline_) return;
    GstIterator *it = gst_bin_iterate_recurse(GST_BIN(pipeline_));
    GValue v = G_VALUE_INIT;
    while (gst_iterator_next(it, &v) == GST_ITERATOR_OK) {
      auto *e = GST_ELEMENT(g_value_get_object(&v));
      if (GST_IS_APP_SINK(e)) {
        gchar *name = gst_element_get_name(e);
        auto *slot = &sinks_[name];
        slot->owner = this;
        slot->name = name;
        g_free(name);
        g_object_set(e, "emit-signals", TRUE, "sync", FALSE, nullptr);
        g_signal_connect(e, "new-sample", G_CALLBACK(on_sample), slot);
      } else if (GST_IS_APP_SRC(e)) {
        g_object_set(e, "max-bytes", static_cast<guint64>(0), "format", GST_FORMAT_TIME, nullptr);
      }
      g_value_reset(&v);
    }
    g_value_unset(&v);
    gst_iterator_free(it);
  }
  ~AppPipeline() {
    if (pipeline_) {
      gst_element_set_state(pipeline_, GST_STATE_NULL);
      gst_object_unref(pipeline_);
    }
  }
  AppPipeline(const AppPipeline &) = delete;
  AppPipeline &operator=(const AppPipeline &) = delete;

  GstElement *pipeline() const { return pipeline_; }
  GstElement *get(const std::string &name) const {
    return gst_bin_get_by_name(GST_BIN(pipeline_), name.c_str());  // caller unrefs
  }
  void set_caps(const std::string &src, const std::string &caps) {
    GstElement *e = get(src);
    ASSERT_NE(e, nullptr) << src;
    GstCaps *c = gst_caps_from_string(caps.c_str());
    ASSERT_NE(c, nullptr) << caps;
    g_object_set(e, "caps", c, nullptr);
    gst_caps_unref(c);
    gst_object_unref(e);
  }
  void push(const std::string &src, const Frame &f) {
    GstElement *e = get(src);
    ASSERT_NE(e, nullptr) << src;
    EXPECT_EQ(gst_app_src_push_buffer(GST_APP_SRC(e), make_buffer(f)), GST_FLOW_OK);
    gst_object_unref(e);
  }
  void eos(const std::string &src) {
    GstElement *e = get(src);
    ASSERT_NE(e, nullptr) << src;
    gst_app_src_end_of_stream(GST_APP_SRC(e));
    gst_object_unref(e);
  }
  RunResult run(double timeout_s = 20.0) { return run_pipeline(pipeline_, timeout_s); }
  std::vector<Frame> frames(const std::string &sink) {
    std::lock_guard<std::mutex> l(m_);
    return sinks_[sink].frames;
  }

 private:
  struct Slot {
    AppPipeline *owner = nullptr;
    std::string name;
    std::vector<Frame> frames;
  };
  static GstFlowReturn on_sample(GstAppSink *sink, gpointer user) {
    auto *slot = static_cast<Slot *>(user);
    GstSample *s = gst_app_sink_pull_sample(sink);
    if (!s) return GST_FLOW_ERROR;
    Frame f = frame_of(gst_sample_get_buffer(s));
    if (GstCaps *c = gst_sample_get_caps(s)) {
      gchar *str = gst_caps_to_string(c);
      f.caps = str;
      g_free(str);
    }
    gst_sample_unref(s);
    std::lock_guard<std::mutex> l(slot->owner->m_);
    slot->frames.push_back(std::move(f));
    return GST_FLOW_OK;
  }

  std::string desc_;
  GstElement *pipeline_ = nullptr;
  std::mutex m_;
  std::map<std::string, Slot> sinks_;
};

// Caps string for appsrc: static tensors "t1,t2" with dims "d1,d2".
inline std::string static_caps(const std::string &dims, const std::string &types,
                               const std::string &rate = "0/1") {
  std::size_t n = 1;
  for (char c : types) n += (c == ',');
  return "other/tensors,format=static,num_tensors=" + std::to_string(n) + ",dimensions=(string)\"" +
         dims + "\",types=(string)\"" + types + "\",framerate=(fraction)" + rate;
}

}  // namespace nns::test

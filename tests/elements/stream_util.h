// SPDX-License-Identifier: LGPL-2.1-only
// Helpers for the stream-composition element tests: pipelines fed by named appsrc elements
// with explicit PTS, and an appsink that keeps every output buffer.
#pragma once

#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstring>
#include <map>
#include <mutex>
#include <string>
#include <vector>

#include "support/harness.h"

namespace nns::test {

inline GstBuffer *make_buffer(const std::vector<std::vector<uint8_t>> &tensors, GstClockTime pts,
                              GstClockTime duration = GST_CLOCK_TIME_NONE) {
  GstBuffer *b = gst_buffer_new();
  for (const auto &t : tensors) {
    GstMemory *m = gst_allocator_alloc(nullptr, t.size(), nullptr);
    GstMapInfo map;
    gst_memory_map(m, &map, GST_MAP_WRITE);
    if (!t.empty()) std::memcpy(map.data, t.data(), t.size());
    gst_memory_unmap(m, &map);
    gst_buffer_append_memory(b, m);
  }
  GST_BUFFER_PTS(b) = pts;
  GST_BUFFER_DURATION(b) = duration;
  return b;
}

inline std::vector<uint8_t> tensor_bytes(GstBuffer *b, guint idx) {
  GstMemory *m = gst_buffer_peek_memory(b, idx);
  GstMapInfo map;
  gst_memory_map(m, &map, GST_MAP_READ);
  std::vector<uint8_t> v(map.data, map.data + map.size);
  gst_memory_unmap(m, &map);
  return v;
}

// A parsed pipeline; owns it and every pulled buffer.
class Pipe {
 public:
  explicit Pipe(const std::string &desc) {
    GError *err = nullptr;
    pipeline_ = gst_parse_launch(desc.c_str(), &err);
    if (err) {
      ADD_FAILURE() << "parse error: " << err->message;
      g_error_free(err);
    }
  }
  ~Pipe() {
    if (pipeline_) {
      gst_element_set_state(pipeline_, GST_STATE_NULL);
      gst_object_unref(pipeline_);
    }
    for (auto &v : out_)
      for (auto *b : v.second) gst_buffer_unref(b);
  }
  Pipe(const Pipe &) = delete;
  Pipe &operator=(const Pipe &) = delete;

  GstElement *get(const char *name) {
    GstElement *e = gst_bin_get_by_name(GST_BIN(pipeline_), name);
    if (e) gst_object_unref(e);  // the pipeline keeps it alive
    return e;
  }
  GstElement *pipeline() { return pipeline_; }
  // Queues a buffer in appsrc `src` (taking it).
  void push(const char *src, GstBuffer *b) {
    ASSERT_EQ(gst_app_src_push_buffer(GST_APP_SRC(get(src)), b), GST_FLOW_OK);
  }
  void eos(const char *src) { gst_app_src_end_of_stream(GST_APP_SRC(get(src))); }
  // Runs to EOS or ERROR, then sets the pipeline to NULL.
  RunResult run(double timeout = 20) { return run_pipeline(pipeline_, timeout); }
  // Keeps every buffer appsink `sink` receives (call before run()).
  void collect(const char *sink) {
    GstAppSinkCallbacks cb{};
    cb.new_sample = [](GstAppSink *s, gpointer user) -> GstFlowReturn {
      auto *self = static_cast<Pipe *>(user);
      GstSample *smp = gst_app_sink_pull_sample(s);
      GstBuffer *b = gst_sample_get_buffer(smp);
      std::lock_guard<std::mutex> g(self->lock_);
      self->out_[GST_OBJECT_NAME(s)].push_back(gst_buffer_ref(b));
      gst_sample_unref(smp);
      return GST_FLOW_OK;
    };
    gst_app_sink_set_callbacks(GST_APP_SINK(get(sink)), &cb, this, nullptr);
  }
  std::vector<GstBuffer *> &out(const std::string &sink = "out") { return out_[sink]; }

 private:
  GstElement *pipeline_ = nullptr;
  std::mutex lock_;
  std::map<std::string, std::vector<GstBuffer *>> out_;
};

// appsrc description for a tensor stream.
inline std::string appsrc(const std::string &name, const std::string &caps) {
  return "appsrc name=" + name + " format=time caps=\"" + caps + "\" ";
}

}  // namespace nns::test

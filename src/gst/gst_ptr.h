// SPDX-License-Identifier: LGPL-2.1-only
// unique_ptr aliases for GLib/GStreamer handles, so error paths never need a manual unref.
#pragma once

#include <gst/gst.h>

#include <memory>

namespace nns::gst {

template <typename T, void (*F)(T *)>
struct Deleter {
  void operator()(T *p) const {
    if (p) F(p);
  }
};

inline void unref_caps(GstCaps *c) {
  gst_caps_unref(c);
}
inline void unref_buffer(GstBuffer *b) {
  gst_buffer_unref(b);
}
inline void unref_memory(GstMemory *m) {
  gst_memory_unref(m);
}
inline void unref_object(GstObject *o) {
  gst_object_unref(o);
}
inline void unref_element(GstElement *e) {
  gst_object_unref(e);
}
inline void unref_message(GstMessage *m) {
  gst_message_unref(m);
}
inline void unref_event(GstEvent *e) {
  gst_event_unref(e);
}
inline void free_gchar(gchar *s) {
  g_free(s);
}
inline void free_error(GError *e) {
  g_error_free(e);
}
inline void free_structure(GstStructure *s) {
  gst_structure_free(s);
}

using CapsPtr = std::unique_ptr<GstCaps, Deleter<GstCaps, unref_caps>>;
using BufferPtr = std::unique_ptr<GstBuffer, Deleter<GstBuffer, unref_buffer>>;
using MemoryPtr = std::unique_ptr<GstMemory, Deleter<GstMemory, unref_memory>>;
using ElementPtr = std::unique_ptr<GstElement, Deleter<GstElement, unref_element>>;
using MessagePtr = std::unique_ptr<GstMessage, Deleter<GstMessage, unref_message>>;
using EventPtr = std::unique_ptr<GstEvent, Deleter<GstEvent, unref_event>>;
using GCharPtr = std::unique_ptr<gchar, Deleter<gchar, free_gchar>>;
using GErrorPtr = std::unique_ptr<GError, Deleter<GError, free_error>>;
using StructurePtr = std::unique_ptr<GstStructure, Deleter<GstStructure, free_structure>>;

// RAII map of a GstMemory or GstBuffer.
class MemoryMap {
 public:
  MemoryMap(GstMemory *mem, GstMapFlags flags) : mem_(mem) {
    ok_ = gst_memory_map(mem, &info_, flags);
  }
  ~MemoryMap() {
    if (ok_) gst_memory_unmap(mem_, &info_);
  }
  MemoryMap(const MemoryMap &) = delete;
  MemoryMap &operator=(const MemoryMap &) = delete;
  bool ok() const { return ok_; }
  guint8 *data() const { return info_.data; }
  gsize size() const { return info_.size; }

 private:
  GstMemory *mem_;
  GstMapInfo info_{};
  bool ok_ = false;
};

class BufferMap {
 public:
  BufferMap(GstBuffer *buf, GstMapFlags flags) : buf_(buf) {
    ok_ = gst_buffer_map(buf, &info_, flags);
  }
  ~BufferMap() {
    if (ok_) gst_buffer_unmap(buf_, &info_);
  }
  BufferMap(const BufferMap &) = delete;
  BufferMap &operator=(const BufferMap &) = delete;
  bool ok() const { return ok_; }
  guint8 *data() const { return info_.data; }
  gsize size() const { return info_.size; }

 private:
  GstBuffer *buf_;
  GstMapInfo info_{};
  bool ok_ = false;
};

}  // namespace nns::gst

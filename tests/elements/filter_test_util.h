// SPDX-License-Identifier: LGPL-2.1-only
// Helpers shared by the tensor_filter tests.
#pragma once

#include <gst/check/gstharness.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "core/nns_conf.h"
#include "support/harness.h"
#include "tensor_filter_custom_easy.h"

namespace nns::test {

inline std::string filter_dir() {
  return NNS_TEST_FILTER_DIR;
}

inline std::string tensors_caps(const std::string &types, const std::string &dims, int num = 1) {
  return "other/tensors,format=static,num_tensors=" + std::to_string(num) + ",types=(string)\"" +
         types + "\",dimensions=(string)\"" + dims + "\",framerate=0/1";
}

// fakesrc producing `n` zero-filled buffers of `bytes` bytes with the given tensor caps.
inline std::string fake_source(std::size_t bytes, const std::string &caps, int n = 3) {
  return "fakesrc num-buffers=" + std::to_string(n) +
         " sizetype=fixed sizemax=" + std::to_string(bytes) + " filltype=zero ! " + caps + " ! ";
}

inline GstTensorsInfo gst_info(tensor_type type, std::initializer_list<uint32_t> dims) {
  GstTensorsInfo i;
  std::memset(&i, 0, sizeof i);
  i.num_tensors = 1;
  i.info[0].type = type;
  unsigned k = 0;
  for (uint32_t d : dims) i.info[0].dimension[k++] = d;
  return i;
}

// A buffer with one memory per tensor.
inline GstBuffer *tensor_buffer(const std::vector<std::vector<uint8_t>> &tensors) {
  GstBuffer *b = gst_buffer_new();
  for (const auto &t : tensors) {
    GstMemory *m = gst_allocator_alloc(nullptr, t.size(), nullptr);
    GstMapInfo map;
    gst_memory_map(m, &map, GST_MAP_WRITE);
    if (!t.empty()) std::memcpy(map.data, t.data(), t.size());
    gst_memory_unmap(m, &map);
    gst_buffer_append_memory(b, m);
  }
  return b;
}

inline std::vector<uint8_t> memory_bytes(GstBuffer *b, guint i) {
  GstMemory *m = gst_buffer_peek_memory(b, i);
  GstMapInfo map;
  gst_memory_map(m, &map, GST_MAP_READ);
  std::vector<uint8_t> v(map.data, map.data + map.size);
  gst_memory_unmap(m, &map);
  return v;
}

// Writes `text` to a new file in a temp folder and returns its path.
inline std::string write_temp(const std::string &name, const std::string &text) {
  std::string p = make_temp_dir() + "/" + name;
  std::ofstream(p) << text;
  return p;
}

// Sets an environment variable for the life of the object.
class ScopedEnv {
 public:
  ScopedEnv(const char *name, const std::string &value) : name_(name) {
    if (const char *old = std::getenv(name)) {
      had_ = true;
      old_ = old;
    }
    setenv(name, value.c_str(), 1);
    nns::Conf::reload();
  }
  ~ScopedEnv() {
    if (had_)
      setenv(name_, old_.c_str(), 1);
    else
      unsetenv(name_);
    nns::Conf::reload();
  }

 private:
  const char *name_;
  bool had_ = false;
  std::string old_;
};

// An nnstreamer.ini whose only filter folder is the test back-end folder.
inline std::string test_ini(const std::string &extra = "") {
  return write_temp("nnstreamer.ini", "[common]\nenable_envvar=False\n[filter]\nfilters=" +
                                          filter_dir() + "\n" + extra);
}

// GstHarness around one element description, with a bus to catch its errors.
struct FilterHarness {
  HarnessPtr h;
  GstBus *bus = nullptr;
  explicit FilterHarness(const std::string &desc, const std::string &src_caps) {
    GstElement *e = gst_parse_launch(desc.c_str(), nullptr);
    bus = gst_bus_new();
    gst_element_set_bus(e, bus);  // before the harness starts it: catches messages of the start
    h.reset(gst_harness_new_with_element(e, "sink", "src"));
    gst_object_unref(e);
    gst_harness_set_src_caps_str(h.get(), src_caps.c_str());
  }
  ~FilterHarness() {
    // Drop the queued messages first: they hold the element, which holds the bus (a leak cycle).
    gst_bus_set_flushing(bus, TRUE);
    h.reset();
    gst_object_unref(bus);
  }
  GstElement *element() { return h->element; }
  std::string error_text() { return message_text(GST_MESSAGE_ERROR); }
  std::string warning_text() { return message_text(GST_MESSAGE_WARNING); }
  // The texts of the queued messages of `type` (ERROR or WARNING), which are taken off the bus.
  std::string message_text(GstMessageType type) {
    std::string out;
    while (GstMessage *m = gst_bus_pop_filtered(bus, type)) {
      GError *e = nullptr;
      gchar *dbg = nullptr;
      if (type == GST_MESSAGE_ERROR)
        gst_message_parse_error(m, &e, &dbg);
      else
        gst_message_parse_warning(m, &e, &dbg);
      out += e->message;
      g_error_free(e);
      g_free(dbg);
      gst_message_unref(m);
    }
    return out;
  }
};

}  // namespace nns::test

// SPDX-License-Identifier: LGPL-2.1-only
// Shared by the python3 converter and decoder sub-plugin tests: script paths, "is it built"
// checks, and buffer/caps helpers for GstHarness.
#pragma once

#include <gst/check/gstharness.h>
#include <gst/gst.h>
#include <gtest/gtest.h>

#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "support/harness.h"

namespace nns::test::convdec {

// tests/data/python/convdec/<name>.
inline std::string script(const std::string &name) {
  return std::string(NNS_SOURCE_DIR) + "/tests/data/python/convdec/" + name;
}

// True when build/subplugins/<kind>s/libnnstreamer_<kind>_python3.so exists (kind: "converter"
// or "decoder").
inline bool python3_subplugin_built(const std::string &kind) {
  return std::filesystem::exists(std::string(NNS_BUILD_DIR) + "/subplugins/" + kind +
                                 "s/libnnstreamer_" + kind + "_python3.so");
}

// True when `element` is registered and the python3 sub-plugin of `kind` is built.
inline bool available(const char *element, const std::string &kind) {
  GstElementFactory *f = gst_element_factory_find(element);
  if (!f) return false;
  gst_object_unref(f);
  return python3_subplugin_built(kind);
}

// Skips the test unless `element` is registered and the python3 sub-plugin of `kind` is built.
#define REQUIRE_PYTHON3_SUBPLUGIN(element, kind)                            \
  do {                                                                      \
    if (!nns::test::convdec::available(element, kind))                      \
      GTEST_SKIP() << "the python3 " << kind << " sub-plugin is not built"; \
  } while (0)

inline GstBuffer *bytes_buffer(const std::vector<uint8_t> &v) {
  GstBuffer *b = gst_buffer_new_allocate(nullptr, v.size(), nullptr);
  gst_buffer_fill(b, 0, v.data(), v.size());
  return b;
}

// `r` ended in an error whose text contains every one of `parts`.
inline void expect_error_parts(const nns::test::RunResult &r,
                               const std::vector<std::string> &parts) {
  ASSERT_TRUE(r.error) << "expected an error";
  for (const auto &p : parts)
    EXPECT_NE(r.error_text.find(p), std::string::npos) << p << " not in:\n" << r.error_text;
}

// The caps on the harness' sink pad as a string ("" when none are set).
inline std::string current_caps(GstHarness *h) {
  GstCaps *c = gst_pad_get_current_caps(h->sinkpad);
  if (!c) return "";
  gchar *s = gst_caps_to_string(c);
  std::string r = s;
  g_free(s);
  gst_caps_unref(c);
  return r;
}

}  // namespace nns::test::convdec

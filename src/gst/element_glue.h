// SPDX-License-Identifier: LGPL-2.1-only
// Exception boundary between C++ element code and GLib: every vfunc runs its body through
// guard(), which turns nns::Error and std::exception into a posted GST_ELEMENT_ERROR message.
// No exception ever crosses into GLib.
#pragma once

#include <gst/gst.h>

#include <exception>
#include <string>
#include <utility>

#include "core/error.h"

namespace nns::gst {

// Posts an ERROR message on the bus of `element`. `text` names the property/tensor, what was
// expected and what was got; the element's name is prefixed so the message stands alone.
void post_error(GstElement *element, ErrorKind kind, const std::string &text, const char *file,
                const char *func, int line);
void post_warning(GstElement *element, const std::string &text, const char *file, const char *func,
                  int line);

#define NNS_POST_ERROR(elem, kind, text) \
  ::nns::gst::post_error(GST_ELEMENT_CAST(elem), kind, text, __FILE__, GST_FUNCTION, __LINE__)
#define NNS_POST_WARNING(elem, text) \
  ::nns::gst::post_warning(GST_ELEMENT_CAST(elem), text, __FILE__, GST_FUNCTION, __LINE__)

// Runs `body`; on an exception posts it and returns `on_error`.
template <typename R, typename F>
R guard(gpointer element, R on_error, F &&body) noexcept {
  try {
    return std::forward<F>(body)();
  } catch (const Error &e) {
    NNS_POST_ERROR(element, e.kind(), e.what());
  } catch (const std::exception &e) {
    NNS_POST_ERROR(element, ErrorKind::kInternal, std::string("internal error: ") + e.what());
  } catch (...) {
    NNS_POST_ERROR(element, ErrorKind::kInternal, "internal error: unknown exception");
  }
  return on_error;
}

// Same, for void bodies.
template <typename F>
void guard_void(gpointer element, F &&body) noexcept {
  guard(element, 0, [&] {
    std::forward<F>(body)();
    return 0;
  });
}

}  // namespace nns::gst

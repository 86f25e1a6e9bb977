// SPDX-License-Identifier: LGPL-2.1-only
// Small helpers shared by the built-in back ends (custom, custom-easy, cpp).
#pragma once

#include <cerrno>
#include <cstring>
#include <exception>
#include <string>

#include "nns_filter_backend.hh"

namespace nns::builtin {

inline int set_err(char *err, std::size_t len, const std::string &msg, int code = -EINVAL) {
  ::nns::detail::write_err(err, len, msg.c_str());
  return code;
}

// Runs f() (returning int); exceptions become an error code plus message.
template <typename F>
int guarded(char *err, std::size_t len, F &&f) noexcept {
  try {
    return f();
  } catch (const std::exception &e) {
    return set_err(err, len, e.what(), -EIO);
  } catch (...) {
    return set_err(err, len, "unknown exception", -EIO);
  }
}

}  // namespace nns::builtin

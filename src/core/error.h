// SPDX-License-Identifier: LGPL-2.1-only
// Errors raised by GStreamer-free code. The GStreamer layer maps `kind` to a GError domain/code
// and posts the message on the bus (src/gst/element_glue.h).
#pragma once

#include <stdexcept>
#include <string>

namespace nns {

enum class ErrorKind {
  kSettings,     // a property or option value is malformed or out of range
  kNotFound,     // a file, model or registered name does not exist
  kNegotiation,  // caps cannot be agreed on
  kStream,       // data does not match what was negotiated
  kLibrary,      // a back end / sub-plugin failed
  kInternal,
};

class Error : public std::runtime_error {
 public:
  Error(ErrorKind kind, const std::string &msg) : std::runtime_error(msg), kind_(kind) {}
  ErrorKind kind() const noexcept { return kind_; }

 private:
  ErrorKind kind_;
};

[[noreturn]] inline void fail(ErrorKind kind, const std::string &msg) {
  throw Error(kind, msg);
}

}  // namespace nns

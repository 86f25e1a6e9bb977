// SPDX-License-Identifier: LGPL-2.1-only
// Shared by datareposrc and datareposink: what kind of stream a caps describes, and the
// "%04d"-style sample file names of image repositories.
#pragma once

#include <gst/gst.h>

#include <cstdint>
#include <string>

namespace nns::gst::datarepo {

enum class Kind { kUnknown, kTensorStatic, kTensorFlexible, kVideo, kAudio, kText, kOctet, kImage };

// Kind of the first structure of `caps` (other/tensors static vs flexible/sparse, video/x-raw,
// audio/x-raw, text/x-raw, application/octet-stream, image/*).
Kind kind_of(const GstCaps *caps);
const char *kind_name(Kind k);

// `pattern` with its one integer conversion (%d, %04d, %ld, %04lld, %u ...) replaced by `index`;
// "%%" is a literal '%'. Throws nns::Error(kSettings) naming `prop` when the pattern has no
// integer conversion, more than one, or any other conversion (no user format string ever
// reaches printf).
std::string format_index(const std::string &pattern, uint64_t index, const char *prop);

// Checks a pattern without formatting (same errors).
void check_index_pattern(const std::string &pattern, const char *prop);

}  // namespace nns::gst::datarepo

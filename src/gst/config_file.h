// SPDX-License-Identifier: LGPL-2.1-only
// config-file= support shared by tensor_filter and tensor_decoder: a text file of
// `property=value` lines applied to the element, as NNStreamer's
// gst_tensor_parse_config_file(). Empty lines and lines starting with '#' are skipped;
// spaces around names and values are trimmed; values are converted with
// gst_util_set_object_arg() (so enums, booleans and numbers work as on the command line).
//
// Unlike NNStreamer (which ignores problems silently) every problem is reported: the returned
// list holds one message per unreadable file, unknown property or bad line; elements post
// them as a bus error when they start.
#pragma once

#include <gst/gst.h>

#include <string>
#include <vector>

namespace nns::gst {

// Applies `path` to `object`. `skip` names properties that must not be set from the file
// (e.g. "config-file" itself). Returns the problems found (empty when all went well).
std::vector<std::string> apply_config_file(GObject *object, const std::string &path,
                                           const std::vector<std::string> &skip = {"config-file"});

}  // namespace nns::gst

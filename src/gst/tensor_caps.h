// SPDX-License-Identifier: LGPL-2.1-only
// other/tensors and other/tensor caps <-> nns::TensorsConfig. The only place that knows the caps
// field names (format, num_tensors, dimensions, types, framerate; dimension, type for the
// legacy single-tensor caps).
#pragma once

#include <gst/gst.h>

#include "core/tensor_info.h"

namespace nns::gst {

// Pad-template caps strings.
#define NNS_TENSOR_CAPS_ANY_STR                       \
  "other/tensor, framerate = (fraction) [ 0, max ]; " \
  "other/tensors, format = (string) { static, flexible }, framerate = (fraction) [ 0, max ]"
#define NNS_TENSOR_CAPS_ALL_FORMATS_STR                             \
  "other/tensor, framerate = (fraction) [ 0, max ]; "               \
  "other/tensors, format = (string) { static, flexible, sparse }, " \
  "framerate = (fraction) [ 0, max ]"

bool is_tensor_structure(const GstStructure *s);
bool is_tensor_caps(const GstCaps *caps);  // every structure is other/tensor(s)

// Whether a stream of `format` fits structure `s`: other/tensor is static only; other/tensors
// without a format field takes any, with a string or a list of strings those named.
bool structure_allows_format(const GstStructure *s, TensorFormat format);

// Flexible caps a peer may still decorate with static fields (a capsfilter
// `other/tensors,types=uint8` intersected with `other/tensors,format=flexible`). Throws
// nns::Error(kNegotiation), naming the field, what the caps say and what `info` (what the element
// pushes) says, when such a field (num_tensors, types, dimensions) disagrees with `info`.
// `who` starts the message (e.g. "mode=typecast option=float32 makes").
void check_flexible_caps_fields(const GstCaps *caps, const TensorsInfo &info,
                                const std::string &who);

// Whether the first structure of `caps` is decorated flexible caps: other/tensors with
// format=flexible (one string) and at least one of num_tensors, types, dimensions.
bool is_decorated_flexible(const GstCaps *caps);

// Reads whatever fields are fixed; unfixed/missing fields stay unset (empty tensors,
// rate -1). Throws nns::Error(kNegotiation) on malformed dimension/type strings or when
// num_tensors disagrees with the lists.
TensorsConfig config_from_structure(const GstStructure *s);
// First structure of `caps`; throws if caps are empty or not tensor caps.
TensorsConfig config_from_caps(const GstCaps *caps);

// Fixed caps for a complete config. A single static tensor also gets a second, legacy
// other/tensor structure so peers that only accept other/tensor still link.
// If `dim_variants`, dimension strings are given as lists of equivalent spellings
// (trailing ":1" added or dropped) so a capsfilter written either way intersects; with several
// tensors, dimensions and types are also offered joined with "." (upstream's spelling).
GstCaps *caps_from_config(const TensorsConfig &config, bool dim_variants = false);
GstStructure *structure_from_config(const TensorsConfig &config);
// Takes `caps`; when they are fixed static caps of several tensors, returns
// caps_from_config(config, true) for them (the same config, also in the '.'-joined
// spellings), else `caps` unchanged. For sources whose caps come as a string from a peer or file.
GstCaps *with_tensor_spellings(GstCaps *caps);
// Fixed `caps` (not taken) in the spelling the peer of `srcpad` takes, by with_tensor_spellings;
// a new reference to `caps` itself when the peer takes none of them or they have no variants.
GstCaps *caps_in_peer_spelling(GstPad *srcpad, GstCaps *caps);

// Caps describing `format` with the given rate (or any rate if rate_n < 0).
GstCaps *caps_for_format(TensorFormat format, int rate_n = -1, int rate_d = -1);
// Legacy single-tensor `other/tensor` caps with the given rate (or any rate if rate_n < 0).
GstCaps *legacy_tensor_caps(int rate_n = -1, int rate_d = -1);

// Equivalent spellings of one dimension string: minimal rank up to max(rank, 4).
std::vector<std::string> dim_spellings(const Dims &d);

// Human-readable caps for error messages.
std::string caps_to_string(const GstCaps *caps);

}  // namespace nns::gst

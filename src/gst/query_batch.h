// SPDX-License-Identifier: LGPL-2.1-only
// Dynamic batching of a query server (tensor_query_serversrc max-batch, docs/elements/
// tensor_query_serversrc.md): requests of several clients stacked along the outermost
// dimension into one buffer of N slots (N = max-batch, fixed in the caps; slots without a
// request are zero and their answers are dropped), and tensor_query_serversink splitting the
// answer back. The slots' client ids travel in a custom meta ("GstQueryBatchMeta", no tags, so
// it survives transforms as GstMetaQuery does).
#pragma once

#include <gst/gst.h>

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "core/tensor_info.h"

namespace nns::gst {

// Caps of one request from caps of a batch of `n`: every static tensor structure whose
// tensors all have `n` as outermost dimension gets 1 there; others are dropped. ANY stays ANY.
// Fixed caps give fixed caps (one structure, no dimension variants), as NNStreamer's client
// requires of the answer caps. Returns a new reference.
GstCaps *unbatch_caps(GstCaps *caps, guint n);

// Why `caps` cannot carry batches of `n` (nullopt when they can): tensor caps, static, at
// most 16 tensors, each with outermost dimension `n`.
std::optional<std::string> batch_caps_problem(GstCaps *caps, guint n);
// The index of the first tensor of `info` whose outermost dimension is not `n` (the batch);
// nullopt when every tensor carries the batch outermost.
std::optional<std::size_t> tensor_without_batch(const TensorsInfo &info, guint n);

// Per-slot byte sizes of each tensor of a batch of `n` described by `info`.
std::vector<std::size_t> slot_sizes(const TensorsInfo &info, guint n);

void buffer_add_batch_meta(GstBuffer *buf, guint slots, const std::vector<int64_t> &clients);
// The slot client ids (empty when the buffer carries no batch meta) and the slot count.
std::vector<int64_t> buffer_get_batch_meta(GstBuffer *buf, guint *slots);

// The first element with a property `property` found from pad `from` in its direction
// (upstream from a sink pad, downstream from a src pad), walking past elements with one pad
// of that direction (capsfilters, queues, transforms), at most 8 hops; nullptr if none.
// `first` (optional) gets the name of the first element met. Returns a new reference.
GstElement *find_along(GstPad *from, const char *property, std::string *first);
// find_along() from `e`'s "sink" pad.
GstElement *find_upstream(GstElement *e, const char *property);
// "tensor_query_serversrc 'src'" for messages.
std::string element_label(GstElement *e);

// The batching source feeding `e` (a tensor_query_serversrc with max-batch > 1, or any
// element with a `max-batch` property above 1): "tensor_query_serversrc 'src'" and max-batch.
struct UpstreamBatch {
  std::string who;
  guint n = 1;
};
std::optional<UpstreamBatch> upstream_batch(GstElement *e);

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
// GstTensorSync: the base shared by tensor_mux and tensor_merge. It owns the request pads
// `sink_%u` (each with a queue), applies the sync-mode policy (src/core/time_sync.h) to choose
// one buffer per pad, negotiates the src caps and timestamps the output (PTS = the policy's
// time, other metadata from the buffer that set it). Subclasses only say how input configs
// become the output config (`configure`) and how the chosen buffers become one output
// (`combine`); the subclass must add a "src" pad template (always) and a "sink_%u" one
// (request, with the GstTensorSyncPad type).
#pragma once

#include <gst/gst.h>

#include <string>
#include <vector>

#include "core/tensor_info.h"

G_BEGIN_DECLS

#define GST_TYPE_TENSOR_SYNC_PAD (gst_tensor_sync_pad_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSyncPad, gst_tensor_sync_pad, GST, TENSOR_SYNC_PAD, GstPad)

#define GST_TYPE_TENSOR_SYNC (gst_tensor_sync_get_type())
G_DECLARE_DERIVABLE_TYPE(GstTensorSync, gst_tensor_sync, GST, TENSOR_SYNC, GstElement)

struct _GstTensorSyncClass {
  GstElementClass parent_class;
  const char *default_sync_mode;  // set by sync_install_properties
  // Output config from the sink pads' configs (pad order; `names` are the pad names for
  // messages). Called when the inputs change, by the one thread that builds outputs at that
  // moment (configure and combine never run concurrently); throws nns::Error.
  nns::TensorsConfig (*configure)(GstTensorSync *self, const std::vector<nns::TensorsConfig> &in,
                                  const std::vector<std::string> &names);
  // One output buffer (without timestamps) from one buffer per pad, in pad order, for the
  // last configured inputs. Throws nns::Error.
  GstBuffer *(*combine)(GstTensorSync *self, GstBuffer *const *in, std::size_t n);
  // Optional: validates the subclass's own properties when the element starts (throws).
  void (*check_settings)(GstTensorSync *self);
};

G_END_DECLS

namespace nns::gst {

// Installs `silent`, `sync-mode` (default `default_mode`) and `sync-option` on a subclass,
// with property ids first_id, first_id+1, first_id+2. The subclass forwards those ids to
// sync_set_property / sync_get_property (they return false for other ids).
void sync_install_properties(GObjectClass *klass, guint first_id, const char *default_mode);
bool sync_set_property(GstTensorSync *self, guint first_id, guint id, const GValue *value);
bool sync_get_property(GstTensorSync *self, guint first_id, guint id, GValue *value);

// The output config negotiated last (valid inside combine).
const TensorsConfig &sync_output_config(GstTensorSync *self);
// The slowest of the input frame rates, 0/1 when none is known.
void sync_slowest_rate(const std::vector<TensorsConfig> &in, int *rate_n, int *rate_d);
// Name of the i-th sink pad (for messages).
std::string sync_pad_name(GstTensorSync *self, std::size_t i);

}  // namespace nns::gst

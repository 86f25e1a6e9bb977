// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter's GObject properties: their ids, their installation from one table, and the
// FilterSettings fields the non-string ones set and read back (string ones: string_setting()).
// Shared by the element (elements/tensor_filter.cc) and NNStreamer 2.x's GTensorFilterSingle
// (src/compat/tensor_filter_single.cc), which has tensor_filter's properties as upstream's does.
// GLib only, no GStreamer: libnnstreamer-single.so builds it too.
#pragma once

#include <glib-object.h>

#include <string>

#include "gst/filter_settings.h"

namespace nns::gst {

// Property ids, in the order gst-inspect-1.0 lists tensor_filter's properties (GLib lists a
// class's properties by id).
enum class FilterProp : guint {
  kSilent = 1,
  kFramework,
  kModel,
  kInput,
  kInputType,
  kInputName,
  kInputLayout,
  kInputRanks,
  kOutput,
  kOutputType,
  kOutputName,
  kOutputLayout,
  kOutputRanks,
  kCustom,
  kSubPlugins,
  kAccelerator,
  kIsUpdatable,
  kLatency,
  kThroughput,
  kInputCombination,
  kOutputCombination,
  kSharedKey,
  kLatencyReport,
  kInvokeDynamic,
  kInvokeAsync,
  kConfigFile,
  kSuspend,
};

// Installs every property on `k`. `mutable_playing` is added to the flags of those the element
// lets change while PLAYING (silent, model, latency, throughput, latency-report): the element
// passes GST_PARAM_MUTABLE_PLAYING, an object without states 0.
void install_filter_properties(GObjectClass *k, GParamFlags mutable_playing);

// The boolean and number properties (silent, is-updatable, latency, throughput, latency-report,
// invoke-dynamic, invoke-async, suspend): stores `value` in / reads it back from `s`. False
// for any other id (nothing done).
bool set_filter_value(FilterSettings &s, guint id, const GValue *value);
bool get_filter_value(const FilterSettings &s, guint id, GValue *value);

// What sub-plugins reads: the filter back ends nnstreamer.ini and the registry offer,
// separated with ','; empty when they cannot be listed.
std::string available_filters();

}  // namespace nns::gst

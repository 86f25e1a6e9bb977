// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/filter_properties.h"

#include <exception>

#include "core/filter_registry.h"

namespace nns::gst {

namespace {

enum class Kind { kString, kReadOnlyString, kBool, kMode, kUint };

struct PropSpec {
  FilterProp id;
  const char *name;
  Kind kind;
  const char *str_default;  // kString
  gboolean bool_default;    // kBool
  bool mutable_playing;
  const char *blurb;
};

constexpr PropSpec kProps[] = {
    {FilterProp::kSilent, "silent", Kind::kBool, nullptr, TRUE, true, "Produce verbose output"},
    {FilterProp::kFramework, "framework", Kind::kString, "auto", FALSE, false,
     "Neural network framework (filter back end); 'auto' detects it from the model file "
     "extension"},
    {FilterProp::kModel, "model", Kind::kString, "", FALSE, true,
     "Model file path(s), separated with ',' when the framework needs several files"},
    {FilterProp::kInput, "input", Kind::kString, "", FALSE, false,
     "Input tensor dimensions from the innermost axis, tensors separated with ','"},
    {FilterProp::kInputType, "inputtype", Kind::kString, "", FALSE, false,
     "Element type of each input tensor"},
    {FilterProp::kInputName, "inputname", Kind::kString, "", FALSE, false,
     "Name of each input tensor"},
    {FilterProp::kInputLayout, "inputlayout", Kind::kString, "", FALSE, false,
     "Layout of each input tensor: NHWC, NCHW, ANY or NONE"},
    {FilterProp::kInputRanks, "inputranks", Kind::kReadOnlyString, "", FALSE, false,
     "Rank of each input tensor"},
    {FilterProp::kOutput, "output", Kind::kString, "", FALSE, false,
     "Output tensor dimensions from the innermost axis, tensors separated with ','"},
    {FilterProp::kOutputType, "outputtype", Kind::kString, "", FALSE, false,
     "Element type of each output tensor"},
    {FilterProp::kOutputName, "outputname", Kind::kString, "", FALSE, false,
     "Name of each output tensor"},
    {FilterProp::kOutputLayout, "outputlayout", Kind::kString, "", FALSE, false,
     "Layout of each output tensor: NHWC, NCHW, ANY or NONE"},
    {FilterProp::kOutputRanks, "outputranks", Kind::kReadOnlyString, "", FALSE, false,
     "Rank of each output tensor"},
    {FilterProp::kCustom, "custom", Kind::kString, "", FALSE, false,
     "Options for the framework, key:value pairs separated with ','"},
    {FilterProp::kSubPlugins, "sub-plugins", Kind::kReadOnlyString, "", FALSE, false,
     "Available filter back ends"},
    {FilterProp::kAccelerator, "accelerator", Kind::kString, "", FALSE, false,
     "Accelerators, (true|false):ACCL[,ACCL...], e.g. true:npu,gpu,!cpu"},
    {FilterProp::kIsUpdatable, "is-updatable", Kind::kBool, nullptr, FALSE, false,
     "Allow loading another model (model property) while running"},
    {FilterProp::kLatency, "latency", Kind::kMode, nullptr, FALSE, true,
     "1: measure the average invoke latency of the last 10 frames (us), read back from this "
     "property (-1 when off)"},
    {FilterProp::kThroughput, "throughput", Kind::kMode, nullptr, FALSE, true,
     "1: measure the invoke throughput, outputs per second x 1000, read back from this property "
     "(-1 when off)"},
    {FilterProp::kInputCombination, "input-combination", Kind::kString, "", FALSE, false,
     "Input tensors given to the model, e.g. 0,2"},
    {FilterProp::kOutputCombination, "output-combination", Kind::kString, "", FALSE, false,
     "Tensors of the output frame: i<N> input tensors and o<N> model outputs, e.g. i0,o0,o2"},
    {FilterProp::kSharedKey, "shared-tensor-filter-key", Kind::kString, nullptr, FALSE, false,
     "Filters with the same key, framework and model share one model instance"},
    {FilterProp::kLatencyReport, "latency-report", Kind::kBool, nullptr, FALSE, true,
     "Add the measured invoke latency to LATENCY queries and post latency messages"},
    {FilterProp::kInvokeDynamic, "invoke-dynamic", Kind::kBool, nullptr, FALSE, false,
     "Flexible tensors whose shapes change per frame; the output is always flexible"},
    {FilterProp::kInvokeAsync, "invoke-async", Kind::kBool, nullptr, FALSE, false,
     "The back end may emit any number of outputs per input, from its own threads (LLM back "
     "ends); back ends without invoke_async run synchronously"},
    {FilterProp::kConfigFile, "config-file", Kind::kString, "", FALSE, false,
     "File of property=value lines applied to this element"},
    {FilterProp::kSuspend, "suspend", Kind::kUint, nullptr, FALSE, false,
     "Suspend (unload) the model after this many ms without data; 0: never"},
};

// The FilterSettings field of each boolean and number property (one pointer set).
struct ValueField {
  FilterProp id;
  bool FilterSettings::*flag;
  int FilterSettings::*mode;
  uint32_t FilterSettings::*count;
};

constexpr ValueField kValueFields[] = {
    {FilterProp::kSilent, &FilterSettings::silent, nullptr, nullptr},
    {FilterProp::kIsUpdatable, &FilterSettings::is_updatable, nullptr, nullptr},
    {FilterProp::kLatency, nullptr, &FilterSettings::latency_mode, nullptr},
    {FilterProp::kThroughput, nullptr, &FilterSettings::throughput_mode, nullptr},
    {FilterProp::kLatencyReport, &FilterSettings::latency_report, nullptr, nullptr},
    {FilterProp::kInvokeDynamic, &FilterSettings::invoke_dynamic, nullptr, nullptr},
    {FilterProp::kInvokeAsync, &FilterSettings::invoke_async, nullptr, nullptr},
    {FilterProp::kSuspend, nullptr, nullptr, &FilterSettings::suspend_ms},
};

const ValueField *value_field(guint id) {
  for (const ValueField &f : kValueFields)
    if (static_cast<guint>(f.id) == id) return &f;
  return nullptr;
}

GParamSpec *make_spec(const PropSpec &p, GParamFlags mutable_playing) {
  auto flags = static_cast<GParamFlags>(
      (p.kind == Kind::kReadOnlyString ? G_PARAM_READABLE : G_PARAM_READWRITE) |
      G_PARAM_STATIC_STRINGS | (p.mutable_playing ? mutable_playing : 0));
  switch (p.kind) {
    case Kind::kString:
    case Kind::kReadOnlyString:
      return g_param_spec_string(p.name, p.name, p.blurb, p.str_default, flags);
    case Kind::kBool:
      return g_param_spec_boolean(p.name, p.name, p.blurb, p.bool_default, flags);
    case Kind::kMode:  // 0: off, 1: on
      return g_param_spec_int(p.name, p.name, p.blurb, 0, 1, 0, flags);
    case Kind::kUint:
      return g_param_spec_uint(p.name, p.name, p.blurb, 0, G_MAXUINT, 0, flags);
  }
  return nullptr;
}

}  // namespace

void install_filter_properties(GObjectClass *k, GParamFlags mutable_playing) {
  for (const PropSpec &p : kProps)
    g_object_class_install_property(k, static_cast<guint>(p.id), make_spec(p, mutable_playing));
}

bool set_filter_value(FilterSettings &s, guint id, const GValue *value) {
  const ValueField *f = value_field(id);
  if (!f) return false;
  if (f->flag)
    s.*(f->flag) = g_value_get_boolean(value);
  else if (f->mode)
    s.*(f->mode) = g_value_get_int(value);
  else
    s.*(f->count) = g_value_get_uint(value);
  return true;
}

bool get_filter_value(const FilterSettings &s, guint id, GValue *value) {
  const ValueField *f = value_field(id);
  if (!f) return false;
  if (f->flag)
    g_value_set_boolean(value, s.*(f->flag));
  else if (f->mode)
    g_value_set_int(value, s.*(f->mode));
  else
    g_value_set_uint(value, s.*(f->count));
  return true;
}

std::string available_filters() {
  try {
    return join(FilterRegistry::get().available(*current_filter_conf()), ",");
  } catch (const std::exception &) {
    return {};
  }
}

}  // namespace nns::gst

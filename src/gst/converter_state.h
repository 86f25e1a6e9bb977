// SPDX-License-Identifier: LGPL-2.1-only
// tensor_converter's state and its two halves: negotiation (converter_negotiation.cc: settings,
// input caps -> output tensors, src caps) and the data path (converter_data.cc: one input
// buffer -> tensor buffers pushed downstream). The element file is the GObject shell.
#pragma once

#include <gst/base/gstadapter.h>
#include <gst/gst.h>

#include <string>
#include <vector>

#include "core/tensor_info.h"
#include "gst/converter_media.h"
#include "gst/converter_registry.h"

GST_DEBUG_CATEGORY_EXTERN(nns_tensor_converter_debug);

namespace nns::gst {

// Properties (the element guards them with its object lock).
struct ConverterSettings {
  std::string input_dim, input_type, mode;
  guint frames_per_tensor = 1;
  bool set_timestamp = true;
  bool silent = true;
};

enum class ConverterMode { kNone, kCustomCode, kCustomScript };

struct ConverterState {
  GstElement *element = nullptr;  // for errors, clock and logs
  GstPad *srcpad = nullptr;

  // Settings in force: taken at start and again at every CAPS event.
  ConverterSettings active;
  std::vector<Dims> prop_dims;
  std::vector<TensorType> prop_types;
  TensorsInfo props;         // valid only when props_valid
  bool props_valid = false;  // input-dim and input-type both given, same count
  guint fpt = 1;
  bool set_ts = true;
  ConverterMode mode = ConverterMode::kNone;
  std::string mode_option;

  // Negotiation.
  MediaInfo media;
  bool configured = false;
  bool derive_per_buffer = false;  // output config comes from each buffer (flex in, custom)
  bool flex_passthrough = false;   // flexible in, flexible out, untouched
  bool out_flexible = false;       // src caps are format=flexible
  bool headers_ready = false;      // buffers already carry flexible headers
  bool caps_sent = false;
  TensorsConfig sent;  // config of the current src caps
  guint frames_out = 1;
  CustomConverter custom;
  const NNStreamerExternalConverter *ext = nullptr;
  void *ext_priv = nullptr;
  int in_rate_n = 0, in_rate_d = 1;

  // Stream.
  GstAdapter *adapter = nullptr;
  GstSegment segment;
  bool need_segment = false;  // push `segment` (converted from bytes if needed) before data
  GstClockTime old_ts = GST_CLOCK_TIME_NONE;
};

// converter_negotiation.cc. Each throws nns::Error with the message to post.
void snapshot_settings(ConverterState *p, const ConverterSettings &s);
void reset_stream(ConverterState *p);
void close_external(ConverterState *p);
void configure(ConverterState *p, GstCaps *caps);  // CAPS event
void send_caps(ConverterState *p, const TensorsConfig &cfg);
std::string props_string(const ConverterState *p);
// Why a converter sub-plugin failed, when its private data starts with the error slot of
// backends/decoder/common/decoder_common.h (magic "NNSDERR" + message), else "".
std::string subplugin_reason(const void *priv);

// converter_data.cc
GstFlowReturn process_buffer(ConverterState *p, GstBuffer *buf);  // takes `buf`; throws
void push_segment(ConverterState *p);

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_filter property values and their parsing (input/output tensors, layouts,
// input-combination / output-combination, model list). Kept apart from the element so the
// single-shot API can parse the same strings.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/filter_instance.h"
#include "core/tensor_info.h"

namespace nns::gst {

struct FilterSettings {
  bool silent = true;
  std::string framework = "auto";
  std::string model;
  std::string input, inputtype, inputname, inputlayout;
  std::string output, outputtype, outputname, outputlayout;
  std::string custom;
  std::string accelerator;
  bool is_updatable = false;
  int latency_mode = 0;     // latency=1
  int throughput_mode = 0;  // throughput=1
  std::string input_combination;
  std::string output_combination;
  std::string shared_key;
  bool latency_report = false;
  bool invoke_dynamic = false;
  bool invoke_async = false;
  std::string config_file;
  uint32_t suspend_ms = 0;

  bool operator==(const FilterSettings &) const = default;
};

// The string-valued setting named like its tensor_filter property ("model", "inputtype",
// "shared-tensor-filter-key", ...); nullptr for other names.
std::string *string_setting(FilterSettings &s, std::string_view property);

// input-combination="0,2": model inputs are input tensors 0 and 2.
// output-combination="i0,o0,o2": the output frame is input tensor 0 then model outputs 0 and 2
// (NNStreamer's order: every listed input tensor first, then the listed model outputs in
// model order).
struct Combination {
  bool in_defined = false;
  std::vector<uint32_t> in;
  bool out_defined = false;
  std::vector<uint32_t> out_in;   // i<N>
  std::vector<uint32_t> out_out;  // o<N>, sorted
  bool out_o_defined = false;     // some o<N> given (else no model output is kept)

  // Model input from the frame's tensors. Throws Error(kNegotiation) for an index out of range.
  TensorsInfo model_input(const TensorsInfo &frame) const;
  // Output frame from the frame's tensors and the model output.
  TensorsInfo frame_output(const TensorsInfo &frame, const TensorsInfo &model_out) const;
  bool keeps_output(uint32_t o) const;
};

Combination parse_combination(const std::string &input_combination,
                              const std::string &output_combination);

// input=/inputtype=/inputname= (or the output ones) as tensors; empty when dims and types are
// both empty. `prefix` is "input" or "output" for messages. Throws Error(kSettings).
TensorsInfo parse_tensor_props(const std::string &dims, const std::string &types,
                               const std::string &names, const std::string &prefix);
// "NHWC,NCHW": one layout per tensor; unknown words are NONE (as NNStreamer).
std::vector<tensor_layout> parse_layouts(const std::string &s);
std::string layouts_string(const std::vector<tensor_layout> &l, std::size_t n);
std::vector<std::string> split_models(const std::string &model);
// Rank list "4,2" of the given tensors.
std::string ranks_string(const TensorsInfo &info);

// Everything the back end needs to open, from the settings. Throws Error(kSettings).
FilterOpenSpec make_open_spec(const FilterSettings &s);

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/filter_settings.h"

#include <algorithm>
#include <cctype>
#include <cerrno>
#include <cstdlib>
#include <strings.h>
#include <utility>

#include "core/error.h"

namespace nns::gst {
namespace {

uint32_t parse_index(const std::string &tok, const std::string &prop) {
  if (tok.empty() || !std::all_of(tok.begin(), tok.end(), [](char c) {
        return std::isdigit(static_cast<unsigned char>(c));
      }))
    fail(ErrorKind::kSettings, prop + ": '" + tok + "' is not a tensor index");
  errno = 0;
  unsigned long v = std::strtoul(tok.c_str(), nullptr, 10);
  if (errno == ERANGE || v >= kTensorLimit)
    fail(ErrorKind::kSettings, prop + ": tensor index '" + tok + "' is out of range (0.." +
                                   std::to_string(kTensorLimit - 1) + ")");
  return static_cast<uint32_t>(v);
}

}  // namespace

Combination parse_combination(const std::string &in_s, const std::string &out_s) {
  Combination c;
  for (const auto &tok : split(in_s, ",")) {
    c.in.push_back(parse_index(tok, "input-combination"));
    c.in_defined = true;
  }
  for (const auto &tok : split(out_s, ",")) {
    if (tok.size() < 2 || (tok[0] != 'i' && tok[0] != 'o'))
      fail(ErrorKind::kSettings, "output-combination: '" + tok +
                                     "' is neither i<N> (input tensor) nor o<N> (model output);"
                                     " e.g. output-combination=i0,o0,o2");
    uint32_t idx = parse_index(tok.substr(1), "output-combination");
    if (tok[0] == 'i') {
      c.out_in.push_back(idx);
    } else {
      c.out_out.push_back(idx);
      c.out_o_defined = true;
    }
    c.out_defined = true;
  }
  std::sort(c.out_out.begin(), c.out_out.end());
  c.out_out.erase(std::unique(c.out_out.begin(), c.out_out.end()), c.out_out.end());
  return c;
}

bool Combination::keeps_output(uint32_t o) const {
  if (!out_defined) return true;
  return std::binary_search(out_out.begin(), out_out.end(), o);
}

TensorsInfo Combination::model_input(const TensorsInfo &frame) const {
  if (!in_defined) return frame;
  TensorsInfo r;
  r.format = frame.format;
  for (uint32_t i : in) {
    if (i >= frame.size())
      fail(ErrorKind::kNegotiation, "input-combination index " + std::to_string(i) +
                                        " is out of range: the input has " +
                                        std::to_string(frame.size()) + " tensor(s)");
    r.tensors.push_back(frame[i]);
  }
  return r;
}

TensorsInfo Combination::frame_output(const TensorsInfo &frame,
                                      const TensorsInfo &model_out) const {
  if (!out_defined) return model_out;
  TensorsInfo r;
  r.format = model_out.format;
  for (uint32_t i : out_in) {
    if (i >= frame.size())
      fail(ErrorKind::kNegotiation, "output-combination i" + std::to_string(i) +
                                        " is out of range: the input has " +
                                        std::to_string(frame.size()) + " tensor(s)");
    r.tensors.push_back(frame[i]);
  }
  for (uint32_t o : out_out) {
    if (o >= model_out.size())
      fail(ErrorKind::kNegotiation, "output-combination o" + std::to_string(o) +
                                        " is out of range: the model has " +
                                        std::to_string(model_out.size()) + " output(s)");
    r.tensors.push_back(model_out[o]);
  }
  if (r.tensors.empty()) fail(ErrorKind::kSettings, "output-combination selects no tensor");
  return r;
}

TensorsInfo parse_tensor_props(const std::string &dims, const std::string &types,
                               const std::string &names, const std::string &prefix) {
  TensorsInfo info;
  std::string d = trim(dims), t = trim(types);
  if (d.empty() && t.empty()) {
    if (!trim(names).empty()) {
      // Names alone are kept for back ends that select tensors by name.
      for (auto &n : parse_names_list(names))
        info.tensors.push_back(TensorInfo{n, TensorType::kEnd, {}});
    }
    return info;
  }
  if (d.empty())
    fail(ErrorKind::kSettings,
         prefix + "type='" + t + "' is set but " + prefix + "= (the dimensions) is not; set both");
  if (t.empty())
    fail(ErrorKind::kSettings,
         prefix + "='" + d + "' is set but " + prefix + "type= is not; set both");
  auto dl = parse_dims_list(d, prefix);
  auto tl = parse_types_list(t, prefix + "type");
  if (dl.size() != tl.size())
    fail(ErrorKind::kSettings, prefix + "= gives " + std::to_string(dl.size()) + " tensor(s) but " +
                                   prefix + "type= gives " + std::to_string(tl.size()));
  auto nl = parse_names_list(names);
  if (!nl.empty() && nl.size() != dl.size())
    fail(ErrorKind::kSettings, prefix + "name= gives " + std::to_string(nl.size()) +
                                   " name(s) for " + std::to_string(dl.size()) + " tensor(s)");
  for (std::size_t i = 0; i < dl.size(); ++i)
    info.tensors.push_back(TensorInfo{i < nl.size() ? nl[i] : "", tl[i], dl[i]});
  return info;
}

std::vector<tensor_layout> parse_layouts(const std::string &s) {
  std::vector<tensor_layout> out;
  for (const auto &tok : split(s, ",.")) {
    if (strcasecmp(tok.c_str(), "NHWC") == 0)
      out.push_back(_NNS_LAYOUT_NHWC);
    else if (strcasecmp(tok.c_str(), "NCHW") == 0)
      out.push_back(_NNS_LAYOUT_NCHW);
    else if (strcasecmp(tok.c_str(), "ANY") == 0 || tok.empty())
      out.push_back(_NNS_LAYOUT_ANY);
    else
      out.push_back(_NNS_LAYOUT_NONE);
  }
  return out;
}

std::string layouts_string(const std::vector<tensor_layout> &l, std::size_t n) {
  std::string s;
  for (std::size_t i = 0; i < n; ++i) {
    tensor_layout x = i < l.size() ? l[i] : _NNS_LAYOUT_ANY;
    const char *w = x == _NNS_LAYOUT_NHWC   ? "NHWC"
                    : x == _NNS_LAYOUT_NCHW ? "NCHW"
                    : x == _NNS_LAYOUT_NONE ? "NONE"
                                            : "ANY";
    s += (i ? "," : "") + std::string(w);
  }
  return s;
}

std::vector<std::string> split_models(const std::string &model) {
  return split(model, ",");
}

std::string ranks_string(const TensorsInfo &info) {
  std::string s;
  for (std::size_t i = 0; i < info.size(); ++i)
    s += (i ? "," : "") + std::to_string(info[i].rank());
  return s;
}

FilterOpenSpec make_open_spec(const FilterSettings &s) {
  FilterOpenSpec spec;
  spec.framework = trim(s.framework);
  spec.models = split_models(s.model);
  spec.input = parse_tensor_props(s.input, s.inputtype, s.inputname, "input");
  spec.output = parse_tensor_props(s.output, s.outputtype, s.outputname, "output");
  // Names alone (type kEnd, no dims) go to back ends that pick tensors by name; the shape
  // checks skip them (FilterEngine::check_model_shapes).
  spec.custom = s.custom;
  spec.accelerator = s.accelerator;
  spec.input_layout = parse_layouts(s.inputlayout);
  spec.output_layout = parse_layouts(s.outputlayout);
  spec.invoke_dynamic = s.invoke_dynamic;
  spec.verbose = !s.silent;
  spec.shared_key = s.shared_key;
  return spec;
}

std::string *string_setting(FilterSettings &s, std::string_view property) {
  static constexpr std::pair<std::string_view, std::string FilterSettings::*> kFields[] = {
      {"framework", &FilterSettings::framework},
      {"model", &FilterSettings::model},
      {"input", &FilterSettings::input},
      {"inputtype", &FilterSettings::inputtype},
      {"inputname", &FilterSettings::inputname},
      {"inputlayout", &FilterSettings::inputlayout},
      {"output", &FilterSettings::output},
      {"outputtype", &FilterSettings::outputtype},
      {"outputname", &FilterSettings::outputname},
      {"outputlayout", &FilterSettings::outputlayout},
      {"custom", &FilterSettings::custom},
      {"accelerator", &FilterSettings::accelerator},
      {"input-combination", &FilterSettings::input_combination},
      {"output-combination", &FilterSettings::output_combination},
      {"shared-tensor-filter-key", &FilterSettings::shared_key},
      {"config-file", &FilterSettings::config_file},
  };
  for (const auto &[name, field] : kFields)
    if (name == property) return &(s.*field);
  return nullptr;
}

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
// ml_single_set_property / ml_single_get_property: tensor_filter's property names on an open
// handle (NNStreamer's list: input, inputtype, inputname, inputlayout, output, outputtype,
// outputname, outputlayout, accelerator, custom, is-updatable; plus model, framework,
// inputranks, outputranks to read).
//
// After open: input/inputtype/inputname go through the back end's set-input (as
// ml_single_set_input_info); outputname is kept as metadata; output/outputtype only when the
// model does not know its output (the caller described it); custom, accelerator and the
// layouts reopen the model with the new value (the old one stays when that fails); model
// reloads it when is-updatable is true. framework and the ranks are read-only.
#include <strings.h>

#include <cstring>

#include "api/ml_single_handle.h"
#include "core/tensor_info.h"
#include "gst/filter_settings.h"
#include "nnstreamer-single.h"

using namespace nns;
using namespace nns::api;

namespace {

const char *const kKnown =
    "input, inputtype, inputname, inputlayout, inputranks, output, outputtype, outputname, "
    "outputlayout, outputranks, custom, accelerator, is-updatable, model, framework";

// The value get_property reports; false for an unknown name. mu held.
bool current_value(const SingleHandle &h, const std::string &n, std::string &v) {
  if (n == "input")
    v = h.in.dims_string();
  else if (n == "inputtype")
    v = h.in.types_string();
  else if (n == "inputname")
    v = h.in.names_string();
  else if (n == "inputlayout")
    v = gst::layouts_string(h.spec.input_layout, h.in.size());
  else if (n == "inputranks")
    v = gst::ranks_string(h.in);
  else if (n == "output")
    v = h.out.dims_string();
  else if (n == "outputtype")
    v = h.out.types_string();
  else if (n == "outputname")
    v = h.out.names_string();
  else if (n == "outputlayout")
    v = gst::layouts_string(h.spec.output_layout, h.out.size());
  else if (n == "outputranks")
    v = gst::ranks_string(h.out);
  else if (n == "custom")
    v = h.spec.custom;
  else if (n == "accelerator")
    v = h.spec.accelerator;
  else if (n == "is-updatable")
    v = h.is_updatable ? "true" : "false";
  else if (n == "framework")
    v = h.inst->name();
  else if (n == "model")
    v = join(h.spec.models, ",");
  else
    return false;
  return true;
}

// `info` with one of dims/types/names replaced from `value` (the tensor count must stay).
// Throws nns::Error(kSettings).
TensorsInfo edited(const TensorsInfo &info, const std::string &what, const std::string &value,
                   const std::string &prop) {
  TensorsInfo r = info;
  std::size_t got;
  if (what == "type") {
    auto t = parse_types_list(value, prop);
    got = t.size();
    for (std::size_t i = 0; i < t.size() && i < r.size(); ++i) r[i].type = t[i];
  } else if (what == "name") {
    auto t = parse_names_list(value);
    got = t.size();
    for (std::size_t i = 0; i < t.size() && i < r.size(); ++i) r[i].name = t[i];
  } else {
    auto t = parse_dims_list(value, prop);
    got = t.size();
    for (std::size_t i = 0; i < t.size() && i < r.size(); ++i) r[i].dims = t[i];
  }
  if (got != info.size())
    fail(ErrorKind::kSettings, prop + "='" + value + "' gives " + std::to_string(got) +
                                   " tensor(s); the model has " + std::to_string(info.size()) +
                                   " (" + info.to_string() + ")");
  return r;
}

int set_locked(SingleHandle &h, const std::string &n, const std::string &value,
               const std::string &fn) {
  bool is_input = n == "input" || n == "inputtype" || n == "inputname";
  bool is_output = n == "output" || n == "outputtype" || n == "outputname";
  std::string what = is_input ? n.substr(5) : is_output ? n.substr(6) : "";
  try {
    if (n == "is-updatable") {
      if (strcasecmp(value.c_str(), "true") == 0)
        h.is_updatable = true;
      else if (strcasecmp(value.c_str(), "false") == 0)
        h.is_updatable = false;
      else
        return h.fail(ML_ERROR_INVALID_PARAMETER,
                      fn + ": is-updatable takes 'true' or 'false', got '" + value + "'");
      return ML_ERROR_NONE;
    }
    if (n == "model") {
      if (!h.is_updatable)
        return h.fail(ML_ERROR_NOT_SUPPORTED,
                      fn + ": model cannot change while is-updatable is false; set "
                           "is-updatable to true first to reload the model");
      auto models = split(value, ",");
      if (models.empty()) return h.fail(ML_ERROR_INVALID_PARAMETER, fn + ": model is empty");
      std::vector<std::string> prev = h.spec.models;
      h.inst->reload(models);  // keeps the previous model when this throws
      try {
        Settled s = settle(*h.inst, &h.in, h.out_from_user ? &h.out : nullptr, true);
        h.spec.models = models;
        h.apply(s);
      } catch (...) {
        h.inst->reload(prev);
        throw;
      }
      return ML_ERROR_NONE;
    }
    if (n == "custom" || n == "accelerator" || n == "inputlayout" || n == "outputlayout") {
      FilterOpenSpec spec = h.spec;
      if (n == "custom")
        spec.custom = value;
      else if (n == "accelerator")
        spec.accelerator = value;
      else if (n == "inputlayout")
        spec.input_layout = gst::parse_layouts(value);
      else
        spec.output_layout = gst::parse_layouts(value);
      reopen(h, spec);
      return ML_ERROR_NONE;
    }
    if (is_input || is_output) {
      if (is_input) return apply_input_info(h, edited(h.in, what, value, n), fn);
      if (h.out.size() == 0)
        return h.fail(ML_ERROR_NOT_SUPPORTED,
                      fn + ": " + n + ": " + h.inst->describe() +
                          " decides its output at each invoke (dynamic model)");
      TensorsInfo out = edited(h.out, what, value, n);
      if (what == "name" || h.out_from_user) {
        if (!out.valid())
          return h.fail(ML_ERROR_INVALID_PARAMETER, fn + ": " + n + "='" + value +
                                                        "' gives an incomplete output (" +
                                                        out.to_string() + ")");
        h.out = out;
        return ML_ERROR_NONE;
      }
      return h.fail(ML_ERROR_INVALID_PARAMETER,
                    fn + ": " + n + " follows from the model and its input (now " +
                        h.out.to_string() + "); change input/inputtype instead");
    }
    if (n == "framework" || n == "inputranks" || n == "outputranks")
      return h.fail(ML_ERROR_NOT_SUPPORTED,
                    fn + ": " + n + " is read-only once the model is open" +
                        (n == "framework" ? "; open a new handle for another framework" : ""));
  } catch (const std::bad_alloc &) {
    return h.fail(ML_ERROR_OUT_OF_MEMORY, fn + ": out of memory");
  } catch (const std::exception &e) {
    // The value is what the back end or the parser refused.
    return h.fail(ML_ERROR_INVALID_PARAMETER, fn + ": " + n + "='" + value + "': " + e.what());
  }
  return h.fail(ML_ERROR_NOT_SUPPORTED,
                fn + ": unknown property '" + n + "' (known: " + kKnown + ")");
}

}  // namespace

NNS_API int ml_single_set_property(ml_single_h single, const char *name, const char *value) {
  const std::string fn = "ml_single_set_property";
  REQUIRE_SINGLE(h, single);
  if (!name || !value)
    return h->fail(
        ML_ERROR_INVALID_PARAMETER,
        fn + ": " + (!name ? "name" : "value of '" + std::string(name) + "'") + " is NULL");
  std::unique_lock<std::mutex> lk(h->mu);
  REQUIRE_IDLE(h, fn);
  std::string n = name, cur;
  // As NNStreamer: setting the current value is a no-op.
  if (current_value(*h, n, cur) && cur == value) return ML_ERROR_NONE;
  return set_locked(*h, n, value, fn);
}

NNS_API int ml_single_get_property(ml_single_h single, const char *name, char **value) {
  const std::string fn = "ml_single_get_property";
  REQUIRE_SINGLE(h, single);
  if (!name || !value)
    return h->fail(ML_ERROR_INVALID_PARAMETER, fn + ": " + (!name ? "name" : "value") + " is NULL");
  *value = nullptr;
  std::lock_guard<std::mutex> g(h->mu);
  std::string v;
  if (!current_value(*h, name, v))
    return h->fail(ML_ERROR_NOT_SUPPORTED,
                   fn + ": unknown property '" + std::string(name) + "' (known: " + kKnown + ")");
  *value = strdup(v.c_str());
  if (!*value) return h->fail(ML_ERROR_OUT_OF_MEMORY, fn + ": out of memory");
  return ML_ERROR_NONE;
}

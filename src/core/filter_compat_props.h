// SPDX-License-Identifier: LGPL-2.1-only
// GstTensorFilterProperties (NNStreamer's layout, nnstreamer_plugin_api_filter.h) built from
// the back-end ABI's nns_filter_props, for the built-in custom, custom-easy and cpp back ends.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "core/filter_compat_async.h"
#include "nns_filter_backend.h"
#include "nnstreamer_plugin_api_filter.h"

namespace nns {

class CompatProps {
 public:
  explicit CompatProps(const nns_filter_props &p);
  ~CompatProps();
  CompatProps(const CompatProps &) = delete;
  CompatProps &operator=(const CompatProps &) = delete;

  GstTensorFilterProperties *get() { return &prop_; }
  const GstTensorFilterProperties *get() const { return &prop_; }
  // Records the negotiated shapes (input_meta/output_meta, *_configured, *_ranks).
  void set_input(const nns_tensors_desc &d);
  void set_output(const nns_tensors_desc &d);
  void set_input(const GstTensorsInfo &i);
  void set_output(const GstTensorsInfo &i);
  // 2.x callbacks that fill GstTensorsInfo: `query(in, out)` (getInputDim + getOutputDim, ...)
  // or `set(in, out)` with `in` given (setInputDim, ...) returns 0 on success; then the tensors
  // are copied to *in / *out and recorded here. Returns the callback's code.
  using InfoCall = std::function<int(GstTensorsInfo *in, GstTensorsInfo *out)>;
  int query_model_info(nns_tensors_desc *in, nns_tensors_desc *out, const InfoCall &query);
  int negotiate_input(const nns_tensors_desc &in, nns_tensors_desc *out, const InfoCall &set);
  // invoke-async state (prop_.async_user_data points at it).
  CompatAsync &async() { return async_; }

 private:
  GstTensorFilterProperties prop_;
  CompatAsync async_;
  std::string fwname_, custom_, accl_;
  std::vector<std::string> models_;
  std::vector<const char *> model_ptrs_;
};

}  // namespace nns

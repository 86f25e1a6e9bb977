// SPDX-License-Identifier: LGPL-2.1-only
// Conversions between nns::TensorsInfo/TensorsConfig and NNStreamer's plain C structs
// (GstTensorsInfo / GstTensorsConfig of tensor_typedef.h), for the C APIs that sub-plugins and
// custom callbacks use. Memory rules follow NNStreamer: names are g_malloc'ed strings, tensors
// 16.. live in `extra` (g_new0 of NNS_TENSOR_SIZE_EXTRA_LIMIT entries); free_c() releases both.
#pragma once

#include <glib.h>

#include "core/tensor_info.h"
#include "tensor_typedef.h"

namespace nns::gst {

// Empty info: 0 tensors, every type _NNS_END, every dim 0, no names, no extra.
void init_c(GstTensorsInfo *info);
void init_c(GstTensorsConfig *config);  // also rate -1/-1 (unset)
// Frees names and extra, then re-initialises.
void free_c(GstTensorsInfo *info);
void free_c(GstTensorsConfig *config);

// Entry `i` (< NNS_TENSOR_SIZE_LIMIT) wherever it lives; allocates `extra` when needed.
GstTensorInfo *c_tensor_at(GstTensorsInfo *info, unsigned i);
// Read-only access; nullptr when `i` is in a missing extra block or out of range.
const GstTensorInfo *c_tensor_at(const GstTensorsInfo *info, unsigned i);

// Fills `out` (freed first with free_c, so it must be initialised) from `in`. Throws
// nns::Error(kSettings) when `in` has more than NNS_TENSOR_SIZE_LIMIT tensors.
void to_c(const TensorsInfo &in, GstTensorsInfo *out);
void to_c(const TensorsConfig &in, GstTensorsConfig *out);
// Reads a C description. Throws nns::Error(kStream) naming the field when num_tensors or a
// type is out of range.
TensorsInfo from_c(const GstTensorsInfo *in);
TensorsConfig from_c(const GstTensorsConfig *in);

// RAII holder for a C config (init on construction, free_c on destruction).
class CTensorsConfig {
 public:
  CTensorsConfig() { init_c(&c_); }
  explicit CTensorsConfig(const TensorsConfig &cfg) {
    init_c(&c_);
    to_c(cfg, &c_);
  }
  ~CTensorsConfig() { free_c(&c_); }
  CTensorsConfig(const CTensorsConfig &) = delete;
  CTensorsConfig &operator=(const CTensorsConfig &) = delete;
  GstTensorsConfig *get() { return &c_; }
  const GstTensorsConfig *get() const { return &c_; }

 private:
  GstTensorsConfig c_;
};

}  // namespace nns::gst

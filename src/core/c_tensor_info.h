// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer's plain C tensor descriptions (GstTensorsInfo / GstTensorsConfig of
// tensor_typedef.h): initialisation, release, and conversions to and from nns::TensorsInfo and
// the filter ABI's nns_tensors_desc. GStreamer-free; used by tensor_converter (custom
// converters), tensor_decoder, tensor_if (custom callbacks), the compatibility filter back ends
// and the single-shot API.
//
// Memory rules: tensor names are heap strings (malloc) owned by the struct; tensors 16.. live in
// `extra`, one calloc'ed block of NNS_TENSOR_SIZE_EXTRA_LIMIT entries. gst_info_clear() frees
// every name (info[] and extra[], whatever num_tensors says) and `extra`. GLib >= 2.46 always
// uses the system allocator, so names a sub-plugin makes with g_strdup() are freed correctly too.
#pragma once

#include <memory>

#include "core/tensor_info.h"
#include "nns_filter_backend.h"
#include "tensor_typedef.h"

namespace nns {

// Empty info: 0 tensors, every type _NNS_END, every dim 0, no names, no extra (the struct need
// not be initialised before).
void gst_info_init(GstTensorsInfo *info);
void gst_config_init(GstTensorsConfig *config);  // also rate -1/-1 (unset)
// Frees names and extra, then re-initialises. `info` must be initialised.
void gst_info_clear(GstTensorsInfo *info);
void gst_config_clear(GstTensorsConfig *config);

// Entry `i` (info[] for the first 16, extra[] after); nullptr when `i` is out of range or lies
// in a missing extra block.
GstTensorInfo *gst_info_at(GstTensorsInfo *info, unsigned i);
const GstTensorInfo *gst_info_at(const GstTensorsInfo *info, unsigned i);

// nns_tensors_desc -> GstTensorsInfo. `out` need not be initialised (anything it held is not
// freed); at most NNS_TENSOR_SIZE_LIMIT tensors are copied.
void gst_info_from_desc(const nns_tensors_desc &desc, GstTensorsInfo *out);
// GstTensorsInfo -> nns_tensors_desc; names are cut to NNS_TENSOR_NAME_MAX - 1 characters and
// the count stops at the first tensor whose extra block is missing.
void desc_from_gst_info(const GstTensorsInfo *info, nns_tensors_desc &out);

// Fills `out` (cleared first, so it must be initialised) from `in`. Throws nns::Error(kSettings)
// when `in` has more than NNS_TENSOR_SIZE_LIMIT tensors.
void to_c(const TensorsInfo &in, GstTensorsInfo *out);
void to_c(const TensorsConfig &in, GstTensorsConfig *out);
// Reads a C description. Throws nns::Error(kStream) naming the field when num_tensors, the
// format or a type is out of range.
TensorsInfo from_c(const GstTensorsInfo *in);
TensorsConfig from_c(const GstTensorsConfig *in);

// RAII holder for a C config (initialised on construction, cleared on destruction).
class CTensorsConfig {
 public:
  CTensorsConfig() { gst_config_init(&c_); }
  explicit CTensorsConfig(const TensorsConfig &cfg) {
    gst_config_init(&c_);
    to_c(cfg, &c_);
  }
  ~CTensorsConfig() { gst_config_clear(&c_); }
  CTensorsConfig(const CTensorsConfig &) = delete;
  CTensorsConfig &operator=(const CTensorsConfig &) = delete;
  GstTensorsConfig *get() { return &c_; }
  const GstTensorsConfig *get() const { return &c_; }

 private:
  GstTensorsConfig c_;
};

}  // namespace nns

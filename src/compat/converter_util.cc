// SPDX-License-Identifier: LGPL-2.1-only
// libnnstreamer-converter-util.so: the helper NNStreamer's converter sub-plugins link.
#include "compat/compat_export.h"
#include "compat/ext_util.h"
#include "nnstreamer_plugin_api_util.h"

NNS_COMPAT_API gboolean tcu_get_out_config(const GstCaps *in_cap, GstTensorsConfig *config) {
  if (!config) return FALSE;
  gst_tensors_config_init(config);
  if (!in_cap || gst_caps_get_size(in_cap) == 0) return FALSE;
  const GstStructure *s = gst_caps_get_structure(in_cap, 0);
  // The real tensors are only known per buffer; the converter fills them in convert().
  config->info.num_tensors = 1;
  config->info.info[0].type = _NNS_UINT8;
  gst_tensor_parse_dimension("1:1:1:1", config->info.info[0].dimension);
  if (gst_structure_has_field(s, "framerate")) {
    // Left -1/-1 when the field is not a single fraction (e.g. still a range).
    gst_structure_get_fraction(s, "framerate", &config->rate_n, &config->rate_d);
  } else {
    config->rate_n = 0;
    config->rate_d = 1;
  }
  return TRUE;
}

/* SPDX-License-Identifier: LGPL-2.1-only */
/* An NNStreamer 2.x converter sub-plugin "twox_conv" for application/x-twox streams: each
 * buffer becomes one uint8 tensor of its size with every byte + 1. It registers from a struct
 * on the constructor's stack (NNStreamer copies nothing; nnstreamer-cpp must), after trying
 * the reserved name "any" (refused). */
#include <string.h>

#include "nnstreamer_plugin_api_converter.h"

static GstBuffer *conv_convert(GstBuffer *in, GstTensorsConfig *config, void *priv) {
  (void)priv;
  GstMapInfo map;
  if (!gst_buffer_map(in, &map, GST_MAP_READ)) return NULL;
  GstBuffer *out = gst_buffer_new_allocate(NULL, map.size, NULL);
  GstMapInfo om;
  gst_buffer_map(out, &om, GST_MAP_WRITE);
  for (gsize i = 0; i < map.size; ++i) om.data[i] = (guint8)(map.data[i] + 1);
  gst_buffer_unmap(out, &om);
  gst_buffer_unmap(in, &map);
  memset(config->info.info[0].dimension, 0, sizeof(tensor_dim));
  config->info.num_tensors = 1;
  config->info.format = _NNS_TENSOR_FORMAT_STATIC;
  config->info.info[0].type = _NNS_UINT8;
  config->info.info[0].dimension[0] = (uint32_t)map.size;
  config->info.info[0].dimension[1] = 1;
  config->rate_n = 0;
  config->rate_d = 1;
  return out;
}

static gboolean conv_out_config(const GstCaps *caps, GstTensorsConfig *config) {
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  int n = 0;
  if (!gst_structure_get_int(s, "n", &n) || n <= 0) return FALSE;
  memset(config->info.info[0].dimension, 0, sizeof(tensor_dim));
  config->info.num_tensors = 1;
  config->info.format = _NNS_TENSOR_FORMAT_STATIC;
  config->info.info[0].type = _NNS_UINT8;
  config->info.info[0].dimension[0] = (uint32_t)n;
  config->info.info[0].dimension[1] = 1;
  config->rate_n = 0;
  config->rate_d = 1;
  return TRUE;
}

static GstCaps *conv_query_caps(const GstTensorsConfig *config) {
  (void)config;
  return gst_caps_from_string("application/x-twox");
}

__attribute__((constructor)) static void init_conv(void) {
  NNStreamerExternalConverter ex;
  memset(&ex, 0, sizeof ex);
  ex.convert = conv_convert;
  ex.get_out_config = conv_out_config;
  ex.query_caps = conv_query_caps;
  char name[32];
  strcpy(name, "any");
  ex.name = name;
  registerExternalConverter(&ex); /* refused: reserved */
  strcpy(name, "twox_conv");
  registerExternalConverter(&ex);
  /* The caller's struct and name go away: scribble over them. */
  memset(name, 'x', sizeof name - 1);
  name[sizeof name - 1] = '\0';
  memset(&ex, 0, sizeof ex);
}

__attribute__((destructor)) static void fini_conv(void) {
  unregisterExternalConverter("twox_conv");
}

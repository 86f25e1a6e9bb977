/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * A converter sub-plugin for tensor_converter_test, built twice: as
 * libnnstreamer_converter_testentry.so (announces itself through the entry point) and as
 * libnnstreamer_converter_testctor.so (registers from a constructor, NNStreamer style).
 * It accepts application/x-nns-<name>, n=(int)N and turns each byte into a float32, giving
 * one N:1 float32 tensor per buffer.
 */
#include <gst/gst.h>
#include <string.h>

#include "nnstreamer_plugin_api_converter.h"

#define MIME "application/x-nns-" NNS_TEST_CONVERTER_NAME

static gboolean get_out_config(const GstCaps *caps, GstTensorsConfig *config) {
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  int n = 0;
  if (!gst_structure_get_int(s, "n", &n) || n <= 0) return FALSE;
  config->info.num_tensors = 1;
  config->info.format = _NNS_TENSOR_FORMAT_STATIC;
  config->info.info[0].type = _NNS_FLOAT32;
  memset(config->info.info[0].dimension, 0, sizeof(config->info.info[0].dimension));
  config->info.info[0].dimension[0] = (uint32_t)n;
  config->info.info[0].dimension[1] = 1;
  config->rate_n = 0;
  config->rate_d = 1;
  return TRUE;
}

static GstBuffer *convert(GstBuffer *in, GstTensorsConfig *config, void *priv) {
  GstMapInfo im, om;
  GstBuffer *out;
  gsize i;
  (void)priv;
  if (!gst_buffer_map(in, &im, GST_MAP_READ)) return NULL;
  out = gst_buffer_new_allocate(NULL, im.size * sizeof(float), NULL);
  gst_buffer_map(out, &om, GST_MAP_WRITE);
  for (i = 0; i < im.size; ++i) ((float *)om.data)[i] = (float)im.data[i];
  gst_buffer_unmap(out, &om);
  gst_buffer_unmap(in, &im);
  config->info.num_tensors = 1;
  config->info.info[0].type = _NNS_FLOAT32;
  memset(config->info.info[0].dimension, 0, sizeof(config->info.info[0].dimension));
  config->info.info[0].dimension[0] = (uint32_t)im.size;
  config->info.info[0].dimension[1] = 1;
  config->rate_n = 0;
  config->rate_d = 1;
  return out;
}

static GstCaps *query_caps(const GstTensorsConfig *config) {
  (void)config;
  return gst_caps_from_string(MIME);
}

static NNStreamerExternalConverter converter = {
    .name = NNS_TEST_CONVERTER_NAME,
    .convert = convert,
    .get_out_config = get_out_config,
    .query_caps = query_caps,
    .open = NULL,
    .close = NULL,
};

#ifdef NNS_TEST_USE_CTOR
__attribute__((constructor)) static void init_converter(void) {
  registerExternalConverter(&converter);
}
#else
const NNStreamerExternalConverter *nns_converter_subplugin_entry(void) {
  return &converter;
}
#endif

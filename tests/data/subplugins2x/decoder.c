/* SPDX-License-Identifier: LGPL-2.1-only */
/* An NNStreamer 2.x decoder sub-plugin "twox_dec" with only the callbacks NNStreamer requires
 * (init, getOutCaps, decode; no exit, setOption or getTransformSize): writes the text
 * "sum=<sum of the uint8 bytes of tensor 0>\n" for each frame. */
#include <stdio.h>
#include <string.h>

#include "nnstreamer_plugin_api_decoder.h"

static int dec_init(void **pdata) {
  *pdata = NULL;
  return TRUE;
}

static GstCaps *dec_caps(void **pdata, const GstTensorsConfig *config) {
  (void)pdata;
  (void)config;
  return gst_caps_from_string("text/x-raw, format = (string) utf8");
}

static GstFlowReturn dec_decode(void **pdata, const GstTensorsConfig *config,
                                const GstTensorMemory *input, GstBuffer *outbuf) {
  (void)pdata;
  (void)config;
  unsigned long sum = 0;
  const unsigned char *b = input[0].data;
  for (size_t i = 0; i < input[0].size; ++i) sum += b[i];
  char text[64];
  int n = snprintf(text, sizeof text, "sum=%lu\n", sum);
  GstMemory *mem = gst_allocator_alloc(NULL, (gsize)n, NULL);
  GstMapInfo map;
  gst_memory_map(mem, &map, GST_MAP_WRITE);
  memcpy(map.data, text, (size_t)n);
  gst_memory_unmap(mem, &map);
  gst_buffer_append_memory(outbuf, mem);
  return GST_FLOW_OK;
}

static GstTensorDecoderDef def;

#ifndef NNS2X_DEC_NAME
#define NNS2X_DEC_NAME "twox_dec"
#endif

/* NNS2X_DEC_BAD: no decode callback, so the probe is refused. */
__attribute__((constructor)) static void init_dec(void) {
  def.modename = (char *)NNS2X_DEC_NAME;
  def.init = dec_init;
  def.getOutCaps = dec_caps;
#ifndef NNS2X_DEC_BAD
  def.decode = dec_decode;
#else
  (void)dec_decode;
#endif
  nnstreamer_decoder_probe(&def);
}

__attribute__((destructor)) static void fini_dec(void) {
  nnstreamer_decoder_exit(NNS2X_DEC_NAME);
}

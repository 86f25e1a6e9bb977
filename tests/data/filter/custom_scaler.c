/* SPDX-License-Identifier: LGPL-2.1-only */
/* Test custom filter (framework=custom): nearest-neighbour scaler for uint8 C:W:H:1 tensors.
 * The output size comes from custom="WxH" (default: half size). Uses setInputDim and
 * allocate_invoke + destroy_notify. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "tensor_filter_custom.h"

typedef struct {
  unsigned w, h;
} sc_data;

static void *sc_init(const GstTensorFilterProperties *prop) {
  sc_data *d = calloc(1, sizeof(sc_data));
  if (prop->custom_properties && sscanf(prop->custom_properties, "%ux%u", &d->w, &d->h) != 2) {
    d->w = 0;
    d->h = 0;
  }
  return d;
}

static void sc_exit(void *priv, const GstTensorFilterProperties *prop) {
  (void)prop;
  free(priv);
}

static int sc_set_in(void *priv, const GstTensorFilterProperties *prop, const GstTensorsInfo *in,
                     GstTensorsInfo *out) {
  sc_data *d = priv;
  (void)prop;
  if (in->num_tensors != 1 || in->info[0].type != _NNS_UINT8) return -22;
  out->num_tensors = 1;
  out->info[0] = in->info[0];
  out->info[0].name = NULL;
  out->info[0].dimension[1] = d->w ? d->w : in->info[0].dimension[1] / 2;
  out->info[0].dimension[2] = d->h ? d->h : in->info[0].dimension[2] / 2;
  return 0;
}

static int sc_invoke(void *priv, const GstTensorFilterProperties *prop,
                     const GstTensorMemory *input, GstTensorMemory *output) {
  (void)priv;
  const unsigned c = prop->input_meta.info[0].dimension[0];
  const unsigned iw = prop->input_meta.info[0].dimension[1];
  const unsigned ih = prop->input_meta.info[0].dimension[2];
  const unsigned ow = prop->output_meta.info[0].dimension[1];
  const unsigned oh = prop->output_meta.info[0].dimension[2];
  unsigned char *dst = malloc((size_t)c * ow * oh);
  const unsigned char *src = input[0].data;
  for (unsigned y = 0; y < oh; ++y)
    for (unsigned x = 0; x < ow; ++x)
      for (unsigned k = 0; k < c; ++k)
        dst[(y * ow + x) * c + k] = src[((y * ih / oh) * iw + (x * iw / ow)) * c + k];
  output[0].data = dst;
  output[0].size = (size_t)c * ow * oh;
  return 0;
}

static void sc_free(void *data) {
  free(data);
}

static NNStreamer_custom_class sc_class = {
    .initfunc = sc_init,
    .exitfunc = sc_exit,
    .getInputDim = NULL,
    .getOutputDim = NULL,
    .setInputDim = sc_set_in,
    .invoke = NULL,
    .allocate_invoke = sc_invoke,
    .destroy_notify = sc_free,
};

NNStreamer_custom_class *NNStreamer_custom = &sc_class;

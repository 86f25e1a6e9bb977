/* SPDX-License-Identifier: LGPL-2.1-only */
/* Test custom filter (framework=custom): fixed float32 10:1:1:1 in and out, copies input to
 * output. Written in plain C against tensor_filter_custom.h like NNStreamer's examples. */
#include <stdlib.h>
#include <string.h>

#include "tensor_filter_custom.h"

typedef struct {
  int calls;
} pt_data;

static void *pt_init(const GstTensorFilterProperties *prop) {
  (void)prop;
  return calloc(1, sizeof(pt_data));
}

static void pt_exit(void *priv, const GstTensorFilterProperties *prop) {
  (void)prop;
  free(priv);
}

static void set_info(GstTensorsInfo *info) {
  info->num_tensors = 1;
  info->info[0].type = _NNS_FLOAT32;
  info->info[0].dimension[0] = 10;
  info->info[0].dimension[1] = 1;
  info->info[0].dimension[2] = 1;
  info->info[0].dimension[3] = 1;
}

static int pt_get_in(void *priv, const GstTensorFilterProperties *prop, GstTensorsInfo *info) {
  (void)priv;
  (void)prop;
  set_info(info);
  return 0;
}

static int pt_get_out(void *priv, const GstTensorFilterProperties *prop, GstTensorsInfo *info) {
  (void)priv;
  (void)prop;
  set_info(info);
  return 0;
}

static int pt_invoke(void *priv, const GstTensorFilterProperties *prop,
                     const GstTensorMemory *input, GstTensorMemory *output) {
  pt_data *d = priv;
  d->calls++;
  /* The element passes the configured shapes in prop. */
  if (prop->input_meta.num_tensors != 1 || prop->input_meta.info[0].dimension[0] != 10) return -1;
  if (input[0].size != output[0].size) return -2;
  memcpy(output[0].data, input[0].data, input[0].size);
  return 0;
}

static NNStreamer_custom_class pt_class = {
    .initfunc = pt_init,
    .exitfunc = pt_exit,
    .getInputDim = pt_get_in,
    .getOutputDim = pt_get_out,
    .setInputDim = NULL,
    .invoke = pt_invoke,
    .allocate_invoke = NULL,
    .destroy_notify = NULL,
};

NNStreamer_custom_class *NNStreamer_custom = &pt_class;

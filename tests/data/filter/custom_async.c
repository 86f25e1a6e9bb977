/* SPDX-License-Identifier: LGPL-2.1-only */
/* Test custom filter (framework=custom) for invoke-async=true, written the NNStreamer way:
 * uint8 4:1:1:1 in and out; invoke sends two outputs per input with
 * nnstreamer_filter_dispatch_output_async() (input + 1, input + 2), handing the blocks over
 * to tensor_filter, which releases them with destroy_notify. custom_async_released() counts
 * those releases. */
#include <stdlib.h>
#include <string.h>

#include "nnstreamer_plugin_api_filter.h"
#include "tensor_filter_custom.h"

static int released;

__attribute__((visibility("default"))) int custom_async_released(void) {
  return released;
}

static void *ca_init(const GstTensorFilterProperties *prop) {
  (void)prop;
  return NULL;
}

static void ca_exit(void *priv, const GstTensorFilterProperties *prop) {
  (void)priv;
  (void)prop;
}

static int ca_dims(void *priv, const GstTensorFilterProperties *prop, GstTensorsInfo *info) {
  (void)priv;
  (void)prop;
  info->num_tensors = 1;
  info->info[0].type = _NNS_UINT8;
  info->info[0].dimension[0] = 4;
  info->info[0].dimension[1] = 1;
  info->info[0].dimension[2] = 1;
  info->info[0].dimension[3] = 1;
  return 0;
}

static int ca_invoke(void *priv, const GstTensorFilterProperties *prop,
                     const GstTensorMemory *input, GstTensorMemory *output) {
  GstTensorMemory out;
  unsigned char *p;
  size_t i;
  int k, rc;
  (void)priv;
  (void)output;
  if (!prop->invoke_async) return -22;
  for (k = 1; k <= 2; k++) {
    p = malloc(input[0].size);
    if (!p) return -12;
    for (i = 0; i < input[0].size; i++)
      p[i] = (unsigned char)(((const unsigned char *)input[0].data)[i] + k);
    out.data = p;
    out.size = input[0].size;
    rc = nnstreamer_filter_dispatch_output_async((GstTensorFilterProperties *)prop, &out);
    if (rc != 0) return rc;
  }
  return 1; /* as NNStreamer's async filters do: nothing on the regular path */
}

static void ca_free(void *data) {
  released++;
  free(data);
}

static NNStreamer_custom_class ca_class = {
    .initfunc = ca_init,
    .exitfunc = ca_exit,
    .getInputDim = ca_dims,
    .getOutputDim = ca_dims,
    .setInputDim = NULL,
    .invoke = ca_invoke,
    .allocate_invoke = NULL,
    .destroy_notify = ca_free,
};

NNStreamer_custom_class *NNStreamer_custom = &ca_class;

/* SPDX-License-Identifier: LGPL-2.1-only */
/* Benchmark custom filter (framework=custom) written against NNStreamer 2.x's
 * tensor_filter_custom.h ABI only (plain struct access): any input, the same output, copied. */
#include <stdlib.h>
#include <string.h>

#include "tensor_filter_custom.h"

static void *cp_init(const GstTensorFilterProperties *prop) {
  (void)prop;
  return malloc(1);
}

static void cp_exit(void *priv, const GstTensorFilterProperties *prop) {
  (void)prop;
  free(priv);
}

static int cp_set_in(void *priv, const GstTensorFilterProperties *prop, const GstTensorsInfo *in,
                     GstTensorsInfo *out) {
  (void)priv;
  (void)prop;
  if (in->num_tensors < 1 || in->num_tensors > NNS_TENSOR_MEMORY_MAX) return -1;
  out->num_tensors = in->num_tensors;
  out->format = in->format;
  for (unsigned i = 0; i < in->num_tensors; ++i) {
    out->info[i].name = NULL;
    out->info[i].type = in->info[i].type;
    memcpy(out->info[i].dimension, in->info[i].dimension, sizeof(tensor_dim));
  }
  return 0;
}

static int cp_invoke(void *priv, const GstTensorFilterProperties *prop,
                     const GstTensorMemory *input, GstTensorMemory *output) {
  (void)priv;
  for (unsigned i = 0; i < prop->input_meta.num_tensors; ++i)
    memcpy(output[i].data, input[i].data, input[i].size);
  return 0;
}

static NNStreamer_custom_class cp_class = {
    .initfunc = cp_init,
    .exitfunc = cp_exit,
    .setInputDim = cp_set_in,
    .invoke = cp_invoke,
};

__attribute__((visibility("default"))) NNStreamer_custom_class *NNStreamer_custom = &cp_class;

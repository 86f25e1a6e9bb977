/* SPDX-License-Identifier: LGPL-2.1-only */
/* An NNStreamer 2.x filter sub-plugin, table layout 0, written against the 2.x ABI only
 * (plain struct access, no helper functions): registers "twox_v0" from its constructor.
 * setInputDimension: any single uint8 tensor; the output has the same shape. invoke_NN
 * allocates the output (allocate_in_invoke) and writes 255 - x; destroyNotify frees it.
 * Counters (nns2x_v0_counters) let tests check open/close and alloc/free balance. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "nnstreamer_plugin_api_filter.h"

static int g_opens, g_closes, g_allocs, g_frees;

__attribute__((visibility("default"))) void nns2x_v0_counters(int *c) {
  c[0] = g_opens;
  c[1] = g_closes;
  c[2] = g_allocs;
  c[3] = g_frees;
}

static size_t bytes_of(const GstTensorInfo *t) {
  size_t n = 1;
  for (int i = 0; i < NNS_TENSOR_RANK_LIMIT && t->dimension[i]; ++i) n *= t->dimension[i];
  return n;
}

static int v0_open(const GstTensorFilterProperties *prop, void **priv) {
  /* As NNStreamer's sub-plugins do: the shared-model functions must resolve when loading. */
  if (prop->shared_tensor_filter_key &&
      nnstreamer_filter_shared_model_get(priv, prop->shared_tensor_filter_key))
    return -EINVAL;
  *priv = malloc(sizeof(size_t));
  *(size_t *)*priv = 0;
  ++g_opens;
  return 0;
}

static void v0_close(const GstTensorFilterProperties *prop, void **priv) {
  (void)prop;
  free(*priv);
  *priv = NULL;
  ++g_closes;
}

static int v0_set_input(const GstTensorFilterProperties *prop, void **priv,
                        const GstTensorsInfo *in, GstTensorsInfo *out) {
  (void)prop;
  if (in->num_tensors != 1 || in->info[0].type != _NNS_UINT8) return -EINVAL;
  out->num_tensors = 1;
  out->format = _NNS_TENSOR_FORMAT_STATIC;
  out->info[0].name = NULL;
  out->info[0].type = _NNS_UINT8;
  memcpy(out->info[0].dimension, in->info[0].dimension, sizeof(tensor_dim));
  *(size_t *)*priv = bytes_of(&in->info[0]);
  return 0;
}

static int v0_invoke(const GstTensorFilterProperties *prop, void **priv, const GstTensorMemory *in,
                     GstTensorMemory *out) {
  size_t n = bytes_of(&prop->input_meta.info[0]);
  if (n != *(size_t *)*priv || in[0].size != n) return -EINVAL;
  unsigned char *o = malloc(n);
  if (!o) return -ENOMEM;
  ++g_allocs;
  for (size_t i = 0; i < n; ++i)
    o[i] = (unsigned char)(255 - ((const unsigned char *)in[0].data)[i]);
  out[0].data = o;
  out[0].size = n;
  return 0;
}

static void v0_destroy(void **priv, void *data) {
  (void)priv;
  ++g_frees;
  free(data);
}

static GstTensorFilterFramework fw = {
    .version = GST_TENSOR_FILTER_FRAMEWORK_V0,
    .open = v0_open,
    .close = v0_close,
};

__attribute__((constructor)) static void init_v0(void) {
  fw.name = (char *)"twox_v0";
  fw.allocate_in_invoke = 1;
  fw.run_without_model = 1;
  fw.invoke_NN = v0_invoke;
  fw.setInputDimension = v0_set_input;
  fw.destroyNotify = v0_destroy;
  nnstreamer_filter_probe(&fw);
}

__attribute__((destructor)) static void fini_v0(void) {
  nnstreamer_filter_exit("twox_v0");
}

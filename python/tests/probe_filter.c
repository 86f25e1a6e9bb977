/* SPDX-License-Identifier: LGPL-2.1-only */
/* A custom filter (framework=custom) for the Python package's tests and benchmark: output =
 * input, any shape (setInputDim), default shape from the custom string "<type>,<dims>"
 * (uint8,4 when none). It records where each invoke's input tensor 0 was, so a test can check
 * that the model saw the numpy array's own memory: probe_last_input() (read with ctypes). */
#include <stdint.h>
#include <stdlib.h>
#include <string.h>

#include "tensor_filter_custom.h"

static void *g_last_input;
static unsigned g_calls;

__attribute__((visibility("default"))) void *probe_last_input(void) {
  return g_last_input;
}

__attribute__((visibility("default"))) unsigned probe_calls(void) {
  return g_calls;
}

static const char *const kTypes[] = {"int32",   "uint32",  "int16", "uint16", "int8",   "uint8",
                                     "float64", "float32", "int64", "uint64", "float16"};

typedef struct {
  GstTensorsInfo info;
} probe_data;

static void *probe_init(const GstTensorFilterProperties *prop) {
  probe_data *d = calloc(1, sizeof(*d));
  if (!d) return NULL;
  d->info.num_tensors = 1;
  d->info.info[0].type = _NNS_UINT8;
  d->info.info[0].dimension[0] = 4;
  const char *c = prop->custom_properties;
  if (c && *c) {
    const char *comma = strchr(c, ',');
    size_t tl = comma ? (size_t)(comma - c) : strlen(c);
    for (unsigned t = 0; t < sizeof(kTypes) / sizeof(kTypes[0]); ++t)
      if (strlen(kTypes[t]) == tl && strncmp(kTypes[t], c, tl) == 0) d->info.info[0].type = t;
    if (comma) {
      memset(d->info.info[0].dimension, 0, sizeof(d->info.info[0].dimension));
      const char *p = comma + 1;
      for (unsigned k = 0; k < NNS_TENSOR_RANK_LIMIT && *p; ++k) {
        char *end = NULL;
        d->info.info[0].dimension[k] = (uint32_t)strtoul(p, &end, 10);
        p = (*end == ':') ? end + 1 : end;
      }
    }
  }
  return d;
}

static void probe_exit(void *priv, const GstTensorFilterProperties *prop) {
  (void)prop;
  free(priv);
}

static int probe_get(void *priv, const GstTensorFilterProperties *prop, GstTensorsInfo *info) {
  (void)prop;
  *info = ((probe_data *)priv)->info;
  return 0;
}

static int probe_set(void *priv, const GstTensorFilterProperties *prop, const GstTensorsInfo *in,
                     GstTensorsInfo *out) {
  (void)prop;
  probe_data *d = priv;
  d->info = *in;
  d->info.extra = NULL;
  for (unsigned i = 0; i < NNS_TENSOR_MEMORY_MAX; ++i) d->info.info[i].name = NULL;  // not ours
  *out = d->info;
  return 0;
}

static int probe_invoke(void *priv, const GstTensorFilterProperties *prop,
                        const GstTensorMemory *input, GstTensorMemory *output) {
  (void)priv;
  (void)prop;
  g_last_input = input[0].data;
  g_calls++;
  if (input[0].size != output[0].size) return -1;
  memcpy(output[0].data, input[0].data, input[0].size);
  return 0;
}

static NNStreamer_custom_class probe_class = {
    .initfunc = probe_init,
    .exitfunc = probe_exit,
    .getInputDim = probe_get,
    .getOutputDim = probe_get,
    .setInputDim = probe_set,
    .invoke = probe_invoke,
    .allocate_invoke = NULL,
    .destroy_notify = NULL,
};

__attribute__((visibility("default"))) NNStreamer_custom_class *NNStreamer_custom = &probe_class;

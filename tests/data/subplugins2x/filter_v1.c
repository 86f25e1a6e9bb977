/* SPDX-License-Identifier: LGPL-2.1-only */
/* An NNStreamer 2.x filter sub-plugin, table layout 1 ("twox_v1" by default; NNS2X_NAME and
 * NNS2X_ADD override them for the name-clash test). The model: input 4 x uint8, output
 * 4 x float32 = x * 0.5 + add, where add comes from custom=add:<n> (default NNS2X_ADD) and
 * can be changed at run time with the CUSTOM_PROP event. Supported accelerators: cpu. */
#include <errno.h>
#include <stdlib.h>
#include <string.h>

#include "nnstreamer_plugin_api_filter.h"

#ifndef NNS2X_NAME
#define NNS2X_NAME "twox_v1"
#endif
#ifndef NNS2X_ADD
#define NNS2X_ADD 1.0f
#endif

static int g_opens, g_closes;
static int g_last_hw[5] = {-1, -1, -1, -1, -1}; /* num_hw, then up to 4 entries of hw_list */
static const accl_hw hw[] = {ACCL_CPU};

__attribute__((visibility("default"))) void nns2x_v1_counters(int *c) {
  c[0] = g_opens;
  c[1] = g_closes;
}

/* The accelerator list the last open() was given: c[0] = num_hw, c[1..4] = hw_list (-1 past
 * the end). */
__attribute__((visibility("default"))) void nns2x_v1_last_accelerators(int *c) {
  memcpy(c, g_last_hw, sizeof g_last_hw);
}

typedef struct {
  float add;
  accl_hw accl;
} v1_priv;

static float parse_add(const char *custom) {
  const char *p = custom ? strstr(custom, "add:") : NULL;
  return p ? strtof(p + 4, NULL) : NNS2X_ADD;
}

static int v1_open(const GstTensorFilterProperties *prop, void **priv) {
  v1_priv *p = malloc(sizeof *p);
  if (!p) return -ENOMEM;
  p->add = parse_add(prop->custom_properties);
  /* No list (accelerator unset): this model's own default, the CPU. */
  p->accl = prop->num_hw > 0 ? prop->hw_list[0] : ACCL_CPU;
  g_last_hw[0] = prop->num_hw;
  for (int i = 0; i < 4; ++i) g_last_hw[1 + i] = i < prop->num_hw ? (int)prop->hw_list[i] : -1;
  *priv = p;
  ++g_opens;
  return 0;
}

static void v1_close(const GstTensorFilterProperties *prop, void **priv) {
  (void)prop;
  free(*priv);
  *priv = NULL;
  ++g_closes;
}

static int v1_info(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                   void *priv, GstTensorFilterFrameworkInfo *info) {
  (void)self;
  (void)prop;
  (void)priv;
  info->name = NNS2X_NAME;
  info->allow_in_place = 0;
  info->allocate_in_invoke = 0;
  info->run_without_model = 1;
  info->verify_model_path = 0;
  info->hw_list = hw;
  info->num_hw = 1;
  info->accl_auto = ACCL_CPU;
  info->accl_default = ACCL_CPU;
  info->statistics = NULL;
  return 0;
}

static void set_one(GstTensorsInfo *i, tensor_type t) {
  memset(i->info[0].dimension, 0, sizeof(tensor_dim));
  i->num_tensors = 1;
  i->format = _NNS_TENSOR_FORMAT_STATIC;
  i->info[0].name = NULL;
  i->info[0].type = t;
  i->info[0].dimension[0] = 4;
  i->info[0].dimension[1] = 1;
}

static int v1_model_info(const GstTensorFilterFramework *self,
                         const GstTensorFilterProperties *prop, void *priv, model_info_ops ops,
                         GstTensorsInfo *in, GstTensorsInfo *out) {
  (void)self;
  (void)prop;
  (void)priv;
  if (ops != GET_IN_OUT_INFO) return -ENOENT;
  set_one(in, _NNS_UINT8);
  set_one(out, _NNS_FLOAT32);
  return 0;
}

static int v1_event(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                    void *priv, event_ops ops, GstTensorFilterFrameworkEventData *data) {
  (void)self;
  (void)prop;
  if (ops == CUSTOM_PROP && priv && data) {
    ((v1_priv *)priv)->add = parse_add(data->custom_properties);
    return 0;
  }
  return -ENOENT;
}

static int v1_invoke(const GstTensorFilterFramework *self, GstTensorFilterProperties *prop,
                     void *priv, const GstTensorMemory *in, GstTensorMemory *out) {
  (void)self;
  const v1_priv *p = priv;
  if (prop->invoke_dynamic) {
    /* As NNStreamer's dynamic sub-plugins: allocate the output and describe it in
     * prop->output_meta. Here: n float32 values (x * 0.5 + add) for an input of n bytes. */
    size_t n = in[0].size;
    float *y = malloc(n * sizeof(float) + 1);
    if (!y) return -ENOMEM;
    for (size_t i = 0; i < n; ++i) y[i] = ((const unsigned char *)in[0].data)[i] * 0.5f + p->add;
    set_one(&prop->output_meta, _NNS_FLOAT32);
    prop->output_meta.info[0].dimension[0] = (uint32_t)n;
    out[0].data = y;
    out[0].size = n * sizeof(float);
    return 0;
  }
  if (in[0].size != 4 || out[0].size != 16) return -EINVAL;
  if (p->accl != ACCL_CPU) return -ENODEV;
  const unsigned char *x = in[0].data;
  float *y = out[0].data;
  for (int i = 0; i < 4; ++i) y[i] = x[i] * 0.5f + p->add;
  return 0;
}

static GstTensorFilterFramework fw = {
    .version = GST_TENSOR_FILTER_FRAMEWORK_V1 | 7, /* low 16 bits: the sub-plugin's own */
    .open = v1_open,
    .close = v1_close,
};

__attribute__((constructor)) static void init_v1(void) {
  fw.invoke = v1_invoke;
  fw.getFrameworkInfo = v1_info;
  fw.getModelInfo = v1_model_info;
  fw.eventHandler = v1_event;
  nnstreamer_filter_probe(&fw);
}

__attribute__((destructor)) static void fini_v1(void) {
  nnstreamer_filter_exit(NNS2X_NAME);
}

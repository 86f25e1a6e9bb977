/* SPDX-License-Identifier: LGPL-2.1-only */
/* Benchmark NNStreamer 2.x filter sub-plugin "bench2x_pass" (table layout 1, 2.x ABI only):
 * any input, the same output, copied. */
#include <errno.h>
#include <string.h>

#include "nnstreamer_plugin_api_filter.h"

static int sp_info(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                   void *priv, GstTensorFilterFrameworkInfo *info) {
  (void)self;
  (void)prop;
  (void)priv;
  memset(info, 0, sizeof *info);
  info->name = "bench2x_pass";
  info->run_without_model = 1;
  return 0;
}

static int sp_model(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                    void *priv, model_info_ops ops, GstTensorsInfo *in, GstTensorsInfo *out) {
  (void)self;
  (void)prop;
  (void)priv;
  if (ops != SET_INPUT_INFO || in->num_tensors < 1 || in->num_tensors > NNS_TENSOR_MEMORY_MAX)
    return -ENOENT;
  out->num_tensors = in->num_tensors;
  out->format = in->format;
  for (unsigned i = 0; i < in->num_tensors; ++i) {
    out->info[i].name = NULL;
    out->info[i].type = in->info[i].type;
    memcpy(out->info[i].dimension, in->info[i].dimension, sizeof(tensor_dim));
  }
  return 0;
}

static int sp_event(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                    void *priv, event_ops ops, GstTensorFilterFrameworkEventData *data) {
  (void)self;
  (void)prop;
  (void)priv;
  (void)ops;
  (void)data;
  return -ENOENT;
}

static int sp_invoke(const GstTensorFilterFramework *self, GstTensorFilterProperties *prop,
                     void *priv, const GstTensorMemory *in, GstTensorMemory *out) {
  (void)self;
  (void)priv;
  for (unsigned i = 0; i < prop->input_meta.num_tensors; ++i)
    memcpy(out[i].data, in[i].data, in[i].size);
  return 0;
}

static GstTensorFilterFramework fw = {.version = GST_TENSOR_FILTER_FRAMEWORK_V1};

__attribute__((constructor)) static void sp_init(void) {
  fw.invoke = sp_invoke;
  fw.getFrameworkInfo = sp_info;
  fw.getModelInfo = sp_model;
  fw.eventHandler = sp_event;
  nnstreamer_filter_probe(&fw);
}

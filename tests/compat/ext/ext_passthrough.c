/* SPDX-License-Identifier: LGPL-2.1-only */
/* An extension as NNStreamer users write them: a custom filter (framework=custom) built only
 * from the installed headers, linked to libnnstreamer-single.so. Fixed-size pass-through of
 * one uint8 3:4:2:1 tensor; the tensor description is made with the utility API. */
#include <glib.h>
#include <string.h>

#include <nnstreamer_plugin_api_util.h>
#include <nnstreamer_util.h>
#include <tensor_filter_custom.h>

typedef struct {
  GstTensorsInfo info;
} pt_data;

static void *pt_init(const GstTensorFilterProperties *prop) {
  pt_data *d = g_new0(pt_data, 1);
  GstTensorInfo *t;
  UNUSED(prop);
  gst_tensors_info_init(&d->info);
  d->info.num_tensors = 1;
  t = gst_tensors_info_get_nth_info(&d->info, 0);
  t->name = g_strdup("frame");
  t->type = gst_tensor_get_type("uint8");
  if (gst_tensor_parse_dimension("3:4:2:1", t->dimension) != 4) {
    gst_tensors_info_free(&d->info);
    g_free(d);
    return NULL;
  }
  return d;
}

static void pt_exit(void *priv, const GstTensorFilterProperties *prop) {
  pt_data *d = priv;
  UNUSED(prop);
  if (!d) return;
  gst_tensors_info_free(&d->info);
  g_free(d);
}

static int pt_get_dim(void *priv, const GstTensorFilterProperties *prop, GstTensorsInfo *info) {
  pt_data *d = priv;
  UNUSED(prop);
  if (!d) return -1;
  /* the host hands an initialised, empty info */
  gst_tensors_info_copy(info, &d->info);
  return 0;
}

static int pt_invoke(void *priv, const GstTensorFilterProperties *prop,
                     const GstTensorMemory *input, GstTensorMemory *output) {
  pt_data *d = priv;
  gsize size = gst_tensors_info_get_size(&d->info, 0);
  UNUSED(prop);
  if (input[0].size != size || output[0].size != size) return -1;
  memcpy(output[0].data, input[0].data, size);
  return 0;
}

static NNStreamer_custom_class pt_class = {
    .initfunc = pt_init,
    .exitfunc = pt_exit,
    .getInputDim = pt_get_dim,
    .getOutputDim = pt_get_dim,
    .invoke = pt_invoke,
};

NNStreamer_custom_class *NNStreamer_custom = &pt_class;

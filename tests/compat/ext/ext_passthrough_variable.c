/* SPDX-License-Identifier: LGPL-2.1-only */
/* Extension custom filter: pass-through of whatever tensors come in (setInputDim). The output
 * description is a copy of the input's; invoke checks every tensor's size against
 * prop->input_meta with gst_tensors_info_get_size(). */
#include <glib.h>
#include <string.h>

#include <nnstreamer_plugin_api_util.h>
#include <nnstreamer_util.h>
#include <tensor_filter_custom.h>

static void *pv_init(const GstTensorFilterProperties *prop) {
  UNUSED(prop);
  return g_new0(int, 1); /* invocations */
}

static void pv_exit(void *priv, const GstTensorFilterProperties *prop) {
  UNUSED(prop);
  g_free(priv);
}

static int pv_set_in(void *priv, const GstTensorFilterProperties *prop, const GstTensorsInfo *in,
                     GstTensorsInfo *out) {
  UNUSED(priv);
  UNUSED(prop);
  if (!gst_tensors_info_validate(in)) return -22;
  gst_tensors_info_free(out);
  gst_tensors_info_copy(out, in);
  return 0;
}

static int pv_invoke(void *priv, const GstTensorFilterProperties *prop,
                     const GstTensorMemory *input, GstTensorMemory *output) {
  guint i;
  for (i = 0; i < prop->input_meta.num_tensors; ++i) {
    gsize size = gst_tensors_info_get_size(&prop->input_meta, (gint)i);
    if (size != input[i].size || size != output[i].size) return -1;
    memcpy(output[i].data, input[i].data, size);
  }
  ++*(int *)priv;
  return 0;
}

static NNStreamer_custom_class pv_class = {
    .initfunc = pv_init,
    .exitfunc = pv_exit,
    .setInputDim = pv_set_in,
    .invoke = pv_invoke,
};

NNStreamer_custom_class *NNStreamer_custom = &pv_class;

/* SPDX-License-Identifier: LGPL-2.1-only */
/* Extension custom filter: nearest-neighbour scaler of a uint8 C:W:H:1 tensor, output allocated
 * by the filter (allocate_invoke + destroy_notify). custom="W:H" gives the output size, read
 * with gst_tensor_parse_dimension(). */
#include <glib.h>
#include <string.h>

#include <nnstreamer_plugin_api_util.h>
#include <nnstreamer_util.h>
#include <tensor_filter_custom.h>

typedef struct {
  tensor_dim size; /* [0] = W, [1] = H */
} sc_data;

static int sc_freed; /* blocks released through destroy_notify */

static void *sc_init(const GstTensorFilterProperties *prop) {
  sc_data *d = g_new0(sc_data, 1);
  if (gst_tensor_parse_dimension(prop->custom_properties, d->size) != 2) {
    g_free(d);
    return NULL;
  }
  return d;
}

static void sc_exit(void *priv, const GstTensorFilterProperties *prop) {
  UNUSED(prop);
  g_free(priv);
}

static int sc_set_in(void *priv, const GstTensorFilterProperties *prop, const GstTensorsInfo *in,
                     GstTensorsInfo *out) {
  sc_data *d = priv;
  GstTensorInfo *o;
  UNUSED(prop);
  if (!d || in->num_tensors != 1 || in->info[0].type != _NNS_UINT8) return -22;
  gst_tensors_info_free(out);
  out->num_tensors = 1;
  o = gst_tensors_info_get_nth_info(out, 0);
  gst_tensor_info_copy(o, &in->info[0]);
  o->dimension[1] = d->size[0];
  o->dimension[2] = d->size[1];
  return 0;
}

static int sc_invoke(void *priv, const GstTensorFilterProperties *prop,
                     const GstTensorMemory *input, GstTensorMemory *output) {
  const GstTensorInfo *in = &prop->input_meta.info[0];
  const GstTensorInfo *out = &prop->output_meta.info[0];
  const guint c = in->dimension[0], iw = in->dimension[1], ih = in->dimension[2];
  const guint ow = out->dimension[1], oh = out->dimension[2];
  const guint8 *src = input[0].data;
  gsize bytes = gst_tensor_info_get_size(out);
  guint8 *dst;
  guint x, y, k;
  UNUSED(priv);
  if (input[0].size != gst_tensor_info_get_size(in)) return -1;
  dst = g_malloc(bytes);
  for (y = 0; y < oh; ++y)
    for (x = 0; x < ow; ++x)
      for (k = 0; k < c; ++k)
        dst[(y * ow + x) * c + k] = src[((y * ih / oh) * iw + (x * iw / ow)) * c + k];
  output[0].data = dst;
  output[0].size = bytes;
  return 0;
}

static void sc_destroy(void *data) {
  ++sc_freed;
  g_free(data);
}

/* For the test: how many output blocks went back through destroy_notify. */
int ext_scaler_freed(void) {
  return sc_freed;
}

static NNStreamer_custom_class sc_class = {
    .initfunc = sc_init,
    .exitfunc = sc_exit,
    .setInputDim = sc_set_in,
    .allocate_invoke = sc_invoke,
    .destroy_notify = sc_destroy,
};

NNStreamer_custom_class *NNStreamer_custom = &sc_class;

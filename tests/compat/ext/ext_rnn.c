/* SPDX-License-Identifier: LGPL-2.1-only */
/* Extension custom filter with state, for a tensor_reposrc -> filter -> tensor_reposink loop:
 * input h(t-1) (float32 4:1), output h(t) = 0.5 * h(t-1) + x(t), where x(t)[j] = t + j (t
 * counts the invocations from 1). The tensor descriptions come from the string parsers of the
 * utility API; setInputDim refuses any other input with gst_tensors_info_is_equal(). */
#include <glib.h>
#include <string.h>

#include <nnstreamer_plugin_api_util.h>
#include <nnstreamer_util.h>
#include <tensor_filter_custom.h>

typedef struct {
  GstTensorsInfo info;
  guint step;
} rnn_data;

static void *rnn_init(const GstTensorFilterProperties *prop) {
  rnn_data *d = g_new0(rnn_data, 1);
  UNUSED(prop);
  gst_tensors_info_init(&d->info);
  d->info.num_tensors = gst_tensors_info_parse_dimensions_string(&d->info, "4:1");
  gst_tensors_info_parse_types_string(&d->info, "float32");
  gst_tensors_info_parse_names_string(&d->info, "hidden");
  return d;
}

static void rnn_exit(void *priv, const GstTensorFilterProperties *prop) {
  rnn_data *d = priv;
  UNUSED(prop);
  gst_tensors_info_free(&d->info);
  g_free(d);
}

static int rnn_set_in(void *priv, const GstTensorFilterProperties *prop, const GstTensorsInfo *in,
                      GstTensorsInfo *out) {
  rnn_data *d = priv;
  UNUSED(prop);
  if (!gst_tensors_info_is_equal(in, &d->info)) return -22;
  gst_tensors_info_free(out);
  gst_tensors_info_copy(out, &d->info);
  return 0;
}

static int rnn_invoke(void *priv, const GstTensorFilterProperties *prop,
                      const GstTensorMemory *input, GstTensorMemory *output) {
  rnn_data *d = priv;
  const float *h = input[0].data;
  float *next = output[0].data;
  guint j, n = (guint)gst_tensor_get_element_count(d->info.info[0].dimension);
  UNUSED(prop);
  if (output[0].size != gst_tensors_info_get_size(&d->info, -1)) return -1;
  ++d->step;
  for (j = 0; j < n; ++j) next[j] = 0.5f * h[j] + (float)(d->step + j);
  return 0;
}

static NNStreamer_custom_class rnn_class = {
    .initfunc = rnn_init,
    .exitfunc = rnn_exit,
    .setInputDim = rnn_set_in,
    .invoke = rnn_invoke,
};

NNStreamer_custom_class *NNStreamer_custom = &rnn_class;

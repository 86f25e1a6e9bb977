/* SPDX-License-Identifier: LGPL-2.1-only */
/* A custom filter (framework=custom) as a user writes it against the installed packages:
 * compiled in the test root with `pkg-config --cflags --libs nnstreamer` (checks.sh). It
 * inverts one uint8 tensor of 784 elements (a 28x28 picture): out = 255 - in. */
#include <string.h>

#include <nnstreamer_plugin_api_util.h>
#include <tensor_filter_custom.h>

static void *inv_init(const GstTensorFilterProperties *prop) {
  (void)prop;
  static int token;
  return &token;
}

static void inv_exit(void *priv, const GstTensorFilterProperties *prop) {
  (void)priv;
  (void)prop;
}

static int inv_dim(void *priv, const GstTensorFilterProperties *prop, GstTensorsInfo *info) {
  GstTensorInfo *t;
  (void)priv;
  (void)prop;
  gst_tensors_info_init(info);
  info->num_tensors = 1;
  t = gst_tensors_info_get_nth_info(info, 0);
  t->type = _NNS_UINT8;
  return gst_tensor_parse_dimension("1:28:28:1", t->dimension) == 4 ? 0 : -1;
}

static int inv_invoke(void *priv, const GstTensorFilterProperties *prop,
                      const GstTensorMemory *input, GstTensorMemory *output) {
  const unsigned char *in = input[0].data;
  unsigned char *out = output[0].data;
  (void)priv;
  (void)prop;
  if (input[0].size != 784 || output[0].size != 784) return -1;
  for (size_t i = 0; i < 784; ++i) out[i] = (unsigned char)(255 - in[i]);
  return 0;
}

static NNStreamer_custom_class inv_class = {
    .initfunc = inv_init,
    .exitfunc = inv_exit,
    .getInputDim = inv_dim,
    .getOutputDim = inv_dim,
    .invoke = inv_invoke,
};

NNStreamer_custom_class *NNStreamer_custom = &inv_class;

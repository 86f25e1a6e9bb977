/* SPDX-License-Identifier: LGPL-2.1-only */
/* An nnstreamer-cpp back end named "clash" (our ABI), for the name-clash test beside the
 * NNStreamer 2.x sub-plugin of the same name: input 4 x uint8, output 4 x float32 = x + 100. */
#include <errno.h>
#include <string.h>

#include "nns_filter_backend.h"

static int c_open(const nns_filter_props *p, void **priv, char *err, size_t len) {
  (void)p;
  (void)err;
  (void)len;
  *priv = NULL;
  return 0;
}
static void c_close(void *priv) {
  (void)priv;
}
static void one(nns_tensors_desc *d, uint32_t type) {
  memset(d, 0, sizeof *d);
  d->num_tensors = 1;
  d->tensors[0].type = type;
  d->tensors[0].dims[0] = 4;
  d->tensors[0].dims[1] = 1;
}
static int c_info(void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *err, size_t len) {
  (void)priv;
  (void)err;
  (void)len;
  one(in, _NNS_UINT8);
  one(out, _NNS_FLOAT32);
  return 0;
}
static int c_invoke(void *priv, const GstTensorMemory *in, uint32_t ni, GstTensorMemory *out,
                    uint32_t no, char *err, size_t len) {
  (void)priv;
  (void)ni;
  (void)no;
  (void)err;
  (void)len;
  const unsigned char *x = in[0].data;
  float *y = out[0].data;
  for (int i = 0; i < 4; ++i) y[i] = x[i] + 100.0f;
  return 0;
}

static const nns_filter_backend_i table = {
    .api_version = NNS_FILTER_BACKEND_API_VERSION,
    .name = "clash",
    .flags = NNS_FILTER_FLAG_RUN_WITHOUT_MODEL,
    .open = c_open,
    .close = c_close,
    .get_model_info = c_info,
    .invoke = c_invoke,
};

__attribute__((visibility("default"))) const nns_filter_backend_i *nns_filter_backend_entry(void) {
  return &table;
}

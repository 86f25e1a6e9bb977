/* SPDX-License-Identifier: LGPL-2.1-only */
/* Test back end built for a future ABI version: the loader must refuse it. */
#include <stddef.h>

#include "nns_filter_backend.h"

static int bad_open(const nns_filter_props *p, void **priv, char *err, size_t len) {
  (void)p;
  (void)priv;
  (void)err;
  (void)len;
  return 0;
}
static void bad_close(void *priv) {
  (void)priv;
}
static int bad_invoke(void *priv, const GstTensorMemory *in, uint32_t ni, GstTensorMemory *out,
                      uint32_t no, char *err, size_t len) {
  (void)priv;
  (void)in;
  (void)ni;
  (void)out;
  (void)no;
  (void)err;
  (void)len;
  return 0;
}

static const nns_filter_backend_i table = {
    .api_version = 99,
    .name = "badversion",
    .open = bad_open,
    .close = bad_close,
    .invoke = bad_invoke,
};

__attribute__((visibility("default"))) const nns_filter_backend_i *nns_filter_backend_entry(void) {
  return &table;
}

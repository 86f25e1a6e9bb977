/* SPDX-License-Identifier: LGPL-2.1-only */
/* NNStreamer 2.x filter sub-plugins that fail their probe: NNS2X_BAD_VERSION builds one with
 * a version word that is not NNStreamer's ABI, otherwise a layout 1 table without
 * getModelInfo. NNS2X_NAME is the name. */
#include <errno.h>

#include "nnstreamer_plugin_api_filter.h"

static int bad_info(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                    void *priv, GstTensorFilterFrameworkInfo *info) {
  (void)self;
  (void)prop;
  (void)priv;
  info->name = NNS2X_NAME;
  return 0;
}

static int bad_invoke(const GstTensorFilterFramework *self, GstTensorFilterProperties *prop,
                      void *priv, const GstTensorMemory *in, GstTensorMemory *out) {
  (void)self;
  (void)prop;
  (void)priv;
  (void)in;
  (void)out;
  return -EINVAL;
}

static int bad_event(const GstTensorFilterFramework *self, const GstTensorFilterProperties *prop,
                     void *priv, event_ops ops, GstTensorFilterFrameworkEventData *data) {
  (void)self;
  (void)prop;
  (void)priv;
  (void)ops;
  (void)data;
  return -ENOENT;
}

static GstTensorFilterFramework fw;

__attribute__((constructor)) static void init_bad(void) {
#ifdef NNS2X_BAD_VERSION
  fw.version = 0x0000000200000000ULL;
#else
  fw.version = GST_TENSOR_FILTER_FRAMEWORK_V1;
#endif
  fw.invoke = bad_invoke;
  fw.getFrameworkInfo = bad_info;
  fw.eventHandler = bad_event;
  nnstreamer_filter_probe(&fw);
}

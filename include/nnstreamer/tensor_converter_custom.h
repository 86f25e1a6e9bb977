/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Custom conversion callbacks for tensor_converter (mode=custom-code:<name>), with the same
 * names, signatures and return values as NNStreamer's tensor_converter_custom.h.
 *
 * The callback gets the incoming media buffer (borrowed: do not unref it) and returns the
 * tensor buffer to push, one GstMemory per tensor (a new reference; returning in_buf itself
 * passes the element's reference on). It fills `config` (tensor count, types, dimensions,
 * format, and optionally the frame rate; left at -1 the input caps' rate is used). Returning
 * NULL stops the stream with an error naming the callback.
 */
#ifndef NNSTREAMER_CPP_TENSOR_CONVERTER_CUSTOM_H_
#define NNSTREAMER_CPP_TENSOR_CONVERTER_CUSTOM_H_

#include <glib.h>
#include <gst/gst.h>

#include "tensor_typedef.h"

G_BEGIN_DECLS

typedef GstBuffer *(*tensor_converter_custom)(GstBuffer *in_buf, void *data,
                                              GstTensorsConfig *config);

/* Registers `func` under `name`; `data` is passed back on every call.
 * Returns 0, or -EINVAL when name is empty, func is NULL or the name is taken. */
extern int nnstreamer_converter_custom_register(const gchar *name, tensor_converter_custom func,
                                                void *data);

/* Removes the callback registered as `name`. Returns 0, or -EINVAL when there is none. */
extern int nnstreamer_converter_custom_unregister(const gchar *name);

G_END_DECLS

#endif /* NNSTREAMER_CPP_TENSOR_CONVERTER_CUSTOM_H_ */

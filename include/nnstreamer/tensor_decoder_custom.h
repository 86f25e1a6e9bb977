/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * In-process custom decoders: tensor_decoder mode=custom-code option1=<name> calls the
 * function registered under <name>. Same names and signature as NNStreamer.
 */
#ifndef NNSTREAMER_CPP_TENSOR_DECODER_CUSTOM_H_
#define NNSTREAMER_CPP_TENSOR_DECODER_CUSTOM_H_

#include <glib.h>
#include <gst/gst.h>

#include "tensor_typedef.h"

G_BEGIN_DECLS

/* Fills out_buf from the input tensors; returns 0 on success, a negative errno otherwise. */
typedef int (*tensor_decoder_custom)(const GstTensorMemory *input, const GstTensorsConfig *config,
                                     void *data, GstBuffer *out_buf);

/* 0 on success; -EINVAL for a bad argument or a name already registered. */
extern int nnstreamer_decoder_custom_register(const gchar *name, tensor_decoder_custom func,
                                              void *data);
/* 0 on success; -EINVAL when nothing is registered under name. */
extern int nnstreamer_decoder_custom_unregister(const gchar *name);

G_END_DECLS

#endif /* NNSTREAMER_CPP_TENSOR_DECODER_CUSTOM_H_ */

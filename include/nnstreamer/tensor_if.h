/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Custom conditions for tensor_if (compared-value=CUSTOM compared-value-option=<name>), with
 * the same names, signature and return values as NNStreamer's tensor_if.h.
 *
 * The callback gets the negotiated input tensors' description and one GstTensorMemory per
 * tensor (read only, valid during the call), and `data` as registered. It stores the decision
 * in *result (TRUE: `then` branch, FALSE: `else` branch) and returns TRUE; returning FALSE stops
 * the stream with an error naming the condition.
 */
#ifndef NNSTREAMER_CPP_TENSOR_IF_H_
#define NNSTREAMER_CPP_TENSOR_IF_H_

#include <glib.h>

#include "tensor_typedef.h"

G_BEGIN_DECLS

typedef gboolean (*tensor_if_custom)(const GstTensorsInfo *info, const GstTensorMemory *input,
                                     void *data, gboolean *result);

/* Registers `func` under `name`. Returns 0, or -EINVAL when name is empty, func is NULL or the
 * name is taken. */
extern int nnstreamer_if_custom_register(const gchar *name, tensor_if_custom func, void *data);

/* Removes the condition registered as `name`. Returns 0, or -EINVAL when there is none. */
extern int nnstreamer_if_custom_unregister(const gchar *name);

G_END_DECLS

#endif /* NNSTREAMER_CPP_TENSOR_IF_H_ */

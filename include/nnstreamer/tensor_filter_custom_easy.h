/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * framework=custom-easy: register a C function in the running process and use it as a
 * model, `tensor_filter framework=custom-easy model=<name>`. Same functions as NNStreamer's
 * tensor_filter_custom_easy.h.
 *
 * The function receives the mapped input memories directly (no copy) and fills the output
 * buffers the element allocated. Return 0 on success, a negative value on error (the stream
 * stops with an error naming the model), a positive value to drop the frame.
 *
 * Registration is process-wide and thread-safe. A name can be registered once; unregister
 * it first to replace it. Unregistering a name while a pipeline uses it fails with -EBUSY.
 */
#ifndef NNSTREAMER_CPP_TENSOR_FILTER_CUSTOM_EASY_H_
#define NNSTREAMER_CPP_TENSOR_FILTER_CUSTOM_EASY_H_

#include <stdint.h>

#include "tensor_filter_custom.h"
#include "tensor_typedef.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Registers `func` as model `modelname` with fixed input and output tensors.
 * Returns 0, -EINVAL (bad arguments) or -EEXIST (name taken). */
int NNS_custom_easy_register(const char *modelname, NNS_custom_invoke func, void *data,
                             const GstTensorsInfo *in_info, const GstTensorsInfo *out_info);

/* Flexible variant for invoke-dynamic=true: the function fills out_info and allocates each
 * output[i].data with malloc(); the element frees it with free(). */
typedef int (*NNS_custom_invoke_dynamic)(void *private_data, const GstTensorsInfo *in_info,
                                         GstTensorsInfo *out_info, const GstTensorMemory *input,
                                         GstTensorMemory *output);

int NNS_custom_easy_dynamic_register(const char *modelname, NNS_custom_invoke_dynamic func,
                                     void *data, const GstTensorsInfo *in_info);

/* Returns 0, -EINVAL (unknown name) or -EBUSY (a filter still uses it). */
int NNS_custom_easy_unregister(const char *modelname);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_TENSOR_FILTER_CUSTOM_EASY_H_ */

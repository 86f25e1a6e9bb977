/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * framework=custom: a shared object that exports
 *
 *   NNStreamer_custom_class *NNStreamer_custom;
 *
 * used as `tensor_filter framework=custom model=/path/libmyfilter.so`. The class table and
 * the callbacks follow NNStreamer's tensor_filter_custom.h, so filters compiled for
 * NNStreamer load unchanged.
 *
 * Rules (checked when the filter opens, with an error naming the .so):
 *   - initfunc and exitfunc are called once per open/close; initfunc's result is the
 *     private_data handed to every other callback (it may be NULL);
 *   - either getInputDim and getOutputDim, or setInputDim, must be set;
 *   - exactly one of invoke (fill the given output buffers) and allocate_invoke (allocate the
 *     output; released with destroy_notify, or free() when destroy_notify is NULL) is set.
 * Callbacks return 0 on success; a negative value is an error, a positive value from
 * invoke drops the frame.
 */
#ifndef NNSTREAMER_CPP_TENSOR_FILTER_CUSTOM_H_
#define NNSTREAMER_CPP_TENSOR_FILTER_CUSTOM_H_

#include <stdint.h>

#include "nnstreamer_plugin_api_filter.h"
#include "tensor_typedef.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef void *(*NNS_custom_init_func)(const GstTensorFilterProperties *prop);
typedef void (*NNS_custom_exit_func)(void *private_data, const GstTensorFilterProperties *prop);
typedef int (*NNS_custom_get_input_dimension)(void *private_data,
                                              const GstTensorFilterProperties *prop,
                                              GstTensorsInfo *info);
typedef int (*NNS_custom_get_output_dimension)(void *private_data,
                                               const GstTensorFilterProperties *prop,
                                               GstTensorsInfo *info);
typedef int (*NNS_custom_set_input_dimension)(void *private_data,
                                              const GstTensorFilterProperties *prop,
                                              const GstTensorsInfo *in_info,
                                              GstTensorsInfo *out_info);
typedef int (*NNS_custom_invoke)(void *private_data, const GstTensorFilterProperties *prop,
                                 const GstTensorMemory *input, GstTensorMemory *output);
typedef int (*NNS_custom_allocate_invoke)(void *private_data, const GstTensorFilterProperties *prop,
                                          const GstTensorMemory *input, GstTensorMemory *output);
typedef void (*NNS_custom_destroy_notify)(void *data);

struct _NNStreamer_custom_class {
  NNS_custom_init_func initfunc;
  NNS_custom_exit_func exitfunc;
  NNS_custom_get_input_dimension getInputDim;
  NNS_custom_get_output_dimension getOutputDim;
  NNS_custom_set_input_dimension setInputDim;
  NNS_custom_invoke invoke;
  NNS_custom_allocate_invoke allocate_invoke;
  NNS_custom_destroy_notify destroy_notify;
};
typedef struct _NNStreamer_custom_class NNStreamer_custom_class;

/* Every custom filter defines this symbol. */
extern NNStreamer_custom_class *NNStreamer_custom;

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_TENSOR_FILTER_CUSTOM_H_ */

/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * GstTensorFilterProperties: what tensor_filter tells NNStreamer-style custom filters
 * (framework=custom, custom-easy, cpp). The field order and types match NNStreamer's
 * nnstreamer_plugin_api_filter.h so custom filter objects compiled against NNStreamer's
 * headers read the same offsets. Fields at the end that a filter does not know about are
 * simply never read by it.
 *
 * New back ends should not use this struct: they implement nns_filter_backend.h.
 */
#ifndef NNSTREAMER_CPP_PLUGIN_API_FILTER_H_
#define NNSTREAMER_CPP_PLUGIN_API_FILTER_H_

#include <stdint.h>

#include "tensor_typedef.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Accelerators (same values as NNStreamer). */
typedef enum {
  ACCL_NONE = 0,
  ACCL_AUTO = 0x1,
  ACCL_DEFAULT = 0x2,
  ACCL_CPU = 0x1000,
  ACCL_CPU_SIMD = 0x1100,
  ACCL_CPU_NEON = 0x1100,
  ACCL_GPU = 0x2000,
  ACCL_NPU = 0x4000,
  ACCL_NPU_MOVIDIUS = 0x4001,
  ACCL_NPU_EDGE_TPU = 0x4002,
  ACCL_NPU_VIVANTE = 0x4003,
  ACCL_NPU_SRCN = 0x4004,
  ACCL_NPU_SLSI = 0x4005,
  ACCL_NPU_SR = 0x4100,
} accl_hw;

typedef struct _GstTensorFilterProperties {
  const char *fwname;       /* framework name */
  int fw_opened;            /* non-zero once the filter is open */
  const char **model_files; /* model= split on ',' */
  int num_models;

  int input_configured;        /* non-zero when input_meta is final */
  GstTensorsInfo input_meta;   /* input tensors */
  tensors_layout input_layout; /* inputlayout= per tensor */
  unsigned int input_ranks[NNS_TENSOR_SIZE_LIMIT];

  int output_configured;
  GstTensorsInfo output_meta;
  tensors_layout output_layout;
  unsigned int output_ranks[NNS_TENSOR_SIZE_LIMIT];

  const char *custom_properties; /* custom= */
  accl_hw *hw_list;              /* accelerators requested and supported */
  int num_hw;
  const char *accl_str; /* accelerator= as given */
  char *shared_tensor_filter_key;

  int latency;           /* average invoke latency (us) when latency=1 */
  int throughput;        /* outputs per second x 1000 when throughput=1 */
  int invoke_dynamic;    /* invoke-dynamic=true */
  uint32_t suspend;      /* suspend= (ms) */
  int invoke_async;      /* invoke-async=true: send outputs with the functions below */
  void *async_callback;  /* host-private (set when invoke_async is set) */
  void *async_user_data; /* host-private */
} GstTensorFilterProperties;

/* invoke-async -----------------------------------------------------------------------------
 *
 * With invoke-async=true (prop->invoke_async != 0), tensor_filter ignores what invoke writes
 * into its output array: outputs are sent with the functions below, each becoming one output
 * buffer with the timestamps of the input it belongs to. A negative return from invoke is
 * still an error; other values are ignored. */

/* NNStreamer's call: emits output[0..n) described by prop->output_meta (which the filter may
 * update before the call, e.g. per generated token; n = output_meta.num_tensors). The output
 * belongs to the input most recently invoked, and is copied; as in NNStreamer, the data
 * blocks are then released by tensor_filter: with the custom filter's destroy_notify when it
 * has one, else free() (allocate them with malloc/strdup/g_malloc). Call it during invoke or
 * from another thread while the filter is open (prop is freed when the filter closes).
 * Returns 0 or a negative errno (-EINVAL: not an invoke-async filter or output_meta does
 * not match the data; -ESHUTDOWN: the element stopped). */
int nnstreamer_filter_dispatch_output_async(GstTensorFilterProperties *prop,
                                            GstTensorMemory *output);

/* nnstreamer-cpp extension: a handle naming the input being invoked, usable after invoke
 * returned, from any thread, also after the filter closed (calls then return -ESHUTDOWN). */
typedef struct _GstTensorFilterAsyncHandle {
  uint64_t opaque[8];
} GstTensorFilterAsyncHandle;

/* Call during invoke: fills *handle for the current input and announces that its outputs
 * follow later: EOS waits until the filter ends the input (last != 0 below). Returns 0, or
 * -EINVAL when prop is not in an invoke with invoke-async=true. */
int nnstreamer_filter_async_capture(const GstTensorFilterProperties *prop,
                                    GstTensorFilterAsyncHandle *handle);

/* Emits output[0..info->num_tensors) (info NULL: the negotiated output tensors) for the input
 * of `handle`; last != 0 ends that input (output may then be NULL: no buffer). The data is
 * copied; the caller keeps ownership. Returns 0 or a negative errno as
 * nnstreamer_filter_dispatch_output_async(); also -ECANCELED after a flush. */
int nnstreamer_filter_async_dispatch(const GstTensorFilterAsyncHandle *handle,
                                     const GstTensorsInfo *info, const GstTensorMemory *output,
                                     int last);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_PLUGIN_API_FILTER_H_ */

/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Copy counters of the pytorch filter back end, for tests and benchmarks that prove the
 * zero-copy paths. libnnstreamer_filter_pytorch.so exports
 *
 *   int nns_filter_pytorch_get_stats(void *priv, nns_pytorch_stats *out);
 *
 * where priv is the instance returned by the back end's open(). Returns 0, or -EINVAL for
 * NULL arguments.
 */
#ifndef NNSTREAMER_CPP_PYTORCH_STATS_H_
#define NNSTREAMER_CPP_PYTORCH_STATS_H_

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

typedef struct {
  uint64_t invokes;          /* successful invoke + invoke_dynamic calls */
  uint64_t input_copies;     /* input tensors copied before inference (always 0 on CPU) */
  uint64_t output_copies;    /* output tensors copied (into caller buffers, or cloned) */
  uint64_t output_zero_copy; /* output tensors handed over without a copy */
} nns_pytorch_stats;

typedef int (*nns_filter_pytorch_get_stats_fn)(void *priv, nns_pytorch_stats *out);
#define NNS_FILTER_PYTORCH_GET_STATS "nns_filter_pytorch_get_stats"

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_PYTORCH_STATS_H_ */

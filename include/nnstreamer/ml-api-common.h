/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Common types of the ML API (names, values and semantics of NNStreamer's ml-api-common.h,
 * non-Tizen build): error codes, tensor types, tensors-info and tensors-data handles, options.
 */
#ifndef NNSTREAMER_CPP_ML_API_COMMON_H_
#define NNSTREAMER_CPP_ML_API_COMMON_H_

#include <errno.h>
#include <stdbool.h>
#include <stddef.h>

#ifdef __cplusplus
extern "C" {
#endif

#define ML_TENSOR_RANK_LIMIT (16)
#define ML_TENSOR_SIZE_LIMIT (256)

#define ML_ERROR_UNKNOWN_BASE (-1073741824LL)
typedef enum {
  ML_ERROR_NONE = 0,
  ML_ERROR_INVALID_PARAMETER = -EINVAL,
  ML_ERROR_STREAMS_PIPE = -ESTRPIPE,
  ML_ERROR_TRY_AGAIN = -EAGAIN,
  ML_ERROR_UNKNOWN = ML_ERROR_UNKNOWN_BASE,
  ML_ERROR_TIMED_OUT = ML_ERROR_UNKNOWN_BASE + 1,
  ML_ERROR_NOT_SUPPORTED = ML_ERROR_UNKNOWN_BASE + 2,
  ML_ERROR_PERMISSION_DENIED = -EACCES,
  ML_ERROR_OUT_OF_MEMORY = -ENOMEM,
  ML_ERROR_IO_ERROR = -EIO,
} ml_error_e;

typedef enum {
  ML_TENSOR_TYPE_INT32 = 0,
  ML_TENSOR_TYPE_UINT32,
  ML_TENSOR_TYPE_INT16,
  ML_TENSOR_TYPE_UINT16,
  ML_TENSOR_TYPE_INT8,
  ML_TENSOR_TYPE_UINT8,
  ML_TENSOR_TYPE_FLOAT64,
  ML_TENSOR_TYPE_FLOAT32,
  ML_TENSOR_TYPE_INT64,
  ML_TENSOR_TYPE_UINT64,
  ML_TENSOR_TYPE_FLOAT16,
  ML_TENSOR_TYPE_UNKNOWN
} ml_tensor_type_e;

typedef enum {
  ML_TENSOR_FORMAT_STATIC = 0,
  ML_TENSOR_FORMAT_FLEXIBLE = 1,
  ML_TENSOR_FORMAT_SPARSE = 2,
} ml_tensor_format_e;

typedef unsigned int ml_tensor_dimension[ML_TENSOR_RANK_LIMIT];

typedef void *ml_tensors_info_h;
typedef void *ml_tensors_data_h;
typedef void *ml_option_h;
typedef void (*ml_data_destroy_cb)(void *data);

/* The message of the last error on this thread ("" when none). */
const char *ml_error(void);
/* A short description of an ml_error_e value. */
const char *ml_strerror(int error_code);

int ml_tensors_info_create(ml_tensors_info_h *info);
int ml_tensors_info_create_extended(ml_tensors_info_h *info);
int ml_tensors_info_destroy(ml_tensors_info_h info);
int ml_tensors_info_validate(const ml_tensors_info_h info, bool *valid);
int ml_tensors_info_clone(ml_tensors_info_h dest, const ml_tensors_info_h src);
int ml_tensors_info_set_count(ml_tensors_info_h info, unsigned int count);
int ml_tensors_info_get_count(ml_tensors_info_h info, unsigned int *count);
int ml_tensors_info_set_tensor_name(ml_tensors_info_h info, unsigned int index, const char *name);
/* *name is a copy the caller frees with free(). */
int ml_tensors_info_get_tensor_name(ml_tensors_info_h info, unsigned int index, char **name);
int ml_tensors_info_set_tensor_type(ml_tensors_info_h info, unsigned int index,
                                    const ml_tensor_type_e type);
int ml_tensors_info_get_tensor_type(ml_tensors_info_h info, unsigned int index,
                                    ml_tensor_type_e *type);
int ml_tensors_info_set_tensor_dimension(ml_tensors_info_h info, unsigned int index,
                                         const ml_tensor_dimension dimension);
int ml_tensors_info_get_tensor_dimension(ml_tensors_info_h info, unsigned int index,
                                         ml_tensor_dimension dimension);
/* Bytes of tensor `index`, or of all tensors when index < 0. */
int ml_tensors_info_get_tensor_size(ml_tensors_info_h info, int index, size_t *data_size);

int ml_tensors_data_create(const ml_tensors_info_h info, ml_tensors_data_h *data);
int ml_tensors_data_destroy(ml_tensors_data_h data);
int ml_tensors_data_get_tensor_data(ml_tensors_data_h data, unsigned int index, void **raw_data,
                                    size_t *data_size);
int ml_tensors_data_set_tensor_data(ml_tensors_data_h data, unsigned int index,
                                    const void *raw_data, const size_t data_size);
int ml_tensors_data_get_info(const ml_tensors_data_h data, ml_tensors_info_h *info);

int ml_option_create(ml_option_h *option);
int ml_option_destroy(ml_option_h option);
/* Stores `value` under `key`; destroy (may be NULL) is called on it when replaced or freed. */
int ml_option_set(ml_option_h option, const char *key, void *value, ml_data_destroy_cb destroy);
int ml_option_get(ml_option_h option, const char *key, void **value);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_ML_API_COMMON_H_ */

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
#include <stdint.h>
#include <stdlib.h>

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
  ML_NNFW_TYPE_ANY = 0,
  ML_NNFW_TYPE_CUSTOM_FILTER = 1,
  ML_NNFW_TYPE_TENSORFLOW_LITE = 2,
  ML_NNFW_TYPE_TENSORFLOW = 3,
  ML_NNFW_TYPE_NNFW = 4,
  ML_NNFW_TYPE_MVNC = 5,
  ML_NNFW_TYPE_OPENVINO = 6,
  ML_NNFW_TYPE_VIVANTE = 7,
  ML_NNFW_TYPE_EDGE_TPU = 8,
  ML_NNFW_TYPE_ARMNN = 9,
  ML_NNFW_TYPE_SNPE = 10,
  ML_NNFW_TYPE_PYTORCH = 11,
  ML_NNFW_TYPE_NNTR_INF = 12,
  ML_NNFW_TYPE_VD_AIFW = 13,
  ML_NNFW_TYPE_TRIX_ENGINE = 14,
  ML_NNFW_TYPE_MXNET = 15,
  ML_NNFW_TYPE_TVM = 16,
  ML_NNFW_TYPE_ONNX_RUNTIME = 17,
  ML_NNFW_TYPE_NCNN = 18,
  ML_NNFW_TYPE_TENSORRT = 19,
  ML_NNFW_TYPE_QNN = 20,
  ML_NNFW_TYPE_LLAMACPP = 21,
  ML_NNFW_TYPE_TIZEN_HAL = 22,
  ML_NNFW_TYPE_SNAP = 0x2001,
} ml_nnfw_type_e;

typedef enum {
  ML_NNFW_HW_ANY = 0,
  ML_NNFW_HW_AUTO = 1,
  ML_NNFW_HW_CPU = 0x1000,
  ML_NNFW_HW_CPU_SIMD = 0x1100,
  ML_NNFW_HW_CPU_NEON = 0x1100,
  ML_NNFW_HW_GPU = 0x2000,
  ML_NNFW_HW_NPU = 0x3000,
  ML_NNFW_HW_NPU_MOVIDIUS = 0x3001,
  ML_NNFW_HW_NPU_EDGE_TPU = 0x3002,
  ML_NNFW_HW_NPU_VIVANTE = 0x3003,
  ML_NNFW_HW_NPU_SLSI = 0x3004,
  ML_NNFW_HW_NPU_SR = 0x13000,
} ml_nnfw_hw_e;

typedef enum _ml_tensor_type_e {
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

typedef unsigned int ml_tensor_dimension[ML_TENSOR_RANK_LIMIT];

typedef void *ml_tensors_info_h;
typedef void *ml_tensors_data_h;
typedef void (*ml_data_destroy_cb)(void *data);

/* The message of the last failed call on this thread, NULL when none failed. */
const char *ml_error(void);
/* A short description of an ml_error_e value; NULL for a value that is not one. */
const char *ml_strerror(int error_code);

/* A handle from ml_tensors_info_create() has NNStreamer's old rank limit of 4:
 * set_tensor_dimension reads dimension[0..3] only and get_tensor_dimension writes 0 after them.
 * ml_tensors_info_create_extended() gives the full ML_TENSOR_RANK_LIMIT (16). Clone copies
 * which kind the source is. */
int ml_tensors_info_create(ml_tensors_info_h *info);
int ml_tensors_info_create_extended(ml_tensors_info_h *info);
int ml_tensors_info_destroy(ml_tensors_info_h info);
int ml_tensors_info_validate(const ml_tensors_info_h info, bool *valid);
/* dest must be a created handle; src must be valid (ML_ERROR_INVALID_PARAMETER otherwise). */
int ml_tensors_info_clone(ml_tensors_info_h dest, const ml_tensors_info_h src);
int ml_tensors_info_set_count(ml_tensors_info_h info, unsigned int count);
int ml_tensors_info_get_count(ml_tensors_info_h info, unsigned int *count);
int ml_tensors_info_set_tensor_name(ml_tensors_info_h info, unsigned int index, const char *name);
/* *name is a copy the caller frees with free() (NULL when the tensor has no name). */
int ml_tensors_info_get_tensor_name(ml_tensors_info_h info, unsigned int index, char **name);
int ml_tensors_info_set_tensor_type(ml_tensors_info_h info, unsigned int index,
                                    const ml_tensor_type_e type);
int ml_tensors_info_get_tensor_type(ml_tensors_info_h info, unsigned int index,
                                    ml_tensor_type_e *type);
/* dimension[0] must not be 0 and no value may follow a 0 (within the handle's rank limit). */
int ml_tensors_info_set_tensor_dimension(ml_tensors_info_h info, unsigned int index,
                                         const ml_tensor_dimension dimension);
int ml_tensors_info_get_tensor_dimension(ml_tensors_info_h info, unsigned int index,
                                         ml_tensor_dimension dimension);
/* Bytes of tensor `index`, or of all tensors when index < 0. */
int ml_tensors_info_get_tensor_size(ml_tensors_info_h info, int index, size_t *data_size);

int ml_tensors_data_create(const ml_tensors_info_h info, ml_tensors_data_h *data);
int ml_tensors_data_destroy(ml_tensors_data_h data);
/* *raw_data points into the handle (not a copy). */
int ml_tensors_data_get_tensor_data(ml_tensors_data_h data, unsigned int index, void **raw_data,
                                    size_t *data_size);
int ml_tensors_data_set_tensor_data(ml_tensors_data_h data, unsigned int index,
                                    const void *raw_data, const size_t data_size);
/* *out is a new handle with a copy of every tensor of `in` and its info. */
int ml_tensors_data_clone(const ml_tensors_data_h in, ml_tensors_data_h *out);
int ml_tensors_data_get_info(const ml_tensors_data_h data, ml_tensors_info_h *info);

typedef void *ml_option_h;

int ml_option_create(ml_option_h *option);
int ml_option_destroy(ml_option_h option);
/* Stores `value` under `key` (a non-empty string; value not NULL); destroy (may be NULL) is
 * called on it when replaced or when the option is destroyed. */
int ml_option_set(ml_option_h option, const char *key, void *value, ml_data_destroy_cb destroy);
int ml_option_get(ml_option_h option, const char *key, void **value);

/* Key-value information the library hands out (read-only for applications). */
typedef void *ml_information_h;
typedef void *ml_information_list_h;

int ml_information_destroy(ml_information_h ml_info);
/* *value points into the handle. Unknown key: ML_ERROR_INVALID_PARAMETER. */
int ml_information_get(ml_information_h ml_info, const char *key, void **value);
/* Destroys the list and every information in it. */
int ml_information_list_destroy(ml_information_list_h ml_info_list);
int ml_information_list_length(ml_information_list_h ml_info_list, unsigned int *length);
/* *ml_info stays owned by the list. */
int ml_information_list_get(ml_information_list_h ml_info_list, unsigned int index,
                            ml_information_h *ml_info);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_ML_API_COMMON_H_ */

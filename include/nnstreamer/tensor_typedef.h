/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Plain C types describing tensor streams. The layout of every struct and the numbering of
 * every enum follow NNStreamer's tensor_typedef.h, so filters, converters and decoders compiled
 * against NNStreamer's headers can be used with nnstreamer-cpp.
 */
#ifndef NNSTREAMER_CPP_TENSOR_TYPEDEF_H_
#define NNSTREAMER_CPP_TENSOR_TYPEDEF_H_

#include <stddef.h>
#include <stdint.h>

#define NNS_TENSOR_RANK_LIMIT (16)
#define NNS_TENSOR_SIZE_LIMIT (256)
#define NNS_TENSOR_SIZE_LIMIT_STR "256"
#define NNS_TENSOR_MEMORY_MAX (16)
#define NNS_TENSOR_SIZE_EXTRA_LIMIT (NNS_TENSOR_SIZE_LIMIT - NNS_TENSOR_MEMORY_MAX)
#define NNS_TENSOR_META_RANK_LIMIT (16)

#define GST_TENSOR_NUM_TENSORS_RANGE "(int) [ 1, " NNS_TENSOR_SIZE_LIMIT_STR " ]"
#define GST_TENSOR_RATE_RANGE "(fraction) [ 0, max ]"
#define GST_TENSOR_TYPE_ALL \
  "{ float16, float32, float64, int64, uint64, int32, uint32, int16, uint16, int8, uint8 }"
#define GST_TENSOR_FORMAT_ALL "{ static, flexible, sparse }"

#define NNS_MIMETYPE_TENSOR "other/tensor"
#define NNS_MIMETYPE_TENSORS "other/tensors"

#define GST_TENSOR_CAP_DEFAULT NNS_MIMETYPE_TENSOR ", framerate = " GST_TENSOR_RATE_RANGE
#define GST_TENSORS_CAP_MAKE(fmt) \
  NNS_MIMETYPE_TENSORS ", format = (string) " fmt ", framerate = " GST_TENSOR_RATE_RANGE
#define GST_TENSORS_CAP_WITH_NUM(num)                                   \
  NNS_MIMETYPE_TENSORS ", format = (string) static, num_tensors = " num \
                       ", framerate = " GST_TENSOR_RATE_RANGE
#define GST_TENSORS_CAP_DEFAULT GST_TENSORS_CAP_WITH_NUM(GST_TENSOR_NUM_TENSORS_RANGE)
#define GST_TENSORS_FLEX_CAP_DEFAULT GST_TENSORS_CAP_MAKE("flexible")
#define GST_TENSORS_SPARSE_CAP_DEFAULT GST_TENSORS_CAP_MAKE("sparse")

#ifdef __cplusplus
extern "C" {
#endif

/* Element types; the numbers are part of the wire format (flexible header). */
typedef enum _nns_tensor_type {
  _NNS_INT32 = 0,
  _NNS_UINT32,
  _NNS_INT16,
  _NNS_UINT16,
  _NNS_INT8,
  _NNS_UINT8,
  _NNS_FLOAT64,
  _NNS_FLOAT32,
  _NNS_INT64,
  _NNS_UINT64,
  _NNS_FLOAT16,
  _NNS_END,
} tensor_type;

typedef enum _nns_tensor_format {
  _NNS_TENSOR_FORMAT_STATIC = 0,
  _NNS_TENSOR_FORMAT_FLEXIBLE,
  _NNS_TENSOR_FORMAT_SPARSE,
  _NNS_TENSOR_FORMAT_END,
} tensor_format;

typedef enum _nns_media_type {
  _NNS_MEDIA_INVALID = -1,
  _NNS_VIDEO = 0,
  _NNS_AUDIO = 1,
  _NNS_TEXT = 2,
  _NNS_OCTET = 3,
  _NNS_TENSOR = 4,
  _NNS_MEDIA_ANY = 0x1000,
} media_type;

typedef enum _nns_tensor_layout {
  _NNS_LAYOUT_ANY = 0,
  _NNS_LAYOUT_NHWC,
  _NNS_LAYOUT_NCHW,
  _NNS_LAYOUT_NONE,
} tensor_layout;

typedef tensor_layout tensors_layout[NNS_TENSOR_SIZE_LIMIT];
typedef uint32_t tensor_dim[NNS_TENSOR_RANK_LIMIT];

/* One tensor's bytes as handed to sub-plugins. */
typedef struct {
  void *data;
  size_t size;
} GstTensorMemory;

typedef struct {
  char *name;
  tensor_type type;
  tensor_dim dimension; /* innermost first; 0 marks the end of the rank */
} GstTensorInfo;

typedef struct {
  unsigned int num_tensors;
  GstTensorInfo info[NNS_TENSOR_MEMORY_MAX];
  GstTensorInfo *extra; /* tensors with index >= NNS_TENSOR_MEMORY_MAX */
  tensor_format format;
} GstTensorsInfo;

typedef struct {
  GstTensorsInfo info;
  int rate_n;
  int rate_d;
} GstTensorsConfig;

typedef struct {
  uint32_t nnz;
} GstSparseTensorInfo;

/* The 128-byte header that starts every memory of a flexible or sparse stream. */
typedef struct {
  uint32_t magic;
  uint32_t version;
  uint32_t type;
  tensor_dim dimension;
  uint32_t format;
  uint32_t media_type;
  union {
    GstSparseTensorInfo sparse_info;
  };
} GstTensorMetaInfo;

/* One element of any tensor type, for code written once for every type. */
#if defined(FLOAT16_SUPPORT)
#if defined(__aarch64__) || defined(__arm__)
typedef __fp16 float16; /* 32-bit Arm needs -mfp16-format=ieee */
#elif defined(__x86_64) || defined(__i686__)
typedef _Float16 float16;
#else
#error "FLOAT16_SUPPORT needs aarch64, arm or x86/x86-64"
#endif
#endif

typedef union {
  int32_t _int32_t;
  uint32_t _uint32_t;
  int16_t _int16_t;
  uint16_t _uint16_t;
  int8_t _int8_t;
  uint8_t _uint8_t;
  double _double;
  float _float;
  int64_t _int64_t;
  uint64_t _uint64_t;
#ifdef FLOAT16_SUPPORT
  float16 _float16;
#endif
} tensor_element;

/* Callback receiving one frame of tensors (data is only valid during the call). */
typedef int (*GstTensorDataCallback)(GstTensorMemory *data, GstTensorsInfo *info, void *user_data);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_TENSOR_TYPEDEF_H_ */

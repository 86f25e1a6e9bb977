/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * The C ABI between tensor_filter (and the single-shot API) and inference back ends.
 *
 * A back end is a shared object named libnnstreamer_filter_<name>.so, found in the folders of
 * nnstreamer.ini's [filter] filters= key, NNSTREAMER_FILTERS, or built in. It exports
 *
 *   const nns_filter_backend_i *nns_filter_backend_entry(void);
 *
 * which returns a static table. The loader accepts an api_version from
 * NNS_FILTER_BACKEND_API_VERSION_MIN to NNS_FILTER_BACKEND_API_VERSION and rejects any other
 * with a message naming both versions. A version 1 table ends at check_accelerator: fields added
 * later are read only from tables whose version has them, so back ends built against older
 * headers keep loading unchanged. Every function returns 0 on success or a negative errno
 * value, and on failure writes a message into err (errlen bytes, always NUL-terminated) that
 * names the cause; the host posts it on the GStreamer bus together with the model path.
 *
 * Back ends written in C++ can derive from nns::FilterBackend (nns_filter_backend.hh) instead
 * of filling this table by hand.
 */
#ifndef NNSTREAMER_CPP_FILTER_BACKEND_H_
#define NNSTREAMER_CPP_FILTER_BACKEND_H_

#include <stddef.h>
#include <stdint.h>

#include "tensor_typedef.h"

#ifdef __cplusplus
extern "C" {
#endif

/* 2: invoke_async, nns_filter_props.invoke_async. */
#define NNS_FILTER_BACKEND_API_VERSION 2u
#define NNS_FILTER_BACKEND_API_VERSION_MIN 1u
#define NNS_FILTER_BACKEND_ENTRY "nns_filter_backend_entry"
#define NNS_TENSOR_NAME_MAX 256

/* One tensor: name (may be empty), element type (tensor_type numbering) and dims. */
typedef struct {
  char name[NNS_TENSOR_NAME_MAX];
  uint32_t type;                        /* tensor_type */
  uint32_t dims[NNS_TENSOR_RANK_LIMIT]; /* innermost first, 0 after the rank */
} nns_tensor_desc;

/* A set of tensors. num_tensors == 0 means "not known". */
typedef struct {
  uint32_t num_tensors;
  uint32_t format; /* tensor_format */
  nns_tensor_desc tensors[NNS_TENSOR_SIZE_LIMIT];
} nns_tensors_desc;

/* What the element's properties say. Pointers are valid during the call only. */
typedef struct {
  const char *framework;          /* the framework= name the user asked for */
  const char *const *model_files; /* model= split on ',' */
  uint32_t num_models;
  /* From input=/inputtype=/inputname= (output=/...), or num_tensors 0. With
   * NNS_FILTER_FLAG_TENSOR_NAMES a set may carry names only (inputname= alone: every type
   * _NNS_END, every dim 0); other back ends never see such a set. */
  const nns_tensors_desc *input;
  const nns_tensors_desc *output;
  const char *custom;                 /* custom= "key:value,key:value" or NULL */
  const char *accelerator;            /* accelerator= or NULL */
  const tensor_layout *input_layout;  /* NNS_TENSOR_SIZE_LIMIT entries */
  const tensor_layout *output_layout; /* NNS_TENSOR_SIZE_LIMIT entries */
  int invoke_dynamic;                 /* invoke-dynamic=true */
  int num_threads;                    /* 0: back end default */
  /* Version 2. */
  int invoke_async; /* invoke-async=true and the table has invoke_async: it will be called */
  int verbose;      /* silent=false: the back end may print what it chose (e.g. the
                       accelerator), as NNStreamer's sub-plugins do */
} nns_filter_props;

/* invoke-async (version 2) ------------------------------------------------------------------
 *
 * With invoke-async=true, tensor_filter calls invoke_async instead of invoke. The back end
 * takes the input and emits 0..N output sets through ctx->dispatch, during the call or later
 * from any thread; each becomes one output buffer. The input itself produces no buffer. */

/* No more outputs for this input (dispatch flags). */
#define NNS_FILTER_ASYNC_LAST 1u
/* invoke_async result: outputs of this input will follow; the back end ends the input with a
 * dispatch flagged NNS_FILTER_ASYNC_LAST (EOS is held back until then). */
#define NNS_FILTER_ASYNC_PENDING 1
/* "No timestamp" in nns_filter_async_ctx (GST_CLOCK_TIME_NONE). */
#define NNS_FILTER_TIME_NONE UINT64_MAX

typedef struct nns_filter_async_ctx nns_filter_async_ctx;

/* Emits one output set for the input of `ctx`: num_out tensors out[i] described by `info`
 * (NULL: the negotiated output tensors, which must then be static). The host copies the data;
 * the caller keeps ownership of out[i].data. out may be NULL with num_out 0 (only the flags
 * count). Thread-safe; callable at any time, also after the filter stopped. Returns 0, or
 *   -EINVAL     the tensors do not match the negotiated output (err says how; not pushed),
 *   -ESHUTDOWN  the filter stopped (nothing happens),
 *   -ECANCELED  the stream was flushed after this input (the output is dropped),
 *   -EPIPE      downstream refused the buffer (EOS, not linked, error). */
typedef int (*nns_filter_dispatch_fn)(const nns_filter_async_ctx *ctx, const nns_tensors_desc *info,
                                      const GstTensorMemory *out, uint32_t num_out, uint32_t flags,
                                      char *err, size_t errlen);

/* Where the outputs of one input go. A plain value: copy it, keep it as long as you like. */
struct nns_filter_async_ctx {
  nns_filter_dispatch_fn dispatch;
  uint64_t target; /* host-private: the filter */
  uint64_t input;  /* host-private: the input */
  /* The input's timestamps (ns, NNS_FILTER_TIME_NONE when unset). Every output dispatched
   * with this context gets them; a back end may change its copy before dispatching. */
  uint64_t pts, dts, duration;
};

/* Event codes for handle_event. */
typedef enum {
  NNS_FILTER_EVENT_SUSPEND = 1, /* idle for suspend= ms: may free heavy resources */
  NNS_FILTER_EVENT_RESUME = 2,
} nns_filter_event;

enum {
  NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE = 1u << 0, /* invoke sets out[i].data itself */
  NNS_FILTER_FLAG_THREAD_SAFE = 1u << 1,        /* invoke may run concurrently */
  NNS_FILTER_FLAG_RUN_WITHOUT_MODEL = 1u << 2,  /* model= is a name, not a file */
  NNS_FILTER_FLAG_DYNAMIC = 1u << 3,            /* supports invoke_dynamic */
  NNS_FILTER_FLAG_TENSOR_NAMES = 1u << 4,       /* picks tensors by inputname=/outputname= */
};

typedef struct nns_filter_backend_i {
  uint32_t api_version; /* NNS_FILTER_BACKEND_API_VERSION */
  const char *name;     /* framework name, e.g. "onnxruntime" */
  uint32_t flags;       /* NNS_FILTER_FLAG_* */
  /* Model file extensions this back end reads (".onnx"), NULL-terminated; may be NULL. */
  const char *const *extensions;

  /* Opens the model(s); *priv receives the instance. Mandatory. */
  int (*open)(const nns_filter_props *props, void **priv, char *err, size_t errlen);
  /* Releases everything open() made. Mandatory. */
  void (*close)(void *priv);

  /* Fills the model's input/output tensors when the model knows them; -ENOTSUP otherwise. */
  int (*get_model_info)(void *priv, nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                        size_t errlen);
  /* Tells the back end the input it will get; fills the output that results. -ENOTSUP if the
   * back end cannot change its input. May be NULL. */
  int (*set_input_info)(void *priv, const nns_tensors_desc *in, nns_tensors_desc *out, char *err,
                        size_t errlen);

  /* Runs the model. in[i].data/size are the negotiated input tensors. Unless
   * NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE, out[i] are caller-allocated buffers of the output
   * sizes; otherwise the back end sets out[i].data/size and the host returns them through
   * free_output. Mandatory. */
  int (*invoke)(void *priv, const GstTensorMemory *in, uint32_t num_in, GstTensorMemory *out,
                uint32_t num_out, char *err, size_t errlen);
  /* For NNS_FILTER_FLAG_ALLOCATE_IN_INVOKE back ends. May be NULL. */
  void (*free_output)(void *priv, void *data);

  /* invoke-dynamic: the input shapes may change per call; the back end fills out_info and
   * allocates out[i] (released through free_output). May be NULL. */
  int (*invoke_dynamic)(void *priv, const nns_tensors_desc *in_info, const GstTensorMemory *in,
                        nns_tensors_desc *out_info, GstTensorMemory *out, char *err, size_t errlen);

  /* Reloads the model from props->model_files; on failure the current model must stay. May be
   * NULL. tensor_filter's is-updatable does not call it: it opens the new model with open()
   * beside the old one, checks its tensors and only then swaps (see docs/elements/
   * tensor_filter.md, Reload). */
  int (*reload)(void *priv, const nns_filter_props *props, char *err, size_t errlen);
  /* Suspend/resume and future events; -ENOTSUP when unhandled. May be NULL. */
  int (*handle_event)(void *priv, nns_filter_event event, char *err, size_t errlen);
  /* Whether an accelerator ("cpu", "gpu", "npu", ...) is usable. May be NULL (cpu only). */
  int (*check_accelerator)(const char *accl);

  /* ---- Version 2 ---- */

  /* invoke-async=true: hands one input to the back end (in_info: its tensors; in[i] valid
   * during the call only). Outputs go through ctx->dispatch (copy *ctx to use it later).
   * Returns 0 when every output of this input has been dispatched (or there is none),
   * NNS_FILTER_ASYNC_PENDING when more follow, negative on error. NULL: invoke-async is not
   * supported (the element then invokes synchronously and posts a warning). */
  int (*invoke_async)(void *priv, const nns_tensors_desc *in_info, const GstTensorMemory *in,
                      uint32_t num_in, const nns_filter_async_ctx *ctx, char *err, size_t errlen);
} nns_filter_backend_i;

/* Exported by every back-end .so. */
typedef const nns_filter_backend_i *(*nns_filter_backend_entry_fn)(void);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_FILTER_BACKEND_H_ */

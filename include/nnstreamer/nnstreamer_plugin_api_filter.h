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

/* NNStreamer 2.x filter sub-plugins --------------------------------------------------------
 *
 * A sub-plugin written for NNStreamer 2.x (libnnstreamer_filter_<name>.so in the filters=
 * folders) fills a GstTensorFilterFramework and calls nnstreamer_filter_probe() from a
 * constructor. Both table layouts are accepted: version 0 (the flat v0 fields) and version 1
 * (getFrameworkInfo/getModelInfo/eventHandler). The layouts, enum values and the version word
 * are NNStreamer's; see docs/compat-nnstreamer-2x.md, "Sub-plugins". */

#define ACCL_NONE_STR "none"
#define ACCL_DEFAULT_STR "default"
#define ACCL_AUTO_STR "auto"
#define ACCL_CPU_STR "cpu"
#define ACCL_CPU_SIMD_STR "cpu.simd"
#define ACCL_CPU_NEON_STR "cpu.neon"
#define ACCL_GPU_STR "gpu"
#define ACCL_NPU_STR "npu"
#define ACCL_NPU_MOVIDIUS_STR "npu.movidius"
#define ACCL_NPU_EDGE_TPU_STR "npu.edgetpu"
#define ACCL_NPU_VIVANTE_STR "npu.vivante"
#define ACCL_NPU_SRCN_STR "npu.srcn"
#define ACCL_NPU_SLSI_STR "npu.slsi"
#define ACCL_NPU_SR_STR "npu.sr"

/* The version word: 32 bits of magic, 16 bits of table layout (0 or 1), 16 bits the
 * sub-plugin may use for itself. */
#define GST_TENSOR_FILTER_FRAMEWORK_BASE (0xDEAFDEAD00000000ULL)
#define GST_TENSOR_FILTER_FRAMEWORK_V0 (GST_TENSOR_FILTER_FRAMEWORK_BASE)
#define GST_TENSOR_FILTER_FRAMEWORK_V1 (GST_TENSOR_FILTER_FRAMEWORK_BASE | 0x10000ULL)
#define GST_TENSOR_FILTER_API_VERSION_DEFINED (1)
#define GST_TENSOR_FILTER_API_VERSION_MIN (0)
#define GST_TENSOR_FILTER_API_VERSION_MAX (1)
#define checkGstTensorFilterFrameworkVersion(value, version)           \
  ((GST_TENSOR_FILTER_FRAMEWORK_BASE | ((uint64_t)(version) << 16)) == \
   ((value)&0xFFFFFFFFFFFF0000ULL))

typedef struct _GstTensorFilterFrameworkStatistics {
  int64_t total_invoke_num;
  int64_t total_invoke_latency;   /* us */
  int64_t total_overhead_latency; /* us */
} GstTensorFilterFrameworkStatistics;

/* What a version 1 sub-plugin reports from getFrameworkInfo. */
typedef struct _GstTensorFilterFrameworkInfo {
  const char *name;
  int allow_in_place;
  int allocate_in_invoke; /* invoke allocates output[i].data itself */
  int run_without_model;  /* model= need not name a file */
  int verify_model_path;  /* the host checks that the model files exist */
  const accl_hw *hw_list; /* supported accelerators */
  int num_hw;
  accl_hw accl_auto;
  accl_hw accl_default;
  const GstTensorFilterFrameworkStatistics *statistics;
} GstTensorFilterFrameworkInfo;

typedef enum {
  DESTROY_NOTIFY,  /* free data invoke allocated */
  RELOAD_MODEL,    /* load model_files/num_models */
  CUSTOM_PROP,     /* custom_properties changed */
  SET_INPUT_PROP,  /* info/layout of the input changed */
  SET_OUTPUT_PROP, /* info/layout of the output changed */
  SET_ACCELERATOR, /* hw_list/num_hw changed */
  CHECK_HW_AVAILABILITY,
  SUSPEND,
  RESUME,
} event_ops;

typedef enum {
  GET_IN_OUT_INFO, /* fill in_info and out_info from the model */
  SET_INPUT_INFO,  /* in_info is given; fill out_info */
} model_info_ops;

typedef struct _GstTensorFilterFrameworkEventData {
  union {
    struct {
      void *data;
    };
    struct {
      const char **model_files;
      int num_models;
    };
    struct {
      const char *custom_properties;
    };
    struct {
      const GstTensorsInfo *info;
      tensors_layout layout;
    };
    struct {
      accl_hw *hw_list;
      int num_hw;
    };
    struct {
      accl_hw hw;
      const char *custom;
    };
  };
} GstTensorFilterFrameworkEventData;

typedef struct _GstTensorFilterFramework GstTensorFilterFramework;

struct _GstTensorFilterFramework {
  uint64_t version; /* GST_TENSOR_FILTER_FRAMEWORK_V0 or _V1 (low 16 bits free) */
  int (*open)(const GstTensorFilterProperties *prop, void **private_data);   /* may be NULL */
  void (*close)(const GstTensorFilterProperties *prop, void **private_data); /* may be NULL */
  union {
    struct { /* version 0 */
      char *name;
      int allow_in_place;
      int allocate_in_invoke;
      int run_without_model;
      int verify_model_path;
      const GstTensorFilterFrameworkStatistics *statistics;
      int (*invoke_NN)(const GstTensorFilterProperties *prop, void **private_data,
                       const GstTensorMemory *input, GstTensorMemory *output);
      int (*getInputDimension)(const GstTensorFilterProperties *prop, void **private_data,
                               GstTensorsInfo *info);
      int (*getOutputDimension)(const GstTensorFilterProperties *prop, void **private_data,
                                GstTensorsInfo *info);
      int (*setInputDimension)(const GstTensorFilterProperties *prop, void **private_data,
                               const GstTensorsInfo *in_info, GstTensorsInfo *out_info);
      void (*destroyNotify)(void **private_data, void *data);
      int (*reloadModel)(const GstTensorFilterProperties *prop, void **private_data);
      int (*handleEvent)(event_ops ops, GstTensorFilterFrameworkEventData *data);
      int (*checkAvailability)(accl_hw hw);
      int (*allocateInInvoke)(void **private_data);
    }
#ifdef NO_ANONYMOUS_NESTED_STRUCT
    v0
#endif
        ;
    struct { /* version 1 */
      int (*invoke)(const GstTensorFilterFramework *self, GstTensorFilterProperties *prop,
                    void *private_data, const GstTensorMemory *input, GstTensorMemory *output);
      int (*getFrameworkInfo)(const GstTensorFilterFramework *self,
                              const GstTensorFilterProperties *prop, void *private_data,
                              GstTensorFilterFrameworkInfo *fw_info);
      int (*getModelInfo)(const GstTensorFilterFramework *self,
                          const GstTensorFilterProperties *prop, void *private_data,
                          model_info_ops ops, GstTensorsInfo *in_info, GstTensorsInfo *out_info);
      int (*eventHandler)(const GstTensorFilterFramework *self,
                          const GstTensorFilterProperties *prop, void *private_data, event_ops ops,
                          GstTensorFilterFrameworkEventData *data);
      void *subplugin_data; /* the host's; sub-plugins never touch it */
    }
#ifdef NO_ANONYMOUS_NESTED_STRUCT
    v1
#endif
        ;
  };
};

/* Registers a sub-plugin (call it from the .so's constructor). TRUE (1) when registered;
 * FALSE when the table is invalid (the reason is kept for tensor_filter's error message) or
 * the name is taken. The table must stay valid and unchanged until nnstreamer_filter_exit(). */
extern int nnstreamer_filter_probe(GstTensorFilterFramework *tfsp);
/* Unregisters the sub-plugin registered as `name` (filters already open keep using it). */
extern void nnstreamer_filter_exit(const char *name);
/* The NNStreamer 2.x sub-plugin registered (or loadable from the filters= folders) as `name`,
 * or through nnstreamer.ini's [<name>] subplugin_priority / [filter-aliases]; NULL if none. */
extern const GstTensorFilterFramework *nnstreamer_filter_find(const char *name);
/* Describes the custom= keys of sub-plugin `name`: ("key", "description", ..., NULL). */
extern void nnstreamer_filter_set_custom_property_desc(const char *name, const char *prop, ...);

/* Accelerator names (the ACCL_*_STR strings above, matched exactly) and values. An unknown name
 * gives ACCL_NONE, an unknown value "none". cpu.neon is an accelerator on Arm only; its value
 * (that of cpu.simd) is named cpu.neon there and cpu.simd elsewhere. */
extern accl_hw get_accl_hw_type(const char *str);
extern const char *get_accl_hw_str(const accl_hw key);

/* The arguments of parse_accl_hw(). */
typedef struct {
  const char *in_accl;   /* accelerator= as the user gave it (may be NULL) */
  const char **sup_accl; /* NULL-terminated names the sub-plugin supports */
  const char *auto_accl; /* what "auto" means (NULL: the first supported one) */
  const char *def_accl;  /* what "default" or an unset in_accl means (NULL: the first one) */
} parse_accl_args;

/* The accelerator to use: in_accl "true[:name,...]" gives the first supported name it lists
 * (names after a '!' are skipped; none listed: auto), any other string ACCL_NONE, NULL the
 * default. ACCL_NONE when sup_accl is NULL or empty. Call it as
 * parse_accl_hw(in_accl, sup_accl[, auto_accl[, def_accl]]). */
extern accl_hw parse_accl_hw_fill(parse_accl_args accl_args);
#define parse_accl_hw(...) parse_accl_hw_fill((parse_accl_args){__VA_ARGS__})

/* A model representation shared by filters with the same shared-tensor-filter-key. `instance`
 * identifies the caller (e.g. its private data). */
/* The representation stored for `key` (the caller is added to its users), or NULL. */
extern void *nnstreamer_filter_shared_model_get(void *instance, const char *key);
/* Stores `interpreter` for `key` with `instance` as first user and returns it; NULL when the
 * key is already taken or an argument is NULL. */
extern void *nnstreamer_filter_shared_model_insert_and_get(void *instance, char *key,
                                                           void *interpreter);
/* Removes `instance` from the users of `key`; the last one out frees the representation with
 * free_callback (may be NULL). TRUE when the instance was removed. */
extern int nnstreamer_filter_shared_model_remove(void *instance, const char *key,
                                                 void (*free_callback)(void *));
/* Calls replace_callback(user, new_interpreter) for every user of `key`, then frees the old
 * representation with free_callback and stores the new one. */
extern void nnstreamer_filter_shared_model_replace(void *instance, const char *key,
                                                   void *new_interpreter,
                                                   void (*replace_callback)(void *, void *),
                                                   void (*free_callback)(void *));

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_PLUGIN_API_FILTER_H_ */

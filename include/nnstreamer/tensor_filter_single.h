/* SPDX-License-Identifier: LGPL-2.1-only */
/* NNStreamer 2.x's tensor_filter_single (tensor_filter_single.h): the GObject behind
 * NNStreamer's single-shot ML API library. It has tensor_filter's properties (framework, model,
 * input..., custom, accelerator, invoke-dynamic, ...) and runs one model without a pipeline
 * through the class functions below. Instance and class layouts are NNStreamer's. Exported by
 * libnnstreamer-single.so and libnnstreamer.so. */
#ifndef NNSTREAMER_TENSOR_FILTER_SINGLE_H_
#define NNSTREAMER_TENSOR_FILTER_SINGLE_H_

#include <glib-object.h>
#include <stdint.h>

#include "tensor_typedef.h"

G_BEGIN_DECLS

#define G_TYPE_TENSOR_FILTER_SINGLE (g_tensor_filter_single_get_type())
#define G_TENSOR_FILTER_SINGLE(obj) \
  (G_TYPE_CHECK_INSTANCE_CAST((obj), G_TYPE_TENSOR_FILTER_SINGLE, GTensorFilterSingle))
#define G_TENSOR_FILTER_SINGLE_CLASS(klass) \
  (G_TYPE_CHECK_CLASS_CAST((klass), G_TYPE_TENSOR_FILTER_SINGLE, GTensorFilterSingleClass))
#define G_IS_TENSOR_FILTER_SINGLE(obj) \
  (G_TYPE_CHECK_INSTANCE_TYPE((obj), G_TYPE_TENSOR_FILTER_SINGLE))
#define G_IS_TENSOR_FILTER_SINGLE_CLASS(klass) \
  (G_TYPE_CHECK_CLASS_TYPE((klass), G_TYPE_TENSOR_FILTER_SINGLE))
#define G_TENSOR_FILTER_SINGLE_CAST(obj) ((GTensorFilterSingle *)(obj))

typedef struct _GTensorFilterSingle GTensorFilterSingle;
typedef struct _GTensorFilterSingleClass GTensorFilterSingleClass;

struct _GTensorFilterSingle {
  GObject element;
  gpointer priv; /* private */
};

struct _GTensorFilterSingleClass {
  GObjectClass parent;
  /* Runs the model (starting it first when needed). allocate: the outputs' data are allocated
   * here (release them with destroy_notify when allocate_in_invoke, else g_free). */
  gboolean (*invoke)(GTensorFilterSingle *self, const GstTensorMemory *input,
                     GstTensorMemory *output, gboolean allocate);
  /* Opens the framework and loads the model. */
  gboolean (*start)(GTensorFilterSingle *self);
  /* Closes it. */
  gboolean (*stop)(GTensorFilterSingle *self);
  gboolean (*input_configured)(GTensorFilterSingle *self);
  gboolean (*output_configured)(GTensorFilterSingle *self);
  /* Tells the model its input; fills out_info. 0, or a negative errno. */
  gint (*set_input_info)(GTensorFilterSingle *self, const GstTensorsInfo *in_info,
                         GstTensorsInfo *out_info);
  /* Whether the framework allocates the outputs in invoke. */
  gboolean (*allocate_in_invoke)(GTensorFilterSingle *self);
  /* Releases outputs the framework allocated in invoke. */
  void (*destroy_notify)(GTensorFilterSingle *self, GstTensorMemory *mem);
  /* invoke-async=true: where the outputs go. */
  gboolean (*set_invoke_async_callback)(GTensorFilterSingle *self, GstTensorDataCallback callback,
                                        void *user_data);
};

GType g_tensor_filter_single_get_type(void);

G_END_DECLS

#endif /* NNSTREAMER_TENSOR_FILTER_SINGLE_H_ */

/* SPDX-License-Identifier: LGPL-2.1-only */
/* The parts of NNStreamer 2.x's tensor_common.h that code outside NNStreamer's elements calls:
 * a pad's tensor format, per-client aggregation adapters, splitting a buffer into its tensors,
 * and config-file parsing. Exported by libnnstreamer.so. */
#ifndef NNSTREAMER_TENSOR_COMMON_H_
#define NNSTREAMER_TENSOR_COMMON_H_

#include <glib.h>
#include <gst/base/gstadapter.h>
#include <gst/gst.h>

#include "nnstreamer_plugin_api.h"
#include "tensor_typedef.h"

G_BEGIN_DECLS

/* Sets the properties `object` has from a file of "name = value" lines (others are ignored). */
extern void gst_tensor_parse_config_file(const gchar *config_path, const GObject *object);

/* A buffer whose memories are the tensors `config` describes, sharing `in`'s data (which is
 * unreffed; a buffer already split is returned with a new reference). NULL when the sizes do not
 * match or config is invalid. */
extern GstBuffer *gst_tensor_buffer_from_config(GstBuffer *in, GstTensorsConfig *config);

/* The tensor format of the pad's current caps, _NNS_TENSOR_FORMAT_END without tensor caps. */
extern tensor_format gst_tensor_pad_get_format(GstPad *pad);
#define gst_tensor_pad_caps_is_static(p) (gst_tensor_pad_get_format(p) == _NNS_TENSOR_FORMAT_STATIC)
#define gst_tensor_pad_caps_is_flexible(p) \
  (gst_tensor_pad_get_format(p) == _NNS_TENSOR_FORMAT_FLEXIBLE)
#define gst_tensor_pad_caps_is_sparse(p) (gst_tensor_pad_get_format(p) == _NNS_TENSOR_FORMAT_SPARSE)

/* Aggregation adapters keyed by client id (0: the default one, always there). */
extern GHashTable *gst_tensor_aggregation_init(void);
extern void gst_tensor_aggregation_clear(GHashTable *table, const gint64 key);
extern void gst_tensor_aggregation_clear_all(GHashTable *table);
/* The adapter of `key`, made when missing (owned by the table). */
extern GstAdapter *gst_tensor_aggregation_get_adapter(GHashTable *table, const gint64 key);

G_END_DECLS

#endif /* NNSTREAMER_TENSOR_COMMON_H_ */

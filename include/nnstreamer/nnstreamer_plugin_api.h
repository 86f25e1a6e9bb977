/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * GStreamer-side helpers for extensions: tensor caps <-> GstTensorsConfig, tensor buffers with
 * more than 16 tensors, and flexible headers on GstMemory. Same names, signatures and results
 * as NNStreamer 2.x's nnstreamer_plugin_api.h. Exported by the plugin, libnnstreamer.so, as in
 * NNStreamer (a sub-plugin loaded by the plugin finds them there).
 */
#ifndef NNSTREAMER_CPP_PLUGIN_API_H_
#define NNSTREAMER_CPP_PLUGIN_API_H_

#include <glib.h>
#include <gst/gst.h>

#include "nnstreamer_plugin_api_util.h"
#include "nnstreamer_version.h"
#include "tensor_typedef.h"

G_BEGIN_DECLS

/* The structure is other/tensor or other/tensors. */
extern gboolean gst_structure_is_tensor_stream(const GstStructure *structure);
/* video/ -> _NNS_VIDEO, audio/ -> _NNS_AUDIO, text/ -> _NNS_TEXT, application/octet-stream ->
 * _NNS_OCTET, tensor caps -> _NNS_TENSOR, else _NNS_MEDIA_INVALID. */
extern media_type gst_structure_get_media_type(const GstStructure *structure);
/* Reads whatever the structure fixes (config is initialised first). other/tensor gives one
 * static tensor; other/tensors without a known format gives _NNS_TENSOR_FORMAT_END (static when
 * only num_tensors is present). FALSE for a structure that is not tensor caps. */
extern gboolean gst_tensors_config_from_structure(GstTensorsConfig *config,
                                                  const GstStructure *structure);
/* The first structure of caps; with `validate`, the caps must be fixed and the config valid.
 * On FALSE the config is left freed. */
extern gboolean gst_tensors_config_from_caps(GstTensorsConfig *config, const GstCaps *caps,
                                             const gboolean validate);
/* The first structure of what the peer of `pad` accepts; *is_fixed tells whether those caps are
 * fixed. */
extern gboolean gst_tensors_config_from_peer(GstPad *pad, GstTensorsConfig *config,
                                             gboolean *is_fixed);
/* other/tensor caps for a config of at most one tensor (NULL otherwise). */
extern GstCaps *gst_tensor_caps_from_config(const GstTensorsConfig *config);
/* other/tensors caps (flexible caps when the config is flexible). */
extern GstCaps *gst_tensors_caps_from_config(const GstTensorsConfig *config);
/* Makes the default GstAllocator align memory with the given GStreamer alignment mask (0:
 * back to the system allocator without extra alignment). */
extern void gst_tensor_alloc_init(gsize alignment);
/* Reads the flexible header at the start of `mem`. */
extern gboolean gst_tensor_meta_info_parse_memory(GstTensorMetaInfo *meta, GstMemory *mem);
/* New memory holding the header of `meta` followed by the bytes of `mem` (not consumed). */
extern GstMemory *gst_tensor_meta_info_append_header(GstTensorMetaInfo *meta, GstMemory *mem);
/* For every tensor structure of `caps`, takes the dimension spelling of an equal dimension in
 * `filter` (e.g. "3:4" becomes "3:4:1:1"), so the two intersect. */
extern void gst_tensor_caps_update_dimension(GstCaps *caps, GstCaps *filter);
/* Like gst_caps_can_intersect(), but tensor dimensions compare as dimensions ("3:4" meets
 * "3:4:1:1"). */
extern gboolean gst_tensor_caps_can_intersect(GstCaps *caps1, GstCaps *caps2);
/* New reference to the memory of tensor `index` (a sub-memory for tensors packed into the
 * 16th memory); NULL when there is no such tensor. */
extern GstMemory *gst_tensor_buffer_get_nth_memory(GstBuffer *buffer, const guint index);
/* Appends `memory` (always consumed) as the next tensor; from the 17th tensor on, tensors are
 * packed into the 16th memory behind NNStreamer's extra header, described by `info` (or by the
 * memory's own flexible header). */
extern gboolean gst_tensor_buffer_append_memory(GstBuffer *buffer, GstMemory *memory,
                                                const GstTensorInfo *info);
/* Number of tensors in the buffer (packed ones included). */
extern guint gst_tensor_buffer_get_count(GstBuffer *buffer);

G_END_DECLS

#endif /* NNSTREAMER_CPP_PLUGIN_API_H_ */

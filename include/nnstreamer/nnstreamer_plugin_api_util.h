/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Helpers for the plain C tensor descriptions of tensor_typedef.h, without GStreamer: the
 * functions of NNStreamer 2.x's nnstreamer_plugin_api_util.h with the same names, signatures and
 * results. Exported by libnnstreamer-single.so (and by the plugin, libnnstreamer.so).
 *
 * Memory: tensor names are heap strings owned by the struct (g_strdup/g_free). Tensors with an
 * index of 16 or more live in GstTensorsInfo.extra, one block of NNS_TENSOR_SIZE_EXTRA_LIMIT
 * entries allocated on first use by gst_tensors_info_get_nth_info(); always reach tensor `i`
 * through that function. The *_free() functions release names and `extra` and re-initialise;
 * *_copy() functions initialise the destination first (it must not hold anything to free).
 * Strings returned as gchar * are freed with g_free().
 */
#ifndef NNSTREAMER_CPP_PLUGIN_API_UTIL_H_
#define NNSTREAMER_CPP_PLUGIN_API_UTIL_H_

#include <glib.h>

#include "nnstreamer_version.h"
#include "tensor_typedef.h"

G_BEGIN_DECLS

/* "(NULL)" for a null string, for printf-style logging. */
#define _STR_NULL(str) ((str) ? (str) : "(NULL)")

/* One tensor ----------------------------------------------------------------------------- */

/* No name, type _NNS_END, every dimension 0. */
extern void gst_tensor_info_init(GstTensorInfo *info);
/* Frees the name and re-initialises. */
extern void gst_tensor_info_free(GstTensorInfo *info);
/* Bytes of the tensor: element count x element size (0 when the type or rank is missing). */
extern gsize gst_tensor_info_get_size(const GstTensorInfo *info);
/* A type other than _NNS_END and a valid dimension. */
extern gboolean gst_tensor_info_validate(const GstTensorInfo *info);
/* Both valid, same type, equal dimensions (trailing 1s do not matter); names are ignored. */
extern gboolean gst_tensor_info_is_equal(const GstTensorInfo *i1, const GstTensorInfo *i2);
/* Copies name (duplicated), type and the first n dimensions. */
extern void gst_tensor_info_copy_n(GstTensorInfo *dest, const GstTensorInfo *src, const guint n);
extern void gst_tensor_info_copy(GstTensorInfo *dest, const GstTensorInfo *src);
/* Fills a fresh flexible header for the tensor; FALSE when info is invalid. */
extern gboolean gst_tensor_info_convert_to_meta(GstTensorInfo *info, GstTensorMetaInfo *meta);
/* Number of leading non-zero dimensions. */
extern guint gst_tensor_info_get_rank(const GstTensorInfo *info);
/* "'name' uint8 (3:224:224:1)" (no name part when unnamed). */
extern gchar *gst_tensor_info_to_string(const GstTensorInfo *info);

/* A set of tensors ------------------------------------------------------------------------ */

/* Tensor `index` (0..255): info[] below 16, `extra` (allocated here when missing) above; NULL
 * past NNS_TENSOR_SIZE_LIMIT. */
extern GstTensorInfo *gst_tensors_info_get_nth_info(GstTensorsInfo *info, guint index);
/* 0 tensors, static format, every entry initialised, no extra. */
extern void gst_tensors_info_init(GstTensorsInfo *info);
extern void gst_tensors_info_free(GstTensorsInfo *info);
/* Bytes of tensor `index`, or of all tensors when index < 0; 0 when index >= num_tensors. */
gsize gst_tensors_info_get_size(const GstTensorsInfo *info, gint index);
/* Parse lists separated by ',' or '.' ("3:224:224:1,10") into the tensors in order; return the
 * number of items (at most NNS_TENSOR_SIZE_LIMIT). num_tensors is not changed. */
extern guint gst_tensors_info_parse_dimensions_string(GstTensorsInfo *info,
                                                      const gchar *dim_string);
extern guint gst_tensors_info_parse_types_string(GstTensorsInfo *info, const gchar *type_string);
/* Names are separated by ',' only; spaces around a name are dropped, empty means unnamed. */
extern guint gst_tensors_info_parse_names_string(GstTensorsInfo *info, const gchar *name_string);
/* Comma-separated lists of num_tensors items; NULL when there is no tensor. */
extern gchar *gst_tensors_info_get_dimensions_string(const GstTensorsInfo *info);
/* Dimensions cut at `rank` (0: all); with `padding`, shorter ones are filled with ":1" up to
 * `rank`. */
extern gchar *gst_tensors_info_get_rank_dimensions_string(const GstTensorsInfo *info,
                                                          const unsigned int rank,
                                                          const gboolean padding);
extern gchar *gst_tensors_info_get_types_string(const GstTensorsInfo *info);
extern gchar *gst_tensors_info_get_names_string(const GstTensorsInfo *info);
/* Known format; for static streams also >= 1 tensor, each valid. */
extern gboolean gst_tensors_info_validate(const GstTensorsInfo *info);
/* Same format; for static streams also the same count and equal tensors. */
extern gboolean gst_tensors_info_is_equal(const GstTensorsInfo *i1, const GstTensorsInfo *i2);
extern void gst_tensors_info_copy(GstTensorsInfo *dest, const GstTensorsInfo *src);
/* "Format = static, Num_Tensors = 1, Tensors = [{ uint8 (3:4) }]" */
extern gchar *gst_tensors_info_to_string(const GstTensorsInfo *info);
/* One line per index: "  0 : <left> | <right> Not equal" (the suffix only when they differ;
 * "None" for a missing tensor). */
extern gchar *gst_tensors_info_compare_to_string(const GstTensorsInfo *info1,
                                                 const GstTensorsInfo *info2);

/* Tensors plus frame rate ----------------------------------------------------------------- */

/* Empty info, rate -1/-1 (unset). */
extern void gst_tensors_config_init(GstTensorsConfig *config);
extern void gst_tensors_config_free(GstTensorsConfig *config);
/* rate_n >= 0, rate_d > 0 and valid info. */
extern gboolean gst_tensors_config_validate(const GstTensorsConfig *config);
/* Both valid, the same rate as a fraction (2/4 == 1/2) and equal info. */
extern gboolean gst_tensors_config_is_equal(const GstTensorsConfig *c1, const GstTensorsConfig *c2);
extern void gst_tensors_config_copy(GstTensorsConfig *dest, const GstTensorsConfig *src);
/* gst_tensors_info_to_string() + ", Framerate = n/d". */
extern gchar *gst_tensors_config_to_string(const GstTensorsConfig *config);

#define gst_tensors_config_is_static(c) ((c)->info.format == _NNS_TENSOR_FORMAT_STATIC)
#define gst_tensors_config_is_flexible(c) ((c)->info.format == _NNS_TENSOR_FORMAT_FLEXIBLE)
#define gst_tensors_config_is_sparse(c) ((c)->info.format == _NNS_TENSOR_FORMAT_SPARSE)

/* Dimensions ------------------------------------------------------------------------------ */

/* At least one dimension, and no non-zero value after the first 0. */
extern gboolean gst_tensor_dimension_is_valid(const tensor_dim dim);
/* Both valid and equal where one of them is > 1 (3:4 equals 3:4:1:1). */
extern gboolean gst_tensor_dimension_is_equal(const tensor_dim dim1, const tensor_dim dim2);
extern guint gst_tensor_dimension_get_rank(const tensor_dim dim);
/* Rank without trailing 1s (4:4:4:1 -> 3), at least 1 for a non-empty dimension. */
extern guint gst_tensor_dimension_get_min_rank(const tensor_dim dim);
/* "3:224:224:1" -> dim (every entry first zeroed); returns the rank read. Spaces are ignored,
 * reading stops at an empty field, each field is read as a decimal number. */
extern guint gst_tensor_parse_dimension(const gchar *dimstr, tensor_dim dim);
/* dim as "d1:d2:...", up to the first 0. */
extern gchar *gst_tensor_get_dimension_string(const tensor_dim dim);
/* Cut at `rank` (0 or > NNS_TENSOR_RANK_LIMIT: no cut); with `padding`, filled with ":1" up to
 * `rank` when the dimension is shorter. */
extern gchar *gst_tensor_get_rank_dimension_string(const tensor_dim dim, const unsigned int rank,
                                                   const gboolean padding);
/* Same number of tensors (',' or '.' separated) and equal dimensions, each of rank >= 1. */
extern gboolean gst_tensor_dimension_string_is_equal(const gchar *dimstr1, const gchar *dimstr2);
/* Product of the dimensions up to the first 0; 0 for an empty dimension. */
extern gulong gst_tensor_get_element_count(const tensor_dim dim);

/* Types and formats ----------------------------------------------------------------------- */

/* Bytes per element; 0 for _NNS_END or an unknown value. */
extern gsize gst_tensor_get_element_size(tensor_type type);
/* "uint8", "float32", ... (case and surrounding spaces ignored); _NNS_END when unknown. */
extern tensor_type gst_tensor_get_type(const gchar *typestr);
/* "uint8", ...; NULL for _NNS_END or an unknown value. */
extern const gchar *gst_tensor_get_type_string(tensor_type type);
/* "static", "flexible", "sparse" (case ignored); _NNS_TENSOR_FORMAT_END when unknown. */
extern tensor_format gst_tensor_get_format(const gchar *format_str);
extern const gchar *gst_tensor_get_format_string(tensor_format format);
/* Index of `key` in the NULL-terminated `strv` (case ignored), or -1. */
extern gint find_key_strv(const gchar **strv, const gchar *key);

/* The 128-byte header of flexible and sparse tensors -------------------------------------- */

/* Magic and version 1.0 set, type _NNS_END, static format, media type _NNS_TENSOR. */
extern void gst_tensor_meta_info_init(GstTensorMetaInfo *meta);
extern gboolean gst_tensor_meta_info_get_version(GstTensorMetaInfo *meta, guint *major,
                                                 guint *minor);
/* Magic and version, known type, valid dimension, known format, media type up to _NNS_TENSOR. */
extern gboolean gst_tensor_meta_info_validate(GstTensorMetaInfo *meta);
/* 128 for a version-1 header, 0 when meta is not a header. */
extern gsize gst_tensor_meta_info_get_header_size(GstTensorMetaInfo *meta);
/* Bytes of data after the header (sparse: nnz values plus nnz uint32 indices). */
extern gsize gst_tensor_meta_info_get_data_size(GstTensorMetaInfo *meta);
/* Writes the header (gst_tensor_meta_info_get_header_size() bytes) into `header`. */
extern gboolean gst_tensor_meta_info_update_header(GstTensorMetaInfo *meta, gpointer header);
/* Reads a header; FALSE when it is not valid. */
extern gboolean gst_tensor_meta_info_parse_header(GstTensorMetaInfo *meta, gpointer header);
/* Type and dimension of a valid header into a fresh `info`. */
gboolean gst_tensor_meta_info_convert(GstTensorMetaInfo *meta, GstTensorInfo *info);

/* Version ---------------------------------------------------------------------------------- */

/* "NNStreamer 2.7.0 (nnstreamer-cpp X.Y.Z)"; g_free() it. */
extern gchar *nnstreamer_version_string(void);
/* The NNStreamer API level of nnstreamer_version.h. */
extern void nnstreamer_version_fetch(guint *major, guint *minor, guint *micro);

G_END_DECLS

#endif /* NNSTREAMER_CPP_PLUGIN_API_UTIL_H_ */

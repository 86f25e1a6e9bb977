// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_plugin_api_util.h: GstTensorInfo / GstTensorsInfo / GstTensorsConfig helpers and
// the flexible header, with NNStreamer 2.x's results (lenient parsing: a field that is not a
// number reads as 0, reading stops at an empty field). Type sizes, names and the header
// constants come from src/core (tensor_info.h, meta_header.h).
#include <glib.h>

#include <cstring>

#include "compat/compat_export.h"
#include "core/meta_header.h"
#include "core/tensor_info.h"
#include "nnstreamer_log.h"
#include "nnstreamer_plugin_api_util.h"

#ifndef NNS_VERSION
#define NNS_VERSION "0"
#endif

namespace {

constexpr guint kRank = NNS_TENSOR_RANK_LIMIT;
constexpr const char *kBadDim =
    "invalid tensor dimension: expected d1[:d2[:...:d16]] with every dN a positive integer";

bool type_known(tensor_type t) {
  return static_cast<int>(t) >= 0 && static_cast<int>(t) < static_cast<int>(_NNS_END);
}

bool format_known(tensor_format f) {
  return static_cast<int>(f) >= 0 && static_cast<int>(f) < static_cast<int>(_NNS_TENSOR_FORMAT_END);
}

const char *type_text(tensor_type t) {
  if (!type_known(t)) return nullptr;
  // nns::type_name() returns views of string literals: NUL-terminated.
  return nns::type_name(static_cast<nns::TensorType>(t)).data();
}

const char *format_text(tensor_format f) {
  if (!format_known(f)) return nullptr;
  return nns::format_name(static_cast<nns::TensorFormat>(f)).data();
}

// Tensor i of a set the caller does not modify (the extra block may still be created, as in
// NNStreamer: that is why the API casts constness away).
GstTensorInfo *nth(const GstTensorsInfo *info, guint i) {
  return gst_tensors_info_get_nth_info(const_cast<GstTensorsInfo *>(info), i);
}

// Compares n1/d1 with n2/d2 (denominators non-zero): <0, 0, >0.
int compare_fraction(gint n1, gint d1, gint n2, gint d2) {
  gint64 a = static_cast<gint64>(n1) * d2;
  gint64 b = static_cast<gint64>(n2) * d1;
  if ((d1 < 0) != (d2 < 0)) {  // cross-multiplying by a negative flips the order
    a = -a;
    b = -b;
  }
  return a < b ? -1 : (a > b ? 1 : 0);
}

// Joins one string per tensor with ','; NULL for an empty set.
template <typename F>
gchar *join_tensors(const GstTensorsInfo *info, F &&item) {
  if (info->num_tensors == 0) return nullptr;
  GString *s = g_string_new(nullptr);
  for (guint i = 0; i < info->num_tensors; ++i) {
    if (i > 0) g_string_append_c(s, ',');
    GstTensorInfo *t = nth(info, i);
    if (t) item(s, t);
  }
  return g_string_free(s, FALSE);
}

// Splits on `seps` and applies fn(tensor, field) to at most NNS_TENSOR_SIZE_LIMIT fields.
template <typename F>
guint parse_list(GstTensorsInfo *info, const gchar *text, const gchar *seps, bool any_of, F &&fn) {
  if (!text) return 0;
  gchar **fields = any_of ? g_strsplit_set(text, seps, -1) : g_strsplit(text, seps, -1);
  guint n = g_strv_length(fields);
  if (n > NNS_TENSOR_SIZE_LIMIT) {
    ml_logw("%u items given, at most %d are read", n, NNS_TENSOR_SIZE_LIMIT);
    n = NNS_TENSOR_SIZE_LIMIT;
  }
  for (guint i = 0; i < n; ++i) fn(gst_tensors_info_get_nth_info(info, i), fields[i]);
  g_strfreev(fields);
  return n;
}

}  // namespace

// One tensor -------------------------------------------------------------------------------

NNS_COMPAT_API void gst_tensor_info_init(GstTensorInfo *info) {
  if (!info) return;
  info->name = nullptr;
  info->type = _NNS_END;
  std::memset(info->dimension, 0, sizeof info->dimension);
}

NNS_COMPAT_API void gst_tensor_info_free(GstTensorInfo *info) {
  if (!info) return;
  g_free(info->name);
  gst_tensor_info_init(info);
}

NNS_COMPAT_API gsize gst_tensor_info_get_size(const GstTensorInfo *info) {
  if (!info) return 0;
  return gst_tensor_get_element_count(info->dimension) * gst_tensor_get_element_size(info->type);
}

NNS_COMPAT_API gboolean gst_tensor_info_validate(const GstTensorInfo *info) {
  if (!info) return FALSE;
  if (info->type == _NNS_END) {
    _nnstreamer_error_write("invalid tensor info: no tensor type (e.g. type=uint8)");
    return FALSE;
  }
  return gst_tensor_dimension_is_valid(info->dimension);
}

NNS_COMPAT_API gboolean gst_tensor_info_is_equal(const GstTensorInfo *i1, const GstTensorInfo *i2) {
  if (!gst_tensor_info_validate(i1) || !gst_tensor_info_validate(i2)) return FALSE;
  return i1->type == i2->type && gst_tensor_dimension_is_equal(i1->dimension, i2->dimension);
}

NNS_COMPAT_API void gst_tensor_info_copy_n(GstTensorInfo *dest, const GstTensorInfo *src,
                                           const guint n) {
  if (!dest || !src) return;
  dest->name = g_strdup(src->name);
  dest->type = src->type;
  for (guint i = 0; i < n && i < kRank; ++i) dest->dimension[i] = src->dimension[i];
}

NNS_COMPAT_API void gst_tensor_info_copy(GstTensorInfo *dest, const GstTensorInfo *src) {
  gst_tensor_info_copy_n(dest, src, kRank);
}

NNS_COMPAT_API gboolean gst_tensor_info_convert_to_meta(GstTensorInfo *info,
                                                        GstTensorMetaInfo *meta) {
  if (!gst_tensor_info_validate(info) || !meta) return FALSE;
  gst_tensor_meta_info_init(meta);
  meta->type = info->type;
  std::memcpy(meta->dimension, info->dimension, sizeof meta->dimension);
  return TRUE;
}

NNS_COMPAT_API guint gst_tensor_info_get_rank(const GstTensorInfo *info) {
  return info ? gst_tensor_dimension_get_rank(info->dimension) : 0;
}

NNS_COMPAT_API gchar *gst_tensor_info_to_string(const GstTensorInfo *info) {
  if (!info) return nullptr;
  gchar *dim = gst_tensor_get_dimension_string(info->dimension);
  const char *type = type_text(info->type);
  gchar *out = info->name ? g_strdup_printf("'%s' %s (%s)", info->name, type ? type : "(null)", dim)
                          : g_strdup_printf("%s (%s)", type ? type : "(null)", dim);
  g_free(dim);
  return out;
}

// A set of tensors --------------------------------------------------------------------------

NNS_COMPAT_API GstTensorInfo *gst_tensors_info_get_nth_info(GstTensorsInfo *info, guint index) {
  if (!info) return nullptr;
  if (index < NNS_TENSOR_MEMORY_MAX) return &info->info[index];
  if (index >= NNS_TENSOR_SIZE_LIMIT) {
    ml_loge("tensor index %u is out of range (at most %d tensors)", index, NNS_TENSOR_SIZE_LIMIT);
    return nullptr;
  }
  if (!info->extra) {
    info->extra = g_new0(GstTensorInfo, NNS_TENSOR_SIZE_EXTRA_LIMIT);
    for (guint i = 0; i < NNS_TENSOR_SIZE_EXTRA_LIMIT; ++i) gst_tensor_info_init(&info->extra[i]);
  }
  return &info->extra[index - NNS_TENSOR_MEMORY_MAX];
}

NNS_COMPAT_API void gst_tensors_info_init(GstTensorsInfo *info) {
  if (!info) return;
  info->num_tensors = 0;
  info->extra = nullptr;
  info->format = _NNS_TENSOR_FORMAT_STATIC;
  for (auto &t : info->info) gst_tensor_info_init(&t);
}

NNS_COMPAT_API void gst_tensors_info_free(GstTensorsInfo *info) {
  if (!info) return;
  for (auto &t : info->info) gst_tensor_info_free(&t);
  if (info->extra) {
    for (guint i = 0; i < NNS_TENSOR_SIZE_EXTRA_LIMIT; ++i) gst_tensor_info_free(&info->extra[i]);
    g_free(info->extra);
  }
  gst_tensors_info_init(info);
}

NNS_COMPAT_API gsize gst_tensors_info_get_size(const GstTensorsInfo *info, gint index) {
  if (!info || index >= static_cast<gint>(info->num_tensors)) return 0;
  if (index >= 0) return gst_tensor_info_get_size(nth(info, static_cast<guint>(index)));
  gsize total = 0;
  for (guint i = 0; i < info->num_tensors; ++i) total += gst_tensor_info_get_size(nth(info, i));
  return total;
}

NNS_COMPAT_API guint gst_tensors_info_parse_dimensions_string(GstTensorsInfo *info,
                                                              const gchar *dim_string) {
  if (!info) return 0;
  return parse_list(info, dim_string, ",.", true, [](GstTensorInfo *t, const gchar *f) {
    gst_tensor_parse_dimension(f, t->dimension);
  });
}

NNS_COMPAT_API guint gst_tensors_info_parse_types_string(GstTensorsInfo *info,
                                                         const gchar *type_string) {
  if (!info) return 0;
  return parse_list(info, type_string, ",.", true,
                    [](GstTensorInfo *t, const gchar *f) { t->type = gst_tensor_get_type(f); });
}

NNS_COMPAT_API guint gst_tensors_info_parse_names_string(GstTensorsInfo *info,
                                                         const gchar *name_string) {
  if (!info) return 0;
  return parse_list(info, name_string, ",", false, [](GstTensorInfo *t, const gchar *f) {
    g_free(t->name);
    t->name = nullptr;
    gchar *name = g_strstrip(g_strdup(f));
    if (name[0] != '\0')
      t->name = name;
    else
      g_free(name);
  });
}

NNS_COMPAT_API gchar *gst_tensors_info_get_rank_dimensions_string(const GstTensorsInfo *info,
                                                                  const unsigned int rank,
                                                                  const gboolean padding) {
  if (!info) return nullptr;
  return join_tensors(info, [&](GString *s, const GstTensorInfo *t) {
    gchar *d = gst_tensor_get_rank_dimension_string(t->dimension, rank, padding);
    g_string_append(s, d);
    g_free(d);
  });
}

NNS_COMPAT_API gchar *gst_tensors_info_get_dimensions_string(const GstTensorsInfo *info) {
  return gst_tensors_info_get_rank_dimensions_string(info, kRank, FALSE);
}

NNS_COMPAT_API gchar *gst_tensors_info_get_types_string(const GstTensorsInfo *info) {
  if (!info) return nullptr;
  return join_tensors(info, [](GString *s, const GstTensorInfo *t) {
    if (const char *name = type_text(t->type)) g_string_append(s, name);
  });
}

NNS_COMPAT_API gchar *gst_tensors_info_get_names_string(const GstTensorsInfo *info) {
  if (!info) return nullptr;
  return join_tensors(info, [](GString *s, const GstTensorInfo *t) {
    if (t->name) g_string_append(s, t->name);
  });
}

NNS_COMPAT_API gboolean gst_tensors_info_validate(const GstTensorsInfo *info) {
  if (!info) return FALSE;
  if (!format_known(info->format)) {
    _nnstreamer_error_write("invalid tensors info: format %d is not one of %s",
                            static_cast<int>(info->format), GST_TENSOR_FORMAT_ALL);
    return FALSE;
  }
  if (info->format != _NNS_TENSOR_FORMAT_STATIC) return TRUE;  // nothing more is known
  if (info->num_tensors < 1) {
    _nnstreamer_error_write("invalid tensors info: %u tensors (at least 1 is needed)",
                            info->num_tensors);
    return FALSE;
  }
  for (guint i = 0; i < info->num_tensors; ++i)
    if (!gst_tensor_info_validate(nth(info, i))) return FALSE;
  return TRUE;
}

NNS_COMPAT_API gboolean gst_tensors_info_is_equal(const GstTensorsInfo *i1,
                                                  const GstTensorsInfo *i2) {
  if (!i1 || !i2) return FALSE;
  if (i1->format != i2->format || i1->format == _NNS_TENSOR_FORMAT_END) return FALSE;
  if (i1->format != _NNS_TENSOR_FORMAT_STATIC) return TRUE;
  if (!gst_tensors_info_validate(i1) || !gst_tensors_info_validate(i2)) return FALSE;
  if (i1->num_tensors != i2->num_tensors) return FALSE;
  for (guint i = 0; i < i1->num_tensors; ++i)
    if (!gst_tensor_info_is_equal(nth(i1, i), nth(i2, i))) return FALSE;
  return TRUE;
}

NNS_COMPAT_API void gst_tensors_info_copy(GstTensorsInfo *dest, const GstTensorsInfo *src) {
  if (!dest || !src) return;
  gst_tensors_info_init(dest);
  dest->num_tensors = src->num_tensors;
  dest->format = src->format;
  // Every described tensor is copied, whatever the format.
  for (guint i = 0; i < src->num_tensors && i < NNS_TENSOR_SIZE_LIMIT; ++i)
    gst_tensor_info_copy(gst_tensors_info_get_nth_info(dest, i), nth(src, i));
}

NNS_COMPAT_API gchar *gst_tensors_info_to_string(const GstTensorsInfo *info) {
  if (!info) return nullptr;
  GString *s = g_string_new(nullptr);
  const char *fmt = format_text(info->format);
  g_string_append_printf(s, "Format = %s", fmt ? fmt : "unknown");
  if (info->format == _NNS_TENSOR_FORMAT_STATIC) {
    g_string_append_printf(s, ", Num_Tensors = %u", info->num_tensors);
    guint shown = info->num_tensors;
    if (shown > NNS_TENSOR_SIZE_LIMIT) {
      shown = NNS_TENSOR_SIZE_LIMIT;
      g_string_append_printf(s, " (Num_Tensors out of bound, showing %u only.)", shown);
    }
    if (shown > 0) {
      g_string_append(s, ", Tensors = [");
      for (guint i = 0; i < shown; ++i) {
        gchar *t = gst_tensor_info_to_string(nth(info, i));
        // The separator is left out only after the tensor with the last index.
        g_string_append_printf(s, "{ %s }%s", t, i + 1 == info->num_tensors ? "" : ", ");
        g_free(t);
      }
      g_string_append_c(s, ']');
    }
  }
  return g_string_free(s, FALSE);
}

NNS_COMPAT_API gchar *gst_tensors_info_compare_to_string(const GstTensorsInfo *info1,
                                                         const GstTensorsInfo *info2) {
  if (!info1 || !info2) return nullptr;
  GString *s = g_string_new(nullptr);
  auto side = [](const GstTensorsInfo *info, guint i) {
    return i < info->num_tensors ? gst_tensor_info_to_string(nth(info, i)) : g_strdup("None");
  };
  for (guint i = 0; i < NNS_TENSOR_SIZE_LIMIT; ++i) {
    if (i >= info1->num_tensors && i >= info2->num_tensors) break;
    gchar *l = side(info1, i);
    gchar *r = side(info2, i);
    g_string_append_printf(s, "%3u : %s | %s %s\n", i, l, r,
                           std::strcmp(l, r) == 0 ? "" : "Not equal");
    g_free(l);
    g_free(r);
  }
  return g_string_free(s, FALSE);
}

// Tensors plus frame rate -----------------------------------------------------------------

NNS_COMPAT_API void gst_tensors_config_init(GstTensorsConfig *config) {
  if (!config) return;
  gst_tensors_info_init(&config->info);
  config->rate_n = -1;
  config->rate_d = -1;
}

NNS_COMPAT_API void gst_tensors_config_free(GstTensorsConfig *config) {
  if (config) gst_tensors_info_free(&config->info);
}

NNS_COMPAT_API gboolean gst_tensors_config_validate(const GstTensorsConfig *config) {
  if (!config) return FALSE;
  if (config->rate_n < 0 || config->rate_d <= 0) {
    _nnstreamer_error_write("invalid tensors config: framerate %d/%d (need n >= 0 and d > 0)",
                            config->rate_n, config->rate_d);
    return FALSE;
  }
  return gst_tensors_info_validate(&config->info);
}

NNS_COMPAT_API gboolean gst_tensors_config_is_equal(const GstTensorsConfig *c1,
                                                    const GstTensorsConfig *c2) {
  if (!gst_tensors_config_validate(c1) || !gst_tensors_config_validate(c2)) return FALSE;
  if (compare_fraction(c1->rate_n, c1->rate_d, c2->rate_n, c2->rate_d) != 0) return FALSE;
  return gst_tensors_info_is_equal(&c1->info, &c2->info);
}

NNS_COMPAT_API void gst_tensors_config_copy(GstTensorsConfig *dest, const GstTensorsConfig *src) {
  if (!dest || !src) return;
  gst_tensors_info_copy(&dest->info, &src->info);
  dest->rate_n = src->rate_n;
  dest->rate_d = src->rate_d;
}

NNS_COMPAT_API gchar *gst_tensors_config_to_string(const GstTensorsConfig *config) {
  if (!config) return nullptr;
  gchar *info = gst_tensors_info_to_string(&config->info);
  gchar *out = g_strdup_printf("%s, Framerate = %d/%d", info, config->rate_n, config->rate_d);
  g_free(info);
  return out;
}

// Dimensions ------------------------------------------------------------------------------

NNS_COMPAT_API guint gst_tensor_dimension_get_rank(const tensor_dim dim) {
  guint r = 0;
  while (r < kRank && dim[r] != 0) ++r;
  return r;
}

NNS_COMPAT_API gboolean gst_tensor_dimension_is_valid(const tensor_dim dim) {
  guint r = gst_tensor_dimension_get_rank(dim);
  bool ok = r > 0;
  for (guint i = r; ok && i < kRank; ++i) ok = dim[i] == 0;
  if (!ok) _nnstreamer_error_write("%s", kBadDim);
  return ok ? TRUE : FALSE;
}

NNS_COMPAT_API gboolean gst_tensor_dimension_is_equal(const tensor_dim dim1,
                                                      const tensor_dim dim2) {
  if (!gst_tensor_dimension_is_valid(dim1) || !gst_tensor_dimension_is_valid(dim2)) return FALSE;
  for (guint i = 0; i < kRank; ++i)  // 0 (past the rank) and 1 are the same extent
    if (dim1[i] != dim2[i] && (dim1[i] > 1 || dim2[i] > 1)) return FALSE;
  return TRUE;
}

NNS_COMPAT_API guint gst_tensor_dimension_get_min_rank(const tensor_dim dim) {
  guint r = gst_tensor_dimension_get_rank(dim);
  while (r > 1 && dim[r - 1] == 1) --r;
  return r;
}

NNS_COMPAT_API guint gst_tensor_parse_dimension(const gchar *dimstr, tensor_dim dim) {
  std::memset(dim, 0, sizeof(tensor_dim));
  if (!dimstr) return 0;
  gchar *text = g_strstrip(g_strdup(dimstr));
  // At most 16 fields; the 16th keeps any further ':' and is read up to its first non-digit.
  gchar **fields = g_strsplit(text, ":", kRank);
  guint rank = 0;
  for (guint i = 0; fields[i] != nullptr; ++i) {
    g_strstrip(fields[i]);
    if (fields[i][0] == '\0') break;
    dim[i] = static_cast<uint32_t>(g_ascii_strtoull(fields[i], nullptr, 10));
    rank = i + 1;
  }
  g_strfreev(fields);
  g_free(text);
  return rank;
}

NNS_COMPAT_API gchar *gst_tensor_get_rank_dimension_string(const tensor_dim dim,
                                                           const unsigned int rank,
                                                           const gboolean padding) {
  guint limit = (rank == 0 || rank > kRank) ? kRank : rank;
  GString *s = g_string_new(nullptr);
  guint i = 0;
  for (; i < limit && dim[i] != 0; ++i) {
    if (i > 0) g_string_append_c(s, ':');
    g_string_append_printf(s, "%u", dim[i]);
  }
  if (padding && rank > 0 && gst_tensor_dimension_get_rank(dim) < rank)
    for (; i < rank; ++i) g_string_append(s, ":1");
  return g_string_free(s, FALSE);
}

NNS_COMPAT_API gchar *gst_tensor_get_dimension_string(const tensor_dim dim) {
  return gst_tensor_get_rank_dimension_string(dim, kRank, FALSE);
}

NNS_COMPAT_API gboolean gst_tensor_dimension_string_is_equal(const gchar *dimstr1,
                                                             const gchar *dimstr2) {
  if (!dimstr1 || !dimstr2) return FALSE;
  gchar **a = g_strsplit_set(dimstr1, ",.", -1);
  gchar **b = g_strsplit_set(dimstr2, ",.", -1);
  bool equal = g_strv_length(a) == g_strv_length(b);
  for (guint i = 0; equal && a[i]; ++i) {
    tensor_dim da, db;
    guint ra = gst_tensor_parse_dimension(a[i], da);
    guint rb = gst_tensor_parse_dimension(b[i], db);
    equal = ra > 0 && rb > 0 && gst_tensor_dimension_is_equal(da, db);
  }
  g_strfreev(a);
  g_strfreev(b);
  return equal ? TRUE : FALSE;
}

NNS_COMPAT_API gulong gst_tensor_get_element_count(const tensor_dim dim) {
  guint r = gst_tensor_dimension_get_rank(dim);
  if (r == 0) return 0;
  gulong n = 1;
  for (guint i = 0; i < r; ++i) n *= dim[i];
  return n;
}

// Types and formats -------------------------------------------------------------------------

NNS_COMPAT_API gsize gst_tensor_get_element_size(tensor_type type) {
  return type_known(type) ? nns::type_size(static_cast<nns::TensorType>(type)) : 0;
}

NNS_COMPAT_API tensor_type gst_tensor_get_type(const gchar *typestr) {
  if (!typestr) return _NNS_END;
  gchar *text = g_strstrip(g_strdup(typestr));
  tensor_type found = _NNS_END;
  for (int t = 0; t < static_cast<int>(_NNS_END); ++t) {
    if (g_ascii_strcasecmp(text, type_text(static_cast<tensor_type>(t))) == 0) {
      found = static_cast<tensor_type>(t);
      break;
    }
  }
  g_free(text);
  return found;
}

NNS_COMPAT_API const gchar *gst_tensor_get_type_string(tensor_type type) {
  return type_text(type);
}

NNS_COMPAT_API gint find_key_strv(const gchar **strv, const gchar *key) {
  if (!strv) {
    // NNStreamer aborts the process here; a critical warning is enough to find the caller.
    ml_loge("find_key_strv() called with a NULL list");
    return -1;
  }
  if (!key) return -1;
  for (gint i = 0; strv[i]; ++i)
    if (g_ascii_strcasecmp(strv[i], key) == 0) return i;
  return -1;
}

NNS_COMPAT_API tensor_format gst_tensor_get_format(const gchar *format_str) {
  const gchar *names[] = {"static", "flexible", "sparse", nullptr};
  gint i = find_key_strv(names, format_str);
  return i < 0 ? _NNS_TENSOR_FORMAT_END : static_cast<tensor_format>(i);
}

NNS_COMPAT_API const gchar *gst_tensor_get_format_string(tensor_format format) {
  return format_text(format);
}

// The flexible header -------------------------------------------------------------------------

namespace {

constexpr uint32_t kVersionMark = 0xDE000000;  // high byte of every header version

bool is_header(const GstTensorMetaInfo *m) {
  return m && m->magic == nns::kMetaMagic && (m->version & kVersionMark) == kVersionMark;
}

}  // namespace

NNS_COMPAT_API void gst_tensor_meta_info_init(GstTensorMetaInfo *meta) {
  if (!meta) return;
  std::memset(meta, 0, sizeof *meta);
  meta->magic = nns::kMetaMagic;
  meta->version = nns::kMetaVersion;
  meta->type = _NNS_END;
  meta->format = _NNS_TENSOR_FORMAT_STATIC;
  meta->media_type = _NNS_TENSOR;
}

NNS_COMPAT_API gboolean gst_tensor_meta_info_get_version(GstTensorMetaInfo *meta, guint *major,
                                                         guint *minor) {
  if (!is_header(meta)) return FALSE;
  if (major) *major = (meta->version >> 12) & 0xFFF;
  if (minor) *minor = meta->version & 0xFFF;
  return TRUE;
}

NNS_COMPAT_API gboolean gst_tensor_meta_info_validate(GstTensorMetaInfo *meta) {
  if (!is_header(meta)) return FALSE;
  if (meta->type >= static_cast<uint32_t>(_NNS_END)) return FALSE;
  if (!gst_tensor_dimension_is_valid(meta->dimension)) return FALSE;
  if (meta->format >= static_cast<uint32_t>(_NNS_TENSOR_FORMAT_END)) return FALSE;
  // media_type is unsigned here: _NNS_MEDIA_INVALID and _NNS_MEDIA_ANY are rejected too.
  return meta->media_type <= static_cast<uint32_t>(_NNS_TENSOR) ? TRUE : FALSE;
}

NNS_COMPAT_API gsize gst_tensor_meta_info_get_header_size(GstTensorMetaInfo *meta) {
  if (!is_header(meta)) return 0;
  // Version 1 (major bit set) has a fixed 128-byte header.
  return (meta->version & 0x1000) ? nns::kMetaHeaderSize : 0;
}

NNS_COMPAT_API gsize gst_tensor_meta_info_get_data_size(GstTensorMetaInfo *meta) {
  if (!is_header(meta)) return 0;
  gsize esize = gst_tensor_get_element_size(static_cast<tensor_type>(meta->type));
  if (meta->format == _NNS_TENSOR_FORMAT_SPARSE)
    return meta->sparse_info.nnz * (esize + sizeof(guint));
  return esize * gst_tensor_get_element_count(meta->dimension);
}

NNS_COMPAT_API gboolean gst_tensor_meta_info_update_header(GstTensorMetaInfo *meta,
                                                           gpointer header) {
  if (!header || !gst_tensor_meta_info_validate(meta)) return FALSE;
  std::memset(header, 0, gst_tensor_meta_info_get_header_size(meta));
  std::memcpy(header, meta, sizeof *meta);
  return TRUE;
}

NNS_COMPAT_API gboolean gst_tensor_meta_info_parse_header(GstTensorMetaInfo *meta,
                                                          gpointer header) {
  if (!header || !meta) return FALSE;
  uint32_t w[22];
  std::memcpy(w, header, sizeof w);  // the header may be unaligned
  gst_tensor_meta_info_init(meta);
  meta->magic = w[0];
  meta->version = w[1];
  meta->type = w[2];
  std::memcpy(meta->dimension, &w[3], sizeof meta->dimension);
  meta->format = w[19];
  meta->media_type = w[20];
  if (meta->format == _NNS_TENSOR_FORMAT_SPARSE) meta->sparse_info.nnz = w[21];
  return gst_tensor_meta_info_validate(meta);
}

NNS_COMPAT_API gboolean gst_tensor_meta_info_convert(GstTensorMetaInfo *meta, GstTensorInfo *info) {
  if (!info || !gst_tensor_meta_info_validate(meta)) return FALSE;
  gst_tensor_info_init(info);
  info->type = static_cast<tensor_type>(meta->type);
  std::memcpy(info->dimension, meta->dimension, sizeof info->dimension);
  return TRUE;
}

// Version -----------------------------------------------------------------------------------

// Exactly NNStreamer's "NNStreamer M.m.u" (its versionControl test compares it with the numbers
// nnstreamer_version_fetch() gives); nnstreamer-cpp's own version is the plugin's (gst-inspect).
NNS_COMPAT_API gchar *nnstreamer_version_string(void) {
  return g_strdup_printf("NNStreamer %d.%d.%d", NNSTREAMER_VERSION_MAJOR, NNSTREAMER_VERSION_MINOR,
                         NNSTREAMER_VERSION_MICRO);
}

NNS_COMPAT_API void nnstreamer_version_fetch(guint *major, guint *minor, guint *micro) {
  if (major) *major = NNSTREAMER_VERSION_MAJOR;
  if (minor) *minor = NNSTREAMER_VERSION_MINOR;
  if (micro) *micro = NNSTREAMER_VERSION_MICRO;
}

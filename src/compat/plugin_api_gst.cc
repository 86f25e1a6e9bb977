// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_plugin_api.h: tensor caps <-> GstTensorsConfig with NNStreamer 2.x's results, the
// tensor buffer helpers (over src/gst/tensor_buffer.h, which already packs tensors 16.. behind
// NNStreamer's extra header) and gst_tensor_alloc_init().
#include <gst/gst.h>

#include <cstring>

#include "compat/compat_export.h"
#include "core/error.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "nnstreamer_log.h"
#include "nnstreamer_plugin_api.h"

namespace {

// Rank of the caps NNStreamer 1.x negotiated; caps for such tensors also carry the 4-rank
// spellings ("3:4:1:1" and "3:4") so 1.x-style peers intersect.
constexpr guint kLegacyRank = 4;

bool fits_legacy_rank(const GstTensorsConfig *config) {
  auto *info = const_cast<GstTensorsInfo *>(&config->info);
  if (!gst_tensors_info_validate(info)) return false;
  for (guint i = 0; i < info->num_tensors; ++i) {
    GstTensorInfo *t = gst_tensors_info_get_nth_info(info, i);
    if (!t || gst_tensor_dimension_get_min_rank(t->dimension) > kLegacyRank) return false;
  }
  return true;
}

// A comma list with at least one non-blank item.
bool has_items(const gchar *list) {
  if (!list) return false;
  for (const gchar *p = list; *p; ++p)
    if (*p != ',' && !g_ascii_isspace(*p)) return true;
  return false;
}

void set_rate(GstCaps *caps, const GstTensorsConfig *config) {
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
}

// Full-rank caps, then (for rank <= 4) the 4-rank spelling cut and padded, as in NNStreamer.
GstCaps *single_tensor_caps(const GstTensorsConfig *config) {
  auto *info = const_cast<GstTensorsInfo *>(&config->info);
  if (info->num_tensors > 1) return nullptr;
  const GstTensorInfo *t = gst_tensors_info_get_nth_info(info, 0);
  const bool legacy = fits_legacy_rank(config);
  GstCaps *out = gst_caps_new_empty();
  for (int variant = 0; variant < (legacy ? 3 : 1); ++variant) {
    GstCaps *c = gst_caps_from_string(GST_TENSOR_CAP_DEFAULT);
    if (gst_tensor_dimension_is_valid(t->dimension)) {
      gchar *d = variant == 0 ? gst_tensor_get_dimension_string(t->dimension)
                              : gst_tensor_get_rank_dimension_string(t->dimension, kLegacyRank,
                                                                     variant == 2);
      gst_caps_set_simple(c, "dimension", G_TYPE_STRING, d, nullptr);
      g_free(d);
    }
    if (t->type != _NNS_END)
      gst_caps_set_simple(c, "type", G_TYPE_STRING, gst_tensor_get_type_string(t->type), nullptr);
    set_rate(c, config);
    out = gst_caps_merge(out, c);
  }
  return out;
}

GstCaps *static_tensors_caps(const GstTensorsConfig *config) {
  const bool legacy = fits_legacy_rank(config);
  GstCaps *out = gst_caps_new_empty();
  gchar *types = nullptr;
  bool with_types = false, with_dims = false;
  gchar *dims[3] = {nullptr, nullptr, nullptr};
  if (config->info.num_tensors > 0) {
    types = gst_tensors_info_get_types_string(&config->info);
    dims[0] = gst_tensors_info_get_dimensions_string(&config->info);
    with_types = has_items(types);
    with_dims = has_items(dims[0]);
    if (legacy && with_dims) {
      dims[1] = gst_tensors_info_get_rank_dimensions_string(&config->info, kLegacyRank, FALSE);
      dims[2] = gst_tensors_info_get_rank_dimensions_string(&config->info, kLegacyRank, TRUE);
    }
  }
  for (int variant = 0; variant < (legacy ? 3 : 1); ++variant) {
    GstCaps *c = gst_caps_from_string(GST_TENSORS_CAP_DEFAULT);
    if (config->info.num_tensors > 0) {
      gst_caps_set_simple(c, "num_tensors", G_TYPE_INT, static_cast<gint>(config->info.num_tensors),
                          nullptr);
      if (with_dims) gst_caps_set_simple(c, "dimensions", G_TYPE_STRING, dims[variant], nullptr);
      if (with_types) gst_caps_set_simple(c, "types", G_TYPE_STRING, types, nullptr);
    }
    set_rate(c, config);
    out = gst_caps_merge(out, c);
  }
  g_free(types);
  for (gchar *d : dims) g_free(d);
  return out;
}

GstCaps *flexible_caps(const GstTensorsConfig *config) {
  GstCaps *c = gst_caps_from_string(GST_TENSORS_FLEX_CAP_DEFAULT);
  set_rate(c, config);
  return c;
}

bool same_dimension_field(const GstStructure *a, const GstStructure *b, const char *field) {
  return gst_tensor_dimension_string_is_equal(gst_structure_get_string(a, field),
                                              gst_structure_get_string(b, field));
}

}  // namespace

NNS_COMPAT_API gboolean gst_structure_is_tensor_stream(const GstStructure *structure) {
  if (!structure) return FALSE;
  const gchar *name = gst_structure_get_name(structure);
  return g_strcmp0(name, NNS_MIMETYPE_TENSOR) == 0 || g_strcmp0(name, NNS_MIMETYPE_TENSORS) == 0;
}

NNS_COMPAT_API media_type gst_structure_get_media_type(const GstStructure *structure) {
  if (!structure) return _NNS_MEDIA_INVALID;
  const gchar *name = gst_structure_get_name(structure);
  if (g_str_has_prefix(name, "video/")) return _NNS_VIDEO;
  if (g_str_has_prefix(name, "audio/")) return _NNS_AUDIO;
  if (g_str_has_prefix(name, "text/")) return _NNS_TEXT;
  if (g_str_equal(name, "application/octet-stream")) return _NNS_OCTET;
  if (gst_structure_is_tensor_stream(structure)) return _NNS_TENSOR;
  return _NNS_MEDIA_INVALID;
}

NNS_COMPAT_API gboolean gst_tensors_config_from_structure(GstTensorsConfig *config,
                                                          const GstStructure *structure) {
  if (!config) return FALSE;
  gst_tensors_config_init(config);
  if (!structure) return FALSE;
  const gchar *name = gst_structure_get_name(structure);
  GstTensorsInfo *info = &config->info;
  if (g_str_equal(name, NNS_MIMETYPE_TENSOR)) {
    info->num_tensors = 1;  // other/tensor: one static tensor
    if (gst_structure_has_field(structure, "dimension"))
      gst_tensor_parse_dimension(gst_structure_get_string(structure, "dimension"),
                                 info->info[0].dimension);
    if (gst_structure_has_field(structure, "type"))
      info->info[0].type = gst_tensor_get_type(gst_structure_get_string(structure, "type"));
  } else if (g_str_equal(name, NNS_MIMETYPE_TENSORS)) {
    tensor_format format = _NNS_TENSOR_FORMAT_END;
    if (gst_structure_has_field(structure, "format"))
      format = gst_tensor_get_format(gst_structure_get_string(structure, "format"));
    else if (gst_structure_has_field(structure, "num_tensors"))
      format = _NNS_TENSOR_FORMAT_STATIC;  // num_tensors alone implies a static stream
    info->format = format;
    if (format == _NNS_TENSOR_FORMAT_STATIC) {
      gint n = 0;
      if (gst_structure_get_int(structure, "num_tensors", &n)) info->num_tensors = n;
      if (gst_structure_has_field(structure, "dimensions")) {
        guint got = gst_tensors_info_parse_dimensions_string(
            info, gst_structure_get_string(structure, "dimensions"));
        if (got != info->num_tensors)
          ml_logw("caps list %u dimensions for %u tensors", got, info->num_tensors);
      }
      if (gst_structure_has_field(structure, "types")) {
        guint got =
            gst_tensors_info_parse_types_string(info, gst_structure_get_string(structure, "types"));
        if (got != info->num_tensors)
          ml_logw("caps list %u types for %u tensors", got, info->num_tensors);
      }
    }
  } else {
    ml_logw("not tensor caps: %s", name ? name : "(no name)");
    return FALSE;
  }
  if (gst_structure_has_field(structure, "framerate"))
    gst_structure_get_fraction(structure, "framerate", &config->rate_n, &config->rate_d);
  return TRUE;
}

NNS_COMPAT_API gboolean gst_tensors_config_from_caps(GstTensorsConfig *config, const GstCaps *caps,
                                                     const gboolean validate) {
  if (!config) return FALSE;
  gst_tensors_config_init(config);
  if (!caps || gst_caps_get_size(caps) == 0) return FALSE;
  if (validate && !gst_caps_is_fixed(caps)) return FALSE;
  gboolean ok = gst_tensors_config_from_structure(config, gst_caps_get_structure(caps, 0));
  if (ok && validate) ok = gst_tensors_config_validate(config);
  if (!ok) gst_tensors_config_free(config);
  return ok;
}

NNS_COMPAT_API gboolean gst_tensors_config_from_peer(GstPad *pad, GstTensorsConfig *config,
                                                     gboolean *is_fixed) {
  if (!GST_IS_PAD(pad) || !config) return FALSE;
  gst_tensors_config_init(config);
  GstCaps *peer = gst_pad_peer_query_caps(pad, nullptr);
  if (!peer) return FALSE;
  gboolean ok = FALSE;
  if (gst_caps_get_size(peer) > 0)
    ok = gst_tensors_config_from_structure(config, gst_caps_get_structure(peer, 0));
  if (ok && is_fixed) *is_fixed = gst_caps_is_fixed(peer);
  gst_caps_unref(peer);
  return ok;
}

NNS_COMPAT_API GstCaps *gst_tensor_caps_from_config(const GstTensorsConfig *config) {
  if (!config) return nullptr;
  GstCaps *caps = single_tensor_caps(config);
  return caps ? gst_caps_truncate(caps) : nullptr;
}

NNS_COMPAT_API GstCaps *gst_tensors_caps_from_config(const GstTensorsConfig *config) {
  if (!config) return nullptr;
  GstCaps *caps =
      gst_tensors_config_is_flexible(config) ? flexible_caps(config) : static_tensors_caps(config);
  return gst_caps_truncate(caps);
}

NNS_COMPAT_API void gst_tensor_caps_update_dimension(GstCaps *caps, GstCaps *filter) {
  if (!GST_IS_CAPS(caps) || !GST_IS_CAPS(filter)) return;
  for (guint i = 0; i < gst_caps_get_size(caps); ++i) {
    GstStructure *s = gst_caps_get_structure(caps, i);
    if (!gst_structure_is_tensor_stream(s)) continue;
    for (guint j = 0; j < gst_caps_get_size(filter); ++j) {
      const GstStructure *f = gst_caps_get_structure(filter, j);
      if (!gst_structure_is_tensor_stream(f)) continue;
      for (const char *field : {"dimension", "dimensions"}) {
        if (!gst_structure_has_field(s, field) || !gst_structure_has_field(f, field)) continue;
        if (same_dimension_field(s, f, field))
          gst_structure_set(s, field, G_TYPE_STRING, gst_structure_get_string(f, field), nullptr);
        break;  // other/tensor uses "dimension", other/tensors "dimensions": only one applies
      }
    }
  }
}

NNS_COMPAT_API gboolean gst_tensor_caps_can_intersect(GstCaps *caps1, GstCaps *caps2) {
  if (!caps1 || !caps2) return FALSE;
  if (gst_caps_can_intersect(caps1, caps2)) return TRUE;
  if (gst_caps_get_size(caps1) == 0 || gst_caps_get_size(caps2) == 0) return FALSE;
  const GstStructure *s1 = gst_caps_get_structure(caps1, 0);
  const GstStructure *s2 = gst_caps_get_structure(caps2, 0);
  if (!gst_structure_is_tensor_stream(s1) || !gst_structure_is_tensor_stream(s2)) return FALSE;
  if (!g_str_equal(gst_structure_get_name(s1), gst_structure_get_name(s2))) return FALSE;
  const char *field =
      g_str_equal(gst_structure_get_name(s1), NNS_MIMETYPE_TENSOR) ? "dimension" : "dimensions";
  if (gst_structure_has_field(s1, field) && gst_structure_has_field(s2, field) &&
      !same_dimension_field(s1, s2, field))
    return FALSE;
  // Dimensions agree as dimensions: compare the rest.
  GstStructure *c1 = gst_structure_copy(s1);
  GstStructure *c2 = gst_structure_copy(s2);
  gst_structure_remove_fields(c1, "dimension", "dimensions", nullptr);
  gst_structure_remove_fields(c2, "dimension", "dimensions", nullptr);
  gboolean ok = gst_structure_can_intersect(c1, c2);
  gst_structure_free(c1);
  gst_structure_free(c2);
  return ok;
}

NNS_COMPAT_API gboolean gst_tensor_meta_info_parse_memory(GstTensorMetaInfo *meta, GstMemory *mem) {
  if (!meta || !mem) return FALSE;
  gst_tensor_meta_info_init(meta);
  if (gst_memory_get_sizes(mem, nullptr, nullptr) < gst_tensor_meta_info_get_header_size(meta))
    return FALSE;
  nns::gst::MemoryMap map(mem, GST_MAP_READ);
  if (!map.ok()) return FALSE;
  return gst_tensor_meta_info_parse_header(meta, map.data());
}

NNS_COMPAT_API GstMemory *gst_tensor_meta_info_append_header(GstTensorMetaInfo *meta,
                                                             GstMemory *mem) {
  if (!mem || !gst_tensor_meta_info_validate(meta)) return nullptr;
  nns::gst::MemoryMap src(mem, GST_MAP_READ);
  if (!src.ok()) return nullptr;
  gsize head = gst_tensor_meta_info_get_header_size(meta);
  GstMemory *out = gst_allocator_alloc(nullptr, head + src.size(), nullptr);
  if (!out) return nullptr;
  {
    nns::gst::MemoryMap dst(out, GST_MAP_WRITE);
    if (!dst.ok()) {
      gst_memory_unref(out);
      return nullptr;
    }
    gst_tensor_meta_info_update_header(meta, dst.data());
    if (src.size()) std::memcpy(dst.data() + head, src.data(), src.size());
  }
  return out;
}

NNS_COMPAT_API guint gst_tensor_buffer_get_count(GstBuffer *buffer) {
  if (!GST_IS_BUFFER(buffer)) return 0;
  return static_cast<guint>(nns::gst::buffer_tensor_count(buffer));
}

NNS_COMPAT_API GstMemory *gst_tensor_buffer_get_nth_memory(GstBuffer *buffer, const guint index) {
  if (!GST_IS_BUFFER(buffer)) return nullptr;
  if (index >= gst_tensor_buffer_get_count(buffer)) {
    ml_loge("tensor %u requested from a buffer of %u tensors", index,
            gst_tensor_buffer_get_count(buffer));
    return nullptr;
  }
  return nns::gst::buffer_get_tensor(buffer, index);
}

NNS_COMPAT_API gboolean gst_tensor_buffer_append_memory(GstBuffer *buffer, GstMemory *memory,
                                                        const GstTensorInfo *info) {
  nns::gst::MemoryPtr owned(memory);  // consumed whatever happens
  if (!GST_IS_BUFFER(buffer) || !memory) return FALSE;
  // A memory with a flexible header describes itself; else `info` must.
  nns::TensorInfo t;
  GstTensorMetaInfo meta;
  const uint32_t *dims = nullptr;
  if (gst_tensor_meta_info_parse_memory(&meta, memory)) {
    t.type = static_cast<nns::TensorType>(meta.type);
    dims = meta.dimension;
  } else {
    if (!gst_tensor_info_validate(info)) {
      ml_loge("cannot append a tensor memory without a valid tensor info");
      return FALSE;
    }
    t.type = static_cast<nns::TensorType>(info->type);
    dims = info->dimension;
  }
  for (std::size_t i = 0; i < nns::kRankLimit; ++i) t.dims[i] = dims[i];
  try {
    nns::gst::buffer_append_tensor(buffer, owned.release(), t);
  } catch (const std::exception &e) {
    ml_loge("cannot append tensor memory: %s", e.what());
    return FALSE;
  }
  return TRUE;
}

// gst_tensor_alloc_init ---------------------------------------------------------------------

namespace {

constexpr const char *kAllocatorName = "GstTensorAllocator";
gsize g_alignment = 0;

// A GstAllocator that forwards to the system allocator with the configured alignment.
struct NnsAlignedAllocator {
  GstAllocator parent;
};
struct NnsAlignedAllocatorClass {
  GstAllocatorClass parent_class;
};

GstMemory *aligned_alloc(GstAllocator *, gsize size, GstAllocationParams *params) {
  GstAllocationParams p;
  if (params)
    p = *params;
  else
    gst_allocation_params_init(&p);
  p.align = g_alignment;
  GstAllocator *sys = gst_allocator_find(GST_ALLOCATOR_SYSMEM);
  GstMemory *m = gst_allocator_alloc(sys, size, &p);
  gst_object_unref(sys);
  return m;
}

void aligned_class_init(gpointer klass, gpointer) {
  GST_ALLOCATOR_CLASS(klass)->alloc = aligned_alloc;
}

GType aligned_allocator_type() {
  static GType type = [] {
    GTypeInfo info{};
    info.class_size = sizeof(NnsAlignedAllocatorClass);
    info.class_init = aligned_class_init;
    info.instance_size = sizeof(NnsAlignedAllocator);
    return g_type_register_static(GST_TYPE_ALLOCATOR, "NnsCompatTensorAllocator", &info,
                                  static_cast<GTypeFlags>(0));
  }();
  return type;
}

}  // namespace

NNS_COMPAT_API void gst_tensor_alloc_init(gsize alignment) {
  g_alignment = alignment;
  if (alignment == 0) {
    gst_allocator_set_default(gst_allocator_find(GST_ALLOCATOR_SYSMEM));
    return;
  }
  GstAllocator *a = gst_allocator_find(kAllocatorName);
  if (!a) {
    a = static_cast<GstAllocator *>(g_object_new(aligned_allocator_type(), nullptr));
    gst_object_ref_sink(a);
    gst_allocator_register(kAllocatorName, GST_ALLOCATOR(gst_object_ref(a)));
  }
  gst_allocator_set_default(a);  // takes the reference
}

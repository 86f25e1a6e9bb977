// SPDX-License-Identifier: LGPL-2.1-only
// tensor_common.h and gsttensor_sparseutil.h of NNStreamer 2.x: a pad's tensor format,
// aggregation adapters per client id, buffer_from_config, config-file parsing, and sparse
// conversions. Sizes read from memories are checked before use (NNStreamer trusts them).
#include <cstring>
#include <exception>
#include <string>
#include <vector>

#include "compat/compat_export.h"
#include "core/sparse.h"
#include "gsttensor_sparseutil.h"
#include "gst/config_file.h"
#include "nnstreamer_plugin_api_util.h"
#include "tensor_common.h"

NNS_COMPAT_API tensor_format gst_tensor_pad_get_format(GstPad *pad) {
  g_return_val_if_fail(GST_IS_PAD(pad), _NNS_TENSOR_FORMAT_END);
  tensor_format ret = _NNS_TENSOR_FORMAT_END;
  GstCaps *caps = gst_pad_get_current_caps(pad);
  if (caps) {
    GstTensorsConfig config;
    if (gst_tensors_config_from_caps(&config, caps, TRUE)) ret = config.info.format;
    gst_tensors_config_free(&config);
    gst_caps_unref(caps);
  }
  return ret;
}

// ---- aggregation -------------------------------------------------------------------------

namespace {

void free_adapter(gpointer p) {
  if (p) g_object_unref(p);
}

GstAdapter *add_adapter(GHashTable *table, gint64 key) {
  auto *k = g_new(gint64, 1);
  *k = key;
  GstAdapter *a = gst_adapter_new();
  g_hash_table_insert(table, k, a);
  return a;
}

void clear_one(gpointer, gpointer value, gpointer) {
  if (value) gst_adapter_clear(GST_ADAPTER(value));
}

}  // namespace

NNS_COMPAT_API GHashTable *gst_tensor_aggregation_init(void) {
  GHashTable *t = g_hash_table_new_full(g_int64_hash, g_int64_equal, g_free, free_adapter);
  add_adapter(t, 0);  // the default adapter, for buffers without a client id
  return t;
}

NNS_COMPAT_API void gst_tensor_aggregation_clear(GHashTable *table, const gint64 key) {
  g_return_if_fail(table != nullptr);
  g_return_if_fail(key >= 0);
  clear_one(nullptr, g_hash_table_lookup(table, &key), nullptr);
}

NNS_COMPAT_API void gst_tensor_aggregation_clear_all(GHashTable *table) {
  g_return_if_fail(table != nullptr);
  g_hash_table_foreach(table, clear_one, nullptr);
}

NNS_COMPAT_API GstAdapter *gst_tensor_aggregation_get_adapter(GHashTable *table, const gint64 key) {
  g_return_val_if_fail(table != nullptr, nullptr);
  g_return_val_if_fail(key >= 0, nullptr);
  auto *a = static_cast<GstAdapter *>(g_hash_table_lookup(table, &key));
  return a ? a : add_adapter(table, key);
}

// ---- buffer_from_config ------------------------------------------------------------------

namespace {

// NNStreamer's header before tensors 16.. in the 16th memory (GstTensorExtraInfo).
constexpr gsize kExtraHeaderSize = 24 + sizeof(GstTensorInfo) * NNS_TENSOR_SIZE_EXTRA_LIMIT;

// The memory sizes of a flexible buffer (each tensor: its header + data); false when a header
// is invalid or runs past the end.
bool flexible_sizes(GstBuffer *in, gsize total, std::vector<gsize> &sizes) {
  GstMapInfo map;
  if (!gst_buffer_map(in, &map, GST_MAP_READ)) return false;
  bool ok = true;
  gsize offset = 0;
  while (offset < total) {
    if (sizes.size() + 1 >= NNS_TENSOR_MEMORY_MAX) {  // the rest: extra tensors
      sizes.push_back(total - offset);
      break;
    }
    GstTensorMetaInfo meta;
    gst_tensor_meta_info_init(&meta);
    if (total - offset < 128 || !gst_tensor_meta_info_parse_header(&meta, map.data + offset)) {
      ok = false;
      break;
    }
    gsize s =
        gst_tensor_meta_info_get_header_size(&meta) + gst_tensor_meta_info_get_data_size(&meta);
    if (s == 0 || s > total - offset) {
      ok = false;
      break;
    }
    sizes.push_back(s);
    offset += s;
  }
  gst_buffer_unmap(in, &map);
  return ok;
}

}  // namespace

NNS_COMPAT_API GstBuffer *gst_tensor_buffer_from_config(GstBuffer *in, GstTensorsConfig *config) {
  if (!GST_IS_BUFFER(in)) {
    g_critical("gst_tensor_buffer_from_config: the input is not a buffer");
    return nullptr;
  }
  if (!config || !gst_tensors_config_validate(config)) {
    g_critical("gst_tensor_buffer_from_config: invalid tensor configuration");
    gst_buffer_unref(in);
    return nullptr;
  }
  const guint num = gst_buffer_n_memory(in);
  const gsize total = gst_buffer_get_size(in);
  std::vector<gsize> sizes;
  if (gst_tensors_config_is_static(config)) {
    const guint n = config->info.num_tensors;
    if (num == n) return in;  // the caller's reference becomes the result's
    for (guint i = 0; i < n && i < NNS_TENSOR_MEMORY_MAX; ++i)
      sizes.push_back(gst_tensors_info_get_size(&config->info, static_cast<gint>(i)));
    if (n > NNS_TENSOR_MEMORY_MAX) {
      sizes.back() += kExtraHeaderSize;
      for (guint i = NNS_TENSOR_MEMORY_MAX; i < n; ++i)
        sizes.back() += gst_tensors_info_get_size(&config->info, static_cast<gint>(i));
    }
  } else {
    if (num > 1) return in;  // already one memory per tensor
    if (!flexible_sizes(in, total, sizes)) {
      g_critical("gst_tensor_buffer_from_config: a tensor header is invalid or too large");
      gst_buffer_unref(in);
      return nullptr;
    }
    if (sizes.size() <= 1) return in;
  }
  gsize sum = 0;
  for (gsize s : sizes) sum += s;
  if (sum > total) {
    g_critical("gst_tensor_buffer_from_config: the buffer has %" G_GSIZE_FORMAT
               " bytes, the tensors need %" G_GSIZE_FORMAT,
               total, sum);
    gst_buffer_unref(in);
    return nullptr;
  }
  GstBuffer *out = gst_buffer_new();
  GstMemory *all = gst_buffer_get_all_memory(in);
  gsize offset = 0;
  for (gsize s : sizes) {
    gst_buffer_append_memory(
        out, gst_memory_share(all, static_cast<gssize>(offset), static_cast<gssize>(s)));
    offset += s;
  }
  gst_buffer_copy_into(out, in, GST_BUFFER_COPY_METADATA, 0, static_cast<gsize>(-1));
  gst_memory_unref(all);
  gst_buffer_unref(in);
  return out;
}

// ---- config file -------------------------------------------------------------------------

NNS_COMPAT_API void gst_tensor_parse_config_file(const gchar *config_path, const GObject *object) {
  if (!config_path || !G_IS_OBJECT(object)) return;
  try {
    // NNStreamer ignores what it cannot apply; the problems are only logged here.
    for (const std::string &p :
         nns::gst::apply_config_file(G_OBJECT(const_cast<GObject *>(object)), config_path, {}))
      GST_DEBUG("config file %s: %s", config_path, p.c_str());
  } catch (...) {
  }
}

// ---- sparse ------------------------------------------------------------------------------

NNS_COMPAT_API GstMemory *gst_tensor_sparse_to_dense(GstTensorMetaInfo *meta, GstMemory *mem) {
  if (!meta || !mem) return nullptr;
  GstMapInfo map;
  if (!gst_memory_map(mem, &map, GST_MAP_READ)) return nullptr;
  GstMemory *dense = nullptr;
  try {
    // The core's reader validates the header, the size and every index (tensor_sparse_dec's).
    nns::MetaHeader h = nns::sparse_parse(map.data, map.size);
    const std::size_t out_size = h.info().byte_size();
    auto *out = static_cast<guint8 *>(g_malloc0(out_size ? out_size : 1));
    nns::sparse_decode(h, map.data, out);
    gst_tensor_meta_info_init(meta);
    gst_tensor_meta_info_parse_header(meta, map.data);
    meta->format = _NNS_TENSOR_FORMAT_STATIC;
    dense = gst_memory_new_wrapped(static_cast<GstMemoryFlags>(0), out, out_size, 0, out_size, out,
                                   g_free);
  } catch (const std::exception &e) {
    GST_DEBUG("gst_tensor_sparse_to_dense: %s", e.what());
  }
  gst_memory_unmap(mem, &map);
  return dense;
}

NNS_COMPAT_API GstMemory *gst_tensor_sparse_from_dense(GstTensorMetaInfo *meta, GstMemory *mem) {
  if (!meta || !mem) return nullptr;
  const gsize es = gst_tensor_get_element_size(static_cast<tensor_type>(meta->type));
  const gulong count = gst_tensor_get_element_count(meta->dimension);
  if (!es || !count) return nullptr;
  GstMapInfo map;
  if (!gst_memory_map(mem, &map, GST_MAP_READ)) return nullptr;
  GstMemory *sparse = nullptr;
  if (map.size >= es * count) {
    std::vector<guint8> values;
    std::vector<guint32> indices;
    static const guint8 zero[8] = {};
    for (gulong i = 0; i < count; ++i) {
      const guint8 *e = map.data + i * es;
      bool nonzero;
      if (meta->type == _NNS_FLOAT32) {
        float f;
        std::memcpy(&f, e, 4);
        nonzero = f != 0.0f;
      } else if (meta->type == _NNS_FLOAT64) {
        double d;
        std::memcpy(&d, e, 8);
        nonzero = d != 0.0;
      } else {
        nonzero = std::memcmp(e, zero, es) != 0;
      }
      if (!nonzero) continue;
      values.insert(values.end(), e, e + es);
      indices.push_back(static_cast<guint32>(i));
    }
    meta->format = _NNS_TENSOR_FORMAT_SPARSE;
    meta->sparse_info.nnz = static_cast<guint>(indices.size());
    const gsize hs = gst_tensor_meta_info_get_header_size(meta);
    const gsize out_size = hs + values.size() + indices.size() * sizeof(guint32);
    auto *out = static_cast<guint8 *>(g_malloc0(out_size));
    gst_tensor_meta_info_update_header(meta, out);
    if (!values.empty()) std::memcpy(out + hs, values.data(), values.size());
    if (!indices.empty())
      std::memcpy(out + hs + values.size(), indices.data(), indices.size() * sizeof(guint32));
    sparse = gst_memory_new_wrapped(static_cast<GstMemoryFlags>(0), out, out_size, 0, out_size, out,
                                    g_free);
  }
  gst_memory_unmap(mem, &map);
  return sparse;
}

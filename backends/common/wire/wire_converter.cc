// SPDX-License-Identifier: LGPL-2.1-only
// tensor_converter sub-plugin for one wire format (built three times: protobuf, flatbuf,
// flexbuf, selected by NNS_WIRE_FORMAT). Accepts other/protobuf-tensor, other/flatbuf-tensor
// or other/flexbuf and outputs the tensors they carry; flatbuf/flexbuf tensors share the input
// memory (zero-copy), protobuf tensors share the parsed message.
//
//   gst-launch-1.0 filesrc location=t.pb ! other/protobuf-tensor,framerate=0/1 !
//       tensor_converter ! tensor_sink
#include <gst/gst.h>

#include <cstdint>
#include <cstring>
#include <string>

#include "nnstreamer_plugin_api_converter.h"
#include "wire.h"

GST_DEBUG_CATEGORY_STATIC(wire_conv_debug);
#define GST_CAT_DEFAULT wire_conv_debug

namespace {

using nns::wire::Format;

constexpr Format kFormat = Format::NNS_WIRE_FORMAT;

void ensure_debug() {
  static gsize once = 0;
  if (g_once_init_enter(&once)) {
    GST_DEBUG_CATEGORY_INIT(wire_conv_debug, "nns_converter_wire", 0, "wire converters");
    g_once_init_leave(&once, 1);
  }
}

GstTensorInfo *info_at(GstTensorsInfo *info, unsigned i) {
  if (i < NNS_TENSOR_MEMORY_MAX) return &info->info[i];
  if (!info->extra) info->extra = g_new0(GstTensorInfo, NNS_TENSOR_SIZE_EXTRA_LIMIT);
  return &info->extra[i - NNS_TENSOR_MEMORY_MAX];
}

void fill_config(const nns::wire::Frame &f, GstTensorsConfig *config) {
  config->info.num_tensors = static_cast<unsigned>(f.tensors.size());
  config->info.format = static_cast<tensor_format>(f.format);
  config->rate_n = f.rate_d > 0 && f.rate_n >= 0 ? f.rate_n : -1;
  config->rate_d = f.rate_d > 0 && f.rate_n >= 0 ? f.rate_d : 1;
  for (unsigned i = 0; i < f.tensors.size(); ++i) {
    const nns::wire::Tensor &t = f.tensors[i];
    GstTensorInfo *ti = info_at(&config->info, i);
    g_free(ti->name);
    ti->name = t.name.empty() ? nullptr : g_strdup(t.name.c_str());
    ti->type = static_cast<tensor_type>(t.type);
    std::memcpy(ti->dimension, t.dims.data(), sizeof(ti->dimension));
  }
}

struct Owner {
  std::shared_ptr<const void> keep;
};

// Why convert() last returned NULL on this thread; tensor_converter reads it through
// nns_converter_subplugin_last_error() right after the failing call and puts it in its bus error.
thread_local std::string last_error;

// The bytes to parse as one readable memory: the input's own memory when it is a single one
// (zero-copy), else (several memories, or a misaligned one for the flatbuffers formats, whose
// accessors need 8-byte alignment) an aligned copy.
GstMemory *source_memory(GstBuffer *in) {
  if (gst_buffer_n_memory(in) == 1) {
    GstMemory *m = gst_buffer_peek_memory(in, 0);
    GstMapInfo map;
    if (!gst_memory_map(m, &map, GST_MAP_READ)) return nullptr;
    const bool aligned = reinterpret_cast<std::uintptr_t>(map.data) % 8 == 0;
    gst_memory_unmap(m, &map);
    if (aligned || kFormat == Format::kProtobuf) return gst_memory_ref(m);
  }
  const gsize size = gst_buffer_get_size(in);
  GstAllocationParams params;
  gst_allocation_params_init(&params);
  params.align = 7;
  GstMemory *m = gst_allocator_alloc(nullptr, size, &params);
  GstMapInfo w;
  if (!m || !gst_memory_map(m, &w, GST_MAP_WRITE)) {
    if (m) gst_memory_unref(m);
    return nullptr;
  }
  gst_buffer_extract(in, 0, w.data, size);
  gst_memory_unmap(m, &w);
  return m;
}

GstBuffer *convert(GstBuffer *in, GstTensorsConfig *config, void *) {
  ensure_debug();
  last_error.clear();
  if (!in || !config) {
    last_error = "no input buffer or config";
    return nullptr;
  }
  GstMemory *mem = source_memory(in);
  GstMapInfo map;
  if (!mem || !gst_memory_map(mem, &map, GST_MAP_READ)) {
    if (mem) gst_memory_unref(mem);
    last_error = "cannot map the input buffer";
    return nullptr;
  }
  GstBuffer *out = nullptr;
  try {
    nns::wire::Frame f = nns::wire::decode(kFormat, map.data, map.size);
    fill_config(f, config);
    out = gst_buffer_new();
    for (const nns::wire::Tensor &t : f.tensors) {
      GstMemory *m;
      if (f.owner) {  // protobuf: the message owns the bytes
        auto *o = new Owner{f.owner};
        m = gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, const_cast<uint8_t *>(t.data), t.size,
                                   0, t.size, o,
                                   [](gpointer p) { delete static_cast<Owner *>(p); });
      } else {
        m = gst_memory_share(mem, static_cast<gssize>(t.data - map.data),
                             static_cast<gssize>(t.size));
      }
      gst_buffer_append_memory(out, m);
    }
    gst_buffer_copy_into(out, in, GST_BUFFER_COPY_METADATA, 0, -1);
  } catch (const std::exception &e) {
    last_error = e.what();
    GST_WARNING("tensor_converter::%s: %s", nns::wire::format_name(kFormat), e.what());
    if (out) gst_buffer_unref(out);
    out = nullptr;
  }
  gst_memory_unmap(mem, &map);
  gst_memory_unref(mem);
  return out;
}

gboolean get_out_config(const GstCaps *caps, GstTensorsConfig *config) {
  if (!caps || !config || gst_caps_get_size(caps) < 1) return FALSE;
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  if (!gst_structure_has_name(s, nns::wire::media_type(kFormat))) return FALSE;
  // The tensors are only known from the data: no tensor described here, rate from the caps.
  config->info.num_tensors = 0;
  config->info.format = _NNS_TENSOR_FORMAT_STATIC;
  int n = -1, d = 1;
  if (!gst_structure_get_fraction(s, "framerate", &n, &d)) n = -1, d = 1;
  config->rate_n = n;
  config->rate_d = d;
  return TRUE;
}

GstCaps *query_caps(const GstTensorsConfig *) {
  return gst_caps_new_empty_simple(nns::wire::media_type(kFormat));
}

NNStreamerExternalConverter table = {
    NNS_WIRE_NAME, convert, get_out_config, query_caps, nullptr, nullptr,
};

}  // namespace

extern "C" __attribute__((visibility("default"))) const NNStreamerExternalConverter *
nns_converter_subplugin_entry(void) {
  return &table;
}

extern "C" __attribute__((visibility("default"))) const char *nns_converter_subplugin_last_error(
    void) {
  return last_error.c_str();
}

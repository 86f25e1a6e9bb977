// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=direct_video: one tensor [C:W:H:1] -> video/x-raw.
// option1: output format (GRAY8, GRAY16_LE, GRAY16_BE for C=1; RGB/BGR for C=3;
// RGBA/BGRA/ARGB/ABGR/RGBx/BGRx/xRGB/xBGR for C=4). Defaults by channel count: 1/3/4 ->
// GRAY8/RGB/BGRx; an unknown option1, or one that does not fit the channel count, falls back to
// that default with a warning (as upstream). The element size of the tensor type must match the
// format: 1 byte (uint8 expected) for all formats but GRAY16_*, 2 bytes (uint16 expected) there;
// the bytes are copied as they are. Rows are padded to 4 bytes (GStreamer's default stride).
#include <gst/gst.h>

#include <cstring>
#include <string>

#include "../common/decoder_common.h"
#include "nnstreamer_plugin_api_decoder.h"

namespace {

struct DirectVideo {
  nns::dec::DecoderErrorSlot err;
  std::string format;  // empty: default by channels
};

GST_DEBUG_CATEGORY_STATIC(dv_debug);
#define GST_CAT_DEFAULT dv_debug

void ensure_debug() {
  static gsize once = 0;
  if (g_once_init_enter(&once)) {
    GST_DEBUG_CATEGORY_INIT(dv_debug, "nns_decoder_direct_video", 0, "direct_video decoder");
    g_once_init_leave(&once, 1);
  }
}

// Bytes per element a format stores.
unsigned element_bytes_of(const std::string &f) {
  return f.rfind("GRAY16", 0) == 0 ? 2 : 1;
}

int dv_init(void **pdata) {
  ensure_debug();
  *pdata = new DirectVideo();
  return TRUE;
}
void dv_exit(void **pdata) {
  delete static_cast<DirectVideo *>(*pdata);
  *pdata = nullptr;
}

unsigned channels_of(const std::string &f) {
  if (f == "GRAY8" || f == "GRAY16_LE" || f == "GRAY16_BE") return 1;
  if (f == "RGB" || f == "BGR") return 3;
  for (const char *x : {"RGBA", "BGRA", "ARGB", "ABGR", "RGBx", "BGRx", "xRGB", "xBGR"})
    if (f == x) return 4;
  return 0;
}

int dv_set_option(void **pdata, int op, const char *param) {
  auto *d = static_cast<DirectVideo *>(*pdata);
  if (op != 0) return TRUE;  // other options are ignored, as upstream
  std::string f = param ? param : "";
  if (!f.empty() && channels_of(f) == 0) {
    // Upstream keeps going with the default format of the channel count: so do we, and say so
    // (tensor_decoder posts a message set here after an accepted option as a bus warning).
    d->err.set(
        "option1 '%s' is not a supported video format (GRAY8, GRAY16_LE, GRAY16_BE, RGB, BGR, "
        "RGBA, BGRA, ARGB, ABGR, RGBx, BGRx, xRGB, xBGR); the default format of the channel "
        "count is used",
        f.c_str());
    GST_WARNING("%s", d->err.message);
    f.clear();
  }
  d->format = f;
  return TRUE;
}

const char *default_format(unsigned ch) {
  switch (ch) {
    case 1:
      return "GRAY8";
    case 3:
      return "RGB";
    case 4:
      return "BGRx";
    default:
      return nullptr;
  }
}

GstCaps *dv_get_out_caps(void **pdata, const GstTensorsConfig *config) {
  auto *d = static_cast<DirectVideo *>(*pdata);
  if (config->info.num_tensors != 1) {
    d->err.set("direct_video expects 1 tensor, got %u", config->info.num_tensors);
    return nullptr;
  }
  const GstTensorInfo &t = config->info.info[0];
  unsigned ch = t.dimension[0], w = t.dimension[1], h = t.dimension[2];
  for (unsigned i = 3; i < NNS_TENSOR_RANK_LIMIT && t.dimension[i]; ++i) {
    if (t.dimension[i] != 1) {
      d->err.set("direct_video expects dims C:W:H:1 (one frame), got dim %u = %u", i,
                 t.dimension[i]);
      return nullptr;
    }
  }
  GstCaps *caps;
  const char *fmt = d->format.empty() ? default_format(ch) : d->format.c_str();
  if (ch != 0 && !default_format(ch)) {
    d->err.set("direct_video: %u channels cannot be shown as video (channels must be 1, 3 or 4)",
               ch);
    return nullptr;
  }
  if (ch != 0 && channels_of(fmt) != ch) {
    GST_WARNING("option1 %s does not fit %u channels: %s is used", fmt, ch, default_format(ch));
    fmt = default_format(ch);
  }
  const unsigned es = nns::dec::c_element_size(t.type);
  if (ch != 0 && es != element_bytes_of(fmt)) {
    d->err.set(
        "direct_video: the input tensor's elements have %u byte(s), format %s needs %u (a uint8 "
        "tensor for 8-bit formats, uint16 for GRAY16_LE/GRAY16_BE)",
        es, fmt, element_bytes_of(fmt));
    return nullptr;
  }
  if (ch == 0) {
    caps = gst_caps_from_string("video/x-raw");
  } else {
    caps = gst_caps_new_simple("video/x-raw", "format", G_TYPE_STRING, fmt, nullptr);
  }
  GstStructure *s = gst_caps_get_structure(caps, 0);
  if (w) gst_structure_set(s, "width", G_TYPE_INT, (int)w, nullptr);
  if (h) gst_structure_set(s, "height", G_TYPE_INT, (int)h, nullptr);
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_structure_set(s, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d, nullptr);
  return caps;
}

size_t row_stride(size_t row_bytes) {
  return (row_bytes + 3) & ~size_t(3);
}

size_t dv_transform_size(void **, const GstTensorsConfig *config, GstCaps *, size_t, GstCaps *,
                         GstPadDirection direction) {
  if (direction == GST_PAD_SRC || config->info.num_tensors < 1) return 0;
  const GstTensorInfo &t = config->info.info[0];
  const size_t es = nns::dec::c_element_size(t.type);
  return row_stride(es * t.dimension[0] * t.dimension[1]) * t.dimension[2];
}

GstFlowReturn dv_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = static_cast<DirectVideo *>(*pdata);
  const GstTensorInfo &t = config->info.info[0];
  size_t ch = t.dimension[0], w = t.dimension[1], h = t.dimension[2];
  size_t row = nns::dec::c_element_size(t.type) * ch * w, stride = row_stride(row),
         size = stride * h;
  if (input[0].size < row * h) {
    d->err.set("direct_video: input tensor has %zu bytes, expected %zu", input[0].size, row * h);
    return GST_FLOW_ERROR;
  }
  if (gst_buffer_get_size(outbuf) == 0) {
    gst_buffer_append_memory(outbuf, gst_allocator_alloc(nullptr, size, nullptr));
  }
  GstMapInfo map;
  if (!gst_buffer_map(outbuf, &map, GST_MAP_WRITE)) return GST_FLOW_ERROR;
  const auto *src = static_cast<const uint8_t *>(input[0].data);
  if (stride == row) {
    std::memcpy(map.data, src, size);
  } else {
    for (size_t y = 0; y < h; ++y) {
      std::memcpy(map.data + y * stride, src + y * row, row);
      std::memset(map.data + y * stride + row, 0, stride - row);
    }
  }
  gst_buffer_unmap(outbuf, &map);
  return GST_FLOW_OK;
}

GstTensorDecoderDef kDirectVideo = {const_cast<char *>("direct_video"),
                                    dv_init,
                                    dv_exit,
                                    dv_set_option,
                                    dv_get_out_caps,
                                    dv_decode,
                                    dv_transform_size};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &kDirectVideo;
}

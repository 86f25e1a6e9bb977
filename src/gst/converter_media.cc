// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/converter_media.h"

#include <cstring>

#include "core/error.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

namespace nns::gst {
namespace {

struct VideoFormatInfo {
  GstVideoFormat format;
  uint32_t channels;
  TensorType type;
  bool planar;  // RGBP/BGRP: one plane per channel, tensor W:H:3
};

constexpr VideoFormatInfo kVideoFormats[] = {
    {GST_VIDEO_FORMAT_RGB, 3, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_BGR, 3, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_RGBx, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_BGRx, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_xRGB, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_xBGR, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_RGBA, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_BGRA, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_ARGB, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_ABGR, 4, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_GRAY8, 1, TensorType::kUInt8, false},
    {GST_VIDEO_FORMAT_GRAY16_BE, 1, TensorType::kUInt16, false},
    {GST_VIDEO_FORMAT_GRAY16_LE, 1, TensorType::kUInt16, false},
    {GST_VIDEO_FORMAT_RGBP, 3, TensorType::kUInt8, true},
    {GST_VIDEO_FORMAT_BGRP, 3, TensorType::kUInt8, true},
};

const VideoFormatInfo *video_format_info(GstVideoFormat f) {
  for (const auto &v : kVideoFormats)
    if (v.format == f) return &v;
  return nullptr;
}

TensorType audio_type(GstAudioFormat f, std::size_t *width, bool *other_endian) {
  const GstAudioFormatInfo *fi = gst_audio_format_get_info(f);
  *width = fi ? static_cast<std::size_t>(GST_AUDIO_FORMAT_INFO_WIDTH(fi) / 8) : 0;
  *other_endian = fi && *width > 1 && GST_AUDIO_FORMAT_INFO_ENDIANNESS(fi) != G_BYTE_ORDER;
  switch (f) {
    case GST_AUDIO_FORMAT_S8:
      return TensorType::kInt8;
    case GST_AUDIO_FORMAT_U8:
      return TensorType::kUInt8;
    case GST_AUDIO_FORMAT_S16LE:
    case GST_AUDIO_FORMAT_S16BE:
      return TensorType::kInt16;
    case GST_AUDIO_FORMAT_U16LE:
    case GST_AUDIO_FORMAT_U16BE:
      return TensorType::kUInt16;
    case GST_AUDIO_FORMAT_S32LE:
    case GST_AUDIO_FORMAT_S32BE:
      return TensorType::kInt32;
    case GST_AUDIO_FORMAT_U32LE:
    case GST_AUDIO_FORMAT_U32BE:
      return TensorType::kUInt32;
    case GST_AUDIO_FORMAT_F32LE:
    case GST_AUDIO_FORMAT_F32BE:
      return TensorType::kFloat32;
    case GST_AUDIO_FORMAT_F64LE:
    case GST_AUDIO_FORMAT_F64BE:
      return TensorType::kFloat64;
    default:
      return TensorType::kEnd;
  }
}

void read_rate(const GstStructure *s, TensorsConfig &c) {
  int n = 0, d = 1;
  if (gst_structure_get_fraction(s, "framerate", &n, &d)) {
    c.rate_n = n;
    c.rate_d = d;
  } else {
    c.rate_n = 0;  // unknown rate, as NNStreamer
    c.rate_d = 1;
  }
}

GValue string_list(std::initializer_list<const char *> items) {
  GValue list = G_VALUE_INIT;
  gst_value_list_init(&list, items.size());
  for (const char *s : items) {
    GValue v = G_VALUE_INIT;
    g_value_init(&v, G_TYPE_STRING);
    g_value_set_string(&v, s);
    gst_value_list_append_and_take_value(&list, &v);
  }
  return list;
}

}  // namespace

MediaKind media_kind_of(const GstStructure *s) {
  if (gst_structure_has_name(s, "video/x-raw")) return MediaKind::kVideo;
  if (gst_structure_has_name(s, "audio/x-raw")) return MediaKind::kAudio;
  if (gst_structure_has_name(s, "text/x-raw")) return MediaKind::kText;
  if (gst_structure_has_name(s, "application/octet-stream")) return MediaKind::kOctet;
  if (gst_structure_has_name(s, "other/tensors")) {
    const char *f = gst_structure_get_string(s, "format");
    if (f && std::strcmp(f, "flexible") == 0) return MediaKind::kFlexTensor;
  }
  return MediaKind::kCustom;
}

MediaType media_type_of(MediaKind k) {
  switch (k) {
    case MediaKind::kVideo:
      return MediaType::kVideo;
    case MediaKind::kAudio:
      return MediaType::kAudio;
    case MediaKind::kText:
      return MediaType::kText;
    case MediaKind::kOctet:
      return MediaType::kOctet;
    default:
      return MediaType::kTensor;
  }
}

const char *media_kind_name(MediaKind k) {
  switch (k) {
    case MediaKind::kVideo:
      return "video";
    case MediaKind::kAudio:
      return "audio";
    case MediaKind::kText:
      return "text";
    case MediaKind::kOctet:
      return "octet-stream";
    case MediaKind::kFlexTensor:
      return "flexible tensors";
    case MediaKind::kCustom:
      return "custom";
    default:
      return "none";
  }
}

bool VideoLayout::contiguous() const {
  for (guint p = 0; p < n_planes; ++p) {
    if (static_cast<gsize>(stride[p]) != row_bytes) return false;
    if (offset[p] != p * row_bytes * rows) return false;
  }
  return true;
}

MediaInfo media_from_video(const GstCaps *caps, guint frames_per_tensor) {
  GstVideoInfo vinfo;
  gst_video_info_init(&vinfo);
  if (!gst_video_info_from_caps(&vinfo, caps))
    fail(ErrorKind::kNegotiation, "cannot read video caps " + caps_to_string(caps));
  GstVideoFormat format = GST_VIDEO_INFO_FORMAT(&vinfo);
  const VideoFormatInfo *vf = video_format_info(format);
  const char *fname = gst_video_format_to_string(format);
  if (!vf)
    fail(ErrorKind::kNegotiation, std::string("caps field format='") + (fname ? fname : "?") +
                                      "' is not supported; expected one of " +
                                      NNS_CONVERTER_VIDEO_FORMATS);
  if (GST_VIDEO_INFO_INTERLACE_MODE(&vinfo) != GST_VIDEO_INTERLACE_MODE_PROGRESSIVE)
    fail(
        ErrorKind::kNegotiation,
        "caps field interlace-mode must be progressive, got " +
            std::string(gst_video_interlace_mode_to_string(GST_VIDEO_INFO_INTERLACE_MODE(&vinfo))));
  const uint32_t w = GST_VIDEO_INFO_WIDTH(&vinfo), h = GST_VIDEO_INFO_HEIGHT(&vinfo);
  MediaInfo m;
  m.kind = MediaKind::kVideo;
  TensorInfo t;
  t.type = vf->type;
  if (vf->planar)
    t.dims = make_dims({w, h, vf->channels, frames_per_tensor});
  else
    t.dims = make_dims({vf->channels, w, h, frames_per_tensor});
  m.config.info.tensors.push_back(t);
  m.config.rate_n = GST_VIDEO_INFO_FPS_N(&vinfo);
  m.config.rate_d = GST_VIDEO_INFO_FPS_D(&vinfo);
  VideoLayout &l = m.video;
  l.n_planes = vf->planar ? 3 : 1;
  l.row_bytes = static_cast<gsize>(w) * (vf->planar ? 1 : vf->channels) * type_size(vf->type);
  l.rows = h;
  for (guint p = 0; p < l.n_planes; ++p) {
    l.stride[p] = GST_VIDEO_INFO_PLANE_STRIDE(&vinfo, p);
    l.offset[p] = GST_VIDEO_INFO_PLANE_OFFSET(&vinfo, p);
  }
  l.size = GST_VIDEO_INFO_SIZE(&vinfo);
  m.frame_size = l.tensor_bytes();
  m.describe = std::string("video ") + fname + " " + std::to_string(w) + "x" + std::to_string(h);
  return m;
}

MediaInfo media_from_audio(const GstCaps *caps, guint frames_per_tensor) {
  GstAudioInfo ainfo;
  gst_audio_info_init(&ainfo);
  if (!gst_audio_info_from_caps(&ainfo, caps))
    fail(ErrorKind::kNegotiation, "cannot read audio caps " + caps_to_string(caps));
  if (GST_AUDIO_INFO_LAYOUT(&ainfo) != GST_AUDIO_LAYOUT_INTERLEAVED)
    fail(ErrorKind::kNegotiation, "caps field layout must be interleaved, got non-interleaved");
  GstAudioFormat f = GST_AUDIO_INFO_FORMAT(&ainfo);
  std::size_t width = 0;
  bool swap = false;
  TensorType type = audio_type(f, &width, &swap);
  const char *fname = gst_audio_format_to_string(f);
  if (type == TensorType::kEnd)
    fail(ErrorKind::kNegotiation, std::string("caps field format='") + (fname ? fname : "?") +
                                      "' is not supported; expected one of " +
                                      NNS_CONVERTER_AUDIO_FORMATS);
  MediaInfo m;
  m.kind = MediaKind::kAudio;
  TensorInfo t;
  t.type = type;
  t.dims = make_dims({static_cast<uint32_t>(GST_AUDIO_INFO_CHANNELS(&ainfo)), frames_per_tensor});
  m.config.info.tensors.push_back(t);
  m.config.rate_n = GST_AUDIO_INFO_RATE(&ainfo);
  m.config.rate_d = 1;
  m.frame_size = GST_AUDIO_INFO_BPF(&ainfo);
  m.swap_width = swap ? width : 0;
  m.describe =
      std::string("audio ") + fname + " " + std::to_string(GST_AUDIO_INFO_CHANNELS(&ainfo)) + "ch";
  return m;
}

MediaInfo media_from_text(const GstStructure *s, uint32_t text_size, guint frames_per_tensor) {
  const char *format = gst_structure_get_string(s, "format");
  if (format && g_ascii_strcasecmp(format, "utf8") != 0)
    fail(ErrorKind::kNegotiation,
         std::string("caps field format='") + format + "' is not supported; expected utf8");
  if (text_size == 0)
    fail(ErrorKind::kSettings,
         "property input-dim is required for text/x-raw (bytes of text per frame, e.g. "
         "input-dim=30), got none");
  MediaInfo m;
  m.kind = MediaKind::kText;
  TensorInfo t;
  t.type = TensorType::kUInt8;
  t.dims = make_dims({text_size, frames_per_tensor});
  m.config.info.tensors.push_back(t);
  read_rate(s, m.config);
  m.frame_size = text_size;
  m.describe = "text of " + std::to_string(text_size) + " bytes";
  return m;
}

VideoLayout buffer_video_layout(GstBuffer *buf, const VideoLayout &caps_layout) {
  GstVideoMeta *meta = gst_buffer_get_video_meta(buf);
  if (!meta) return caps_layout;
  VideoLayout l = caps_layout;
  for (guint p = 0; p < l.n_planes && p < meta->n_planes; ++p) {
    l.stride[p] = meta->stride[p];
    l.offset[p] = meta->offset[p];
  }
  gsize end = 0;
  for (guint p = 0; p < l.n_planes; ++p)
    end = std::max(end, l.offset[p] + static_cast<gsize>(l.stride[p]) * (l.rows - 1) + l.row_bytes);
  l.size = end;
  return l;
}

GstMemory *copy_video_frame(GstBuffer *buf, const VideoLayout &l) {
  BufferMap in(buf, GST_MAP_READ);
  if (!in.ok()) fail(ErrorKind::kStream, "cannot map the input video buffer for reading");
  if (in.size() < l.size)
    fail(ErrorKind::kStream, "video buffer has " + std::to_string(in.size()) + " bytes, expected " +
                                 std::to_string(l.size));
  GstMemory *out = gst_allocator_alloc(nullptr, l.tensor_bytes(), nullptr);
  MemoryMap om(out, GST_MAP_WRITE);
  guint8 *dst = om.data();
  for (guint p = 0; p < l.n_planes; ++p) {
    const guint8 *src = in.data() + l.offset[p];
    for (guint r = 0; r < l.rows; ++r) {
      std::memcpy(dst, src, l.row_bytes);
      dst += l.row_bytes;
      src += l.stride[p];
    }
  }
  return out;
}

GstMemory *copy_swapped(GstBuffer *buf, std::size_t width) {
  BufferMap in(buf, GST_MAP_READ);
  if (!in.ok()) fail(ErrorKind::kStream, "cannot map the input audio buffer for reading");
  GstMemory *out = gst_allocator_alloc(nullptr, in.size(), nullptr);
  MemoryMap om(out, GST_MAP_WRITE);
  const guint8 *s = in.data();
  guint8 *d = om.data();
  const std::size_t n = in.size() / width;
  switch (width) {
    case 2:
      for (std::size_t i = 0; i < n; ++i) {
        guint16 v;
        std::memcpy(&v, s + 2 * i, 2);
        v = GUINT16_SWAP_LE_BE(v);
        std::memcpy(d + 2 * i, &v, 2);
      }
      break;
    case 4:
      for (std::size_t i = 0; i < n; ++i) {
        guint32 v;
        std::memcpy(&v, s + 4 * i, 4);
        v = GUINT32_SWAP_LE_BE(v);
        std::memcpy(d + 4 * i, &v, 4);
      }
      break;
    case 8:
      for (std::size_t i = 0; i < n; ++i) {
        guint64 v;
        std::memcpy(&v, s + 8 * i, 8);
        v = GUINT64_SWAP_LE_BE(v);
        std::memcpy(d + 8 * i, &v, 8);
      }
      break;
    default:
      std::memcpy(d, s, in.size());
  }
  return out;
}

GstMemory *copy_resized(GstBuffer *buf, std::size_t size) {
  GstMemory *out = gst_allocator_alloc(nullptr, size, nullptr);
  MemoryMap om(out, GST_MAP_WRITE);
  gsize got = gst_buffer_extract(buf, 0, om.data(), size);
  if (got < size) std::memset(om.data() + got, 0, size - got);
  return out;
}

GstCaps *media_caps_for_tensor(const TensorsConfig &peer, const GstCaps *templ) {
  GstCaps *caps = gst_caps_copy(templ);
  if (peer.info.format != TensorFormat::kStatic || peer.info.size() != 1) return caps;
  const TensorInfo &t = peer.info[0];
  for (guint i = 0; i < gst_caps_get_size(caps); ++i) {
    GstStructure *s = gst_caps_get_structure(caps, i);
    MediaKind k = media_kind_of(s);
    if (k == MediaKind::kVideo && t.type == TensorType::kUInt8) {
      GValue formats = G_VALUE_INIT;
      switch (t.dims[0]) {
        case 1:
          formats = string_list({"GRAY8"});
          break;
        case 3:
          formats = string_list({"RGB", "BGR"});
          break;
        case 4:
          formats = string_list({"RGBx", "BGRx", "xRGB", "xBGR", "RGBA", "BGRA", "ARGB", "ABGR"});
          break;
        default:
          break;
      }
      if (G_IS_VALUE(&formats)) gst_structure_take_value(s, "format", &formats);
      if (t.dims[1] > 0) gst_structure_set(s, "width", G_TYPE_INT, int(t.dims[1]), nullptr);
      if (t.dims[2] > 0) gst_structure_set(s, "height", G_TYPE_INT, int(t.dims[2]), nullptr);
      if (peer.rate_n >= 0 && peer.rate_d > 0)
        gst_structure_set(s, "framerate", GST_TYPE_FRACTION, peer.rate_n, peer.rate_d, nullptr);
    } else if (k == MediaKind::kVideo && t.type == TensorType::kUInt16 && t.dims[0] == 1) {
      GValue formats = string_list({"GRAY16_LE", "GRAY16_BE"});
      gst_structure_take_value(s, "format", &formats);
      if (t.dims[1] > 0) gst_structure_set(s, "width", G_TYPE_INT, int(t.dims[1]), nullptr);
      if (t.dims[2] > 0) gst_structure_set(s, "height", G_TYPE_INT, int(t.dims[2]), nullptr);
    } else if (k == MediaKind::kAudio && t.type != TensorType::kEnd &&
               t.type != TensorType::kFloat16 && t.type != TensorType::kInt64 &&
               t.type != TensorType::kUInt64) {
      static const char *kNative[] = {
          G_BYTE_ORDER == G_LITTLE_ENDIAN ? "S32LE" : "S32BE",
          G_BYTE_ORDER == G_LITTLE_ENDIAN ? "U32LE" : "U32BE",
          G_BYTE_ORDER == G_LITTLE_ENDIAN ? "S16LE" : "S16BE",
          G_BYTE_ORDER == G_LITTLE_ENDIAN ? "U16LE" : "U16BE",
          "S8",
          "U8",
          G_BYTE_ORDER == G_LITTLE_ENDIAN ? "F64LE" : "F64BE",
          G_BYTE_ORDER == G_LITTLE_ENDIAN ? "F32LE" : "F32BE",
      };
      gst_structure_set(s, "format", G_TYPE_STRING, kNative[static_cast<int>(t.type)], nullptr);
      if (t.dims[0] > 0) gst_structure_set(s, "channels", G_TYPE_INT, int(t.dims[0]), nullptr);
      if (peer.rate_n > 0) gst_structure_set(s, "rate", G_TYPE_INT, peer.rate_n, nullptr);
    }
  }
  return caps;
}

}  // namespace nns::gst

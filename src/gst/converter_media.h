// SPDX-License-Identifier: LGPL-2.1-only
// Media -> tensor mapping of tensor_converter: what tensor a video/audio/text caps gives, the
// per-frame byte layout, and the copy helpers used when data cannot be shared as is (padded
// video rows, non-native audio byte order, text shorter or longer than input-dim).
#pragma once

#include <gst/audio/audio.h>
#include <gst/gst.h>
#include <gst/video/video.h>

#include <string>

#include "core/tensor_info.h"

namespace nns::gst {

// Sink pad template pieces (NNStreamer's formats and fields).
#define NNS_CONVERTER_VIDEO_FORMATS                                                           \
  "{ RGB, BGR, RGBx, BGRx, xRGB, xBGR, RGBA, BGRA, ARGB, ABGR, GRAY8, GRAY16_BE, GRAY16_LE, " \
  "RGBP, BGRP }"
#define NNS_CONVERTER_AUDIO_FORMATS                                                         \
  "{ S8, U8, S16LE, S16BE, U16LE, U16BE, S32LE, S32BE, U32LE, U32BE, F32LE, F32BE, F64LE, " \
  "F64BE }"
#define NNS_CONVERTER_MEDIA_CAPS_STR               \
  GST_VIDEO_CAPS_MAKE(NNS_CONVERTER_VIDEO_FORMATS) \
  ", interlace-mode = (string) progressive; " GST_AUDIO_CAPS_MAKE(                   \
      NNS_CONVERTER_AUDIO_FORMATS) ", layout = (string) interleaved; "               \
                                   "text/x-raw, format = (string) utf8; "            \
                                   "application/octet-stream; "                      \
                                   "other/tensors, format = (string) flexible, "     \
                                   "framerate = (fraction) [ 0, max ]"

enum class MediaKind { kNone, kVideo, kAudio, kText, kOctet, kFlexTensor, kCustom };

// Media kind of a caps structure by its name (kCustom for anything else).
MediaKind media_kind_of(const GstStructure *s);
MediaType media_type_of(MediaKind k);  // for flexible headers
const char *media_kind_name(MediaKind k);

// Byte layout of one video frame in the input buffer.
struct VideoLayout {
  guint n_planes = 1;
  gsize row_bytes = 0;  // bytes of one row of one plane without padding
  guint rows = 0;       // rows per plane
  gint stride[GST_VIDEO_MAX_PLANES] = {};
  gsize offset[GST_VIDEO_MAX_PLANES] = {};
  gsize size = 0;  // bytes the caps say a buffer has (with padding)

  gsize tensor_bytes() const { return row_bytes * rows * n_planes; }
  // True when the planes are back to back without row padding (data can be shared).
  bool contiguous() const;
};

// What the negotiated input gives.
struct MediaInfo {
  MediaKind kind = MediaKind::kNone;
  TensorsConfig config;        // output for one tensor frame (frames dim already set)
  std::size_t frame_size = 0;  // bytes of one media frame (video/text: frame, audio: sample)
  std::string describe;        // "video RGB 224x224" for messages
  VideoLayout video;
  std::size_t swap_width = 0;  // audio: byte-swap each sample of this width (0: none)
};

// Each throws nns::Error naming the caps field and value when the caps are not usable.
MediaInfo media_from_video(const GstCaps *caps, guint frames_per_tensor);
MediaInfo media_from_audio(const GstCaps *caps, guint frames_per_tensor);
// `text_size` comes from input-dim (0: missing -> error naming input-dim).
MediaInfo media_from_text(const GstStructure *s, uint32_t text_size, guint frames_per_tensor);

// Video: the layout a buffer actually has (its GstVideoMeta, else `caps_layout`).
VideoLayout buffer_video_layout(GstBuffer *buf, const VideoLayout &caps_layout);
// Copies the frame's rows into a new memory without padding. Throws on short buffers.
GstMemory *copy_video_frame(GstBuffer *buf, const VideoLayout &layout);
// Audio: a new memory with every `width`-byte sample of `buf` byte-swapped.
GstMemory *copy_swapped(GstBuffer *buf, std::size_t width);
// Text: a new memory of exactly `size` bytes: the buffer's bytes, cut or zero-padded.
GstMemory *copy_resized(GstBuffer *buf, std::size_t size);

// Media caps that could produce `peer` (a tensor config downstream wants): video/audio
// structures of `templ` narrowed to the matching format/size/rate. Returns a new reference.
GstCaps *media_caps_for_tensor(const TensorsConfig &peer, const GstCaps *templ);

}  // namespace nns::gst

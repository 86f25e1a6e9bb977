// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=image_segment: a segmentation map -> video/x-raw,format=RGBA of the map's
// width and height, transparent where nothing was found, to be laid over the picture.
//
// option1 (mandatory) picks how the tensor is read:
//   tflite-deeplab  float32 [#classes:W:H:1] class scores (e.g. deeplabv3_257_mv_gpu.tflite,
//                   21:257:257:1). Per pixel the best class wins when its score is above 0.5,
//                   otherwise the pixel is background. #classes must be option2 + 1.
//   snpe-deeplab    [W:H:1:1] class index per pixel (float32 as upstream; integer types are
//                   accepted too). Indices above option2 stay transparent.
//   snpe-depth      float32 [1:W:H:1] depth -> opaque gray, scaled so the largest value is 255
//                   (an all-zero or all-negative map stays transparent).
// option2: number of classes besides background (default 20, PASCAL VOC).
//
// Class 0 is transparent; class c > 0 gets the PASCAL VOC palette colour (the bit-interleaving
// formula of the VOC devkit: bit i of c feeds bit 7-i/3 of R, G or B in turn), opaque.
//
//   gst-launch-1.0 filesrc location=orange.png ! pngdec ! videoconvert ! videoscale !
//     video/x-raw,format=RGB,width=257,height=257 ! tensor_converter !
//     tensor_transform mode=arithmetic option=typecast:float32,div:255.0 !
//     tensor_filter framework=armnn model=deeplabv3_257_mv_gpu.tflite !
//     tensor_decoder mode=image_segment option1=tflite-deeplab ! videoconvert ! pngenc !
//     filesink location=mask.png
#include <gst/gst.h>

#include <cerrno>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "../common/decoder_common.h"
#include "core/tensor_info.h"
#include "nnstreamer_plugin_api_decoder.h"

namespace {

std::string type_str(tensor_type t) {
  return std::string(nns::type_name(static_cast<nns::TensorType>(t)));
}
size_t type_bytes(tensor_type t) {
  return nns::type_size(static_cast<nns::TensorType>(t));
}

enum class Mode { kUnset, kTfliteDeeplab, kSnpeDeeplab, kSnpeDepth };

constexpr float kScoreThreshold = 0.5f;
constexpr unsigned kDefaultLabels = 20;
constexpr unsigned kMaxLabels = 65535;

struct ImageSegment {
  nns::dec::DecoderErrorSlot err;
  Mode mode = Mode::kUnset;
  unsigned max_labels = kDefaultLabels;
  std::vector<uint32_t> colors;  // RGBA as it lies in memory, index = class
};

// PASCAL VOC palette entry for class c, as RGBA bytes in memory order; class 0 transparent.
uint32_t voc_color(unsigned c) {
  if (c == 0) return 0;
  uint8_t rgba[4] = {0, 0, 0, 255};
  unsigned v = c;
  for (int shift = 7; shift >= 0 && v; --shift) {
    rgba[0] |= static_cast<uint8_t>(((v >> 0) & 1) << shift);
    rgba[1] |= static_cast<uint8_t>(((v >> 1) & 1) << shift);
    rgba[2] |= static_cast<uint8_t>(((v >> 2) & 1) << shift);
    v >>= 3;
  }
  uint32_t out;
  std::memcpy(&out, rgba, 4);
  return out;
}

void fill_colors(ImageSegment *d) {
  d->colors.resize(d->max_labels + 1);
  for (unsigned c = 0; c <= d->max_labels; ++c) d->colors[c] = voc_color(c);
}

int is_init(void **pdata) {
  auto *d = new ImageSegment();
  fill_colors(d);
  *pdata = d;
  return TRUE;
}

void is_exit(void **pdata) {
  delete static_cast<ImageSegment *>(*pdata);
  *pdata = nullptr;
}

int is_set_option(void **pdata, int op, const char *param) {
  auto *d = static_cast<ImageSegment *>(*pdata);
  std::string v = param ? param : "";
  if (op == 0) {
    if (v == "tflite-deeplab") {
      d->mode = Mode::kTfliteDeeplab;
    } else if (v == "snpe-deeplab") {
      d->mode = Mode::kSnpeDeeplab;
    } else if (v == "snpe-depth") {
      d->mode = Mode::kSnpeDepth;
    } else {
      d->err.set(
          "option1: unknown image_segment mode '%s'; expected tflite-deeplab, "
          "snpe-deeplab or snpe-depth",
          v.c_str());
      return FALSE;
    }
    return TRUE;
  }
  if (op == 1) {
    char *end = nullptr;
    errno = 0;
    unsigned long n = std::strtoul(v.c_str(), &end, 10);
    if (v.empty() || v[0] == '-' || *end != '\0' || errno || n == 0 || n > kMaxLabels) {
      d->err.set("option2: max labels must be an integer in 1..%u, got '%s'", kMaxLabels,
                 v.c_str());
      return FALSE;
    }
    d->max_labels = static_cast<unsigned>(n);
    fill_colors(d);
    return TRUE;
  }
  return TRUE;  // options 3..9 are not used by this mode (as upstream)
}

const char *mode_name(Mode m) {
  switch (m) {
    case Mode::kTfliteDeeplab:
      return "tflite-deeplab";
    case Mode::kSnpeDeeplab:
      return "snpe-deeplab";
    case Mode::kSnpeDepth:
      return "snpe-depth";
    default:
      return "?";
  }
}

bool is_integer_type(tensor_type t) {
  switch (t) {
    case _NNS_INT8:
    case _NNS_UINT8:
    case _NNS_INT16:
    case _NNS_UINT16:
    case _NNS_INT32:
    case _NNS_UINT32:
    case _NNS_INT64:
    case _NNS_UINT64:
      return true;
    default:
      return false;
  }
}

// Width and height of the map in tensor 0, or false (with the reason set) when the tensor does
// not fit the mode. Unknown (0) dims during negotiation give w/h 0 and true.
bool map_size(ImageSegment *d, const GstTensorInfo &t, unsigned *w, unsigned *h) {
  const uint32_t *dim = t.dimension;
  const char *m = mode_name(d->mode);
  const bool float_ok = t.type == _NNS_FLOAT32;
  if (d->mode == Mode::kSnpeDeeplab) {
    if (!float_ok && !is_integer_type(t.type) && t.type != _NNS_FLOAT64) {
      d->err.set("%s expects a class index tensor (float32 or integer), got type %s", m,
                 type_str(t.type).c_str());
      return false;
    }
  } else if (!float_ok) {
    d->err.set("%s expects a float32 tensor, got type %s", m, type_str(t.type).c_str());
    return false;
  }
  unsigned first = d->mode == Mode::kSnpeDeeplab ? 0 : 1;  // index of the width dim
  for (unsigned i = first + 2; i < NNS_TENSOR_RANK_LIMIT && dim[i]; ++i) {
    if (dim[i] != 1) {
      d->err.set("%s expects dims %s, got dim%u = %u", m,
                 d->mode == Mode::kSnpeDeeplab ? "W:H:1:1" : "C:W:H:1", i, dim[i]);
      return false;
    }
  }
  if (d->mode == Mode::kTfliteDeeplab && dim[0] && dim[0] != d->max_labels + 1) {
    d->err.set("tflite-deeplab expects dim0 = option2 + 1 = %u classes, got %u (set option2=%u)",
               d->max_labels + 1, dim[0], dim[0] > 1 ? dim[0] - 1 : 1);
    return false;
  }
  if (d->mode == Mode::kSnpeDepth && dim[0] && dim[0] != 1) {
    d->err.set("snpe-depth expects dims 1:W:H:1 (one depth channel), got dim0 = %u", dim[0]);
    return false;
  }
  *w = dim[first];
  *h = first + 1 < NNS_TENSOR_RANK_LIMIT ? dim[first + 1] : 0;
  if (*h == 0 && *w != 0) *h = 1;  // a rank-1 snpe map is one row
  return true;
}

GstCaps *is_get_out_caps(void **pdata, const GstTensorsConfig *config) {
  auto *d = static_cast<ImageSegment *>(*pdata);
  if (d->mode == Mode::kUnset) {
    d->err.set("image_segment needs option1=tflite-deeplab|snpe-deeplab|snpe-depth");
    return nullptr;
  }
  if (config->info.num_tensors < 1) {
    d->err.set("image_segment expects 1 tensor, got none");
    return nullptr;
  }
  unsigned w = 0, h = 0;
  if (!map_size(d, config->info.info[0], &w, &h)) return nullptr;
  GstCaps *caps = gst_caps_new_simple("video/x-raw", "format", G_TYPE_STRING, "RGBA", nullptr);
  if (w && h)
    gst_caps_set_simple(caps, "width", G_TYPE_INT, static_cast<int>(w), "height", G_TYPE_INT,
                        static_cast<int>(h), nullptr);
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
  return caps;
}

// tflite-deeplab: scores[(y * W + x) * C + c].
void paint_scores(const ImageSegment *d, const float *scores, size_t pixels, unsigned classes,
                  uint32_t *out) {
  for (size_t p = 0; p < pixels; ++p, scores += classes) {
    unsigned best = 0;
    float best_score = scores[0];
    for (unsigned c = 1; c < classes; ++c) {
      if (scores[c] > best_score) {
        best_score = scores[c];
        best = c;
      }
    }
    out[p] = best_score > kScoreThreshold ? d->colors[best] : 0;
  }
}

// snpe-deeplab: one class index per pixel; out-of-range (or negative) indices stay transparent.
template <typename T>
void paint_indices(const ImageSegment *d, const void *data, size_t pixels, uint32_t *out) {
  const T *v = static_cast<const T *>(data);
  for (size_t p = 0; p < pixels; ++p) {
    // Float indices truncate toward zero as a C cast does (upstream reads them that way).
    if (!(v[p] >= 0) || static_cast<double>(v[p]) >= d->max_labels + 1.0) {
      out[p] = 0;
      continue;
    }
    out[p] = d->colors[static_cast<unsigned>(v[p])];
  }
}

// snpe-depth: gray = value / max * 255 (truncated), opaque.
void paint_depth(const float *v, size_t pixels, uint32_t *out) {
  float max = 0.0f;
  for (size_t p = 0; p < pixels; ++p)
    if (v[p] > max) max = v[p];
  if (max == 0.0f) {
    std::memset(out, 0, pixels * 4);
    return;
  }
  for (size_t p = 0; p < pixels; ++p) {
    float g = v[p] > 0.0f ? v[p] / max * 255.0f : 0.0f;
    uint8_t px[4];
    px[0] = px[1] = px[2] = static_cast<uint8_t>(g > 255.0f ? 255.0f : g);
    px[3] = 255;
    std::memcpy(&out[p], px, 4);
  }
}

GstFlowReturn is_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = static_cast<ImageSegment *>(*pdata);
  const GstTensorInfo &t = config->info.info[0];
  unsigned w = 0, h = 0;
  if (!map_size(d, t, &w, &h) || !w || !h) return GST_FLOW_NOT_NEGOTIATED;
  const size_t pixels = static_cast<size_t>(w) * h;
  const size_t elems = nns::dec::c_elements(t);
  if (input[0].size < elems * type_bytes(t.type)) {
    d->err.set("tensor 0 has %zu bytes, expected %zu", input[0].size, elems * type_bytes(t.type));
    return GST_FLOW_ERROR;
  }
  GstMemory *mem = gst_allocator_alloc(nullptr, pixels * 4, nullptr);
  GstMapInfo map;
  if (!gst_memory_map(mem, &map, GST_MAP_WRITE)) {
    gst_memory_unref(mem);
    d->err.set("cannot map the output frame");
    return GST_FLOW_ERROR;
  }
  auto *out = reinterpret_cast<uint32_t *>(map.data);
  const void *in = input[0].data;
  switch (d->mode) {
    case Mode::kTfliteDeeplab:
      paint_scores(d, static_cast<const float *>(in), pixels, t.dimension[0], out);
      break;
    case Mode::kSnpeDepth:
      paint_depth(static_cast<const float *>(in), pixels, out);
      break;
    case Mode::kSnpeDeeplab:
      switch (t.type) {
        case _NNS_FLOAT32:
          paint_indices<float>(d, in, pixels, out);
          break;
        case _NNS_FLOAT64:
          paint_indices<double>(d, in, pixels, out);
          break;
        case _NNS_INT8:
          paint_indices<int8_t>(d, in, pixels, out);
          break;
        case _NNS_UINT8:
          paint_indices<uint8_t>(d, in, pixels, out);
          break;
        case _NNS_INT16:
          paint_indices<int16_t>(d, in, pixels, out);
          break;
        case _NNS_UINT16:
          paint_indices<uint16_t>(d, in, pixels, out);
          break;
        case _NNS_INT32:
          paint_indices<int32_t>(d, in, pixels, out);
          break;
        case _NNS_UINT32:
          paint_indices<uint32_t>(d, in, pixels, out);
          break;
        case _NNS_INT64:
          paint_indices<int64_t>(d, in, pixels, out);
          break;
        case _NNS_UINT64:
          paint_indices<uint64_t>(d, in, pixels, out);
          break;
        default:
          break;  // rejected by map_size
      }
      break;
    default:
      break;
  }
  gst_memory_unmap(mem, &map);
  gst_buffer_append_memory(outbuf, mem);
  return GST_FLOW_OK;
}

GstTensorDecoderDef kImageSegment = {const_cast<char *>("image_segment"),
                                     is_init,
                                     is_exit,
                                     is_set_option,
                                     is_get_out_caps,
                                     is_decode,
                                     nullptr};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &kImageSegment;
}

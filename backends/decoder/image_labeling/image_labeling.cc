// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=image_labeling: one tensor of class scores [N:1:1:1] (any numeric type)
// -> text/x-raw,format=utf8 holding the label of the highest score (first one on ties).
// option1: label file, one label per line (mandatory; must have at least N lines).
#include <gst/gst.h>

#include <cstring>
#include <fstream>
#include <string>
#include <vector>

#include "../common/decoder_common.h"
#include "nnstreamer_plugin_api_decoder.h"

namespace {

struct ImageLabeling {
  nns::dec::DecoderErrorSlot err;
  std::string path;
  std::vector<std::string> labels;
};

int il_init(void **pdata) {
  *pdata = new ImageLabeling();
  return TRUE;
}
void il_exit(void **pdata) {
  delete static_cast<ImageLabeling *>(*pdata);
  *pdata = nullptr;
}

int il_set_option(void **pdata, int op, const char *param) {
  auto *d = static_cast<ImageLabeling *>(*pdata);
  if (op != 0) return TRUE;
  std::ifstream in(param ? param : "");
  if (!param || !*param || !in) {
    d->err.set("option1: cannot read label file '%s'", param ? param : "");
    return FALSE;
  }
  d->labels.clear();
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    d->labels.push_back(line);
  }
  d->path = param;
  return TRUE;
}

GstCaps *il_get_out_caps(void **pdata, const GstTensorsConfig *config) {
  auto *d = static_cast<ImageLabeling *>(*pdata);
  if (d->path.empty()) {
    d->err.set("image_labeling needs option1=<label file>");
    return nullptr;
  }
  if (config->info.num_tensors != 1) {
    d->err.set("image_labeling expects 1 tensor of class scores, got %u", config->info.num_tensors);
    return nullptr;
  }
  const GstTensorInfo &t = config->info.info[0];
  for (unsigned i = 1; i < NNS_TENSOR_RANK_LIMIT && t.dimension[i]; ++i) {
    if (t.dimension[i] != 1) {
      d->err.set("image_labeling expects dims N:1:1:1 (class scores), got dim %u = %u", i,
                 t.dimension[i]);
      return nullptr;
    }
  }
  if (t.dimension[0] && t.dimension[0] > d->labels.size()) {
    d->err.set("image_labeling: label file '%s' has %zu labels, the tensor has %u classes",
               d->path.c_str(), d->labels.size(), t.dimension[0]);
    return nullptr;
  }
  GstCaps *caps = gst_caps_new_simple("text/x-raw", "format", G_TYPE_STRING, "utf8", nullptr);
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
  return caps;
}

template <typename T>
size_t argmax(const void *data, size_t n) {
  const T *v = static_cast<const T *>(data);
  size_t best = 0;
  for (size_t i = 1; i < n; ++i)
    if (v[i] > v[best]) best = i;
  return best;
}

GstFlowReturn il_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = static_cast<ImageLabeling *>(*pdata);
  const GstTensorInfo &t = config->info.info[0];
  size_t n = t.dimension[0];
  size_t idx;
  switch (t.type) {
    case _NNS_INT8:
      idx = argmax<int8_t>(input[0].data, n);
      break;
    case _NNS_UINT8:
      idx = argmax<uint8_t>(input[0].data, n);
      break;
    case _NNS_INT16:
      idx = argmax<int16_t>(input[0].data, n);
      break;
    case _NNS_UINT16:
      idx = argmax<uint16_t>(input[0].data, n);
      break;
    case _NNS_INT32:
      idx = argmax<int32_t>(input[0].data, n);
      break;
    case _NNS_UINT32:
      idx = argmax<uint32_t>(input[0].data, n);
      break;
    case _NNS_INT64:
      idx = argmax<int64_t>(input[0].data, n);
      break;
    case _NNS_UINT64:
      idx = argmax<uint64_t>(input[0].data, n);
      break;
    case _NNS_FLOAT32:
      idx = argmax<float>(input[0].data, n);
      break;
    case _NNS_FLOAT64:
      idx = argmax<double>(input[0].data, n);
      break;
    default:
      d->err.set("image_labeling: tensor type %d is not supported", (int)t.type);
      return GST_FLOW_NOT_SUPPORTED;
  }
  if (idx >= d->labels.size()) return GST_FLOW_ERROR;
  const std::string &label = d->labels[idx];
  GstMemory *mem = gst_allocator_alloc(nullptr, label.size() + 1, nullptr);
  GstMapInfo map;
  gst_memory_map(mem, &map, GST_MAP_WRITE);
  std::memcpy(map.data, label.c_str(), label.size() + 1);
  gst_memory_unmap(mem, &map);
  gst_memory_resize(mem, 0, label.size());  // text without the terminating NUL
  gst_buffer_append_memory(outbuf, mem);
  return GST_FLOW_OK;
}

GstTensorDecoderDef kImageLabeling = {const_cast<char *>("image_labeling"),
                                      il_init,
                                      il_exit,
                                      il_set_option,
                                      il_get_out_caps,
                                      il_decode,
                                      nullptr};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &kImageLabeling;
}

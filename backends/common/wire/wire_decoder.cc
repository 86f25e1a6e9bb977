// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder sub-plugin for one wire format (built three times: mode=protobuf, flatbuf,
// flexbuf, selected by NNS_WIRE_FORMAT). Serialises each tensors buffer into one memory of
// other/protobuf-tensor, other/flatbuf-tensor or other/flexbuf (framerate from the input).
//
//   gst-launch-1.0 videotestsrc num-buffers=3 ! tensor_converter ! tensor_decoder mode=flatbuf !
//       filesink location=frames.fb
#include <gst/gst.h>

#include <cstring>

#include "../../decoder/common/decoder_common.h"
#include "nnstreamer_plugin_api_decoder.h"
#include "wire.h"

GST_DEBUG_CATEGORY_STATIC(wire_dec_debug);
#define GST_CAT_DEFAULT wire_dec_debug

namespace {

using nns::wire::Format;

void copy_into(GstMemory *m, const uint8_t *src, std::size_t n) {
  GstMapInfo w;
  if (gst_memory_map(m, &w, GST_MAP_WRITE)) {
    std::memcpy(w.data, src, n);
    gst_memory_unmap(m, &w);
  }
}
constexpr Format kFormat = Format::NNS_WIRE_FORMAT;

void ensure_debug() {
  static gsize once = 0;
  if (g_once_init_enter(&once)) {
    GST_DEBUG_CATEGORY_INIT(wire_dec_debug, "nns_decoder_wire", 0, "wire decoders");
    g_once_init_leave(&once, 1);
  }
}

const GstTensorInfo *info_at(const GstTensorsInfo *info, unsigned i) {
  if (i < NNS_TENSOR_MEMORY_MAX) return &info->info[i];
  return info->extra ? &info->extra[i - NNS_TENSOR_MEMORY_MAX] : nullptr;
}

// Private data: the error slot tensor_decoder reads to say why a frame was refused.
int init(void **priv) {
  *priv = new nns::dec::DecoderErrorSlot();
  return TRUE;
}
void exit_(void **priv) {
  delete static_cast<nns::dec::DecoderErrorSlot *>(*priv);
  *priv = nullptr;
}
int set_option(void **, int, const char *) {
  return TRUE;
}

GstCaps *get_out_caps(void **, const GstTensorsConfig *config) {
  GstCaps *caps = gst_caps_new_empty_simple(nns::wire::media_type(kFormat));
  if (config && config->rate_d > 0 && config->rate_n >= 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
  return caps;
}

GstFlowReturn decode(void **priv, const GstTensorsConfig *config, const GstTensorMemory *input,
                     GstBuffer *outbuf) {
  ensure_debug();
  if (!config || !input || !outbuf) return GST_FLOW_ERROR;
  try {
    nns::wire::Frame f;
    f.format = static_cast<uint32_t>(config->info.format);
    f.rate_n = config->rate_n;
    f.rate_d = config->rate_d;
    f.tensors.resize(config->info.num_tensors);
    for (unsigned i = 0; i < config->info.num_tensors; ++i) {
      nns::wire::Tensor &t = f.tensors[i];
      t.data = static_cast<const uint8_t *>(input[i].data);
      t.size = input[i].size;
      if (f.format != 0 && t.size >= nns::wire::kMetaHeaderSize) {
        // Flexible/sparse: the memory starts with the 128-byte header
        // (magic, version, type, dimension[16], ...): take type and dims from it.
        uint32_t hdr[3 + NNS_TENSOR_RANK_LIMIT];
        std::memcpy(hdr, t.data, sizeof(hdr));
        t.type = hdr[2];
        std::memcpy(t.dims.data(), hdr + 3, sizeof(uint32_t) * NNS_TENSOR_RANK_LIMIT);
        continue;
      }
      const GstTensorInfo *ti = info_at(&config->info, i);
      if (!ti) throw nns::wire::WireError("no description of tensor " + std::to_string(i));
      if (ti->name) t.name = ti->name;
      t.type = static_cast<uint32_t>(ti->type);
      std::memcpy(t.dims.data(), ti->dimension, sizeof(ti->dimension));
    }
    thread_local std::vector<uint8_t> bytes;
    nns::wire::encode(kFormat, f, bytes);
    GstMemory *m = gst_allocator_alloc(nullptr, bytes.size(), nullptr);
    copy_into(m, bytes.data(), bytes.size());
    gst_buffer_append_memory(outbuf, m);
    return GST_FLOW_OK;
  } catch (const std::exception &e) {
    GST_WARNING("tensor_decoder::%s: %s", nns::wire::format_name(kFormat), e.what());
    if (priv && *priv) static_cast<nns::dec::DecoderErrorSlot *>(*priv)->set("%s", e.what());
    return GST_FLOW_ERROR;
  }
}

char mode_name[] = NNS_WIRE_NAME;

GstTensorDecoderDef table = {
    mode_name, init, exit_, set_option, get_out_caps, decode, nullptr,
};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &table;
}

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=octet_stream: the frame's tensors, one after the other, as
// application/octet-stream (the inverse of tensor_converter's octet-stream input). No options.
#include <gst/gst.h>

#include <cstring>

#include "../common/decoder_common.h"
#include "nnstreamer_plugin_api_decoder.h"

namespace {

struct OctetStream {
  nns::dec::DecoderErrorSlot err;
};

int os_init(void **pdata) {
  *pdata = new OctetStream();
  return TRUE;
}

void os_exit(void **pdata) {
  delete static_cast<OctetStream *>(*pdata);
  *pdata = nullptr;
}

int os_set_option(void **, int, const char *) {
  return TRUE;
}  // options are ignored

GstCaps *os_get_out_caps(void **, const GstTensorsConfig *config) {
  GstCaps *caps = gst_caps_new_empty_simple("application/octet-stream");
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
  return caps;
}

GstFlowReturn os_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = static_cast<OctetStream *>(*pdata);
  unsigned n = config->info.num_tensors;
  gsize total = 0;
  for (unsigned i = 0; i < n; ++i) total += input[i].size;
  GstMemory *mem = gst_allocator_alloc(nullptr, total, nullptr);
  GstMapInfo map;
  if (!mem || !gst_memory_map(mem, &map, GST_MAP_WRITE)) {
    if (mem) gst_memory_unref(mem);
    d->err.set("octet_stream: cannot allocate %zu bytes", static_cast<size_t>(total));
    return GST_FLOW_ERROR;
  }
  gsize off = 0;
  for (unsigned i = 0; i < n; ++i) {
    std::memcpy(map.data + off, input[i].data, input[i].size);
    off += input[i].size;
  }
  gst_memory_unmap(mem, &map);
  gst_buffer_append_memory(outbuf, mem);
  return GST_FLOW_OK;
}

GstTensorDecoderDef kOctetStream = {const_cast<char *>("octet_stream"),
                                    os_init,
                                    os_exit,
                                    os_set_option,
                                    os_get_out_caps,
                                    os_decode,
                                    nullptr};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &kOctetStream;
}

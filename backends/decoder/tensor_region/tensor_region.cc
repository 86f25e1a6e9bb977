// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=tensor_region: mobilenet-ssd detector output -> crop regions for
// tensor_crop's info pad, as other/tensors,format=flexible: one uint32 tensor 4:option1
// (x, y, w, h per region, best score first, in option4 pixels; slots without a detection are
// zero) behind the 128-byte flexible header.
//
//   ... tensor_mux name=mux ! other/tensors,format=static ! tensor_decoder mode=tensor_region
//       option1=1 option2=coco_labels_list.txt option3=box_priors.txt ! crop.info
//   ... ! tensor_converter ! crop.raw  tensor_crop name=crop ! other/tensors,format=flexible ! ...
//
// option1 number of regions (default 1)   option2 label file (mandatory; >= classes lines)
// option3 box priors and thresholds as bounding_boxes' mobilenet-ssd scheme
// option4 input video W:H (default 300:300)
// The decoding is the mobilenet-ssd scheme of nns_bbox (backends/decoder/bounding_boxes).
#include <gst/gst.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <memory>
#include <string>
#include <vector>

#include "../common/decoder_common.h"
#include "box_scheme.h"
#include "core/meta_header.h"
#include "scheme_input.h"
#include "nnstreamer_plugin_api_decoder.h"

namespace {

struct Region {
  nns::dec::DecoderErrorSlot err;  // first: tensor_decoder reads it
  std::unique_ptr<nns::bbox::Scheme> scheme = nns::bbox::schemes().make("mobilenet-ssd");
  unsigned num = 1;
  std::string label_path;
  std::size_t labels = 0;
  nns::bbox::Context ctx;
  nns::bbox::SchemeInput input;  // what the scheme was checked against
  std::vector<nns::bbox::Box> boxes;
};

int tr_init(void **pdata) {
  *pdata = new Region();
  return static_cast<Region *>(*pdata)->scheme ? TRUE : FALSE;
}

void tr_exit(void **pdata) {
  delete static_cast<Region *>(*pdata);
  *pdata = nullptr;
}

int tr_set_option(void **pdata, int op, const char *param) {
  auto *d = static_cast<Region *>(*pdata);
  const std::string p = param ? param : "";
  d->input.reset();
  switch (op) {
    case 0: {
      char *end = nullptr;
      const long n = std::strtol(p.c_str(), &end, 10);
      if (p.empty() || *end || n < 1 || n > 1024) {
        d->err.set("option1: number of regions must be an integer 1..1024, got '%s'", p.c_str());
        return FALSE;
      }
      d->num = static_cast<unsigned>(n);
      return TRUE;
    }
    case 1: {
      std::ifstream in(p);
      if (p.empty() || !in) {
        d->err.set("option2: cannot read label file '%s'", p.c_str());
        return FALSE;
      }
      std::size_t n = 0;
      std::string line;
      while (std::getline(in, line)) ++n;
      if (n == 0) {
        d->err.set("option2: label file '%s' has no labels", p.c_str());
        return FALSE;
      }
      d->label_path = p;
      d->labels = n;
      return TRUE;
    }
    case 2:
      try {
        d->scheme->set_option3(p);
      } catch (const std::exception &e) {
        d->err.set("%s", e.what());
        return FALSE;
      }
      return TRUE;
    case 3: {
      unsigned w = 0, h = 0;
      char tail = 0;
      if (p.empty()) return TRUE;
      if (std::sscanf(p.c_str(), "%u:%u%c", &w, &h, &tail) != 2 || !w || !h) {
        d->err.set("option4: input video size must be WIDTH:HEIGHT (e.g. 300:300), got '%s'",
                   p.c_str());
        return FALSE;
      }
      d->ctx.in_w = w, d->ctx.in_h = h;
      return TRUE;
    }
    default:
      return TRUE;
  }
}

bool check(Region *d, const GstTensorsConfig *config) {
  d->ctx.num_labels = d->labels;
  std::string why;
  if (d->input.bind(*d->scheme, d->ctx, config->info, why)) return true;
  if (!why.empty()) d->err.set("tensor_region: %s", why.c_str());
  return false;
}

GstCaps *tr_get_out_caps(void **pdata, const GstTensorsConfig *config) {
  auto *d = static_cast<Region *>(*pdata);
  if (!check(d, config)) return nullptr;
  GstCaps *caps =
      gst_caps_new_simple("other/tensors", "format", G_TYPE_STRING, "flexible", nullptr);
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
  return caps;
}

GstFlowReturn tr_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = static_cast<Region *>(*pdata);
  if (!check(d, config)) return GST_FLOW_NOT_NEGOTIATED;
  std::string why;
  if (!d->input.decode(*d->scheme, d->ctx, input, d->boxes, why)) {
    d->err.set("tensor_region: %s", why.c_str());
    return GST_FLOW_ERROR;
  }
  const std::size_t payload = static_cast<std::size_t>(d->num) * 4 * sizeof(uint32_t);
  GstMemory *mem = gst_allocator_alloc(nullptr, nns::kMetaHeaderSize + payload, nullptr);
  GstMapInfo map;
  if (!gst_memory_map(mem, &map, GST_MAP_WRITE)) {
    gst_memory_unref(mem);
    d->err.set("tensor_region: cannot map the output memory");
    return GST_FLOW_ERROR;
  }
  nns::write_meta_header(
      nns::flexible_header(nns::TensorType::kUInt32, nns::make_dims({4, d->num})), map.data);
  auto *out = reinterpret_cast<uint32_t *>(map.data + nns::kMetaHeaderSize);
  std::memset(out, 0, payload);
  for (std::size_t i = 0; i < d->boxes.size() && i < d->num; ++i) {
    const auto &b = d->boxes[i];
    out[i * 4 + 0] = static_cast<uint32_t>(b.x);
    out[i * 4 + 1] = static_cast<uint32_t>(b.y);
    out[i * 4 + 2] = static_cast<uint32_t>(b.w);
    out[i * 4 + 3] = static_cast<uint32_t>(b.h);
  }
  gst_memory_unmap(mem, &map);
  if (gst_buffer_get_size(outbuf) == 0)
    gst_buffer_append_memory(outbuf, mem);
  else
    gst_buffer_replace_all_memory(outbuf, mem);
  return GST_FLOW_OK;
}

GstTensorDecoderDef kTensorRegion = {const_cast<char *>("tensor_region"),
                                     tr_init,
                                     tr_exit,
                                     tr_set_option,
                                     tr_get_out_caps,
                                     tr_decode,
                                     nullptr};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &kTensorRegion;
}

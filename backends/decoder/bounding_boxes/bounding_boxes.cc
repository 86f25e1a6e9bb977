// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=bounding_boxes: detector output tensors -> video/x-raw,format=RGBA
// (transparent background, red 1 px boxes, label text above each box) for compositor, plus
// GstVideoRegionOfInterestMeta per box (and optionally a JSON custom meta).
//
//   gst-launch-1.0 ... ! tensor_decoder mode=bounding_boxes option1=mobilenet-ssd
//       option2=coco_labels_list.txt option3=box_priors.txt option4=640:480 option5=300:300
//       ! compositor ...
//
// option1 scheme (see box_scheme.h; tflite-ssd / tf-ssd are deprecated aliases)
// option2 label file (one label per line; ignored by mp-palm-detection as in NNStreamer)
// option3 scheme-specific (Scheme::set_option3)
// option4 output W:H (default: option5)       option5 model input W:H (default 300:300)
// option6 track 0/1 (centroid tracker; ids from 1 appended to labels as "label-id")
// option7 log 0/1 (boxes to stdout each frame)   option8 box style (accepted, unused)
// option9 our extension: comma/colon separated flags; "json" attaches NnsDetectionsMeta.
#include <gst/gst.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <fstream>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "../common/decoder_common.h"
#include "box_meta.h"
#include "box_scheme.h"
#include "draw.h"
#include "scheme_input.h"
#include "nnstreamer_plugin_api_decoder.h"
#include "tracker.h"

namespace {

using nns::bbox::Box;

struct BBox {
  nns::dec::DecoderErrorSlot err;  // first: tensor_decoder reads it
  std::string scheme_name;         // canonical
  std::unique_ptr<nns::bbox::Scheme> scheme;
  std::string option3;
  std::string label_path;
  std::vector<std::string> labels;
  unsigned out_w = 0, out_h = 0;  // 0: option5
  nns::bbox::Context ctx;
  bool track = false, log = false, json = false;
  nns::bbox::CentroidTracker tracker;

  nns::bbox::SchemeInput input;  // what the scheme was checked against
  std::vector<Box> boxes;
  std::vector<nns::bbox::OutBox> out_boxes;
  std::string text, json_text;

  unsigned width() const { return out_w ? out_w : ctx.in_w; }
  unsigned height() const { return out_h ? out_h : ctx.in_h; }
  bool uses_labels() const { return scheme_name != "mp-palm-detection"; }
};

std::string join_names() {
  std::string s;
  for (const auto &n : nns::bbox::schemes().names()) s += (s.empty() ? "" : ", ") + n;
  return s;
}

bool parse_wh(const char *param, unsigned &w, unsigned &h) {
  unsigned a = 0, b = 0;
  char tail = 0;
  if (!param || std::sscanf(param, "%u:%u%c", &a, &b, &tail) != 2 || a == 0 || b == 0 ||
      a > 16384 || b > 16384)
    return false;
  w = a, h = b;
  return true;
}

bool load_labels(BBox *d, const char *param) {
  d->labels.clear();
  d->label_path = param ? param : "";
  if (d->label_path.empty()) return true;
  std::ifstream in(d->label_path);
  if (!in) {
    d->err.set("option2: cannot read label file '%s'", d->label_path.c_str());
    return false;
  }
  std::string line;
  while (std::getline(in, line)) {
    if (!line.empty() && line.back() == '\r') line.pop_back();
    d->labels.push_back(line);
  }
  while (!d->labels.empty() && d->labels.back().empty()) d->labels.pop_back();
  if (d->labels.empty()) {
    d->err.set("option2: label file '%s' has no labels", d->label_path.c_str());
    return false;
  }
  return true;
}

bool apply_option3(BBox *d) {
  if (!d->scheme) return true;
  try {
    d->scheme->set_option3(d->option3);
  } catch (const std::exception &e) {
    d->err.set("%s", e.what());
    return false;
  }
  return true;
}

int bb_init(void **pdata) {
  *pdata = new BBox();
  return TRUE;
}

void bb_exit(void **pdata) {
  delete static_cast<BBox *>(*pdata);
  *pdata = nullptr;
}

int bb_set_option(void **pdata, int op, const char *param) {
  auto *d = static_cast<BBox *>(*pdata);
  const std::string p = param ? param : "";
  d->input.reset();
  switch (op) {
    case 0: {
      const std::string canon = nns::bbox::schemes().canonical(p);
      if (canon.empty()) {
        d->err.set("option1: unknown bounding-box scheme '%s'; valid schemes: %s", p.c_str(),
                   join_names().c_str());
        return FALSE;
      }
      d->scheme_name = canon;
      d->scheme = nns::bbox::schemes().make(canon);
      return apply_option3(d);
    }
    case 1:
      if (d->scheme && !d->uses_labels()) return TRUE;  // as NNStreamer: palm ignores labels
      return load_labels(d, param);
    case 2:
      d->option3 = p;
      return apply_option3(d);
    case 3:
      if (p.empty()) return TRUE;
      if (!parse_wh(param, d->out_w, d->out_h)) {
        d->err.set("option4: output size must be WIDTH:HEIGHT (e.g. 640:480), got '%s'", p.c_str());
        return FALSE;
      }
      return TRUE;
    case 4:
      if (p.empty()) return TRUE;
      if (!parse_wh(param, d->ctx.in_w, d->ctx.in_h)) {
        d->err.set("option5: model input size must be WIDTH:HEIGHT (e.g. 300:300), got '%s'",
                   p.c_str());
        return FALSE;
      }
      return TRUE;
    case 5:
      d->track = std::strtol(p.c_str(), nullptr, 10) != 0;
      return TRUE;
    case 6:
      d->log = std::strtol(p.c_str(), nullptr, 10) != 0;
      return TRUE;
    case 7:
      return TRUE;  // box style: NYI upstream, accepted and ignored
    case 8:
      d->json = p.find("json") != std::string::npos;
      return TRUE;
    default:
      return TRUE;
  }
}

// Checks the input against the scheme; false (reason in err) when it does not fit.
bool check(BBox *d, const GstTensorsConfig *config) {
  if (!d->scheme) {
    d->err.set("option1 (scheme) is not set; valid schemes: %s", join_names().c_str());
    return false;
  }
  d->ctx.num_labels = d->labels.size();
  std::string why;
  if (d->input.bind(*d->scheme, d->ctx, config->info, why)) return true;
  if (!why.empty()) d->err.set("%s", why.c_str());
  return false;
}

GstCaps *bb_get_out_caps(void **pdata, const GstTensorsConfig *config) {
  auto *d = static_cast<BBox *>(*pdata);
  if (!check(d, config)) return nullptr;
  GstCaps *caps = gst_caps_new_simple("video/x-raw", "format", G_TYPE_STRING, "RGBA", "width",
                                      G_TYPE_INT, static_cast<int>(d->width()), "height",
                                      G_TYPE_INT, static_cast<int>(d->height()), nullptr);
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
  return caps;
}

void log_boxes(BBox *d) {
  std::printf("Detect %zu boxes in %u x %u input image\n", d->boxes.size(), d->ctx.in_w,
              d->ctx.in_h);
  for (const auto &o : d->out_boxes) {
    const Box &b = *o.box;
    std::string head = o.label ? "[" + *o.label + "] " : "";
    std::printf("%sx:%d y:%d w:%d h:%d", head.c_str(), static_cast<int>(b.x), static_cast<int>(b.y),
                static_cast<int>(b.w), static_cast<int>(b.h));
    if (b.angle != 0) std::printf(" angle:%.2f", static_cast<double>(b.angle));
    std::printf(" prob:%.4f", static_cast<double>(b.score));
    if (b.track_id) std::printf(" id:%d", b.track_id);
    std::printf(" -> output x:%d y:%d w:%d h:%d\n", o.x, o.y, o.w, o.h);
  }
  std::fflush(stdout);
}

void draw_box(BBox *d, nns::bbox::Canvas &cv, nns::bbox::OutBox &o) {
  const Box &b = *o.box;
  const uint32_t colour = nns::bbox::box_colour();
  const nns::bbox::Placed p = nns::bbox::draw_box(cv, b, d->ctx.in_w, d->ctx.in_h, colour);
  o.x = p.x, o.y = p.y, o.w = p.w, o.h = p.h;
  if (o.label && b.angle == 0) {  // as NNStreamer: rotated boxes get no label text
    d->text = *o.label;
    if (d->track) {
      char id[16];
      std::snprintf(id, sizeof id, "-%d", b.track_id);
      d->text += id;
    }
    nns::bbox::draw_text(cv, o.x, std::max(0, o.y - 14), d->text, colour);
  }
}

GstFlowReturn bb_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = static_cast<BBox *>(*pdata);
  if (!check(d, config)) return GST_FLOW_NOT_NEGOTIATED;
  std::string why;
  if (!d->input.decode(*d->scheme, d->ctx, input, d->boxes, why)) {
    d->err.set("%s", why.c_str());
    return GST_FLOW_ERROR;
  }
  if (d->track) d->tracker.update(d->boxes);

  const unsigned W = d->width(), H = d->height();
  const std::size_t size = static_cast<std::size_t>(W) * H * 4;
  GstMemory *mem = nullptr;
  const bool append = gst_buffer_get_size(outbuf) == 0;
  if (append) {
    mem = gst_allocator_alloc(nullptr, size, nullptr);
  } else {
    if (gst_buffer_get_size(outbuf) < size) gst_buffer_set_size(outbuf, static_cast<gssize>(size));
    mem = gst_buffer_get_all_memory(outbuf);
  }
  GstMapInfo map;
  if (!mem || !gst_memory_map(mem, &map, GST_MAP_WRITE)) {
    if (mem) gst_memory_unref(mem);
    d->err.set("cannot map the %zu-byte output frame", size);
    return GST_FLOW_ERROR;
  }
  std::memset(map.data, 0, size);
  nns::bbox::Canvas cv{reinterpret_cast<uint32_t *>(map.data), static_cast<int>(W),
                       static_cast<int>(H)};
  const bool use_labels = d->uses_labels() && !d->labels.empty();
  d->out_boxes.clear();
  for (const Box &b : d->boxes) {
    nns::bbox::OutBox o;
    o.box = &b;
    o.sx = static_cast<float>(W) / static_cast<float>(d->ctx.in_w);
    o.sy = static_cast<float>(H) / static_cast<float>(d->ctx.in_h);
    if (use_labels) {
      // As NNStreamer: with labels, boxes of an unknown class are not drawn.
      if (b.class_id < 0 || static_cast<std::size_t>(b.class_id) >= d->labels.size()) continue;
      o.label = &d->labels[static_cast<std::size_t>(b.class_id)];
    }
    draw_box(d, cv, o);
    d->out_boxes.push_back(o);
  }
  gst_memory_unmap(mem, &map);
  if (append)
    gst_buffer_append_memory(outbuf, mem);
  else
    gst_buffer_replace_all_memory(outbuf, mem);

  if (d->log) log_boxes(d);
  nns::bbox::add_roi_metas(outbuf, d->out_boxes);
  if (d->json) {
    nns::bbox::build_json(d->json_text, W, H, d->out_boxes);
    nns::bbox::add_json_meta(outbuf, d->json_text);
  }
  return GST_FLOW_OK;
}

GstTensorDecoderDef kBoundingBoxes = {const_cast<char *>("bounding_boxes"),
                                      bb_init,
                                      bb_exit,
                                      bb_set_option,
                                      bb_get_out_caps,
                                      bb_decode,
                                      nullptr};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &kBoundingBoxes;
}

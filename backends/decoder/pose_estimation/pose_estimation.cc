// SPDX-License-Identifier: LGPL-2.1-only
// tensor_decoder mode=pose_estimation: keypoint heatmaps -> video/x-raw,format=RGBA of option1's
// size, transparent except for the skeleton: a line for each connection between two found
// keypoints (white) and a dot on each found keypoint (yellow). Every output buffer also carries
// a GstVideoRegionOfInterestMeta of type "pose" (the box around the found keypoints) whose
// "pose" param structure lists all keypoints (see docs/decoders/pose_estimation.md).
//
// option1: output W:H (mandatory). option2: W:H the positions are scaled from (heatmap-only:
// default the heatmap grid; heatmap-offset: the model input size, mandatory). option3: keypoint
// file, one line per keypoint "<name> <id> <id>..." (ids = connected keypoints); without it a
// 14-keypoint heatmap uses the 14-point body (top, neck, shoulders, ...) and a 17-keypoint one
// the COCO/PoseNet body. option4: heatmap-only (default) | heatmap-offset | keypoints.
// option5 (ours): the score a keypoint needs to be found, 0..1 (default 0.5).
//
// Input: tensor 0 float32 or uint8 [K:W:H:1] heatmaps (uint8 is read as value / 255, a score in
// 0..1, as quantized models output it); heatmap-offset adds tensor 1 float32 [2K:W:H:1]
// offsets (y offsets in channels 0..K-1, x offsets in K..2K-1, in option2 pixels) and reads the
// heatmap through a sigmoid. keypoints (ours, for MoveNet): tensor 0 float32 [3:K:1:1], per
// keypoint (y, x, score) with y and x normalized to 0..1 of the frame. A keypoint is found when
// its (best) score is >= option5.
//
//   gst-launch-1.0 ... tensor_filter framework=armnn model=posenet.tflite !
//     tensor_decoder mode=pose_estimation option1=640:480 option2=257:257
//       option4=heatmap-offset ! compositor ...
#include <gst/gst.h>
#include <gst/video/gstvideometa.h>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdint>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "../common/decoder_common.h"
#include "nnstreamer_plugin_api_decoder.h"

namespace {

enum class Mode { kHeatmapOnly, kHeatmapOffset, kKeypoints };

constexpr float kDefaultFoundThreshold = 0.5f;
constexpr int kDotRadius = 3;
constexpr uint8_t kLineRgba[4] = {255, 255, 255, 255};
constexpr uint8_t kDotRgba[4] = {255, 255, 0, 255};

struct KeypointDesc {
  std::string name;
  std::vector<unsigned> links;
};

struct Keypoint {
  int x = 0, y = 0;
  float score = 0.0f;
  bool found = false;
};

struct PoseDecoder {
  nns::dec::DecoderErrorSlot err;
  unsigned out_w = 0, out_h = 0;
  unsigned in_w = 0, in_h = 0;
  Mode mode = Mode::kHeatmapOnly;
  float threshold = kDefaultFoundThreshold;
  std::string file;
  std::vector<KeypointDesc> body;  // from option3; empty = default by keypoint count
  std::vector<Keypoint> points;    // scratch, sized at negotiation
  std::vector<float> heat;         // uint8 heatmaps as scores (allocated on the first frame)
};

// The 14-point body of upstream's default (heatmap models such as CPM/hourglass).
const std::vector<KeypointDesc> &body14() {
  static const std::vector<KeypointDesc> b = {
      {"top", {1}},         {"neck", {0, 2, 5, 8, 11}}, {"r_shoulder", {1, 3}}, {"r_elbow", {2, 4}},
      {"r_wrist", {3}},     {"l_shoulder", {1, 6}},     {"l_elbow", {5, 7}},    {"l_wrist", {6}},
      {"r_hip", {1, 9}},    {"r_knee", {8, 10}},        {"r_ankle", {9}},       {"l_hip", {1, 12}},
      {"l_knee", {11, 13}}, {"l_ankle", {12}}};
  return b;
}

// The 17 COCO keypoints in PoseNet's order, with PoseNet's skeleton.
const std::vector<KeypointDesc> &body17() {
  static const std::vector<KeypointDesc> b = {
      {"nose", {1, 2, 3, 4}},        {"leftEye", {0, 2, 3}},
      {"rightEye", {0, 1, 4}},       {"leftEar", {0, 1}},
      {"rightEar", {0, 2}},          {"leftShoulder", {6, 7, 11}},
      {"rightShoulder", {5, 8, 12}}, {"leftElbow", {5, 9}},
      {"rightElbow", {6, 10}},       {"leftWrist", {7}},
      {"rightWrist", {8}},           {"leftHip", {5, 12, 13}},
      {"rightHip", {6, 11, 14}},     {"leftKnee", {11, 15}},
      {"rightKnee", {12, 16}},       {"leftAnkle", {13}},
      {"rightAnkle", {14}}};
  return b;
}

const std::vector<KeypointDesc> *body_for(const PoseDecoder *d, unsigned k) {
  if (!d->body.empty()) return &d->body;
  if (k == 14) return &body14();
  if (k == 17) return &body17();
  return nullptr;
}

int pe_init(void **pdata) {
  *pdata = new PoseDecoder();
  return TRUE;
}

void pe_exit(void **pdata) {
  delete static_cast<PoseDecoder *>(*pdata);
  *pdata = nullptr;
}

// "W:H" with both positive (a third and later field must be 1, as in "640:480:1").
bool parse_wh(const std::string &s, unsigned *w, unsigned *h) {
  unsigned v[2] = {0, 0};
  size_t pos = 0;
  for (int i = 0; i < 2; ++i) {
    if (pos >= s.size() || s[pos] < '0' || s[pos] > '9') return false;
    char *end = nullptr;
    errno = 0;
    unsigned long n = std::strtoul(s.c_str() + pos, &end, 10);
    if (errno || n == 0 || n > 65535) return false;
    v[i] = static_cast<unsigned>(n);
    pos = static_cast<size_t>(end - s.c_str());
    if (i == 0) {
      if (pos >= s.size() || s[pos] != ':') return false;
      ++pos;
    }
  }
  while (pos < s.size()) {
    if (s.compare(pos, 2, ":1") != 0) return false;
    pos += 2;
  }
  *w = v[0];
  *h = v[1];
  return true;
}

bool load_body(PoseDecoder *d, const std::string &path) {
  std::ifstream in(path);
  if (path.empty() || !in) {
    d->err.set("option3: cannot read keypoint file '%s'", path.c_str());
    return false;
  }
  std::vector<KeypointDesc> body;
  std::string line;
  unsigned lineno = 0;
  while (std::getline(in, line)) {
    ++lineno;
    std::istringstream ls(line);
    KeypointDesc kd;
    if (!(ls >> kd.name)) continue;  // blank line
    std::string tok;
    while (ls >> tok) {
      char *end = nullptr;
      long id = std::strtol(tok.c_str(), &end, 10);
      if (*end != '\0' || id < 0 || id > 65535) {
        d->err.set("option3: '%s' line %u: connection '%s' is not a keypoint id", path.c_str(),
                   lineno, tok.c_str());
        return false;
      }
      kd.links.push_back(static_cast<unsigned>(id));
    }
    body.push_back(std::move(kd));
  }
  if (body.empty()) {
    d->err.set("option3: keypoint file '%s' lists no keypoints", path.c_str());
    return false;
  }
  for (size_t i = 0; i < body.size(); ++i)
    for (unsigned id : body[i].links)
      if (id >= body.size()) {
        d->err.set("option3: '%s': keypoint '%s' links to id %u, the file has %zu keypoints",
                   path.c_str(), body[i].name.c_str(), id, body.size());
        return false;
      }
  d->body = std::move(body);
  d->file = path;
  return true;
}

int pe_set_option(void **pdata, int op, const char *param) {
  auto *d = static_cast<PoseDecoder *>(*pdata);
  std::string v = param ? param : "";
  switch (op) {
    case 0:
      if (!parse_wh(v, &d->out_w, &d->out_h)) {
        d->err.set("option1: output size must be WIDTH:HEIGHT (positive), got '%s'", v.c_str());
        return FALSE;
      }
      return TRUE;
    case 1:
      if (!parse_wh(v, &d->in_w, &d->in_h)) {
        d->err.set("option2: input size must be WIDTH:HEIGHT (positive), got '%s'", v.c_str());
        return FALSE;
      }
      return TRUE;
    case 2:
      return load_body(d, v) ? TRUE : FALSE;
    case 3:
      if (v == "heatmap-only") {
        d->mode = Mode::kHeatmapOnly;
      } else if (v == "heatmap-offset") {
        d->mode = Mode::kHeatmapOffset;
      } else if (v == "keypoints") {
        d->mode = Mode::kKeypoints;
      } else {
        d->err.set("option4: unknown mode '%s'; expected heatmap-only, heatmap-offset or keypoints",
                   v.c_str());
        return FALSE;
      }
      return TRUE;
    case 4: {
      char *end = nullptr;
      errno = 0;
      float t = std::strtof(v.c_str(), &end);
      if (v.empty() || *end != '\0' || errno || !(t >= 0.0f && t <= 1.0f)) {
        d->err.set("option5: score threshold must be a number in 0..1, got '%s'", v.c_str());
        return FALSE;
      }
      d->threshold = t;
      return TRUE;
    }
    default:
      return TRUE;
  }
}

// Checks one tensor is float32 (or uint8 if `uint8_ok`) [c:W:H:1]; c == 0 skips the channel
// check.
bool check_map(PoseDecoder *d, const GstTensorInfo &t, unsigned idx, const char *what, unsigned c,
               bool uint8_ok) {
  if (t.type != _NNS_FLOAT32 && !(uint8_ok && t.type == _NNS_UINT8)) {
    d->err.set("tensor %u (%s) must be float32%s, got type %d", idx, what,
               uint8_ok ? " or uint8" : "", static_cast<int>(t.type));
    return false;
  }
  for (unsigned i = 3; i < NNS_TENSOR_RANK_LIMIT && t.dimension[i]; ++i)
    if (t.dimension[i] != 1) {
      d->err.set("tensor %u (%s) must be C:W:H:1, got dim%u = %u", idx, what, i, t.dimension[i]);
      return false;
    }
  if (c && t.dimension[0] && t.dimension[0] != c) {
    d->err.set("tensor %u (%s) must have %u channels in dim0, got %u", idx, what, c,
               t.dimension[0]);
    return false;
  }
  return true;
}

// A body fits k keypoints (k == 0: not known yet). `what` starts the message ("the heatmaps
// have").
bool check_body(PoseDecoder *d, unsigned k, const char *what) {
  if (k && !body_for(d, k)) {
    d->err.set("%s %u keypoints; without option3 only 14 or 17 are known", what, k);
    return false;
  }
  if (k && !d->body.empty() && k != d->body.size()) {
    d->err.set("%s %u keypoints, option3 '%s' describes %zu", what, k, d->file.c_str(),
               d->body.size());
    return false;
  }
  return true;
}

// keypoints mode: float32 [3:K:1:1] (y, x, score per keypoint).
bool check_keypoints(PoseDecoder *d, const GstTensorsConfig *config) {
  if (config->info.num_tensors < 1) {
    d->err.set("keypoints expects 1 tensor (y, x, score per keypoint), got 0 tensor(s)");
    return false;
  }
  const GstTensorInfo &t = config->info.info[0];
  if (t.type != _NNS_FLOAT32) {
    d->err.set("tensor 0 (keypoints) must be float32, got type %d", static_cast<int>(t.type));
    return false;
  }
  if (t.dimension[0] && t.dimension[0] != 3) {
    d->err.set("tensor 0 (keypoints) must be 3:K:1:1 (y, x, score), got dim0 = %u", t.dimension[0]);
    return false;
  }
  for (unsigned i = 2; i < NNS_TENSOR_RANK_LIMIT && t.dimension[i]; ++i)
    if (t.dimension[i] != 1) {
      d->err.set("tensor 0 (keypoints) must be 3:K:1:1, got dim%u = %u", i, t.dimension[i]);
      return false;
    }
  return check_body(d, t.dimension[1], "the tensor has");
}

bool check_input(PoseDecoder *d, const GstTensorsConfig *config) {
  if (d->mode == Mode::kKeypoints) return check_keypoints(d, config);
  const bool offset = d->mode == Mode::kHeatmapOffset;
  if (config->info.num_tensors < (offset ? 2u : 1u)) {
    d->err.set("%s expects %s, got %u tensor(s)", offset ? "heatmap-offset" : "heatmap-only",
               offset ? "2 tensors (heatmaps, offsets)" : "1 tensor (heatmaps)",
               config->info.num_tensors);
    return false;
  }
  const GstTensorInfo &heat = config->info.info[0];
  unsigned k = heat.dimension[0];
  if (!check_map(d, heat, 0, "heatmaps", 0, true)) return false;
  if (!check_body(d, k, "the heatmaps have")) return false;
  if (offset) {
    const GstTensorInfo &off = config->info.info[1];
    if (!check_map(d, off, 1, "offsets", 2 * k, false)) return false;
    for (int i = 1; i < 3; ++i)
      if (heat.dimension[i] && off.dimension[i] && heat.dimension[i] != off.dimension[i]) {
        d->err.set("offsets grid %ux%u differs from the heatmap grid %ux%u", off.dimension[1],
                   off.dimension[2], heat.dimension[1], heat.dimension[2]);
        return false;
      }
    if (!d->in_w) {
      d->err.set("heatmap-offset needs option2=<model input WIDTH:HEIGHT>");
      return false;
    }
  }
  return true;
}

GstCaps *pe_get_out_caps(void **pdata, const GstTensorsConfig *config) {
  auto *d = static_cast<PoseDecoder *>(*pdata);
  if (!d->out_w) {
    d->err.set("pose_estimation needs option1=<output WIDTH:HEIGHT>");
    return nullptr;
  }
  if (!check_input(d, config)) return nullptr;
  GstCaps *caps = gst_caps_new_simple("video/x-raw", "format", G_TYPE_STRING, "RGBA", "width",
                                      G_TYPE_INT, static_cast<int>(d->out_w), "height", G_TYPE_INT,
                                      static_cast<int>(d->out_h), nullptr);
  if (config->rate_n >= 0 && config->rate_d > 0)
    gst_caps_set_simple(caps, "framerate", GST_TYPE_FRACTION, config->rate_n, config->rate_d,
                        nullptr);
  return caps;
}

inline float sigmoid(float x) {
  return 1.0f / (1.0f + std::exp(-x));
}

// Some keypoints land slightly outside the frame: floored and clamped onto it.
void place(const PoseDecoder *d, Keypoint *p, double px, double py) {
  p->x = static_cast<int>(std::fmin(std::fmax(std::floor(px), 0.0), d->out_w - 1.0));
  p->y = static_cast<int>(std::fmin(std::fmax(std::floor(py), 0.0), d->out_h - 1.0));
}

// Best grid cell per keypoint, then its position in the output frame.
void locate(PoseDecoder *d, const float *heat, const float *off, unsigned k, unsigned gw,
            unsigned gh) {
  const bool offset = off != nullptr;
  const unsigned sw = d->in_w ? d->in_w : gw, sh = d->in_h ? d->in_h : gh;
  for (unsigned kp = 0; kp < k; ++kp) {
    unsigned bx = 0, by = 0;
    float best = -INFINITY;
    for (unsigned y = 0; y < gh; ++y)
      for (unsigned x = 0; x < gw; ++x) {
        float v = heat[(static_cast<size_t>(y) * gw + x) * k + kp];
        if (v > best) {
          best = v;
          bx = x;
          by = y;
        }
      }
    Keypoint &p = d->points[kp];
    p.score = offset ? sigmoid(best) : best;
    p.found = p.score >= d->threshold;
    double px, py;
    if (offset) {
      size_t cell = (static_cast<size_t>(by) * gw + bx) * 2 * k;
      float oy = off[cell + kp], ox = off[cell + k + kp];
      px = (gw > 1 ? static_cast<double>(bx) / (gw - 1) : 0.0) * sw + ox;
      py = (gh > 1 ? static_cast<double>(by) / (gh - 1) : 0.0) * sh + oy;
      px = px * d->out_w / sw;
      py = py * d->out_h / sh;
    } else {
      px = static_cast<double>(bx) * d->out_w / sw;
      py = static_cast<double>(by) * d->out_h / sh;
    }
    place(d, &p, px, py);
  }
}

// keypoints mode: (y, x, score) triples, y and x normalized to the frame.
void locate_keypoints(PoseDecoder *d, const float *yxs, unsigned k) {
  for (unsigned kp = 0; kp < k; ++kp) {
    Keypoint &p = d->points[kp];
    const float *t = yxs + 3 * static_cast<size_t>(kp);
    p.score = t[2];
    p.found = p.score >= d->threshold;  // NaN is not found
    double px = std::isfinite(t[1]) ? static_cast<double>(t[1]) * d->out_w : 0.0;
    double py = std::isfinite(t[0]) ? static_cast<double>(t[0]) * d->out_h : 0.0;
    place(d, &p, px, py);
  }
}

struct Canvas {
  uint8_t *px;
  int w, h;
  void put(int x, int y, const uint8_t *rgba) {
    if (x < 0 || y < 0 || x >= w || y >= h) return;
    std::memcpy(px + (static_cast<size_t>(y) * w + x) * 4, rgba, 4);
  }
  void line(int x0, int y0, int x1, int y1, const uint8_t *rgba) {
    int dx = std::abs(x1 - x0), dy = -std::abs(y1 - y0);
    int sx = x0 < x1 ? 1 : -1, sy = y0 < y1 ? 1 : -1, e = dx + dy;
    for (;;) {
      put(x0, y0, rgba);
      if (x0 == x1 && y0 == y1) break;
      int e2 = 2 * e;
      if (e2 >= dy) {
        e += dy;
        x0 += sx;
      }
      if (e2 <= dx) {
        e += dx;
        y0 += sy;
      }
    }
  }
  void dot(int cx, int cy, int r, const uint8_t *rgba) {
    for (int y = -r; y <= r; ++y)
      for (int x = -r; x <= r; ++x)
        if (x * x + y * y <= r * r) put(cx + x, cy + y, rgba);
  }
};

void attach_meta(const PoseDecoder *d, const std::vector<KeypointDesc> &body, GstBuffer *outbuf) {
  int x0 = INT32_MAX, y0 = INT32_MAX, x1 = -1, y1 = -1;
  GValue list = G_VALUE_INIT;
  gst_value_list_init(&list, d->points.size());
  for (size_t i = 0; i < d->points.size(); ++i) {
    const Keypoint &p = d->points[i];
    if (p.found) {
      x0 = std::min(x0, p.x);
      y0 = std::min(y0, p.y);
      x1 = std::max(x1, p.x);
      y1 = std::max(y1, p.y);
    }
    GstStructure *s = gst_structure_new(
        "keypoint", "id", G_TYPE_INT, static_cast<int>(i), "name", G_TYPE_STRING,
        body[i].name.c_str(), "x", G_TYPE_INT, p.x, "y", G_TYPE_INT, p.y, "score", G_TYPE_DOUBLE,
        static_cast<double>(p.score), "found", G_TYPE_BOOLEAN, p.found ? TRUE : FALSE, nullptr);
    GValue sv = G_VALUE_INIT;
    g_value_init(&sv, GST_TYPE_STRUCTURE);
    g_value_take_boxed(&sv, s);
    gst_value_list_append_and_take_value(&list, &sv);
  }
  if (x1 < 0) x0 = y0 = 0, x1 = y1 = -1;  // nothing found: empty box at the origin
  GstVideoRegionOfInterestMeta *m = gst_buffer_add_video_region_of_interest_meta(
      outbuf, "pose", static_cast<guint>(x0), static_cast<guint>(y0),
      static_cast<guint>(x1 - x0 + 1), static_cast<guint>(y1 - y0 + 1));
  GstStructure *param = gst_structure_new_empty("pose");
  gst_structure_take_value(param, "keypoints", &list);
  gst_video_region_of_interest_meta_add_param(m, param);
}

GstFlowReturn draw(PoseDecoder *d, const std::vector<KeypointDesc> &body, GstBuffer *outbuf);

GstFlowReturn pe_decode(void **pdata, const GstTensorsConfig *config, const GstTensorMemory *input,
                        GstBuffer *outbuf) {
  auto *d = static_cast<PoseDecoder *>(*pdata);
  if (!d->out_w || !check_input(d, config)) return GST_FLOW_NOT_NEGOTIATED;
  if (d->mode == Mode::kKeypoints) {
    const unsigned k = config->info.info[0].dimension[1];
    const size_t need = static_cast<size_t>(k) * 3 * sizeof(float);
    if (!k || input[0].size < need) {
      d->err.set("tensor 0 (keypoints) has %zu bytes, expected %zu", input[0].size, need);
      return GST_FLOW_ERROR;
    }
    d->points.resize(k);
    locate_keypoints(d, static_cast<const float *>(input[0].data), k);
    return draw(d, *body_for(d, k), outbuf);
  }
  const GstTensorInfo &heat = config->info.info[0];
  const unsigned k = heat.dimension[0], gw = heat.dimension[1] ? heat.dimension[1] : 1,
                 gh = heat.dimension[2] ? heat.dimension[2] : 1;
  const size_t cells = static_cast<size_t>(k) * gw * gh, need = cells * sizeof(float);
  const bool heat_u8 = heat.type == _NNS_UINT8;
  if (input[0].size < (heat_u8 ? cells : need)) {
    d->err.set("tensor 0 (heatmaps) has %zu bytes, expected %zu", input[0].size,
               heat_u8 ? cells : need);
    return GST_FLOW_ERROR;
  }
  const float *scores = static_cast<const float *>(input[0].data);
  if (heat_u8) {
    d->heat.resize(cells);
    const auto *u = static_cast<const uint8_t *>(input[0].data);
    for (size_t i = 0; i < cells; ++i) d->heat[i] = u[i] / 255.0f;
    scores = d->heat.data();
  }
  const float *off = nullptr;
  if (d->mode == Mode::kHeatmapOffset) {
    if (input[1].size < 2 * need) {
      d->err.set("tensor 1 (offsets) has %zu bytes, expected %zu", input[1].size, 2 * need);
      return GST_FLOW_ERROR;
    }
    off = static_cast<const float *>(input[1].data);
  }
  d->points.resize(k);  // allocates on the first frame only
  locate(d, scores, off, k, gw, gh);
  return draw(d, *body_for(d, k), outbuf);
}

// The skeleton of d->points into a new RGBA frame appended to outbuf, and the meta.
GstFlowReturn draw(PoseDecoder *d, const std::vector<KeypointDesc> &body, GstBuffer *outbuf) {
  const unsigned k = static_cast<unsigned>(d->points.size());
  const size_t size = static_cast<size_t>(d->out_w) * d->out_h * 4;
  GstMemory *mem = gst_allocator_alloc(nullptr, size, nullptr);
  GstMapInfo map;
  if (!gst_memory_map(mem, &map, GST_MAP_WRITE)) {
    gst_memory_unref(mem);
    d->err.set("cannot map the output frame");
    return GST_FLOW_ERROR;
  }
  std::memset(map.data, 0, size);
  Canvas c{map.data, static_cast<int>(d->out_w), static_cast<int>(d->out_h)};
  for (unsigned i = 0; i < k; ++i) {
    if (!d->points[i].found) continue;
    for (unsigned j : body[i].links) {
      // Each connection once (files may list it at both ends), only between found keypoints.
      if (j >= k || !d->points[j].found) continue;
      bool listed_back = false;
      for (unsigned b : body[j].links) listed_back |= (b == i);
      if (listed_back && j < i) continue;
      c.line(d->points[i].x, d->points[i].y, d->points[j].x, d->points[j].y, kLineRgba);
    }
  }
  for (unsigned i = 0; i < k; ++i)
    if (d->points[i].found) c.dot(d->points[i].x, d->points[i].y, kDotRadius, kDotRgba);
  gst_memory_unmap(mem, &map);
  gst_buffer_append_memory(outbuf, mem);
  attach_meta(d, body, outbuf);
  return GST_FLOW_OK;
}

GstTensorDecoderDef kPoseEstimation = {const_cast<char *>("pose_estimation"),
                                       pe_init,
                                       pe_exit,
                                       pe_set_option,
                                       pe_get_out_caps,
                                       pe_decode,
                                       nullptr};

}  // namespace

extern "C" __attribute__((visibility("default"))) const GstTensorDecoderDef *
nns_decoder_subplugin_entry(void) {
  return &kPoseEstimation;
}

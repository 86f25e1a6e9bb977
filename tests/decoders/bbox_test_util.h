// SPDX-License-Identifier: LGPL-2.1-only
// Helpers of the bounding_boxes / tensor_region tests: run a pipeline ending in
// "appsink name=out" and collect each frame with its ROI metas and JSON meta; compare a frame
// with an upstream reference frame.
#pragma once

#include <gst/app/gstappsink.h>
#include <gst/gst.h>
#include <gst/video/gstvideometa.h>

#include <cstdint>
#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "support/harness.h"

namespace nns::test::bbox {

// NNStreamer's captured detector tensors and reference frames (../shared/models/upstream).
inline std::string data_dir() {
  return nns::test::shared_models_dir() + "/decoder/nnstreamer_decoder_boundingbox";
}

// The two captured mobilenet-ssd output tensors (2 frames, run in data_dir()) into "mux".
inline const std::string kSsdInputs =
    " multifilesrc location=mobilenetssd_tensors.0.%d start-index=0 stop-index=1 "
    "caps=application/octet-stream ! tensor_converter input-dim=4:1:1917:1 input-type=float32 ! "
    "mux.sink_0 multifilesrc location=mobilenetssd_tensors.1.%d start-index=0 stop-index=1 "
    "caps=application/octet-stream ! tensor_converter input-dim=91:1917:1 input-type=float32 ! "
    "mux.sink_1";

struct Roi {
  std::string type, label;
  int x = 0, y = 0, w = 0, h = 0, id = 0, class_id = -1, track_id = 0;
  double score = 0, angle = 0;
  std::vector<double> keypoints;
};

struct Frame {
  std::vector<uint8_t> data;
  std::vector<Roi> rois;
  std::string json;
  bool has_json = false;
};

struct Collected {
  std::vector<Frame> frames;
  bool eos = false;
  std::string error;
};

inline Roi roi_of(GstVideoRegionOfInterestMeta *m) {
  Roi r;
  r.type = g_quark_to_string(m->roi_type);
  r.x = static_cast<int>(m->x), r.y = static_cast<int>(m->y);
  r.w = static_cast<int>(m->w), r.h = static_cast<int>(m->h), r.id = m->id;
  if (const GstStructure *s = gst_video_region_of_interest_meta_get_param(m, "detection")) {
    if (const char *l = gst_structure_get_string(s, "label")) r.label = l;
    gst_structure_get_int(s, "class-id", &r.class_id);
    gst_structure_get_int(s, "track-id", &r.track_id);
    gst_structure_get_double(s, "score", &r.score);
    gst_structure_get_double(s, "angle", &r.angle);
    if (const GValue *kp = gst_structure_get_value(s, "keypoints"))
      for (guint i = 0; i < gst_value_array_get_size(kp); ++i)
        r.keypoints.push_back(g_value_get_double(gst_value_array_get_value(kp, i)));
  }
  return r;
}

// The sample's bytes, ROI metas and JSON custom meta.
inline Frame frame_of(GstSample *smp) {
  Frame f;
  GstBuffer *b = gst_sample_get_buffer(smp);
  GstMapInfo map;
  if (gst_buffer_map(b, &map, GST_MAP_READ)) {
    f.data.assign(map.data, map.data + map.size);
    gst_buffer_unmap(b, &map);
  }
  gpointer state = nullptr;
  while (GstMeta *m = gst_buffer_iterate_meta_filtered(b, &state,
                                                       GST_VIDEO_REGION_OF_INTEREST_META_API_TYPE))
    f.rois.push_back(roi_of(reinterpret_cast<GstVideoRegionOfInterestMeta *>(m)));
  if (GstCustomMeta *cm = gst_buffer_get_custom_meta(b, "NnsDetectionsMeta")) {
    f.has_json = true;
    if (const char *j = gst_structure_get_string(gst_custom_meta_get_structure(cm), "json"))
      f.json = j;
  }
  return f;
}

// Runs `desc` (must contain "appsink name=out") to EOS or error, in folder `cwd` if given.
inline Collected collect(const std::string &desc, const std::string &cwd = {},
                         double timeout_s = 20) {
  Collected c;
  const auto old = std::filesystem::current_path();
  if (!cwd.empty()) std::filesystem::current_path(cwd);
  GError *err = nullptr;
  GstElement *pipe = gst_parse_launch(desc.c_str(), &err);
  if (!cwd.empty() && !pipe) std::filesystem::current_path(old);
  if (!pipe) {
    c.error = err ? err->message : "parse failed";
    g_clear_error(&err);
    return c;
  }
  g_clear_error(&err);
  GstElement *sink = gst_bin_get_by_name(GST_BIN(pipe), "out");
  if (sink) g_object_set(sink, "sync", FALSE, nullptr);
  gst_element_set_state(pipe, GST_STATE_PLAYING);
  GstBus *bus = gst_element_get_bus(pipe);
  const gint64 end = g_get_monotonic_time() + static_cast<gint64>(timeout_s * 1e6);
  while (g_get_monotonic_time() < end) {
    if (sink) {
      GstSample *smp = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 10 * GST_MSECOND);
      if (smp) {
        c.frames.push_back(frame_of(smp));
        gst_sample_unref(smp);
        continue;
      }
    }
    GstMessage *msg = gst_bus_timed_pop_filtered(
        bus, sink ? 0 : 10 * GST_MSECOND,
        static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
    if (!msg) continue;
    if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ERROR) {
      GError *e = nullptr;
      gchar *dbg = nullptr;
      gst_message_parse_error(msg, &e, &dbg);
      c.error = std::string(e ? e->message : "") + " | " + (dbg ? dbg : "");
      g_clear_error(&e);
      g_free(dbg);
      gst_message_unref(msg);
      break;
    }
    gst_message_unref(msg);
    // EOS: drain what the sink still holds.
    while (sink) {
      GstSample *smp = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 0);
      if (!smp) break;
      c.frames.push_back(frame_of(smp));
      gst_sample_unref(smp);
    }
    c.eos = true;
    break;
  }
  gst_object_unref(bus);
  if (sink) gst_object_unref(sink);
  gst_element_set_state(pipe, GST_STATE_NULL);
  gst_object_unref(pipe);
  if (!cwd.empty()) std::filesystem::current_path(old);
  return c;
}

struct Rect {
  int x, y, w, h;
};

// The 8x13 label cells drawn above each labelled ROI, as NNStreamer places them: from the box's
// top-left corner 14 px up (row 0 at the most), 9 px apart, only those that fit the frame width
// `w`. `track` adds the "-<id>" the text has in tracking mode.
inline std::vector<Rect> label_cells(const std::vector<Roi> &rois, int w, bool track = false) {
  std::vector<Rect> v;
  for (const auto &r : rois) {
    if (r.label.empty()) continue;
    const std::size_t n = r.label.size() + (track ? 1 + std::to_string(r.track_id).size() : 0);
    const int y = std::max(0, r.y - 14);
    for (std::size_t k = 0; k < n; ++k) {
      const int x = r.x + static_cast<int>(k) * 9;
      if (x + 8 > w) break;
      v.push_back({x, y, 8, 13});
    }
  }
  return v;
}

// Compares `ours` (RGBA) with upstream's reference frame (BGRx bytes when `golden_bgrx`, else
// RGBA) of size w x h, pixel for pixel. Only the glyphs differ by design (ours are the X11
// misc-fixed font, upstream's its own table): inside `cells` both frames must hold box-red or
// clear pixels (the whole cell is written), anywhere else they must be identical. Returns "" when
// they are, else the first differences.
inline std::string compare_exact(const std::vector<uint8_t> &ours,
                                 const std::vector<uint8_t> &golden, bool golden_bgrx, int w, int h,
                                 const std::vector<Rect> &cells) {
  const std::size_t n = static_cast<std::size_t>(w) * h * 4;
  if (ours.size() != n || golden.size() != n)
    return "frame sizes differ: ours " + std::to_string(ours.size()) + ", reference " +
           std::to_string(golden.size()) + ", expected " + std::to_string(n);
  // 0: clear, 1: box red, 2: anything else.
  auto ours_px = [&](int x, int y) {
    const uint8_t *p = &ours[(static_cast<std::size_t>(y) * w + x) * 4];
    if (p[0] == 255 && p[1] == 0 && p[2] == 0 && p[3] == 255) return 1;
    return (p[0] | p[1] | p[2] | p[3]) == 0 ? 0 : 2;
  };
  auto gold_px = [&](int x, int y) {
    const uint8_t *p = &golden[(static_cast<std::size_t>(y) * w + x) * 4];
    if (golden_bgrx) {
      if (p[2] == 255 && p[1] == 0 && p[0] == 0) return 1;
      return (p[0] | p[1] | p[2]) == 0 ? 0 : 2;
    }
    if (p[0] == 255 && p[1] == 0 && p[2] == 0 && p[3] == 255) return 1;
    return (p[0] | p[1] | p[2] | p[3]) == 0 ? 0 : 2;
  };
  auto in_cell = [&](int x, int y) {
    for (const auto &r : cells)
      if (x >= r.x && x < r.x + r.w && y >= r.y && y < r.y + r.h) return true;
    return false;
  };
  std::string out;
  int bad = 0, boxes = 0;
  for (int y = 0; y < h; ++y)
    for (int x = 0; x < w; ++x) {
      const int a = ours_px(x, y), b = gold_px(x, y);
      boxes += b == 1;
      const bool ok = in_cell(x, y) ? (a != 2 && b != 2) : a == b;
      if (!ok && bad++ < 6)
        out += "pixel (" + std::to_string(x) + "," + std::to_string(y) + "): ours " +
               (a == 0   ? "clear"
                : a == 1 ? "red"
                         : "other") +
               ", reference " +
               (b == 0   ? "clear"
                : b == 1 ? "red"
                         : "other") +
               "; ";
    }
  if (bad) out += std::to_string(bad) + " pixel(s) differ";
  if (boxes == 0) out += "the reference frame has no box pixels";
  return out;
}

}  // namespace nns::test::bbox

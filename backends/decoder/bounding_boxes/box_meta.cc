// SPDX-License-Identifier: LGPL-2.1-only
#include "box_meta.h"

#include <gst/video/gstvideometa.h>

#include <cstdio>
#include <mutex>

namespace nns::bbox {

namespace {
const char *roi_type(const OutBox &o) {
  return o.label ? o.label->c_str() : "object";
}

void append_escaped(std::string &out, const std::string &s) {
  out += '"';
  for (char c : s) {
    switch (c) {
      case '"':
        out += "\\\"";
        break;
      case '\\':
        out += "\\\\";
        break;
      case '\n':
        out += "\\n";
        break;
      case '\t':
        out += "\\t";
        break;
      default:
        if (static_cast<unsigned char>(c) < 0x20) {
          char b[8];
          std::snprintf(b, sizeof b, "\\u%04x", c);
          out += b;
        } else {
          out += c;
        }
    }
  }
  out += '"';
}

void append_num(std::string &out, double v) {
  char b[32];
  std::snprintf(b, sizeof b, "%.6g", v);
  out += b;
}
}  // namespace

void add_roi_metas(GstBuffer *buf, const std::vector<OutBox> &boxes) {
  for (const auto &o : boxes) {
    GstVideoRegionOfInterestMeta *m = gst_buffer_add_video_region_of_interest_meta(
        buf, roi_type(o), static_cast<guint>(o.x), static_cast<guint>(o.y), static_cast<guint>(o.w),
        static_cast<guint>(o.h));
    if (!m) continue;
    m->id = o.box->track_id;
    GstStructure *s = gst_structure_new("detection", "class-id", G_TYPE_INT, o.box->class_id,
                                        "label", G_TYPE_STRING, o.label ? o.label->c_str() : "",
                                        "score", G_TYPE_DOUBLE, static_cast<double>(o.box->score),
                                        "track-id", G_TYPE_INT, o.box->track_id, "angle",
                                        G_TYPE_DOUBLE, static_cast<double>(o.box->angle), nullptr);
    if (!o.box->keypoints.empty()) {
      GValue arr = G_VALUE_INIT, v = G_VALUE_INIT;
      g_value_init(&arr, GST_TYPE_ARRAY);
      g_value_init(&v, G_TYPE_DOUBLE);
      for (const auto &[kx, ky] : o.box->keypoints) {
        g_value_set_double(&v, static_cast<double>(kx * o.sx));
        gst_value_array_append_value(&arr, &v);
        g_value_set_double(&v, static_cast<double>(ky * o.sy));
        gst_value_array_append_value(&arr, &v);
      }
      gst_structure_take_value(s, "keypoints", &arr);
      g_value_unset(&v);
    }
    gst_video_region_of_interest_meta_add_param(m, s);
  }
}

void build_json(std::string &out, unsigned width, unsigned height,
                const std::vector<OutBox> &boxes) {
  out.clear();
  out += "{\"width\":" + std::to_string(width) + ",\"height\":" + std::to_string(height) +
         ",\"boxes\":[";
  bool first = true;
  for (const auto &o : boxes) {
    if (!first) out += ',';
    first = false;
    out += "{\"x\":" + std::to_string(o.x) + ",\"y\":" + std::to_string(o.y) +
           ",\"w\":" + std::to_string(o.w) + ",\"h\":" + std::to_string(o.h) +
           ",\"class_id\":" + std::to_string(o.box->class_id) + ",\"label\":";
    append_escaped(out, o.label ? *o.label : std::string());
    out += ",\"score\":";
    append_num(out, o.box->score);
    out += ",\"track_id\":" + std::to_string(o.box->track_id) + ",\"angle\":";
    append_num(out, o.box->angle);
    if (!o.box->keypoints.empty()) {
      out += ",\"keypoints\":[";
      bool f2 = true;
      for (const auto &[kx, ky] : o.box->keypoints) {
        if (!f2) out += ',';
        f2 = false;
        out += '[';
        append_num(out, kx * o.sx);
        out += ',';
        append_num(out, ky * o.sy);
        out += ']';
      }
      out += ']';
    }
    out += '}';
  }
  out += "]}";
}

void add_json_meta(GstBuffer *buf, const std::string &json) {
  static std::once_flag once;
  std::call_once(once, [] {
    if (!gst_meta_get_info(kDetectionsMetaName)) {
      static const gchar *tags[] = {nullptr};
      gst_meta_register_custom(kDetectionsMetaName, tags, nullptr, nullptr, nullptr);
    }
  });
  GstCustomMeta *m = gst_buffer_add_custom_meta(buf, kDetectionsMetaName);
  if (!m) return;
  gst_structure_set(gst_custom_meta_get_structure(m), "json", G_TYPE_STRING, json.c_str(), nullptr);
}

}  // namespace nns::bbox

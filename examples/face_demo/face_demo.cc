// SPDX-License-Identifier: LGPL-2.1-only
/**
 * nns-face-demo: finds faces in a photo with BlazeFace through an NNStreamer pipeline and prints
 * their boxes in pixels of the original photo.
 *
 *   filesrc location=PHOTO ! decodebin ! videoconvert ! videoscale !
 *   video/x-raw,format=RGB,width=128,height=128 ! tensor_converter !
 *   tensor_transform mode=arithmetic option=typecast:float32,div:127.5,add:-1 !
 *   tensor_filter framework=onnxruntime model=face_detection_front_128x128_barracuda.onnx !
 *   tensor_sink name=sink
 *
 * The four output tensors (scores and regressors of 896 anchors) are decoded with MediaPipe's
 * anchors, a sigmoid score threshold and weighted non-maximum suppression
 * (examples/face_demo/blazeface.h, src/core/ssd_decode.h). `--output boxes.png` also writes
 * the photo with the boxes and keypoints drawn.
 *
 * usage: nns-face-demo --image PHOTO --model MODEL.onnx [--output OUT.png] [--threshold 0.5]
 *                      [--framework onnxruntime] [--custom NumThreads:1]
 * exit:  0 ok (faces printed, possibly none), 1 error, 2 usage, 77 a needed element is missing
 */
#include <gst/app/gstappsink.h>
#include <gst/app/gstappsrc.h>
#include <gst/gst.h>
#include <gst/video/video.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "../common/run_to_eos.h"
#include "blazeface.h"

namespace {

struct Args {
  std::string image, model, output, framework = "onnxruntime", custom;
  float threshold = 0.5f;
};

struct Photo {
  int width = 0, height = 0, stride = 0;
  std::vector<uint8_t> rgb;
};

int usage(const char *msg) {
  std::fprintf(stderr,
               "nns-face-demo: %s\nusage: nns-face-demo --image PHOTO --model MODEL.onnx "
               "[--output OUT.png] [--threshold 0.5] [--framework onnxruntime] [--custom K:V]\n",
               msg);
  return 2;
}

// Runs the pipeline to EOS; returns "" or the error text.
std::string run(GstElement *pipeline) {
  return nns_example::run_to_eos(pipeline, 60, "timed out");
}

GstElement *parse(const std::string &desc, std::string &err) {
  GError *e = nullptr;
  GstElement *p = gst_parse_launch(desc.c_str(), &e);
  if (e) {
    err = e->message;
    g_error_free(e);
    if (p) gst_object_unref(p);
    return nullptr;
  }
  return p;
}

std::string quoted(const std::string &s) {
  std::string q = "\"";
  for (char c : s) q += (c == '"' || c == '\\') ? std::string("\\") + c : std::string(1, c);
  return q + "\"";
}

// The original photo as RGB (for its size and for drawing).
bool load_photo(const std::string &path, Photo &ph, std::string &err) {
  GstElement *p = parse("filesrc location=" + quoted(path) +
                            " ! decodebin ! videoconvert ! video/x-raw,format=RGB ! "
                            "appsink name=s sync=false",
                        err);
  if (!p) return false;
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "s");
  gst_element_set_state(p, GST_STATE_PLAYING);
  GstSample *s = gst_app_sink_try_pull_sample(GST_APP_SINK(sink), 30 * GST_SECOND);
  bool ok = false;
  if (s) {
    GstVideoInfo vi;
    GstMapInfo map;
    GstBuffer *b = gst_sample_get_buffer(s);
    if (gst_video_info_from_caps(&vi, gst_sample_get_caps(s)) &&
        gst_buffer_map(b, &map, GST_MAP_READ)) {
      ph.width = GST_VIDEO_INFO_WIDTH(&vi);
      ph.height = GST_VIDEO_INFO_HEIGHT(&vi);
      ph.stride = GST_VIDEO_INFO_PLANE_STRIDE(&vi, 0);
      ph.rgb.assign(map.data, map.data + map.size);
      gst_buffer_unmap(b, &map);
      ok = true;
    }
    gst_sample_unref(s);
  } else {
    GstBus *bus = gst_element_get_bus(p);
    if (GstMessage *m = gst_bus_pop_filtered(bus, GST_MESSAGE_ERROR)) {
      GError *e = nullptr;
      gst_message_parse_error(m, &e, nullptr);
      err = e->message;
      g_error_free(e);
      gst_message_unref(m);
    } else {
      err = "no picture decoded";
    }
    gst_object_unref(bus);
  }
  gst_element_set_state(p, GST_STATE_NULL);
  gst_object_unref(sink);
  gst_object_unref(p);
  return ok;
}

void put(Photo &ph, int x, int y, const uint8_t c[3]) {
  if (x < 0 || y < 0 || x >= ph.width || y >= ph.height) return;
  std::memcpy(&ph.rgb[static_cast<std::size_t>(y) * ph.stride + 3 * x], c, 3);
}

void draw(Photo &ph, const std::vector<nns::ssd::Detection> &faces) {
  const uint8_t green[3] = {0, 255, 0}, red[3] = {255, 0, 0};
  for (const auto &f : faces) {
    int x0 = std::lround(f.xmin * ph.width), x1 = std::lround(f.xmax * ph.width);
    int y0 = std::lround(f.ymin * ph.height), y1 = std::lround(f.ymax * ph.height);
    for (int t = 0; t < 3; ++t) {
      for (int x = x0; x <= x1; ++x) put(ph, x, y0 + t, green), put(ph, x, y1 - t, green);
      for (int y = y0; y <= y1; ++y) put(ph, x0 + t, y, green), put(ph, x1 - t, y, green);
    }
    for (const auto &k : f.keypoints) {
      int kx = std::lround(k.first * ph.width), ky = std::lround(k.second * ph.height);
      for (int dy = -2; dy <= 2; ++dy)
        for (int dx = -2; dx <= 2; ++dx) put(ph, kx + dx, ky + dy, red);
    }
  }
}

bool save_png(const Photo &ph, const std::string &path, std::string &err) {
  GstElement *p =
      parse("appsrc name=src ! videoconvert ! pngenc ! filesink location=" + quoted(path), err);
  if (!p) return false;
  GstElement *src = gst_bin_get_by_name(GST_BIN(p), "src");
  GstCaps *caps = gst_caps_new_simple("video/x-raw", "format", G_TYPE_STRING, "RGB", "width",
                                      G_TYPE_INT, ph.width, "height", G_TYPE_INT, ph.height,
                                      "framerate", GST_TYPE_FRACTION, 0, 1, nullptr);
  g_object_set(src, "caps", caps, "format", GST_FORMAT_TIME, nullptr);
  gst_caps_unref(caps);
  GstBuffer *buf = gst_buffer_new_memdup(ph.rgb.data(), ph.rgb.size());
  GST_BUFFER_PTS(buf) = 0;
  gst_app_src_push_buffer(GST_APP_SRC(src), buf);
  gst_app_src_end_of_stream(GST_APP_SRC(src));
  err = run(p);
  gst_object_unref(src);
  gst_object_unref(p);
  return err.empty();
}

struct Result {
  std::vector<std::vector<float>> tensors;
};

void on_new_data(GstElement *, GstBuffer *buf, gpointer data) {
  auto *r = static_cast<Result *>(data);
  r->tensors.clear();
  for (guint i = 0; i < gst_buffer_n_memory(buf); ++i) {
    GstMemory *m = gst_buffer_peek_memory(buf, i);
    GstMapInfo map;
    if (!gst_memory_map(m, &map, GST_MAP_READ)) continue;
    const auto *f = reinterpret_cast<const float *>(map.data);
    r->tensors.emplace_back(f, f + map.size / sizeof(float));
    gst_memory_unmap(m, &map);
  }
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  Args a;
  for (int i = 1; i < argc; ++i) {
    std::string k = argv[i];
    if (i + 1 >= argc) return usage(("missing value after " + k).c_str());
    std::string v = argv[++i];
    if (k == "--image")
      a.image = v;
    else if (k == "--model")
      a.model = v;
    else if (k == "--output")
      a.output = v;
    else if (k == "--framework")
      a.framework = v;
    else if (k == "--custom")
      a.custom = v;
    else if (k == "--threshold")
      a.threshold = std::stof(v);
    else
      return usage(("unknown option " + k).c_str());
  }
  if (a.image.empty() || a.model.empty()) return usage("--image and --model are required");
  for (const char *e : {"tensor_converter", "tensor_transform", "tensor_filter", "tensor_sink"}) {
    if (GstElementFactory *f = gst_element_factory_find(e)) {
      gst_object_unref(f);
    } else {
      std::fprintf(stderr, "nns-face-demo: element %s is not available (not built yet?)\n", e);
      return 77;
    }
  }

  std::string err;
  Photo photo;
  if (!load_photo(a.image, photo, err)) {
    std::fprintf(stderr, "nns-face-demo: cannot read %s: %s\n", a.image.c_str(), err.c_str());
    return 1;
  }
  const std::string size = std::to_string(nns::face::kInputSize);
  std::string desc =
      "filesrc location=" + quoted(a.image) +
      " ! decodebin ! videoconvert ! videoscale ! video/x-raw,format=RGB,width=" + size +
      ",height=" + size +
      " ! tensor_converter ! tensor_transform mode=arithmetic "
      "option=typecast:float32,div:127.5,add:-1 ! tensor_filter framework=" +
      a.framework + " model=" + quoted(a.model) +
      (a.custom.empty() ? "" : " custom=" + quoted(a.custom)) + " ! tensor_sink name=sink";
  std::printf("pipeline: %s\n", desc.c_str());
  GstElement *p = parse(desc, err);
  if (!p) {
    std::fprintf(stderr, "nns-face-demo: %s\n", err.c_str());
    return 1;
  }
  Result res;
  GstElement *sink = gst_bin_get_by_name(GST_BIN(p), "sink");
  g_signal_connect(sink, "new-data", G_CALLBACK(on_new_data), &res);
  gint64 t0 = g_get_monotonic_time();
  err = run(p);
  gint64 t1 = g_get_monotonic_time();
  gst_object_unref(sink);
  gst_object_unref(p);
  if (!err.empty()) {
    std::fprintf(stderr, "nns-face-demo: pipeline error: %s\n", err.c_str());
    return 1;
  }
  const auto &t = res.tensors;
  if (t.size() != 4 || t[0].size() != nns::face::kAnchorsStride8 ||
      t[1].size() != nns::face::kAnchorsStride16 || t[2].size() != 16 * t[0].size() ||
      t[3].size() != 16 * t[1].size()) {
    std::fprintf(stderr,
                 "nns-face-demo: expected BlazeFace's 4 output tensors (512, 384, 512x16, "
                 "384x16 floats), got %zu tensors\n",
                 t.size());
    return 1;
  }
  nns::face::Options opt;
  opt.min_score = a.threshold;
  auto faces = nns::face::decode_front(t[0].data(), t[1].data(), t[2].data(), t[3].data(), opt);
  std::printf("photo: %s (%dx%d), %zu face(s), pipeline %.0f ms\n", a.image.c_str(), photo.width,
              photo.height, faces.size(), (t1 - t0) / 1000.0);
  static const char *kKeypoints[] = {"right eye", "left eye",  "nose",
                                     "mouth",     "right ear", "left ear"};
  for (std::size_t i = 0; i < faces.size(); ++i) {
    const auto &f = faces[i];
    std::printf("face %zu: score %.2f box x=%ld y=%ld w=%ld h=%ld\n", i + 1, f.score,
                std::lround(f.xmin * photo.width), std::lround(f.ymin * photo.height),
                std::lround(f.width() * photo.width), std::lround(f.height() * photo.height));
    std::printf("        ");
    for (std::size_t k = 0; k < f.keypoints.size() && k < 4; ++k)
      std::printf("%s%s (%ld,%ld)", k ? ", " : "", kKeypoints[k],
                  std::lround(f.keypoints[k].first * photo.width),
                  std::lround(f.keypoints[k].second * photo.height));
    std::printf("\n");
  }
  if (!a.output.empty()) {
    draw(photo, faces);
    if (!save_png(photo, a.output, err)) {
      std::fprintf(stderr, "nns-face-demo: cannot write %s: %s\n", a.output.c_str(), err.c_str());
      return 1;
    }
    std::printf("boxes drawn into %s\n", a.output.c_str());
  }
  return 0;
}

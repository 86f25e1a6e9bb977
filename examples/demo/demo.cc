// SPDX-License-Identifier: LGPL-2.1-only
/**
 * nns-demo: runs an image through a tensor pipeline and prints what reaches tensor_sink.
 *
 * The default pipeline decodes a PNG, scales it to 224x224 RGB, converts it to a tensor and
 * normalises it to float32 in [-1, 1]; a tee writes the tensor bytes to a file and hands them to
 * tensor_sink, whose new-data signal prints dims, type, byte count, SHA-256 and value statistics:
 *
 *   filesrc location=IMG ! pngdec ! videoconvert ! videoscale !
 *   video/x-raw,format=RGB,width=224,height=224 ! tensor_converter !
 *   tensor_transform mode=arithmetic option=typecast:float32,add:-127.5,div:127.5 ! tee name=t
 *   t. ! queue ! filesink location=OUT   t. ! queue ! tensor_sink name=sink
 *
 * Like any application it loads the nnstreamer plugin through GStreamer (GST_PLUGIN_PATH; see
 * build/env.sh). `--stage "<elements>"` inserts more elements after the transform (e.g. a
 * tensor_filter), `--pipeline "<desc>"` replaces the whole description (it must contain
 * `tensor_sink name=sink`).
 *
 * usage: nns-demo --image FILE.png [--output FILE] [--stage DESC] [--pipeline DESC]
 * exit:  0 ok, 1 pipeline error, 2 usage, 77 a needed element is missing (demo skipped)
 */
#include <glib/gstdio.h>
#include <gst/gst.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <limits>
#include <string>
#include <vector>

namespace {

struct TensorDesc {
  std::string type;
  std::string dims;
};

struct DemoState {
  std::vector<TensorDesc> tensors;
  std::string format = "static";
  int frames = 0;
  std::size_t last_bytes = 0;
};

std::vector<std::string> split_list(const std::string &s) {
  std::vector<std::string> out;
  std::string cur;
  for (char c : s) {
    if (c == ',' || c == '.') {
      out.push_back(cur);
      cur.clear();
    } else if (c != ' ') {
      cur += c;
    }
  }
  if (!cur.empty()) out.push_back(cur);
  return out;
}

// Reads dims/types from the negotiated caps (other/tensors or the legacy other/tensor).
void read_caps(GstCaps *caps, DemoState *st) {
  st->tensors.clear();
  if (!caps || gst_caps_is_empty(caps)) return;
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  if (gst_structure_has_name(s, "other/tensor")) {
    const char *d = gst_structure_get_string(s, "dimension");
    const char *t = gst_structure_get_string(s, "type");
    st->tensors.push_back({t ? t : "?", d ? d : "?"});
    return;
  }
  if (const char *f = gst_structure_get_string(s, "format")) st->format = f;
  const char *d = gst_structure_get_string(s, "dimensions");
  const char *t = gst_structure_get_string(s, "types");
  auto dl = split_list(d ? d : "");
  auto tl = split_list(t ? t : "");
  for (std::size_t i = 0; i < std::max(dl.size(), tl.size()); ++i)
    st->tensors.push_back({i < tl.size() ? tl[i] : "?", i < dl.size() ? dl[i] : "?"});
}

template <typename T>
void print_stats(const uint8_t *data, std::size_t bytes) {
  std::size_t n = bytes / sizeof(T);
  if (n == 0) return;
  double mn = std::numeric_limits<double>::max(), mx = -mn, sum = 0;
  for (std::size_t i = 0; i < n; ++i) {
    T v;
    std::memcpy(&v, data + i * sizeof(T), sizeof(T));
    double x = static_cast<double>(v);
    mn = std::min(mn, x);
    mx = std::max(mx, x);
    sum += x;
  }
  std::printf(" min=%g max=%g mean=%.6g", mn, mx, sum / static_cast<double>(n));
}

void print_tensor(std::size_t i, const TensorDesc &d, const uint8_t *data, std::size_t bytes) {
  gchar *sha = g_compute_checksum_for_data(G_CHECKSUM_SHA256, data, bytes);
  std::printf("nns-demo:   tensor[%zu] type=%s dims=%s bytes=%zu sha256=%s", i, d.type.c_str(),
              d.dims.c_str(), bytes, sha);
  g_free(sha);
  if (d.type == "float32")
    print_stats<float>(data, bytes);
  else if (d.type == "float64")
    print_stats<double>(data, bytes);
  else if (d.type == "uint8")
    print_stats<uint8_t>(data, bytes);
  else if (d.type == "int8")
    print_stats<int8_t>(data, bytes);
  else if (d.type == "int32")
    print_stats<int32_t>(data, bytes);
  std::printf("\n");
}

void on_new_data(GstElement *sink, GstBuffer *buf, gpointer user) {
  auto *st = static_cast<DemoState *>(user);
  if (st->frames == 0) {
    GstPad *pad = gst_element_get_static_pad(sink, "sink");
    GstCaps *caps = gst_pad_get_current_caps(pad);
    read_caps(caps, st);
    if (caps) gst_caps_unref(caps);
    gst_object_unref(pad);
    std::printf("nns-demo: stream of %zu tensor(s), format=%s\n", st->tensors.size(),
                st->format.c_str());
  }
  ++st->frames;
  st->last_bytes = gst_buffer_get_size(buf);
  std::printf("nns-demo: frame %d pts=%" GST_TIME_FORMAT " bytes=%zu memories=%u\n", st->frames,
              GST_TIME_ARGS(GST_BUFFER_PTS(buf)), st->last_bytes, gst_buffer_n_memory(buf));
  // One GstMemory per tensor (frames with up to 16 tensors; more are packed in the last one).
  for (guint i = 0; i < gst_buffer_n_memory(buf); ++i) {
    GstMemory *mem = gst_buffer_peek_memory(buf, i);
    GstMapInfo map;
    if (!gst_memory_map(mem, &map, GST_MAP_READ)) continue;
    TensorDesc d = i < st->tensors.size() ? st->tensors[i] : TensorDesc{"?", "?"};
    print_tensor(i, d, map.data, map.size);
    gst_memory_unmap(mem, &map);
  }
  std::fflush(stdout);
}

bool has_element(const char *name) {
  GstElementFactory *f = gst_element_factory_find(name);
  if (f) gst_object_unref(f);
  return f != nullptr;
}

int usage(const char *argv0) {
  std::fprintf(stderr,
               "usage: %s --image FILE.png [--output FILE] [--stage \"<elements>\"] "
               "[--pipeline \"<description with tensor_sink name=sink>\"]\n",
               argv0);
  return 2;
}

}  // namespace

int main(int argc, char **argv) {
  gst_init(&argc, &argv);
  std::string image, output, stage, pipeline_desc;
  for (int i = 1; i < argc; ++i) {
    std::string a = argv[i];
    auto next = [&](std::string *dst) {
      if (i + 1 >= argc) return false;
      *dst = argv[++i];
      return true;
    };
    bool ok = (a == "--image")      ? next(&image)
              : (a == "--output")   ? next(&output)
              : (a == "--stage")    ? next(&stage)
              : (a == "--pipeline") ? next(&pipeline_desc)
                                    : false;
    if (!ok) return usage(argv[0]);
  }
  if (pipeline_desc.empty()) {
    if (image.empty()) return usage(argv[0]);
    for (const char *e : {"tensor_converter", "tensor_transform", "tensor_sink"}) {
      if (!has_element(e)) {
        std::printf(
            "nns-demo: SKIP: element %s is not available (not built yet, or the plugin "
            "is not on GST_PLUGIN_PATH: source build/env.sh)\n",
            e);
        return 77;
      }
    }
    gchar *loc = g_strescape(image.c_str(), nullptr);
    pipeline_desc = std::string("filesrc location=\"") + loc +
                    "\" ! pngdec ! videoconvert ! videoscale ! "
                    "video/x-raw,format=RGB,width=224,height=224 ! tensor_converter ! "
                    "tensor_transform mode=arithmetic option=typecast:float32,add:-127.5,div:127.5";
    g_free(loc);
    if (!stage.empty()) pipeline_desc += " ! " + stage;
    if (!output.empty()) {
      gchar *out = g_strescape(output.c_str(), nullptr);
      pipeline_desc += std::string(" ! tee name=t t. ! queue ! filesink location=\"") + out +
                       "\" t. ! queue ! tensor_sink name=sink";
      g_free(out);
    } else {
      pipeline_desc += " ! tensor_sink name=sink";
    }
  }
  std::printf("nns-demo: pipeline: %s\n", pipeline_desc.c_str());

  GError *err = nullptr;
  GstElement *pipeline = gst_parse_launch(pipeline_desc.c_str(), &err);
  if (!pipeline || err) {
    std::fprintf(stderr, "nns-demo: cannot build the pipeline: %s\n",
                 err ? err->message : "unknown error");
    if (err) g_error_free(err);
    if (pipeline) gst_object_unref(pipeline);
    return 1;
  }
  GstElement *sink = gst_bin_get_by_name(GST_BIN(pipeline), "sink");
  if (!sink) {
    std::fprintf(stderr, "nns-demo: the pipeline has no element named 'sink'\n");
    gst_object_unref(pipeline);
    return 2;
  }
  DemoState st;
  g_signal_connect(sink, "new-data", G_CALLBACK(on_new_data), &st);

  auto t0 = std::chrono::steady_clock::now();
  gst_element_set_state(pipeline, GST_STATE_PLAYING);
  GstBus *bus = gst_element_get_bus(pipeline);
  GstMessage *msg = gst_bus_timed_pop_filtered(
      bus, 60 * GST_SECOND, static_cast<GstMessageType>(GST_MESSAGE_EOS | GST_MESSAGE_ERROR));
  double secs = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  int rc = 0;
  if (!msg) {
    std::fprintf(stderr, "nns-demo: timed out after 60 s\n");
    rc = 1;
  } else if (GST_MESSAGE_TYPE(msg) == GST_MESSAGE_ERROR) {
    GError *e = nullptr;
    gchar *dbg = nullptr;
    gst_message_parse_error(msg, &e, &dbg);
    std::fprintf(stderr, "nns-demo: ERROR from %s: %s\n  %s\n", GST_MESSAGE_SRC_NAME(msg),
                 e->message, dbg ? dbg : "");
    g_error_free(e);
    g_free(dbg);
    rc = 1;
  }
  if (msg) gst_message_unref(msg);
  gst_element_set_state(pipeline, GST_STATE_NULL);
  gst_object_unref(bus);
  gst_object_unref(sink);
  gst_object_unref(pipeline);

  if (rc == 0 && st.frames == 0) {
    std::fprintf(stderr, "nns-demo: the pipeline ended without any tensor frame\n");
    rc = 1;
  }
  if (rc == 0 && !output.empty()) {
    GStatBuf sb;
    if (g_stat(output.c_str(), &sb) != 0 ||
        static_cast<std::size_t>(sb.st_size) != st.last_bytes * st.frames) {
      std::fprintf(stderr, "nns-demo: %s does not hold the %d frame(s) of %zu bytes\n",
                   output.c_str(), st.frames, st.last_bytes);
      rc = 1;
    } else {
      std::printf("nns-demo: wrote %zu bytes to %s\n", st.last_bytes * st.frames, output.c_str());
    }
  }
  if (rc == 0) std::printf("nns-demo: %d frame(s) in %.3f s: OK\n", st.frames, secs);
  return rc;
}

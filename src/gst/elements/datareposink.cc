// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-datareposink
 *
 * Writes a stream to an NNStreamer data repository: the samples go to `location`, their meta
 * (caps, count, sizes) to `json` when the element stops (src/core/datarepo/datarepo_meta.h).
 * Files are NNStreamer's format, so NNStreamer's datareposrc reads them and ours reads theirs.
 *
 * - static tensors, video, audio, text, octet streams: each buffer is one sample, appended as is
 *   (all samples must have one size: the meta records `sample_size`);
 * - flexible and sparse tensors: each tensor is written with its 128-byte header; the meta
 *   records each sample's offset, each tensor's size and each sample's first tensor;
 * - images (image/png, image/jpeg, ...): one file per sample, `location` holding the index as
 *   %d / %04d (image_%04d.png).
 *
 *   gst-launch-1.0 videotestsrc num-buffers=10 ! video/x-raw,format=RGB,width=64,height=48 ! \
 *     datareposink location=video.dat json=video.json
 */
#include <fcntl.h>
#include <gst/base/gstbasesink.h>
#include <sys/uio.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <fstream>
#include <mutex>
#include <vector>

#include "core/datarepo/datarepo_meta.h"
#include "core/meta_header.h"
#include "gst/datarepo/datarepo_common.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"

GST_DEBUG_CATEGORY_STATIC(datareposink_debug);
#define GST_CAT_DEFAULT datareposink_debug

G_BEGIN_DECLS
#define GST_TYPE_DATA_REPO_SINK (gst_data_repo_sink_get_type())
G_DECLARE_FINAL_TYPE(GstDataRepoSink, gst_data_repo_sink, GST, DATA_REPO_SINK, GstBaseSink)
G_END_DECLS

namespace {

using nns::ErrorKind;
using nns::fail;
using nns::gst::datarepo::Kind;

struct SinkPriv {
  std::mutex lock;  // guards the two settings
  std::string location, json;
  // run state (streaming thread, start/stop)
  int fd = -1;
  Kind kind = Kind::kUnknown;
  nns::datarepo::Meta meta;
  uint64_t written = 0;  // bytes in the sample file
  std::string run_location, run_json;
};

enum { PROP_0, PROP_LOCATION, PROP_JSON };

}  // namespace

struct _GstDataRepoSink {
  GstBaseSink parent;
  SinkPriv *priv;
};

G_DEFINE_TYPE(GstDataRepoSink, gst_data_repo_sink, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(datareposink, "datareposink", GST_RANK_NONE, GST_TYPE_DATA_REPO_SINK)

#define DATAREPO_VIDEO_FORMATS "{ RGB, BGR, RGBx, BGRx, xRGB, xBGR, RGBA, BGRA, ARGB, ABGR, GRAY8 }"
#define DATAREPO_AUDIO_FORMATS                                                              \
  "{ S8, U8, S16LE, S16BE, U16LE, U16BE, S32LE, S32BE, U32LE, U32BE, F32LE, F32BE, F64LE, " \
  "F64BE }"

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS(
        "other/tensors, format = (string) { static, flexible, sparse }, "
        "framerate = (fraction) [ 0, max ]; "
        "video/x-raw, format = (string) " DATAREPO_VIDEO_FORMATS
        ", width = (int) [ 1, max ], height = (int) [ 1, max ], framerate = (fraction) [ 0, max "
        "], interlace-mode = (string) progressive; "
        "audio/x-raw, format = (string) " DATAREPO_AUDIO_FORMATS
        ", rate = (int) [ 1, max ], channels = (int) [ 1, max ], layout = (string) interleaved; "
        "image/png, width = (int) [ 16, 1000000 ], height = (int) [ 16, 1000000 ], "
        "framerate = (fraction) [ 0, max ]; "
        "image/jpeg, width = (int) [ 16, 65535 ], height = (int) [ 16, 65535 ], "
        "framerate = (fraction) [ 0, max ], sof-marker = (int) { 0, 1, 2, 4, 9 }; "
        "image/tiff, endianness = (int) { 4321, 1234 }; image/gif; image/bmp; "
        "text/x-raw, format = (string) utf8; application/octet-stream"));

static void gst_data_repo_sink_set_property(GObject *object, guint id, const GValue *value,
                                            GParamSpec *pspec) {
  auto *p = GST_DATA_REPO_SINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  const gchar *v = nullptr;
  switch (id) {
    case PROP_LOCATION:
      v = g_value_get_string(value);
      p->location = v ? v : "";
      break;
    case PROP_JSON:
      v = g_value_get_string(value);
      p->json = v ? v : "";
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_data_repo_sink_get_property(GObject *object, guint id, GValue *value,
                                            GParamSpec *pspec) {
  auto *p = GST_DATA_REPO_SINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  switch (id) {
    case PROP_LOCATION:
      g_value_set_string(value, p->location.empty() ? nullptr : p->location.c_str());
      break;
    case PROP_JSON:
      g_value_set_string(value, p->json.empty() ? nullptr : p->json.c_str());
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static gboolean sink_start(GstBaseSink *bsink) {
  auto *self = GST_DATA_REPO_SINK(bsink);
  auto *p = self->priv;
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    {
      std::lock_guard<std::mutex> l(p->lock);
      p->run_location = p->location;
      p->run_json = p->json;
    }
    if (p->run_location.empty())
      fail(ErrorKind::kSettings, "location is not set (the sample file to write)");
    if (p->run_json.empty())
      fail(ErrorKind::kSettings,
           "json is not set (the meta file to write beside " + p->run_location + ")");
    p->kind = Kind::kUnknown;
    p->meta = nns::datarepo::Meta();
    p->written = 0;
    return TRUE;
  });
}

// Writes the JSON meta (when anything was received) and closes the sample file.
static gboolean sink_stop(GstBaseSink *bsink) {
  auto *self = GST_DATA_REPO_SINK(bsink);
  auto *p = self->priv;
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    if (p->fd >= 0) {
      ::close(p->fd);
      p->fd = -1;
    }
    if (p->kind == Kind::kUnknown || p->meta.total_samples == 0) return TRUE;
    std::ofstream f(p->run_json, std::ios::trunc);
    f << nns::datarepo::write_meta(p->meta);
    f.close();
    if (!f)
      fail(ErrorKind::kLibrary,
           "json: cannot write the meta file " + p->run_json + ": " + std::strerror(errno));
    p->kind = Kind::kUnknown;
    return TRUE;
  });
}

static gboolean sink_set_caps(GstBaseSink *bsink, GstCaps *caps) {
  auto *self = GST_DATA_REPO_SINK(bsink);
  auto *p = self->priv;
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    Kind k = nns::gst::datarepo::kind_of(caps);
    gchar *str = gst_caps_to_string(caps);
    std::string caps_str = str;
    g_free(str);
    if (k == Kind::kUnknown) fail(ErrorKind::kNegotiation, "cannot store caps " + caps_str);
    if (p->kind != Kind::kUnknown && caps_str != p->meta.caps)
      fail(ErrorKind::kNegotiation, "the stream changed caps from " + p->meta.caps + " to " +
                                        caps_str + "; a data repository holds one format");
    p->kind = k;
    p->meta.caps = caps_str;
    if (k == Kind::kImage) {
      nns::gst::datarepo::check_index_pattern(p->run_location, "location");
      return TRUE;
    }
    if (p->fd < 0) {
      p->fd = ::open(p->run_location.c_str(), O_WRONLY | O_CREAT | O_TRUNC | O_CLOEXEC, 0644);
      if (p->fd < 0)
        fail(ErrorKind::kNotFound,
             "location: cannot create " + p->run_location + ": " + std::strerror(errno));
    }
    return TRUE;
  });
}

// Writes every memory of `buf` in order (no merge copy); returns the bytes written.
static uint64_t write_memories(GstDataRepoSink *self, GstBuffer *buf) {
  auto *p = self->priv;
  const guint n = gst_buffer_n_memory(buf);
  std::vector<GstMapInfo> maps(n);
  std::vector<iovec> iov(n);
  guint mapped = 0;
  uint64_t total = 0;
  for (; mapped < n; ++mapped) {
    GstMemory *m = gst_buffer_peek_memory(buf, mapped);
    if (!gst_memory_map(m, &maps[mapped], GST_MAP_READ)) break;
    iov[mapped] = {maps[mapped].data, maps[mapped].size};
    total += maps[mapped].size;
  }
  std::string err;
  if (mapped < n) {
    err = "cannot map memory " + std::to_string(mapped) + " of the buffer";
  } else {
    std::size_t done_iov = 0;
    while (done_iov < n && err.empty()) {
      ssize_t w = ::writev(p->fd, iov.data() + done_iov, static_cast<int>(n - done_iov));
      if (w < 0) {
        if (errno == EINTR) continue;
        err = std::string("cannot write ") + p->run_location + ": " + std::strerror(errno);
        break;
      }
      auto left = static_cast<std::size_t>(w);
      while (done_iov < n && left >= iov[done_iov].iov_len) left -= iov[done_iov++].iov_len;
      if (done_iov < n) {
        iov[done_iov].iov_base = static_cast<uint8_t *>(iov[done_iov].iov_base) + left;
        iov[done_iov].iov_len -= left;
      }
    }
  }
  for (guint i = 0; i < mapped; ++i) gst_memory_unmap(gst_buffer_peek_memory(buf, i), &maps[i]);
  if (!err.empty()) fail(ErrorKind::kLibrary, err);
  return total;
}

static void render_fixed(GstDataRepoSink *self, GstBuffer *buf) {
  auto *p = self->priv;
  const uint64_t size = gst_buffer_get_size(buf);
  auto &m = p->meta;
  if (m.total_samples > 0 && size != m.sample_size)
    fail(ErrorKind::kStream, "sample " + std::to_string(m.total_samples) + " is " +
                                 std::to_string(size) + " bytes but the earlier samples are " +
                                 std::to_string(m.sample_size) + " bytes: a data repository of " +
                                 nns::gst::datarepo::kind_name(p->kind) +
                                 " holds samples of one size (flexible tensors may vary)");
  p->written += write_memories(self, buf);
  m.sample_size = size;
  ++m.total_samples;
}

static void write_all(SinkPriv *p, const uint8_t *data, std::size_t size) {
  while (size > 0) {
    ssize_t w = ::write(p->fd, data, size);
    if (w < 0 && errno == EINTR) continue;
    if (w < 0)
      fail(ErrorKind::kLibrary,
           std::string("cannot write ") + p->run_location + ": " + std::strerror(errno));
    data += w;
    size -= static_cast<std::size_t>(w);
    p->written += static_cast<uint64_t>(w);
  }
}

// Each tensor (header included) in turn: a buffer with more than 16 tensors packs the rest in
// its last memory, so the memories are not the tensors.
static void render_flexible(GstDataRepoSink *self, GstBuffer *buf) {
  auto *p = self->priv;
  auto &m = p->meta;
  const std::size_t n = nns::gst::buffer_tensor_count(buf);
  m.sample_offset.push_back(p->written);
  m.tensor_count.push_back(m.tensor_size.size());
  for (std::size_t i = 0; i < n; ++i) {
    nns::gst::MemoryPtr mem(nns::gst::buffer_get_tensor(buf, i));
    nns::gst::MemoryMap map(mem.get(), GST_MAP_READ);
    if (!map.ok()) fail(ErrorKind::kStream, "cannot map tensor " + std::to_string(i));
    try {
      nns::parse_meta_header(map.data(), map.size());
    } catch (const nns::Error &e) {
      fail(ErrorKind::kStream, "sample " + std::to_string(m.total_samples) + ", tensor " +
                                   std::to_string(i) + ": " + e.what());
    }
    write_all(p, map.data(), map.size());
    m.tensor_size.push_back(map.size());
  }
  m.sample_size = 0;
  ++m.total_samples;
}

static void render_image(GstDataRepoSink *self, GstBuffer *buf) {
  auto *p = self->priv;
  const std::string name =
      nns::gst::datarepo::format_index(p->run_location, p->meta.total_samples, "location");
  nns::gst::BufferMap map(buf, GST_MAP_READ);
  GError *err = nullptr;
  if (!map.ok() || !g_file_set_contents(name.c_str(), reinterpret_cast<const gchar *>(map.data()),
                                        static_cast<gssize>(map.size()), &err)) {
    std::string why = err ? err->message : "cannot map the buffer";
    if (err) g_error_free(err);
    fail(ErrorKind::kLibrary, "cannot write " + name + ": " + why);
  }
  p->meta.sample_size = map.size();
  ++p->meta.total_samples;
}

static GstFlowReturn sink_render(GstBaseSink *bsink, GstBuffer *buf) {
  auto *self = GST_DATA_REPO_SINK(bsink);
  auto *p = self->priv;
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    switch (p->kind) {
      case Kind::kTensorFlexible:
        render_flexible(self, buf);
        break;
      case Kind::kImage:
        render_image(self, buf);
        break;
      case Kind::kUnknown:
        fail(ErrorKind::kNegotiation, "a buffer arrived before caps");
      default:
        render_fixed(self, buf);
    }
    return GST_FLOW_OK;
  });
}

static void gst_data_repo_sink_finalize(GObject *object) {
  auto *p = GST_DATA_REPO_SINK(object)->priv;
  if (p->fd >= 0) ::close(p->fd);
  delete p;
  G_OBJECT_CLASS(gst_data_repo_sink_parent_class)->finalize(object);
}

static void gst_data_repo_sink_class_init(GstDataRepoSinkClass *klass) {
  GST_DEBUG_CATEGORY_INIT(datareposink_debug, "datareposink", 0, "datareposink");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *base_class = GST_BASE_SINK_CLASS(klass);
  gobject_class->set_property = gst_data_repo_sink_set_property;
  gobject_class->get_property = gst_data_repo_sink_get_property;
  gobject_class->finalize = gst_data_repo_sink_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                     GST_PARAM_MUTABLE_READY);
  g_object_class_install_property(
      gobject_class, PROP_LOCATION,
      g_param_spec_string("location", "File Location",
                          "Location to write files to MLOps Data Repository. if the files are "
                          "images, use placeholder in indexes for filename(e.g., "
                          "filename%04d.png).",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_JSON,
      g_param_spec_string("json", "JSON file path",
                          "JSON file path to write the meta information of a sample", nullptr, rw));
  gst_element_class_set_static_metadata(element_class, "NNStreamer MLOps Data Repository Sink",
                                        "Sink/File", "Write files to MLOps Data Repository",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  base_class->start = sink_start;
  base_class->stop = sink_stop;
  base_class->set_caps = sink_set_caps;
  base_class->render = sink_render;
}

static void gst_data_repo_sink_init(GstDataRepoSink *self) {
  self->priv = new SinkPriv();
}

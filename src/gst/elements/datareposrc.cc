// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-datareposrc
 *
 * Reads the samples of an NNStreamer data repository (`location` + its `json` meta, as
 * datareposink or NNStreamer writes them) as a stream: samples start-sample-index ..
 * stop-sample-index, `epochs` times, in file order or shuffled anew each epoch (`is-shuffle`,
 * seeded by `shuffle-seed`). Output caps are the meta's `gst_caps` (or the `caps` property);
 * `tensors-sequence` picks and orders the tensors of each sample.
 *
 * Every sample is read with one pread; the tensors of a static or flexible sample are shares of
 * that one memory (no copy). The meta is checked against the sample file at start: a truncated
 * file or a meta that disagrees with it is an error naming the sample index and byte offset.
 *
 *   gst-launch-1.0 datareposrc location=mnist.data json=mnist.json epochs=5 ! tensor_sink
 */
#include <fcntl.h>
#include <gst/audio/audio-info.h>
#include <gst/base/gstpushsrc.h>
#include <gst/video/video-info.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <fstream>
#include <memory>
#include <mutex>
#include <optional>
#include <sstream>

#include "core/datarepo/datarepo_meta.h"
#include "core/datarepo/sample_order.h"
#include "core/meta_header.h"
#include "gst/datarepo/datarepo_common.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(datareposrc_debug);
#define GST_CAT_DEFAULT datareposrc_debug

G_BEGIN_DECLS
#define GST_TYPE_DATA_REPO_SRC (gst_data_repo_src_get_type())
G_DECLARE_FINAL_TYPE(GstDataRepoSrc, gst_data_repo_src, GST, DATA_REPO_SRC, GstPushSrc)
G_END_DECLS

namespace {

using nns::ErrorKind;
using nns::fail;
using nns::gst::datarepo::Kind;

struct Settings {
  std::string location, json, sequence;
  guint start = 0, stop = 0, epochs = 1;
  bool shuffle = true;
  guint64 seed = 0;
  GstCaps *caps = nullptr;  // the `caps` property
};

struct Run {
  int fd = -1;
  Kind kind = Kind::kUnknown;
  nns::datarepo::Meta meta;
  std::unique_ptr<nns::datarepo::SampleOrder> order;
  nns::TensorsConfig config;               // static tensors as stored
  std::vector<std::size_t> tensor_offset;  // static: offset of each tensor in a sample
  std::vector<std::size_t> sequence;       // tensors to output, in order (empty: all)
  uint64_t sample_size = 0;
  int rate_n = 0, rate_d = 1;
  uint64_t frames = 0;
  std::string location;
  bool sequential = false;  // not shuffled: read ahead in chunks
  uint64_t file_size = 0;
  nns::gst::MemoryPtr chunk;  // the last chunk read
  uint64_t chunk_offset = 0;
};

struct SrcPriv {
  std::mutex lock;  // guards settings and caps
  Settings s;
  GstCaps *out_caps = nullptr;  // fixed output caps while started
  Run run;
};

enum {
  PROP_0,
  PROP_LOCATION,
  PROP_JSON,
  PROP_START,
  PROP_STOP,
  PROP_EPOCHS,
  PROP_SHUFFLE,
  PROP_SEQUENCE,
  PROP_CAPS,
  PROP_SEED
};

}  // namespace

struct _GstDataRepoSrc {
  GstPushSrc parent;
  SrcPriv *priv;
};

G_DEFINE_TYPE(GstDataRepoSrc, gst_data_repo_src, GST_TYPE_PUSH_SRC)
GST_ELEMENT_REGISTER_DEFINE(datareposrc, "datareposrc", GST_RANK_NONE, GST_TYPE_DATA_REPO_SRC)

static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void gst_data_repo_src_set_property(GObject *object, guint id, const GValue *value,
                                           GParamSpec *pspec) {
  auto *p = GST_DATA_REPO_SRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  auto str = [&](std::string &field) {
    const gchar *v = g_value_get_string(value);
    field = v ? v : "";
  };
  switch (id) {
    case PROP_LOCATION:
      str(p->s.location);
      break;
    case PROP_JSON:
      str(p->s.json);
      break;
    case PROP_START:
      p->s.start = g_value_get_uint(value);
      break;
    case PROP_STOP:
      p->s.stop = g_value_get_uint(value);
      break;
    case PROP_EPOCHS:
      p->s.epochs = g_value_get_uint(value);
      break;
    case PROP_SHUFFLE:
      p->s.shuffle = g_value_get_boolean(value);
      break;
    case PROP_SEQUENCE:
      str(p->s.sequence);
      break;
    case PROP_SEED:
      p->s.seed = g_value_get_uint64(value);
      break;
    case PROP_CAPS: {
      const GstCaps *c = gst_value_get_caps(value);
      gst_caps_take(&p->s.caps, c ? gst_caps_copy(c) : nullptr);
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_data_repo_src_get_property(GObject *object, guint id, GValue *value,
                                           GParamSpec *pspec) {
  auto *p = GST_DATA_REPO_SRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  auto str = [&](const std::string &v) {
    g_value_set_string(value, v.empty() ? nullptr : v.c_str());
  };
  switch (id) {
    case PROP_LOCATION:
      str(p->s.location);
      break;
    case PROP_JSON:
      str(p->s.json);
      break;
    case PROP_START:
      g_value_set_uint(value, p->s.start);
      break;
    case PROP_STOP:
      g_value_set_uint(value, p->s.stop);
      break;
    case PROP_EPOCHS:
      g_value_set_uint(value, p->s.epochs);
      break;
    case PROP_SHUFFLE:
      g_value_set_boolean(value, p->s.shuffle);
      break;
    case PROP_SEQUENCE:
      str(p->s.sequence);
      break;
    case PROP_SEED:
      g_value_set_uint64(value, p->s.seed);
      break;
    case PROP_CAPS:
      gst_value_set_caps(value, p->s.caps);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static std::string read_text(const std::string &path, const char *prop) {
  std::ifstream f(path, std::ios::binary);
  if (!f)
    fail(ErrorKind::kNotFound,
         std::string(prop) + ": cannot read " + path + ": " + std::strerror(errno));
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

static std::string caps_str(const GstCaps *c) {
  gchar *s = gst_caps_to_string(c);
  std::string r = s;
  g_free(s);
  return r;
}

// Picks the tensors of `sequence` ("2,0") out of the static config; fills run.sequence.
static void apply_sequence(Run &r, const std::string &sequence) {
  if (sequence.empty()) return;
  if (r.kind != Kind::kTensorStatic && r.kind != Kind::kTensorFlexible)
    fail(ErrorKind::kSettings, "tensors-sequence applies to tensor streams, but " + r.location +
                                   " holds " + nns::gst::datarepo::kind_name(r.kind));
  for (const auto &tok : nns::split(sequence, ",")) {
    char *end = nullptr;
    unsigned long v = std::strtoul(tok.c_str(), &end, 10);
    if (tok.empty() || *end || v >= nns::kTensorLimit)
      fail(ErrorKind::kSettings,
           "tensors-sequence '" + sequence + "': '" + tok + "' is not a tensor index");
    if (r.kind == Kind::kTensorStatic && v >= r.config.info.size())
      fail(ErrorKind::kSettings, "tensors-sequence '" + sequence + "': tensor " + tok +
                                     " does not exist (a sample has " +
                                     std::to_string(r.config.info.size()) + " tensors)");
    r.sequence.push_back(v);
  }
}

static gboolean src_start(GstBaseSrc *bsrc) {
  auto *self = GST_DATA_REPO_SRC(bsrc);
  auto *p = self->priv;
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    Settings s;
    nns::gst::CapsPtr prop_caps;
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->s;
      s.caps = nullptr;
      if (p->s.caps) prop_caps.reset(gst_caps_ref(p->s.caps));
    }
    Run r;
    r.location = s.location;
    if (s.location.empty()) fail(ErrorKind::kSettings, "location is not set (the sample file)");
    // The meta: from the json file, or the caps property alone (then sizes come from the caps,
    // or from blocksize for text/octet, and stop-sample-index bounds the samples).
    if (!s.json.empty()) r.meta = nns::datarepo::parse_meta(read_text(s.json, "json"), s.json);
    nns::gst::CapsPtr caps(prop_caps ? gst_caps_ref(prop_caps.get())
                                     : gst_caps_from_string(r.meta.caps.c_str()));
    if (!caps || (s.json.empty() && !prop_caps))
      fail(ErrorKind::kSettings, "set json (the meta file) or caps (the sample format)");
    if (!gst_caps_is_fixed(caps.get()))
      fail(ErrorKind::kNegotiation, "the sample caps " + caps_str(caps.get()) + " are not fixed");
    r.kind = nns::gst::datarepo::kind_of(caps.get());
    if (r.kind == Kind::kUnknown)
      fail(ErrorKind::kNegotiation, "cannot read samples of caps " + caps_str(caps.get()));
    const GstStructure *st = gst_caps_get_structure(caps.get(), 0);
    if (gst_structure_has_field(st, "framerate"))
      gst_structure_get_fraction(st, "framerate", &r.rate_n, &r.rate_d);
    // Sample size: what the caps imply, checked against the meta when it has one.
    uint64_t implied = 0;
    if (r.kind == Kind::kTensorStatic) {
      r.config = nns::gst::config_from_caps(caps.get());
      if (!r.config.info.valid())
        fail(ErrorKind::kNegotiation,
             "caps " + caps_str(caps.get()) + " do not give every tensor's type and dimensions");
      for (const auto &t : r.config.info.tensors) {
        r.tensor_offset.push_back(implied);
        implied += t.byte_size();
      }
    } else if (r.kind == Kind::kVideo) {
      GstVideoInfo vi;
      if (gst_video_info_from_caps(&vi, caps.get())) implied = GST_VIDEO_INFO_SIZE(&vi);
    } else if (r.kind == Kind::kAudio) {
      GstAudioInfo ai;  // NNStreamer's default audio sample: one second
      if (gst_audio_info_from_caps(&ai, caps.get()))
        implied = static_cast<uint64_t>(GST_AUDIO_INFO_BPF(&ai)) * GST_AUDIO_INFO_RATE(&ai);
    } else if (r.kind == Kind::kText || r.kind == Kind::kOctet) {
      guint bs = gst_base_src_get_blocksize(bsrc);
      if (s.json.empty()) implied = bs;
    }
    if (!s.json.empty() && !r.meta.per_sample() && r.kind != Kind::kImage) {
      if (r.kind == Kind::kTensorStatic || r.kind == Kind::kVideo) {
        if (r.meta.sample_size != implied)
          fail(ErrorKind::kStream, s.json + " says sample_size " +
                                       std::to_string(r.meta.sample_size) + " but its caps " +
                                       r.meta.caps + " make a sample " + std::to_string(implied) +
                                       " bytes");
      }
      r.sample_size = r.meta.sample_size;
    } else {
      r.sample_size = implied;
    }
    if (r.kind == Kind::kTensorFlexible && !r.meta.per_sample())
      fail(ErrorKind::kSettings,
           "flexible/sparse tensors need the json meta with sample_offset, "
           "tensor_size and tensor_count");
    if (r.kind != Kind::kImage && r.kind != Kind::kTensorFlexible && r.sample_size == 0)
      fail(ErrorKind::kSettings,
           "the size of a sample is unknown (set json, or blocksize with "
           "caps for text/octet samples)");
    if (s.json.empty()) {
      if (s.stop == 0)
        fail(ErrorKind::kSettings,
             "stop-sample-index must be set when caps replace the json "
             "meta (the number of samples is unknown)");
      r.meta.total_samples = static_cast<uint64_t>(s.stop) + 1;
      r.meta.sample_size = r.sample_size;
    }
    // Range: stop-sample-index 0 means the last sample (as NNStreamer).
    const uint64_t last = r.meta.total_samples - 1;
    const uint64_t stop = s.stop == 0 ? last : s.stop;
    if (s.start > stop || stop > last)
      fail(ErrorKind::kSettings,
           "start-sample-index " + std::to_string(s.start) + " / stop-sample-index " +
               std::to_string(s.stop) + " select no samples of " + r.location + " (it has " +
               std::to_string(r.meta.total_samples) + ": indices 0.." + std::to_string(last) +
               "; stop-sample-index 0 means the last)");
    if (s.epochs == 0) fail(ErrorKind::kSettings, "epochs must be at least 1");
    apply_sequence(r, s.sequence);
    // The sample file, checked against the meta.
    if (r.kind == Kind::kImage) {
      nns::gst::datarepo::check_index_pattern(s.location, "location");
    } else {
      r.fd = ::open(s.location.c_str(), O_RDONLY | O_CLOEXEC);
      if (r.fd < 0)
        fail(ErrorKind::kNotFound,
             "location: cannot open " + s.location + ": " + std::strerror(errno));
      struct stat sb {};
      if (::fstat(r.fd, &sb) != 0 || !S_ISREG(sb.st_mode)) {
        ::close(r.fd);
        fail(ErrorKind::kNotFound, "location: " + s.location + " is not a regular file");
      }
      try {
        nns::datarepo::Meta bounded = r.meta;
        bounded.total_samples = stop + 1;  // only what will be read must be there
        if (bounded.per_sample()) {
          bounded.sample_offset.resize(stop + 1);
          bounded.tensor_count.resize(stop + 1);
        }
        nns::datarepo::check_against_file(bounded, static_cast<uint64_t>(sb.st_size), s.location,
                                          s.json.empty() ? "caps" : s.json);
      } catch (...) {
        ::close(r.fd);
        throw;
      }
    }
    r.order = std::make_unique<nns::datarepo::SampleOrder>(s.start, static_cast<uint32_t>(stop),
                                                           s.epochs, s.shuffle, s.seed);
    // Output caps: the stored caps, narrowed to the tensors-sequence.
    nns::gst::CapsPtr out(gst_caps_copy(caps.get()));
    if (!r.sequence.empty() && r.kind == Kind::kTensorStatic) {
      nns::TensorsConfig c = r.config;
      c.info.tensors.clear();
      for (std::size_t i : r.sequence) c.info.tensors.push_back(r.config.info[i]);
      out.reset(nns::gst::caps_from_config(c));
    }
    std::lock_guard<std::mutex> l(p->lock);
    p->run = std::move(r);
    gst_caps_replace(&p->out_caps, out.get());
    return TRUE;
  });
}

static gboolean src_stop(GstBaseSrc *bsrc) {
  auto *p = GST_DATA_REPO_SRC(bsrc)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (p->run.fd >= 0) ::close(p->run.fd);
  p->run = Run();
  gst_caps_replace(&p->out_caps, nullptr);
  return TRUE;
}

static GstCaps *src_get_caps(GstBaseSrc *bsrc, GstCaps *filter) {
  auto *p = GST_DATA_REPO_SRC(bsrc)->priv;
  GstCaps *caps = nullptr;
  {
    std::lock_guard<std::mutex> l(p->lock);
    if (p->out_caps) caps = gst_caps_ref(p->out_caps);
  }
  // Static tensors also in their '.'-joined spellings, so a capsfilter written so intersects.
  if (caps) caps = nns::gst::with_tensor_spellings(caps);
  if (!caps) caps = gst_caps_new_any();
  if (filter) {
    GstCaps *i = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    return i;
  }
  return caps;
}

// Reads `size` bytes at `offset` into a new memory; names the sample on failure.
static GstMemory *read_direct(const Run &r, uint32_t index, uint64_t offset, uint64_t size) {
  GstMemory *mem = gst_allocator_alloc(nullptr, size, nullptr);
  nns::gst::MemoryPtr owned(mem);
  nns::gst::MemoryMap map(mem, GST_MAP_WRITE);
  uint64_t done = 0;
  while (done < size) {
    ssize_t n = ::pread(r.fd, map.data() + done, size - done, static_cast<off_t>(offset + done));
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0)
      fail(ErrorKind::kStream, "sample " + std::to_string(index) + " of " + r.location +
                                   " at byte offset " + std::to_string(offset) + ": " +
                                   (n < 0 ? std::strerror(errno)
                                          : "the file ended after " + std::to_string(done) +
                                                " of " + std::to_string(size) + " bytes"));
    done += static_cast<uint64_t>(n);
  }
  return owned.release();
}

// Samples read in file order come out of one 256 KiB read shared by many samples (one syscall
// for many samples); shuffled samples are read one by one.
// Makes r.chunk cover [offset, offset + size) (sequential reading only).
static void ensure_chunk(Run &r, uint32_t index, uint64_t offset, uint64_t size) {
  if (r.chunk && offset >= r.chunk_offset &&
      offset + size <= r.chunk_offset + gst_memory_get_sizes(r.chunk.get(), nullptr, nullptr))
    return;
  constexpr uint64_t kChunk = 256 * 1024;
  uint64_t len = std::max(size, kChunk);
  if (offset < r.file_size) len = std::max(size, std::min(len, r.file_size - offset));
  r.chunk.reset(read_direct(r, index, offset, len));
  r.chunk_offset = offset;
}

static GstMemory *read_at(Run &r, uint32_t index, uint64_t offset, uint64_t size) {
  if (!r.sequential) return read_direct(r, index, offset, size);
  ensure_chunk(r, index, offset, size);
  return gst_memory_share(r.chunk.get(), static_cast<gssize>(offset - r.chunk_offset),
                          static_cast<gssize>(size));
}

static GstBuffer *read_sample(Run &r, uint32_t index) {
  nns::gst::BufferPtr buf(gst_buffer_new());
  switch (r.kind) {
    case Kind::kImage: {
      const std::string name = nns::gst::datarepo::format_index(r.location, index, "location");
      gchar *data = nullptr;
      gsize size = 0;
      GError *err = nullptr;
      if (!g_file_get_contents(name.c_str(), &data, &size, &err)) {
        std::string why = err ? err->message : "unknown error";
        if (err) g_error_free(err);
        fail(ErrorKind::kNotFound,
             "sample " + std::to_string(index) + ": cannot read " + name + ": " + why);
      }
      gst_buffer_append_memory(buf.get(), gst_memory_new_wrapped(GST_MEMORY_FLAG_READONLY, data,
                                                                 size, 0, size, data, g_free));
      break;
    }
    case Kind::kTensorStatic: {
      const uint64_t base = static_cast<uint64_t>(index) * r.sample_size;
      const std::size_t n = r.sequence.empty() ? r.config.info.size() : r.sequence.size();
      if (n == 1 && r.config.info.size() == 1) {
        gst_buffer_append_memory(buf.get(), read_at(r, index, base, r.sample_size));
        break;
      }
      // In file order the tensors are shared straight out of the read-ahead chunk; otherwise
      // out of the sample's own memory.
      nns::gst::MemoryPtr all;
      uint64_t from = 0;  // offset of the sample in `src`
      GstMemory *src = nullptr;
      if (r.sequential) {
        ensure_chunk(r, index, base, r.sample_size);
        src = r.chunk.get();
        from = base - r.chunk_offset;
      } else {
        all.reset(read_at(r, index, base, r.sample_size));
        src = all.get();
      }
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t t = r.sequence.empty() ? k : r.sequence[k];
        const auto &info = r.config.info[t];
        GstMemory *part = gst_memory_share(src, static_cast<gssize>(from + r.tensor_offset[t]),
                                           static_cast<gssize>(info.byte_size()));
        nns::gst::buffer_append_tensor(buf.get(), part, info);
      }
      break;
    }
    case Kind::kTensorFlexible: {
      const auto &m = r.meta;
      const uint64_t off = m.sample_offset[index];
      nns::gst::MemoryPtr all(read_at(r, index, off, m.sample_bytes(index)));
      nns::gst::MemoryMap map(all.get(), GST_MAP_READ);
      std::vector<std::pair<std::size_t, std::size_t>> spans;  // offset, size per tensor
      std::vector<nns::MetaHeader> heads;
      std::size_t pos = 0;
      for (std::size_t k = 0; k < m.tensor_count_of(index); ++k) {
        const std::size_t size = m.tensor_size[m.first_tensor(index) + k];
        try {
          heads.push_back(nns::parse_meta_header(map.data() + pos, size));
          if (nns::kMetaHeaderSize + heads.back().payload_size() > size)
            fail(ErrorKind::kStream, "its header describes " +
                                         std::to_string(heads.back().payload_size()) +
                                         " bytes of data, the meta gives it " +
                                         std::to_string(size - nns::kMetaHeaderSize));
        } catch (const nns::Error &e) {
          fail(ErrorKind::kStream,
               "sample " + std::to_string(index) + ", tensor " + std::to_string(k) + " of " +
                   r.location + " at byte offset " + std::to_string(off + pos) + ": " + e.what());
        }
        spans.emplace_back(pos, size);
        pos += size;
      }
      const std::size_t n = r.sequence.empty() ? spans.size() : r.sequence.size();
      for (std::size_t k = 0; k < n; ++k) {
        const std::size_t t = r.sequence.empty() ? k : r.sequence[k];
        if (t >= spans.size())
          fail(ErrorKind::kStream, "tensors-sequence names tensor " + std::to_string(t) +
                                       " but sample " + std::to_string(index) + " has " +
                                       std::to_string(spans.size()));
        GstMemory *part = gst_memory_share(all.get(), static_cast<gssize>(spans[t].first),
                                           static_cast<gssize>(spans[t].second));
        nns::gst::buffer_append_tensor(buf.get(), part, heads[t].info());
      }
      break;
    }
    default:
      gst_buffer_append_memory(
          buf.get(),
          read_at(r, index, static_cast<uint64_t>(index) * r.sample_size, r.sample_size));
  }
  return buf.release();
}

static GstFlowReturn src_create(GstPushSrc *psrc, GstBuffer **out) {
  auto *self = GST_DATA_REPO_SRC(psrc);
  auto *p = self->priv;
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    Run &r = p->run;
    uint32_t index = 0;
    if (!r.order || !r.order->next(&index)) return GST_FLOW_EOS;
    GstBuffer *buf = read_sample(r, index);
    if (r.rate_n > 0 && r.kind != Kind::kAudio) {
      GST_BUFFER_PTS(buf) = gst_util_uint64_scale(r.frames, GST_SECOND * r.rate_d, r.rate_n);
      GST_BUFFER_DURATION(buf) = gst_util_uint64_scale(GST_SECOND, r.rate_d, r.rate_n);
    }
    GST_BUFFER_OFFSET(buf) = index;  // the sample index, for applications
    ++r.frames;
    *out = buf;
    return GST_FLOW_OK;
  });
}

static void gst_data_repo_src_finalize(GObject *object) {
  auto *p = GST_DATA_REPO_SRC(object)->priv;
  if (p->run.fd >= 0) ::close(p->run.fd);
  gst_caps_replace(&p->s.caps, nullptr);
  gst_caps_replace(&p->out_caps, nullptr);
  delete p;
  G_OBJECT_CLASS(gst_data_repo_src_parent_class)->finalize(object);
}

static void gst_data_repo_src_class_init(GstDataRepoSrcClass *klass) {
  GST_DEBUG_CATEGORY_INIT(datareposrc_debug, "datareposrc", 0, "datareposrc");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *base_class = GST_BASE_SRC_CLASS(klass);
  gobject_class->set_property = gst_data_repo_src_set_property;
  gobject_class->get_property = gst_data_repo_src_get_property;
  gobject_class->finalize = gst_data_repo_src_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                     GST_PARAM_MUTABLE_READY);
  g_object_class_install_property(
      gobject_class, PROP_LOCATION,
      g_param_spec_string("location", "File Location",
                          "Location of the file to read that is stored in MLOps Data "
                          "Repository, if the files are images, write the index of filename "
                          "name like %04ld or %04lld (e.g., filename%04ld.png)",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_JSON,
      g_param_spec_string("json", "Json file path",
                          "Json file path containing the meta information of the file "
                          "specified as location",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_START,
      g_param_spec_uint("start-sample-index", "Start index of samples",
                        "Start index of sample to read, in case of image, the starting index of "
                        "the numbered files. start at 0.",
                        0, G_MAXINT, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_STOP,
      g_param_spec_uint("stop-sample-index", "Stop index of samples",
                        "Stop index of sample to read, in case of image, the stopping index of "
                        "the numbered files. start at 0 (0: the last sample).",
                        0, G_MAXINT, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_EPOCHS,
      g_param_spec_uint("epochs", "Epochs",
                        "Repetition of range of files or samples to read, set number of "
                        "repetitions",
                        0, G_MAXINT, 1, rw));
  g_object_class_install_property(
      gobject_class, PROP_SEQUENCE,
      g_param_spec_string("tensors-sequence", "Tensors sequence",
                          "Tensors in a sample are read into gstBuffer according to "
                          "tensors-sequence (e.g. 2,1: only tensor 2 then tensor 1). Default: "
                          "all tensors in stored order.",
                          nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_SHUFFLE,
      g_param_spec_boolean("is-shuffle", "Is shuffle", "If the value is true, samples are shuffled",
                           TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_CAPS,
      g_param_spec_boxed("caps", "Caps",
                         "Optional property, Caps describing the format of the sample data.",
                         GST_TYPE_CAPS, rw));
  g_object_class_install_property(
      gobject_class, PROP_SEED,
      g_param_spec_uint64("shuffle-seed", "Shuffle seed",
                          "Seed of the shuffle (nnstreamer-cpp): the same seed gives the same "
                          "order on every machine",
                          0, G_MAXUINT64, 0, rw));
  gst_element_class_set_static_metadata(
      element_class, "NNStreamer MLOps Data Repository Source", "Source/File",
      "Read files in MLOps Data Repository into buffers", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &src_template);
  base_class->start = src_start;
  base_class->stop = src_stop;
  base_class->get_caps = src_get_caps;
  GST_PUSH_SRC_CLASS(klass)->create = src_create;
}

static void gst_data_repo_src_init(GstDataRepoSrc *self) {
  self->priv = new SrcPriv();
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
}

// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_converter
 *
 * Turns media into tensor frames (NNStreamer's tensor_converter): raw video becomes a
 * `C:W:H:N` uint8 tensor (uint16 for GRAY16, `W:H:3:N` for RGBP/BGRP), interleaved audio a
 * `channels:N` tensor of the sample type, utf8 text an `input-dim:N` uint8 tensor, an octet
 * stream the tensors of `input-dim`/`input-type` (or one flexible tensor when downstream wants
 * flexible), a flexible tensor stream static tensors. N is `frames-per-tensor`. Data is shared,
 * not copied, whenever the bytes are already laid out as the tensor (e.g. RGB with width % 4 ==
 * 0). `mode=custom-code:<name>` runs a callback registered with
 * nnstreamer_converter_custom_register(); other media types go to converter sub-plugins.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=224,height=224 !
 *       tensor_converter ! tensor_sink
 */
#include <gst/base/gstadapter.h>

#include <mutex>

#include "gst/c_tensor_info.h"
#include "gst/converter_media.h"
#include "gst/converter_registry.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_converter_debug);
#define GST_CAT_DEFAULT tensor_converter_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_CONVERTER (gst_tensor_converter_get_type())
G_DECLARE_FINAL_TYPE(GstTensorConverter, gst_tensor_converter, GST, TENSOR_CONVERTER, GstElement)
G_END_DECLS

namespace {

using nns::ErrorKind;
using nns::fail;
using nns::TensorFormat;
using nns::TensorsConfig;
using nns::TensorsInfo;
using nns::gst::MediaKind;

enum class Mode { kNone, kCustomCode, kCustomScript };

// Properties, guarded by the object lock.
struct Settings {
  std::string input_dim, input_type, mode;
  guint frames_per_tensor = 1;
  bool set_timestamp = true;
  bool silent = true;
};

struct ConverterPriv {
  Settings settings;

  // Snapshot of the settings taken when the element starts (READY -> PAUSED).
  std::vector<nns::Dims> prop_dims;
  std::vector<nns::TensorType> prop_types;
  TensorsInfo props;          // valid only when props_valid
  bool props_valid = false;   // input-dim and input-type both given, same count
  guint fpt = 1;
  bool set_ts = true;
  Mode mode = Mode::kNone;
  std::string mode_option;

  // Negotiation (streaming thread / caps event).
  nns::gst::MediaInfo media;
  bool configured = false;
  bool derive_per_buffer = false;  // output config comes from each buffer (flex in, custom)
  bool flex_passthrough = false;   // flexible in, flexible out, untouched
  bool out_flexible = false;       // src caps are format=flexible
  bool headers_ready = false;      // buffers already carry flexible headers
  bool caps_sent = false;
  TensorsConfig sent;              // config of the current src caps
  guint frames_out = 1;
  nns::gst::CustomConverter custom;
  const NNStreamerExternalConverter *ext = nullptr;
  void *ext_priv = nullptr;
  int in_rate_n = 0, in_rate_d = 1;

  // Stream state.
  GstAdapter *adapter = nullptr;
  GstSegment segment;
  bool need_segment = false;  // push `segment` (converted from bytes if needed) before data
  GstClockTime old_ts = GST_CLOCK_TIME_NONE;
};

enum {
  PROP_0,
  PROP_INPUT_DIM,
  PROP_INPUT_TYPE,
  PROP_FRAMES_PER_TENSOR,
  PROP_SET_TIMESTAMP,
  PROP_SUB_PLUGINS,
  PROP_SILENT,
  PROP_MODE
};

constexpr GParamFlags kRW = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);

}  // namespace

struct _GstTensorConverter {
  GstElement parent;
  GstPad *sinkpad;
  GstPad *srcpad;
  ConverterPriv *priv;
};

G_DEFINE_TYPE(GstTensorConverter, gst_tensor_converter, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_converter, "tensor_converter", GST_RANK_NONE,
                            GST_TYPE_TENSOR_CONVERTER)

namespace {

// ---- settings ------------------------------------------------------------------------------

void snapshot_settings(GstTensorConverter *self) {
  ConverterPriv *p = self->priv;
  Settings s;
  GST_OBJECT_LOCK(self);
  s = p->settings;
  GST_OBJECT_UNLOCK(self);
  p->prop_dims = nns::parse_dims_list(s.input_dim, "input-dim");
  p->prop_types = nns::parse_types_list(s.input_type, "input-type");
  p->props = {};
  p->props_valid = false;
  if (!p->prop_dims.empty() && !p->prop_types.empty()) {
    if (p->prop_dims.size() != p->prop_types.size())
      fail(ErrorKind::kSettings, "input-dim='" + s.input_dim + "' lists " +
                                     std::to_string(p->prop_dims.size()) +
                                     " tensors but input-type='" + s.input_type + "' lists " +
                                     std::to_string(p->prop_types.size()));
    for (std::size_t i = 0; i < p->prop_dims.size(); ++i)
      p->props.tensors.push_back({"", p->prop_types[i], p->prop_dims[i]});
    p->props_valid = true;
  }
  p->fpt = s.frames_per_tensor;
  p->set_ts = s.set_timestamp;
  p->mode = Mode::kNone;
  p->mode_option.clear();
  std::string mode = nns::trim(s.mode);
  if (!mode.empty()) {
    auto colon = mode.find(':');
    std::string kind = mode.substr(0, colon);
    std::string opt = colon == std::string::npos ? "" : nns::trim(mode.substr(colon + 1));
    if (g_ascii_strcasecmp(kind.c_str(), "custom-code") == 0)
      p->mode = Mode::kCustomCode;
    else if (g_ascii_strcasecmp(kind.c_str(), "custom-script") == 0)
      p->mode = Mode::kCustomScript;
    else
      fail(ErrorKind::kSettings, "mode='" + mode +
                                     "' is not custom-code:<registered name> or "
                                     "custom-script:<script path>");
    if (opt.empty())
      fail(ErrorKind::kSettings, "mode='" + mode + "' lacks the name after '" + kind + ":'");
    p->mode_option = opt;
  }
}

void reset_stream(ConverterPriv *p) {
  if (p->adapter) gst_adapter_clear(p->adapter);
  gst_segment_init(&p->segment, GST_FORMAT_TIME);
  p->need_segment = false;
  p->old_ts = GST_CLOCK_TIME_NONE;
}

void close_external(ConverterPriv *p) {
  if (p->ext && p->ext->close && p->ext_priv) p->ext->close(&p->ext_priv);
  p->ext = nullptr;
  p->ext_priv = nullptr;
}

// ---- negotiation ---------------------------------------------------------------------------

GstCaps *flexible_caps(int rate_n, int rate_d) {
  return nns::gst::caps_for_format(TensorFormat::kFlexible, rate_n, rate_d);
}

bool peer_accepts_flexible(GstTensorConverter *self, int rate_n, int rate_d) {
  nns::gst::CapsPtr peer(gst_pad_peer_query_caps(self->srcpad, nullptr));
  nns::gst::CapsPtr flex(flexible_caps(rate_n, rate_d));
  return peer && gst_caps_can_intersect(peer.get(), flex.get());
}

// Sets the src caps for `cfg` (static, or flexible when `cfg` is flexible or downstream only
// takes flexible). Throws when downstream accepts neither.
void send_caps(GstTensorConverter *self, const TensorsConfig &cfg) {
  ConverterPriv *p = self->priv;
  if (p->caps_sent && cfg.same_as(p->sent) && cfg.info.format == p->sent.info.format &&
      cfg.rate_n == p->sent.rate_n && cfg.rate_d == p->sent.rate_d)
    return;
  nns::gst::CapsPtr caps;
  bool flexible = cfg.info.format != TensorFormat::kStatic || p->flex_passthrough;
  if (!flexible) {
    nns::gst::CapsPtr mine(nns::gst::caps_from_config(cfg, true));
    nns::gst::CapsPtr peer(gst_pad_peer_query_caps(self->srcpad, nullptr));
    nns::gst::CapsPtr both(gst_caps_intersect_full(mine.get(), peer.get(), GST_CAPS_INTERSECT_FIRST));
    if (!gst_caps_is_empty(both.get())) {
      caps.reset(gst_caps_fixate(both.release()));
    } else if (peer_accepts_flexible(self, cfg.rate_n, cfg.rate_d)) {
      flexible = true;
    } else {
      nns::gst::CapsPtr plain(nns::gst::caps_from_config(cfg, false));
      fail(ErrorKind::kNegotiation, "downstream accepts " + nns::gst::caps_to_string(peer.get()) +
                                        " but the " + p->media.describe + " input gives " +
                                        nns::gst::caps_to_string(plain.get()));
    }
  }
  if (flexible) caps.reset(flexible_caps(cfg.rate_n, cfg.rate_d));
  GST_DEBUG_OBJECT(self, "src caps %" GST_PTR_FORMAT, caps.get());
  if (!gst_pad_set_caps(self->srcpad, caps.get()))
    fail(ErrorKind::kNegotiation,
         "downstream refused caps " + nns::gst::caps_to_string(caps.get()));
  p->out_flexible = flexible;
  p->sent = cfg;
  p->caps_sent = true;
}

void set_frames_dim(TensorsConfig &cfg, guint fpt) {
  // The frames dimension follows the last non-1 dimension of a single tensor.
  auto &d = cfg.info[0].dims;
  std::size_t r = nns::rank_of(d);
  while (r > 1 && d[r - 1] == 1) --r;
  if (r >= nns::kRankLimit)
    fail(ErrorKind::kSettings, "frames-per-tensor=" + std::to_string(fpt) +
                                   " needs one more dimension than input-dim has room for");
  for (std::size_t i = r; i < nns::kRankLimit; ++i) d[i] = 0;
  d[r] = fpt;
}

std::string props_string(const ConverterPriv *p) {
  return "input-dim='" + p->settings.input_dim + "', input-type='" + p->settings.input_type + "'";
}

void configure_octet(GstTensorConverter *self, const GstStructure *s) {
  ConverterPriv *p = self->priv;
  auto &m = p->media;
  TensorsConfig cfg;
  if (p->props_valid) {
    cfg.info = p->props;
  } else {
    // No properties: take what downstream fixes, or go flexible when it takes that.
    nns::gst::CapsPtr peer(gst_pad_peer_query_caps(self->srcpad, nullptr));
    TensorsConfig pc;
    bool got = false;
    if (peer && !gst_caps_is_any(peer.get()) && nns::gst::is_tensor_caps(peer.get())) {
      try {
        pc = nns::gst::config_from_caps(peer.get());
        got = pc.info.format == TensorFormat::kStatic && pc.info.valid();
      } catch (const nns::Error &) {
      }
    }
    if (got) {
      cfg.info = pc.info;
    } else if (peer_accepts_flexible(self, -1, -1) &&
               !(peer && gst_caps_is_any(peer.get()))) {
      cfg.info.format = TensorFormat::kFlexible;
    } else {
      std::string missing = p->prop_dims.empty() && p->prop_types.empty()
                                ? "input-dim and input-type are"
                                : (p->prop_dims.empty() ? "input-dim is" : "input-type is");
      fail(ErrorKind::kSettings, "property " + missing +
                                     " required for application/octet-stream (e.g. "
                                     "input-dim=30 input-type=uint8), got " + props_string(p));
    }
  }
  if (p->fpt > 1 && cfg.info.size() > 1)
    fail(ErrorKind::kSettings, "frames-per-tensor=" + std::to_string(p->fpt) +
                                   " needs a single tensor, but " + props_string(p) + " gives " +
                                   std::to_string(cfg.info.size()));
  if (p->fpt > 1 && cfg.info.format == TensorFormat::kFlexible)
    fail(ErrorKind::kSettings, "frames-per-tensor=" + std::to_string(p->fpt) +
                                   " cannot be used with flexible output from an octet stream");
  int n = 0, d = 1;
  if (!gst_structure_get_fraction(s, "framerate", &n, &d)) n = 0, d = 1;
  cfg.rate_n = n;
  cfg.rate_d = d;
  if (cfg.info.format == TensorFormat::kStatic) {
    m.frame_size = cfg.info.total_bytes();
    if (p->fpt > 1) set_frames_dim(cfg, p->fpt);
    m.describe = "octet stream of " + cfg.info.to_string();
  } else {
    m.frame_size = 0;
    m.describe = "octet stream";
  }
  m.config = cfg;
}

// Handles the sink CAPS event: works out the output and sets src caps when they are known.
void configure(GstTensorConverter *self, GstCaps *caps) {
  ConverterPriv *p = self->priv;
  if (!gst_caps_is_fixed(caps))
    fail(ErrorKind::kNegotiation, "input caps are not fixed: " + nns::gst::caps_to_string(caps));
  snapshot_settings(self);  // properties may have changed since the element started
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  if (!gst_structure_get_fraction(s, "framerate", &p->in_rate_n, &p->in_rate_d))
    p->in_rate_n = 0, p->in_rate_d = 1;
  MediaKind kind = p->mode != Mode::kNone ? MediaKind::kCustom : nns::gst::media_kind_of(s);
  p->configured = false;
  p->derive_per_buffer = p->flex_passthrough = p->headers_ready = false;
  p->frames_out = p->fpt;
  close_external(p);
  p->custom = {};
  nns::gst::MediaInfo &m = p->media;
  m = {};
  switch (kind) {
    case MediaKind::kVideo:
      m = nns::gst::media_from_video(caps, p->fpt);
      break;
    case MediaKind::kAudio:
      m = nns::gst::media_from_audio(caps, p->fpt);
      break;
    case MediaKind::kText:
      m = nns::gst::media_from_text(s, p->prop_dims.empty() ? 0 : p->prop_dims[0][0], p->fpt);
      break;
    case MediaKind::kOctet:
      configure_octet(self, s);
      break;
    case MediaKind::kFlexTensor:
      if (p->fpt != 1)
        fail(ErrorKind::kSettings, "frames-per-tensor=" + std::to_string(p->fpt) +
                                       " is not supported for flexible tensor input (use 1)");
      m.describe = "flexible tensors";
      m.config.rate_n = p->in_rate_n;
      m.config.rate_d = p->in_rate_d;
      if (p->props_valid) {
        m.config.info = p->props;
      } else if (peer_accepts_flexible(self, p->in_rate_n, p->in_rate_d)) {
        p->flex_passthrough = p->headers_ready = true;
        m.config.info.format = TensorFormat::kFlexible;
      } else {
        p->derive_per_buffer = true;
      }
      p->frames_out = 1;
      break;
    case MediaKind::kCustom:
    default: {
      p->frames_out = 1;
      p->derive_per_buffer = true;
      auto &reg = nns::gst::ConverterRegistry::instance();
      if (p->mode == Mode::kCustomCode) {
        auto cb = reg.find_custom(p->mode_option);
        if (!cb)
          fail(ErrorKind::kNotFound, "mode=custom-code:" + p->mode_option + ": no callback is "
                                     "registered as '" + p->mode_option +
                                     "' (nnstreamer_converter_custom_register)");
        p->custom = *cb;
        m.describe = "custom-code:" + p->mode_option;
        break;
      }
      std::string want;
      if (p->mode == Mode::kCustomScript) {
        auto dot = p->mode_option.rfind('.');
        std::string ext = dot == std::string::npos ? "" : p->mode_option.substr(dot + 1);
        want = ext == "py" ? "python3" : ext;
        p->ext = want.empty() ? nullptr : reg.find(want);
        if (!p->ext) {
          std::string why = reg.load_error(want);
          fail(ErrorKind::kNotFound, "mode=custom-script:" + p->mode_option +
                                         ": no converter sub-plugin '" + want + "' for it" +
                                         (why.empty() ? "" : " (" + why + ")"));
        }
        if (p->ext->open) {
          int r = p->ext->open(p->mode_option.c_str(), &p->ext_priv);
          if (r < 0) {
            p->ext = nullptr;
            fail(ErrorKind::kLibrary, "mode=custom-script:" + p->mode_option +
                                          ": sub-plugin '" + want + "' failed to open it (" +
                                          std::to_string(r) + ")");
          }
        }
      } else {
        want = gst_structure_get_name(s);
        p->ext = reg.find_for_media(want);
        if (!p->ext)
          fail(ErrorKind::kNegotiation, "input caps " + nns::gst::caps_to_string(caps) +
                                            " are not a supported media type and no converter "
                                            "sub-plugin accepts '" + want + "'");
      }
      m.describe = std::string("converter sub-plugin '") + p->ext->name + "'";
      nns::gst::CTensorsConfig c;
      if (p->ext->get_out_config(caps, c.get())) {
        m.config = nns::gst::from_c(c.get());
        if (m.config.rate_n < 0) m.config.rate_n = p->in_rate_n, m.config.rate_d = p->in_rate_d;
        p->derive_per_buffer = !(m.config.info.valid() && !m.config.info.tensors.empty()) &&
                               m.config.info.format == TensorFormat::kStatic;
      } else if (p->mode != Mode::kCustomScript) {
        fail(ErrorKind::kNegotiation, m.describe + " cannot describe tensors for caps " +
                                          nns::gst::caps_to_string(caps));
      }
      break;
    }
  }
  m.kind = kind;
  // Properties given for media that fix the tensor themselves must agree with it.
  if (p->props_valid &&
      (kind == MediaKind::kVideo || kind == MediaKind::kAudio || kind == MediaKind::kText) &&
      !p->props.same_as(m.config.info))
    fail(ErrorKind::kSettings, props_string(p) + " do not match the " + m.describe +
                                   " input, which gives " + m.config.info.to_string());
  p->configured = true;
  if (!p->derive_per_buffer) send_caps(self, m.config);
}

// ---- data ----------------------------------------------------------------------------------

GstBuffer *shell_with(GstBuffer *in, GstMemory *mem) {
  GstBuffer *out = gst_buffer_new();
  gst_buffer_append_memory(out, mem);
  gst_buffer_copy_into(out, in,
                       static_cast<GstBufferCopyFlags>(GST_BUFFER_COPY_FLAGS |
                                                       GST_BUFFER_COPY_TIMESTAMPS),
                       0, static_cast<gsize>(-1));
  return out;
}

// The whole buffer as one memory: its only memory (a new ref) or a merged copy.
GstMemory *single_memory(GstBuffer *buf, gsize size) {
  GstMemory *mem = gst_buffer_n_memory(buf) == 1 ? gst_buffer_get_memory(buf, 0)
                                                 : gst_buffer_get_all_memory(buf);
  if (gst_memory_get_sizes(mem, nullptr, nullptr) != size) {
    GstMemory *sub = gst_memory_share(mem, 0, size);
    gst_memory_unref(mem);
    mem = sub;
  }
  return mem;
}

void push_segment(GstTensorConverter *self) {
  ConverterPriv *p = self->priv;
  if (!p->need_segment) return;
  p->need_segment = false;
  if (p->segment.format == GST_FORMAT_BYTES) {
    GstSegment seg;
    gst_segment_init(&seg, GST_FORMAT_TIME);
    const auto &c = p->sent;
    if (c.rate_n > 0 && c.rate_d > 0 && p->segment.start > 0 && p->media.frame_size > 0) {
      seg.start = seg.time = gst_util_uint64_scale(p->segment.start * c.rate_d, GST_SECOND,
                                                   p->media.frame_size * c.rate_n);
    }
    p->segment = seg;
  }
  gst_pad_push_event(self->srcpad, gst_event_new_segment(&p->segment));
}

void stamp(GstTensorConverter *self, GstBuffer *buf, guint frames_in) {
  ConverterPriv *p = self->priv;
  if (p->set_ts) {
    const auto &c = p->sent;
    const bool rate = c.rate_n > 0 && c.rate_d > 0;
    GstClockTime dur = GST_BUFFER_DURATION(buf);
    if (!GST_CLOCK_TIME_IS_VALID(dur) && rate) {
      dur = gst_util_uint64_scale_int(static_cast<guint64>(frames_in) * c.rate_d, GST_SECOND,
                                      c.rate_n);
      GST_BUFFER_DURATION(buf) = dur;
    }
    if (!GST_BUFFER_PTS_IS_VALID(buf)) {
      GstClockTime pts = p->segment.start;
      if (rate) {
        if (GST_CLOCK_TIME_IS_VALID(p->old_ts) && GST_CLOCK_TIME_IS_VALID(dur))
          pts = p->old_ts + dur;
      } else if (GstClock *clock = gst_element_get_clock(GST_ELEMENT(self))) {
        GstClockTime base = gst_element_get_base_time(GST_ELEMENT(self));
        GstClockTime now = gst_clock_get_time(clock);
        pts = base < now ? now - base : 0;
        gst_object_unref(clock);
      }
      GST_BUFFER_PTS(buf) = pts;
    }
  }
  p->old_ts = GST_BUFFER_PTS(buf);
}

// Final shaping (octet split, flexible headers) and push.
GstFlowReturn push_out(GstTensorConverter *self, GstBuffer *buf) {
  ConverterPriv *p = self->priv;
  nns::gst::BufferPtr out(buf);
  const TensorsInfo &info = p->sent.info;
  if (p->media.kind == MediaKind::kOctet && info.format == TensorFormat::kStatic &&
      (info.size() > 1 || gst_buffer_n_memory(out.get()) > 1)) {
    nns::gst::MemoryPtr all(gst_buffer_get_all_memory(out.get()));
    nns::gst::BufferPtr split(gst_buffer_new());
    gsize off = 0;
    for (const auto &t : info.tensors) {
      nns::gst::buffer_append_tensor(split.get(), gst_memory_share(all.get(), off, t.byte_size()),
                                     t);
      off += t.byte_size();
    }
    gst_buffer_copy_into(split.get(), out.get(), GST_BUFFER_COPY_METADATA, 0, -1);
    out = std::move(split);
  }
  if (p->out_flexible && !p->headers_ready) {
    nns::gst::BufferPtr flex(gst_buffer_new());
    guint n = gst_buffer_n_memory(out.get());
    for (guint i = 0; i < n; ++i) {
      GstMemory *mem = gst_buffer_peek_memory(out.get(), i);
      nns::MetaHeader h;
      if (i < info.size() && info.format == TensorFormat::kStatic) {
        h.type = info[i].type;
        h.dims = info[i].dims;
      } else {  // octet stream: the whole buffer as bytes
        h.type = nns::TensorType::kUInt8;
        h.dims = nns::make_dims({static_cast<uint32_t>(gst_memory_get_sizes(mem, nullptr, nullptr)),
                                 1, 1, 1});
      }
      h.format = TensorFormat::kFlexible;
      h.media_type = nns::gst::media_type_of(p->media.kind);
      gst_buffer_append_memory(flex.get(), nns::gst::memory_with_header(h, mem));
    }
    gst_buffer_copy_into(flex.get(), out.get(), GST_BUFFER_COPY_METADATA, 0, -1);
    out = std::move(flex);
  }
  return gst_pad_push(self->srcpad, out.release());
}

GstFlowReturn push_chunks(GstTensorConverter *self, GstBuffer *inbuf, guint frames_in) {
  ConverterPriv *p = self->priv;
  const auto &c = p->sent;
  const bool rate = c.rate_n > 0 && c.rate_d > 0;
  const std::size_t fsize = p->media.frame_size;
  GstClockTime dur = GST_BUFFER_DURATION(inbuf);
  if (GST_CLOCK_TIME_IS_VALID(dur)) dur = gst_util_uint64_scale_int(dur, p->frames_out, frames_in);
  gst_adapter_push(p->adapter, inbuf);
  const gsize out_size = static_cast<gsize>(p->frames_out) * fsize;
  GstFlowReturn ret = GST_FLOW_OK;
  while (ret == GST_FLOW_OK && gst_adapter_available(p->adapter) >= out_size) {
    guint64 pdist = 0, ddist = 0;
    GstClockTime pts = gst_adapter_prev_pts(p->adapter, &pdist);
    GstClockTime dts = gst_adapter_prev_dts(p->adapter, &ddist);
    if (frames_in > 1 && rate) {
      if (GST_CLOCK_TIME_IS_VALID(pts))
        pts += gst_util_uint64_scale(pdist * c.rate_d, GST_SECOND, c.rate_n * fsize);
      if (GST_CLOCK_TIME_IS_VALID(dts))
        dts += gst_util_uint64_scale(ddist * c.rate_d, GST_SECOND, c.rate_n * fsize);
    }
    GstBuffer *out = gst_buffer_make_writable(gst_adapter_take_buffer(p->adapter, out_size));
    GST_BUFFER_PTS(out) = pts;
    GST_BUFFER_DTS(out) = dts;
    GST_BUFFER_DURATION(out) = dur;
    ret = push_out(self, out);
  }
  return ret;
}

// Flexible tensors in: strip the headers (sharing the payload), static out.
GstBuffer *from_flexible(GstTensorConverter *self, GstBuffer *in) {
  ConverterPriv *p = self->priv;
  guint n = gst_buffer_n_memory(in);
  if (p->props_valid && n != p->props.size())
    fail(ErrorKind::kStream, "flexible buffer has " + std::to_string(n) + " tensors, " +
                                 props_string(p) + " describe " + std::to_string(p->props.size()));
  TensorsConfig cfg;
  cfg.rate_n = p->in_rate_n;
  cfg.rate_d = p->in_rate_d;
  nns::gst::BufferPtr out(gst_buffer_new());
  for (guint i = 0; i < n; ++i) {
    GstMemory *mem = gst_buffer_peek_memory(in, i);
    nns::MetaHeader h = nns::gst::memory_header(mem);
    gsize payload = gst_memory_get_sizes(mem, nullptr, nullptr) - nns::kMetaHeaderSize;
    nns::TensorInfo t = p->props_valid ? p->props[i] : h.info();
    if (payload != t.byte_size() || h.payload_size() != payload)
      fail(ErrorKind::kStream, "flexible tensor " + std::to_string(i) + " carries " +
                                   std::to_string(payload) + " bytes (header: " +
                                   h.info().to_string() + "), expected " +
                                   std::to_string(t.byte_size()) + " for " + t.to_string() +
                                   (p->props_valid ? " from " + props_string(p) : ""));
    cfg.info.tensors.push_back(t);
    nns::gst::buffer_append_tensor(out.get(), gst_memory_share(mem, nns::kMetaHeaderSize, payload),
                                   t);
  }
  gst_buffer_copy_into(out.get(), in, GST_BUFFER_COPY_METADATA, 0, -1);
  send_caps(self, cfg);
  return out.release();
}

// custom-code callback or converter sub-plugin.
GstBuffer *from_custom(GstTensorConverter *self, GstBuffer *in, bool *owns_in) {
  ConverterPriv *p = self->priv;
  nns::gst::CTensorsConfig c;
  GstBuffer *out = p->custom.func ? p->custom.func(in, p->custom.data, c.get())
                                  : p->ext->convert(in, c.get(), p->ext_priv);
  const std::string who = p->media.describe;
  if (!out) fail(ErrorKind::kStream, who + " returned no buffer");
  if (out == in) *owns_in = false;  // the element's reference moved to the output
  nns::gst::BufferPtr guard_out(out);
  TensorsConfig cfg = nns::gst::from_c(c.get());
  if (cfg.rate_n < 0 || cfg.rate_d <= 0) cfg.rate_n = p->in_rate_n, cfg.rate_d = p->in_rate_d;
  if (cfg.info.format == TensorFormat::kStatic) {
    if (!cfg.info.valid() || cfg.info.tensors.empty())
      fail(ErrorKind::kStream, who + " described invalid tensors: " + cfg.info.to_string());
    try {
      nns::gst::check_static_buffer(out, cfg.info);
    } catch (const nns::Error &e) {
      fail(ErrorKind::kStream, who + ": " + e.what());
    }
  }
  p->headers_ready = cfg.info.format != TensorFormat::kStatic;
  send_caps(self, cfg);
  return guard_out.release();
}

GstFlowReturn chain_body(GstTensorConverter *self, GstBuffer *buf) {
  ConverterPriv *p = self->priv;
  nns::gst::BufferPtr in(buf);
  if (!p->configured)
    fail(ErrorKind::kNegotiation, "received a buffer before caps were set");
  const gsize size = gst_buffer_get_size(buf);
  const auto &m = p->media;
  guint frames_in = 1;
  GstBuffer *conv = nullptr;  // owned result of the media step
  switch (m.kind) {
    case MediaKind::kVideo: {
      nns::gst::VideoLayout l = nns::gst::buffer_video_layout(buf, m.video);
      if (size != l.size && !(gst_buffer_get_video_meta(buf) && size > l.size))
        fail(ErrorKind::kStream, "buffer has " + std::to_string(size) + " bytes, expected " +
                                     std::to_string(l.size) + " for " + m.describe);
      conv = l.contiguous() ? shell_with(buf, single_memory(buf, m.frame_size))
                            : shell_with(buf, nns::gst::copy_video_frame(buf, l));
      break;
    }
    case MediaKind::kAudio:
      if (size == 0 || size % m.frame_size)
        fail(ErrorKind::kStream, "buffer has " + std::to_string(size) +
                                     " bytes, expected a multiple of " +
                                     std::to_string(m.frame_size) + " (one sample of each "
                                     "channel) for " + m.describe);
      frames_in = static_cast<guint>(size / m.frame_size);
      conv = m.swap_width ? shell_with(buf, nns::gst::copy_swapped(buf, m.swap_width))
                          : shell_with(buf, single_memory(buf, size));
      break;
    case MediaKind::kText:
      conv = size == m.frame_size ? shell_with(buf, single_memory(buf, size))
                                  : shell_with(buf, nns::gst::copy_resized(buf, m.frame_size));
      break;
    case MediaKind::kOctet:
      if (m.config.info.format == TensorFormat::kStatic) {
        if (size == 0 || size % m.frame_size)
          fail(ErrorKind::kStream, "buffer has " + std::to_string(size) + " bytes, expected " +
                                       std::to_string(m.frame_size) + " (or a multiple) for " +
                                       m.config.info.to_string() + " from " + props_string(p));
        frames_in = static_cast<guint>(size / m.frame_size);
      } else if (size == 0) {
        fail(ErrorKind::kStream, "received an empty octet-stream buffer");
      }
      conv = shell_with(buf, single_memory(buf, size));
      break;
    case MediaKind::kFlexTensor:
      if (p->flex_passthrough) {
        conv = in.release();
      } else {
        conv = from_flexible(self, buf);
      }
      break;
    default: {
      bool owns = true;
      conv = from_custom(self, buf, &owns);
      if (!owns) (void)in.release();
      break;
    }
  }
  nns::gst::BufferPtr out(conv);
  in.reset();
  if (!p->caps_sent) send_caps(self, m.config);
  push_segment(self);
  out.reset(gst_buffer_make_writable(out.release()));
  stamp(self, out.get(), frames_in);
  if (frames_in == p->frames_out) return push_out(self, out.release());
  return push_chunks(self, out.release(), frames_in);
}

GstFlowReturn chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_CONVERTER(parent);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&] { return chain_body(self, buf); });
}

// ---- events and queries --------------------------------------------------------------------

gboolean sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_CONVERTER(parent);
  ConverterPriv *p = self->priv;
  switch (GST_EVENT_TYPE(event)) {
    case GST_EVENT_CAPS: {
      GstCaps *caps = nullptr;
      gst_event_parse_caps(event, &caps);
      gboolean ok = nns::gst::guard(self, FALSE, [&]() -> gboolean {
        configure(self, caps);
        return TRUE;
      });
      gst_event_unref(event);
      return ok;
    }
    case GST_EVENT_SEGMENT: {
      GstSegment seg;
      gst_event_copy_segment(event, &seg);
      if (seg.format != GST_FORMAT_TIME && seg.format != GST_FORMAT_BYTES) {
        NNS_POST_ERROR(self, ErrorKind::kStream,
                       std::string("segment format ") + gst_format_get_name(seg.format) +
                           " is not supported (expected time or bytes)");
        gst_event_unref(event);
        return FALSE;
      }
      p->segment = seg;
      if (seg.format == GST_FORMAT_TIME && p->caps_sent) {
        p->need_segment = false;
        return gst_pad_push_event(self->srcpad, event);
      }
      p->need_segment = true;  // pushed after the src caps, before the next buffer
      gst_event_unref(event);
      return TRUE;
    }
    case GST_EVENT_EOS:
      if (p->adapter && gst_adapter_available(p->adapter) > 0)
        GST_INFO_OBJECT(self, "dropping %" G_GSIZE_FORMAT " bytes: fewer than frames-per-tensor",
                        gst_adapter_available(p->adapter));
      if (p->need_segment && p->caps_sent) push_segment(self);
      break;
    case GST_EVENT_FLUSH_STOP:
      reset_stream(p);
      break;
    default:
      break;
  }
  return gst_pad_event_default(pad, parent, event);
}

GstCaps *sink_base_caps(GstTensorConverter *self) {
  GstCaps *caps = gst_pad_get_pad_template_caps(self->sinkpad);
  GstCaps *ext = nns::gst::ConverterRegistry::instance().all_caps();
  return gst_caps_merge(caps, ext);
}

GstCaps *sink_query_caps(GstTensorConverter *self, GstCaps *filter) {
  GstCaps *caps = sink_base_caps(self);
  bool custom_mode;
  GST_OBJECT_LOCK(self);
  custom_mode = !self->priv->settings.mode.empty();
  GST_OBJECT_UNLOCK(self);
  if (!custom_mode) {
    nns::gst::CapsPtr peer(gst_pad_peer_query_caps(self->srcpad, nullptr));
    if (peer && !gst_caps_is_any(peer.get()) && !gst_caps_is_empty(peer.get()) &&
        nns::gst::is_tensor_caps(peer.get())) {
      try {
        TensorsConfig pc = nns::gst::config_from_caps(peer.get());
        GstCaps *narrowed = nns::gst::media_caps_for_tensor(pc, caps);
        gst_caps_unref(caps);
        caps = narrowed;
      } catch (const nns::Error &) {
      }
    }
  }
  if (filter) {
    GstCaps *x = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    caps = x;
  }
  return caps;
}

gboolean sink_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  auto *self = GST_TENSOR_CONVERTER(parent);
  switch (GST_QUERY_TYPE(query)) {
    case GST_QUERY_CAPS: {
      GstCaps *filter = nullptr;
      gst_query_parse_caps(query, &filter);
      GstCaps *caps = sink_query_caps(self, filter);
      gst_query_set_caps_result(query, caps);
      gst_caps_unref(caps);
      return TRUE;
    }
    case GST_QUERY_ACCEPT_CAPS: {
      GstCaps *caps = nullptr;
      gst_query_parse_accept_caps(query, &caps);
      gboolean ok = FALSE;
      if (gst_caps_is_fixed(caps)) {
        nns::gst::CapsPtr base(sink_base_caps(self));
        // Raw media outside the template (e.g. format=I420) is let through so the CAPS
        // event can post an error naming the field; caps queries still offer the template.
        MediaKind k = nns::gst::media_kind_of(gst_caps_get_structure(caps, 0));
        ok = gst_caps_can_intersect(base.get(), caps) || k == MediaKind::kVideo ||
             k == MediaKind::kAudio || k == MediaKind::kText;
      }
      gst_query_set_accept_caps_result(query, ok);
      return TRUE;
    }
    default:
      return gst_pad_query_default(pad, parent, query);
  }
}

gboolean src_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  if (GST_QUERY_TYPE(query) != GST_QUERY_CAPS) return gst_pad_query_default(pad, parent, query);
  GstCaps *filter = nullptr;
  gst_query_parse_caps(query, &filter);
  GstCaps *caps = gst_pad_get_current_caps(pad);
  if (!caps) caps = gst_pad_get_pad_template_caps(pad);
  if (filter) {
    GstCaps *x = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    caps = x;
  }
  gst_query_set_caps_result(query, caps);
  gst_caps_unref(caps);
  return TRUE;
}

}  // namespace

// ---- GObject -------------------------------------------------------------------------------

static void gst_tensor_converter_set_property(GObject *object, guint id, const GValue *value,
                                              GParamSpec *pspec) {
  auto *self = GST_TENSOR_CONVERTER(object);
  Settings &s = self->priv->settings;
  GST_OBJECT_LOCK(self);
  switch (id) {
    case PROP_INPUT_DIM:
      s.input_dim = g_value_get_string(value) ? g_value_get_string(value) : "";
      break;
    case PROP_INPUT_TYPE:
      s.input_type = g_value_get_string(value) ? g_value_get_string(value) : "";
      break;
    case PROP_FRAMES_PER_TENSOR:
      s.frames_per_tensor = g_value_get_uint(value);
      break;
    case PROP_SET_TIMESTAMP:
      s.set_timestamp = g_value_get_boolean(value);
      break;
    case PROP_SILENT:
      s.silent = g_value_get_boolean(value);
      break;
    case PROP_MODE:
      s.mode = g_value_get_string(value) ? g_value_get_string(value) : "";
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
  GST_OBJECT_UNLOCK(self);
}

static void gst_tensor_converter_get_property(GObject *object, guint id, GValue *value,
                                              GParamSpec *pspec) {
  auto *self = GST_TENSOR_CONVERTER(object);
  if (id == PROP_SUB_PLUGINS) {
    std::string list;
    for (const auto &n : nns::gst::ConverterRegistry::instance().names())
      list += (list.empty() ? "" : ",") + n;
    g_value_set_string(value, list.c_str());
    return;
  }
  const Settings &s = self->priv->settings;
  GST_OBJECT_LOCK(self);
  switch (id) {
    case PROP_INPUT_DIM:
      g_value_set_string(value, s.input_dim.c_str());
      break;
    case PROP_INPUT_TYPE:
      g_value_set_string(value, s.input_type.c_str());
      break;
    case PROP_FRAMES_PER_TENSOR:
      g_value_set_uint(value, s.frames_per_tensor);
      break;
    case PROP_SET_TIMESTAMP:
      g_value_set_boolean(value, s.set_timestamp);
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, s.silent);
      break;
    case PROP_MODE:
      g_value_set_string(value, s.mode.c_str());
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
  GST_OBJECT_UNLOCK(self);
}

static GstStateChangeReturn gst_tensor_converter_change_state(GstElement *element,
                                                              GstStateChange transition) {
  auto *self = GST_TENSOR_CONVERTER(element);
  ConverterPriv *p = self->priv;
  if (transition == GST_STATE_CHANGE_READY_TO_PAUSED) {
    gboolean ok = nns::gst::guard(self, FALSE, [&]() -> gboolean {
      snapshot_settings(self);
      return TRUE;
    });
    if (!ok) return GST_STATE_CHANGE_FAILURE;
    reset_stream(p);
    p->configured = p->caps_sent = false;
  }
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_converter_parent_class)->change_state(element, transition);
  if (transition == GST_STATE_CHANGE_PAUSED_TO_READY) {
    reset_stream(p);
    close_external(p);
    p->configured = p->caps_sent = false;
  }
  return ret;
}

static void gst_tensor_converter_finalize(GObject *object) {
  auto *self = GST_TENSOR_CONVERTER(object);
  close_external(self->priv);
  if (self->priv->adapter) g_object_unref(self->priv->adapter);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_converter_parent_class)->finalize(object);
}

static void gst_tensor_converter_class_init(GstTensorConverterClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_converter_debug, "tensor_converter", 0,
                          "Converts media streams to tensor streams");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_converter_set_property;
  gobject_class->get_property = gst_tensor_converter_get_property;
  gobject_class->finalize = gst_tensor_converter_finalize;

  g_object_class_install_property(
      gobject_class, PROP_INPUT_DIM,
      g_param_spec_string("input-dim", "Input tensor dimension",
                          "Input tensor dimension from inner array", "", kRW));
  g_object_class_install_property(
      gobject_class, PROP_INPUT_TYPE,
      g_param_spec_string("input-type", "Input tensor type",
                          "Type of each element of the input tensor", "", kRW));
  g_object_class_install_property(
      gobject_class, PROP_FRAMES_PER_TENSOR,
      g_param_spec_uint("frames-per-tensor", "Frames per tensor",
                        "The number of frames in output tensor", 1, G_MAXUINT, 1, kRW));
  g_object_class_install_property(
      gobject_class, PROP_SET_TIMESTAMP,
      g_param_spec_boolean("set-timestamp", "Set timestamp",
                           "The flag to set timestamp when received a buffer with invalid "
                           "timestamp",
                           TRUE, kRW));
  g_object_class_install_property(
      gobject_class, PROP_SUB_PLUGINS,
      g_param_spec_string("sub-plugins", "Sub-plugins", "Registrable sub-plugins list", "",
                          static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Produce verbose output", TRUE, kRW));
  g_object_class_install_property(
      gobject_class, PROP_MODE,
      g_param_spec_string("mode", "Mode",
                          "Converter mode. e.g., mode=custom-code:<registered callback name> "
                          "or mode=custom-script:<script path>",
                          "", kRW));

  GstCaps *sink_caps = gst_caps_from_string(NNS_CONVERTER_MEDIA_CAPS_STR);
  sink_caps = gst_caps_merge(sink_caps, nns::gst::ConverterRegistry::instance().all_caps());
  gst_element_class_add_pad_template(
      element_class, gst_pad_template_new("sink", GST_PAD_SINK, GST_PAD_ALWAYS, sink_caps));
  gst_caps_unref(sink_caps);
  GstCaps *src_caps = gst_caps_from_string(NNS_TENSOR_CAPS_ANY_STR);
  gst_element_class_add_pad_template(
      element_class, gst_pad_template_new("src", GST_PAD_SRC, GST_PAD_ALWAYS, src_caps));
  gst_caps_unref(src_caps);

  gst_element_class_set_static_metadata(
      element_class, "TensorConverter", "Converter/Tensor",
      "Converts an audio, video, text, or arbitrary stream to a tensor stream of C-Array for "
      "neural network framework filters",
      "nnstreamer-cpp");
  element_class->change_state = gst_tensor_converter_change_state;
}

static void gst_tensor_converter_init(GstTensorConverter *self) {
  self->priv = new ConverterPriv();
  self->priv->adapter = gst_adapter_new();
  gst_segment_init(&self->priv->segment, GST_FORMAT_TIME);
  auto *klass = GST_ELEMENT_GET_CLASS(self);
  self->sinkpad =
      gst_pad_new_from_template(gst_element_class_get_pad_template(klass, "sink"), "sink");
  gst_pad_set_event_function(self->sinkpad, GST_DEBUG_FUNCPTR(sink_event));
  gst_pad_set_query_function(self->sinkpad, GST_DEBUG_FUNCPTR(sink_query));
  gst_pad_set_chain_function(self->sinkpad, GST_DEBUG_FUNCPTR(chain));
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
  self->srcpad = gst_pad_new_from_template(gst_element_class_get_pad_template(klass, "src"), "src");
  gst_pad_set_query_function(self->srcpad, GST_DEBUG_FUNCPTR(src_query));
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
}

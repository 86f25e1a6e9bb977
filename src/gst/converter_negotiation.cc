// SPDX-License-Identifier: LGPL-2.1-only
// tensor_converter negotiation: settings, input caps -> output tensors, src caps.
#include <cstring>

#include "core/error.h"
#include "core/c_tensor_info.h"
#include "gst/converter_state.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

#define GST_CAT_DEFAULT nns_tensor_converter_debug

namespace nns::gst {

void snapshot_settings(ConverterState *p, const ConverterSettings &s) {
  p->active = s;
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
  p->mode = ConverterMode::kNone;
  p->mode_option.clear();
  std::string mode = nns::trim(s.mode);
  if (!mode.empty()) {
    auto colon = mode.find(':');
    std::string kind = mode.substr(0, colon);
    std::string opt = colon == std::string::npos ? "" : nns::trim(mode.substr(colon + 1));
    if (g_ascii_strcasecmp(kind.c_str(), "custom-code") == 0)
      p->mode = ConverterMode::kCustomCode;
    else if (g_ascii_strcasecmp(kind.c_str(), "custom-script") == 0)
      p->mode = ConverterMode::kCustomScript;
    else
      fail(ErrorKind::kSettings, "mode='" + mode +
                                     "' is not custom-code:<registered name> or "
                                     "custom-script:<script path>");
    if (opt.empty())
      fail(ErrorKind::kSettings, "mode='" + mode + "' lacks the name after '" + kind + ":'");
    p->mode_option = opt;
  }
}

void reset_stream(ConverterState *p) {
  if (p->adapter) gst_adapter_clear(p->adapter);
  gst_segment_init(&p->segment, GST_FORMAT_TIME);
  p->need_segment = false;
  p->old_ts = GST_CLOCK_TIME_NONE;
}

void close_external(ConverterState *p) {
  if (p->ext && p->ext->close && p->ext_priv) p->ext->close(&p->ext_priv);
  p->ext = nullptr;
  p->ext_priv = nullptr;
}

std::string subplugin_reason(const void *priv) {
  static constexpr char kMagic[8] = {'N', 'N', 'S', 'D', 'E', 'R', 'R', '\0'};
  if (!priv || std::memcmp(priv, kMagic, sizeof kMagic) != 0) return {};
  const char *msg = static_cast<const char *>(priv) + sizeof kMagic;
  return std::string(msg, strnlen(msg, 512));
}

namespace {

GstCaps *flexible_caps(int rate_n, int rate_d) {
  return caps_for_format(TensorFormat::kFlexible, rate_n, rate_d);
}

bool peer_accepts_flexible(ConverterState *p, int rate_n, int rate_d) {
  CapsPtr peer(gst_pad_peer_query_caps(p->srcpad, nullptr));
  CapsPtr flex(flexible_caps(rate_n, rate_d));
  return peer && gst_caps_can_intersect(peer.get(), flex.get());
}

// Flexible caps for the tensors of `cfg` as a peer may read them: format=flexible plus the static
// description, so a peer (capsfilter) asking for other types or dimensions does not intersect.
bool peer_accepts_flexible_for(ConverterState *p, const TensorsConfig &cfg) {
  CapsPtr peer(gst_pad_peer_query_caps(p->srcpad, nullptr));
  if (!peer) return false;
  CapsPtr flex(flexible_caps(cfg.rate_n, cfg.rate_d));
  if (!cfg.info.valid()) return gst_caps_can_intersect(peer.get(), flex.get());
  TensorsConfig described = cfg;
  described.info.format = TensorFormat::kStatic;
  nns::gst::StructurePtr s(structure_from_config(described));
  gst_structure_set(s.get(), "format", G_TYPE_STRING, "flexible", nullptr);
  CapsPtr honest(gst_caps_new_full(s.release(), nullptr));
  return gst_caps_can_intersect(peer.get(), honest.get());
}

bool peer_accepts_static(ConverterState *p, int rate_n, int rate_d) {
  CapsPtr peer(gst_pad_peer_query_caps(p->srcpad, nullptr));
  CapsPtr fixed(caps_for_format(TensorFormat::kStatic, rate_n, rate_d));
  gst_caps_append(fixed.get(), legacy_tensor_caps(rate_n, rate_d));
  return peer && gst_caps_can_intersect(peer.get(), fixed.get());
}

// Sets the src caps for `cfg` (static, or flexible when `cfg` is flexible or downstream only
// takes flexible). Throws when downstream accepts neither.
}  // namespace

void send_caps(ConverterState *p, const TensorsConfig &cfg) {
  if (p->caps_sent && cfg.same_as(p->sent) && cfg.info.format == p->sent.info.format &&
      cfg.rate_n == p->sent.rate_n && cfg.rate_d == p->sent.rate_d)
    return;
  CapsPtr caps;
  bool flexible = cfg.info.format != TensorFormat::kStatic || p->flex_passthrough;
  if (!flexible) {
    CapsPtr mine(caps_from_config(cfg, true));
    CapsPtr peer(gst_pad_peer_query_caps(p->srcpad, nullptr));
    CapsPtr both(gst_caps_intersect_full(mine.get(), peer.get(), GST_CAPS_INTERSECT_FIRST));
    if (!gst_caps_is_empty(both.get())) {
      caps.reset(gst_caps_fixate(both.release()));
    } else if (peer_accepts_flexible_for(p, cfg)) {
      flexible = true;
    } else {
      CapsPtr plain(caps_from_config(cfg, false));
      fail(ErrorKind::kNegotiation, "downstream accepts " + caps_to_string(peer.get()) +
                                        " but the " + p->media.describe + " input gives " +
                                        caps_to_string(plain.get()));
    }
  }
  if (flexible) caps.reset(flexible_caps(cfg.rate_n, cfg.rate_d));
  GST_DEBUG_OBJECT(p->element, "src caps %" GST_PTR_FORMAT, caps.get());
  if (!gst_pad_set_caps(p->srcpad, caps.get()))
    fail(ErrorKind::kNegotiation, "downstream refused caps " + caps_to_string(caps.get()));
  p->out_flexible = flexible;
  p->sent = cfg;
  p->caps_sent = true;
}

namespace {

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

}  // namespace

std::string props_string(const ConverterState *p) {
  return "input-dim='" + p->active.input_dim + "', input-type='" + p->active.input_type + "'";
}

namespace {

void configure_octet(ConverterState *p, const GstStructure *s) {
  auto &m = p->media;
  TensorsConfig cfg;
  if (p->props_valid) {
    cfg.info = p->props;
  } else {
    // No properties: take what downstream fixes, or go flexible when it takes that.
    CapsPtr peer(gst_pad_peer_query_caps(p->srcpad, nullptr));
    TensorsConfig pc;
    bool got = false;
    if (peer && !gst_caps_is_any(peer.get()) && is_tensor_caps(peer.get())) {
      try {
        pc = config_from_caps(peer.get());
        got = pc.info.format == TensorFormat::kStatic && pc.info.valid();
      } catch (const nns::Error &) {
      }
    }
    if (got) {
      cfg.info = pc.info;
    } else if (peer_accepts_flexible(p, -1, -1) && !(peer && gst_caps_is_any(peer.get()))) {
      cfg.info.format = TensorFormat::kFlexible;
    } else {
      std::string missing = p->prop_dims.empty() && p->prop_types.empty()
                                ? "input-dim and input-type are"
                                : (p->prop_dims.empty() ? "input-dim is" : "input-type is");
      fail(ErrorKind::kSettings, "property " + missing +
                                     " required for application/octet-stream (e.g. "
                                     "input-dim=30 input-type=uint8), got " +
                                     props_string(p));
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

// `info` with its frames dimension set to 1.
TensorsInfo one_frame(TensorsInfo info, MediaKind kind) {
  info[0].dims[kind == MediaKind::kVideo ? 3 : 1] = 1;
  return info;
}

}  // namespace

// Handles the sink CAPS event: works out the output and sets src caps when they are known.
void configure(ConverterState *p, GstCaps *caps) {
  if (!gst_caps_is_fixed(caps))
    fail(ErrorKind::kNegotiation, "input caps are not fixed: " + caps_to_string(caps));
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  if (!gst_structure_get_fraction(s, "framerate", &p->in_rate_n, &p->in_rate_d))
    p->in_rate_n = 0, p->in_rate_d = 1;
  MediaKind kind = p->mode != ConverterMode::kNone ? MediaKind::kCustom : media_kind_of(s);
  p->configured = false;
  if (gst_adapter_available(p->adapter) > 0) {
    GST_INFO_OBJECT(p->element, "new caps: dropping %" G_GSIZE_FORMAT " bytes of incomplete tensor",
                    gst_adapter_available(p->adapter));
    gst_adapter_clear(p->adapter);
  }
  p->derive_per_buffer = p->flex_passthrough = p->headers_ready = false;
  p->frames_out = p->fpt;
  close_external(p);
  p->custom = {};
  MediaInfo &m = p->media;
  m = {};
  switch (kind) {
    case MediaKind::kVideo:
      m = media_from_video(caps, p->fpt);
      break;
    case MediaKind::kAudio:
      m = media_from_audio(caps, p->fpt);
      break;
    case MediaKind::kText:
      m = media_from_text(s, p->prop_dims.empty() ? 0 : p->prop_dims[0][0], p->fpt);
      break;
    case MediaKind::kOctet:
      configure_octet(p, s);
      break;
    case MediaKind::kFlexTensor:
      if (p->fpt != 1)
        fail(ErrorKind::kSettings, "frames-per-tensor=" + std::to_string(p->fpt) +
                                       " is not supported for flexible tensor input (use 1)");
      m.describe = "flexible tensors";
      m.config.rate_n = p->in_rate_n;
      m.config.rate_d = p->in_rate_d;
      // As upstream, flexible in gives static out (headers stripped, caps from each buffer's
      // headers); passed through untouched only to a peer that takes flexible tensors alone.
      if (p->props_valid) {
        m.config.info = p->props;
      } else if (!peer_accepts_static(p, p->in_rate_n, p->in_rate_d) &&
                 peer_accepts_flexible(p, p->in_rate_n, p->in_rate_d)) {
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
      auto &reg = ConverterRegistry::instance();
      if (p->mode == ConverterMode::kCustomCode) {
        auto cb = reg.find_custom(p->mode_option);
        if (!cb)
          fail(ErrorKind::kNotFound, "mode=custom-code:" + p->mode_option +
                                         ": no callback is "
                                         "registered as '" +
                                         p->mode_option +
                                         "' (nnstreamer_converter_custom_register)");
        p->custom = *cb;
        m.describe = "custom-code:" + p->mode_option;
        break;
      }
      std::string want;
      if (p->mode == ConverterMode::kCustomScript) {
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
            std::string why = subplugin_reason(p->ext_priv);
            close_external(p);  // a sub-plugin may keep data (its error slot) after a failure
            fail(ErrorKind::kLibrary, "mode=custom-script:" + p->mode_option + ": sub-plugin '" +
                                          want + "' failed to open it (" + std::to_string(r) + ")" +
                                          (why.empty() ? "" : ": " + why));
          }
        }
      } else {
        want = gst_structure_get_name(s);
        p->ext = reg.find_for_media(want);
        if (!p->ext)
          fail(ErrorKind::kNegotiation, "input caps " + caps_to_string(caps) +
                                            " are not a supported media type and no converter "
                                            "sub-plugin accepts '" +
                                            want + "'");
      }
      m.describe = std::string("converter sub-plugin '") + p->ext->name + "'";
      CTensorsConfig c;
      if (p->ext->get_out_config(caps, c.get())) {
        m.config = from_c(c.get());
        if (m.config.rate_n < 0) m.config.rate_n = p->in_rate_n, m.config.rate_d = p->in_rate_d;
        p->derive_per_buffer = !(m.config.info.valid() && !m.config.info.tensors.empty()) &&
                               m.config.info.format == TensorFormat::kStatic;
      } else if (p->mode != ConverterMode::kCustomScript) {
        fail(ErrorKind::kNegotiation,
             m.describe + " cannot describe tensors for caps " + caps_to_string(caps));
      }
      break;
    }
  }
  m.kind = kind;
  // Properties given for media that fix the tensor themselves must agree with it.
  // (either for the whole tensor or for a single frame).
  if (p->props_valid &&
      (kind == MediaKind::kVideo || kind == MediaKind::kAudio || kind == MediaKind::kText) &&
      !p->props.same_as(m.config.info) && !p->props.same_as(one_frame(m.config.info, kind)))
    fail(ErrorKind::kSettings, props_string(p) + " do not match the " + m.describe +
                                   " input, which gives " + m.config.info.to_string());
  p->configured = true;
  if (!p->derive_per_buffer) send_caps(p, m.config);
}

}  // namespace nns::gst

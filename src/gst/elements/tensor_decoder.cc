// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_decoder
 *
 * Turns tensor frames into media (video, text, ...) with a decoder sub-plugin chosen by `mode`
 * (libnnstreamer_decoder_<mode>.so, see docs/elements/tensor_decoder.md) configured by
 * option1..option9, or with an application callback (mode=custom-code option1=<name>).
 * Static and flexible input: for a flexible stream the tensors are read from each buffer's
 * headers, the decoder sees them as a static config (headers stripped) and the output caps are
 * negotiated again whenever they change. The serialising modes (protobuf, flatbuf, flexbuf) get
 * the flexible config and each tensor with its 128-byte header instead, as upstream passes them,
 * so the bytes they write keep the headers.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=3 ! video/x-raw,format=RGB,width=64,height=48 !
 *     tensor_converter ! tensor_decoder mode=direct_video ! videoconvert ! fakesink
 */
#include <gst/base/gstbasetransform.h>

#include <array>
#include <atomic>
#include <cstring>
#include <optional>
#include <mutex>
#include <string>

#include "core/c_tensor_info.h"
#include "core/tensor_info.h"
#include "gst/config_file.h"
#include "gst/decoder_registry.h"
#include "core/meta_header.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_decoder_debug);
#define GST_CAT_DEFAULT tensor_decoder_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_DECODER (gst_tensor_decoder_get_type())
G_DECLARE_FINAL_TYPE(GstTensorDecoder, gst_tensor_decoder, GST, TENSOR_DECODER, GstBaseTransform)
G_END_DECLS

namespace {

constexpr int kNumOptions = 9;
constexpr const char *kCustomMode = "custom-code";

struct DecoderPriv {
  // Settings
  std::mutex lock;
  std::string mode;
  std::array<std::optional<std::string>, kNumOptions> options;
  std::string config_file;
  std::atomic<bool> silent{true};
  std::vector<std::string> config_problems;
  // State: the active decoder, created on first use after mode/options change.
  const GstTensorDecoderDef *def = nullptr;
  void *pdata = nullptr;
  bool configured = false;
  std::optional<nns::gst::CustomDecoder> custom;
  nns::CTensorsConfig in_config;
  nns::TensorsConfig in_cfg;  // static config the decoder sees
  // Flexible input given to the decoder as it is (headers kept, config format flexible).
  bool raw_flexible = false;
  // Flexible input: upstream caps are format=flexible; flex_cfg is the static config the
  // headers of the last buffer described (flex_known once a buffer came).
  bool flexible = false;
  int flex_rate_n = 0, flex_rate_d = 1;
  bool flex_known = false;
  nns::TensorsConfig flex_cfg;
  // Sticky events (segment, tags) that came after a flexible CAPS event: forwarded once caps are
  // negotiated, so downstream sees caps before them.
  std::vector<GstEvent *> held;

  void drop_held() {
    for (GstEvent *e : held) gst_event_unref(e);
    held.clear();
  }

  void release() {
    if (def && pdata && def->exit) def->exit(&pdata);
    def = nullptr;
    pdata = nullptr;
    custom.reset();
    configured = false;
  }
};

enum {
  PROP_0,
  PROP_SILENT,
  PROP_MODE,
  PROP_OPTION1,
  PROP_OPTION9 = PROP_OPTION1 + kNumOptions - 1,
  PROP_SUBPLUGINS,
  PROP_CONFIG_FILE,
};

// Why a built-in decoder refused (see backends/decoder/common/decoder_common.h), or "".
std::string decoder_reason(void *pdata) {
  static constexpr char kMagic[8] = {'N', 'N', 'S', 'D', 'E', 'R', 'R', '\0'};
  if (!pdata || std::memcmp(pdata, kMagic, sizeof kMagic) != 0) return {};
  const char *msg = static_cast<const char *>(pdata) + sizeof kMagic;
  return std::string(msg, strnlen(msg, 512));
}

// Modes that serialise the tensors: with flexible input they get the memories with their
// headers and a flexible config, as NNStreamer hands them over (the headers end up in the bytes).
bool keeps_flexible_headers(const std::string &mode) {
  return mode == "protobuf" || mode == "flatbuf" || mode == "flexbuf";
}

// Empties the message a built-in decoder left in its private data (see decoder_reason).
void clear_decoder_reason(void *pdata) {
  if (!decoder_reason(pdata).empty()) static_cast<char *>(pdata)[8] = '\0';
}

// Creates the decoder for the current mode and applies the options. Throws nns::Error with a
// message naming the mode or option. A built-in decoder that accepts an option but leaves a
// message (e.g. direct_video's unknown format, replaced by the default) gets it posted as a
// warning on `element`'s bus. Caller holds p->lock.
void configure(DecoderPriv *p, GstElement *element) {
  if (p->configured) return;
  if (!p->config_problems.empty())
    throw nns::Error(nns::ErrorKind::kSettings,
                     "config-file: " + nns::join(p->config_problems, ", "));
  if (p->mode.empty())
    throw nns::Error(nns::ErrorKind::kSettings,
                     "property 'mode' is not set; available modes: " +
                         nns::join(nns::gst::DecoderRegistry::instance().names(), ", ") + ", " +
                         kCustomMode);
  if (p->mode == kCustomMode) {
    const auto &name = p->options[0];
    if (!name || name->empty())
      throw nns::Error(nns::ErrorKind::kSettings,
                       "mode=custom-code needs option1=<name of a registered custom decoder>");
    p->custom = nns::gst::DecoderRegistry::instance().find_custom(*name);
    if (!p->custom)
      throw nns::Error(nns::ErrorKind::kSettings, "mode=custom-code: no custom decoder '" + *name +
                                                      "' is registered (option1)");
    p->configured = true;
    return;
  }
  auto &reg = nns::gst::DecoderRegistry::instance();
  const GstTensorDecoderDef *def = reg.find(p->mode);
  if (!def) {
    std::string why = reg.load_error(p->mode);
    throw nns::Error(nns::ErrorKind::kSettings,
                     "unknown mode '" + p->mode + "'" + (why.empty() ? "" : " (" + why + ")") +
                         "; available modes: " + nns::join(reg.names(), ", ") + ", " + kCustomMode);
  }
  void *pdata = nullptr;
  if (!def->init(&pdata))
    throw nns::Error(nns::ErrorKind::kSettings, "mode '" + p->mode + "': decoder init failed");
  for (int i = 0; i < kNumOptions; ++i) {
    if (!p->options[i]) continue;
    if (!def->setOption) break;  // optional, as in NNStreamer: the decoder takes no options
    if (!def->setOption(&pdata, i, p->options[i]->c_str())) {
      std::string why = decoder_reason(pdata);
      if (def->exit) def->exit(&pdata);
      throw nns::Error(nns::ErrorKind::kSettings,
                       "mode '" + p->mode + "' rejected option" + std::to_string(i + 1) + "='" +
                           *p->options[i] + "'" + (why.empty() ? "" : ": " + why));
    }
    std::string note = decoder_reason(pdata);
    if (!note.empty()) {
      clear_decoder_reason(pdata);
      NNS_POST_WARNING(element, "mode '" + p->mode + "' option" + std::to_string(i + 1) + "='" +
                                    *p->options[i] + "': " + note);
    }
  }
  p->def = def;
  p->pdata = pdata;
  p->configured = true;
}

}  // namespace

struct _GstTensorDecoder {
  GstBaseTransform parent;
  DecoderPriv *priv;
};

G_DEFINE_TYPE(GstTensorDecoder, gst_tensor_decoder, GST_TYPE_BASE_TRANSFORM)
GST_ELEMENT_REGISTER_DEFINE(tensor_decoder, "tensor_decoder", GST_RANK_NONE,
                            GST_TYPE_TENSOR_DECODER)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_TENSOR_CAPS_ALL_FORMATS_STR));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void gst_tensor_decoder_set_property(GObject *object, guint id, const GValue *value,
                                            GParamSpec *pspec) {
  auto *self = GST_TENSOR_DECODER(object);
  auto *p = self->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (id >= PROP_OPTION1 && id <= PROP_OPTION9) {
    const char *s = g_value_get_string(value);
    p->options[id - PROP_OPTION1] = s ? std::optional<std::string>(s) : std::nullopt;
    p->release();
    return;
  }
  switch (id) {
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    case PROP_MODE: {
      const char *s = g_value_get_string(value);
      p->mode = s ? s : "";
      p->release();
      break;
    }
    case PROP_CONFIG_FILE: {
      const char *s = g_value_get_string(value);
      p->config_file = s ? s : "";
      if (!p->config_file.empty()) {
        p->lock.unlock();  // the file sets other properties on this object
        auto problems = nns::gst::apply_config_file(object, std::string(s));
        p->lock.lock();
        p->config_problems = std::move(problems);
      }
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_decoder_get_property(GObject *object, guint id, GValue *value,
                                            GParamSpec *pspec) {
  auto *self = GST_TENSOR_DECODER(object);
  auto *p = self->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (id >= PROP_OPTION1 && id <= PROP_OPTION9) {
    const auto &o = p->options[id - PROP_OPTION1];
    g_value_set_string(value, o ? o->c_str() : nullptr);
    return;
  }
  switch (id) {
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    case PROP_MODE:
      g_value_set_string(value, p->mode.c_str());
      break;
    case PROP_CONFIG_FILE:
      g_value_set_string(value, p->config_file.c_str());
      break;
    case PROP_SUBPLUGINS: {
      std::string s;
      for (const auto &n : nns::gst::DecoderRegistry::instance().names())
        s += (s.empty() ? "" : ",") + n;
      g_value_set_string(value, s.c_str());
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

// Output caps for one (possibly unfixed) tensor structure.
static GstCaps *out_caps_for(DecoderPriv *p, const GstStructure *s) {
  if (p->custom) return gst_caps_new_empty_simple("application/octet-stream");
  nns::TensorsConfig cfg;
  try {
    cfg = nns::gst::config_from_structure(s);
  } catch (const nns::Error &) {
    return gst_caps_new_any();  // not a complete description yet
  }
  // Flexible input: the tensors are known from the last buffer's headers (before the first
  // buffer anything may come out). Sparse input is not decoded (tensor_sparse_dec first): such a
  // structure maps to nothing (a caps query may list it beside others; that is no error).
  if (cfg.info.format == nns::TensorFormat::kFlexible) {
    if (!p->flex_known) return gst_caps_new_any();
    cfg = p->flex_cfg;
  } else if (cfg.info.format != nns::TensorFormat::kStatic) {
    return gst_caps_new_empty();
  } else if (cfg.info.size() == 0 || !cfg.info.valid()) {
    // Static tensors not described yet, e.g. "other/tensors, format=static, framerate=30/1":
    // what tensor_transform mode=transpose asks downstream with before its input is known.
    return gst_caps_new_any();
  }
  nns::CTensorsConfig c(cfg);
  GstCaps *caps = p->def->getOutCaps(&p->pdata, c.get());
  bool fixed = gst_structure_foreach(
      s, [](GQuark, const GValue *v, gpointer) -> gboolean { return gst_value_is_fixed(v); },
      nullptr);
  if (!caps && fixed) {
    std::string why = decoder_reason(p->pdata);
    throw nns::Error(nns::ErrorKind::kNegotiation, "mode '" + p->mode + "' cannot decode input " +
                                                       "'" + cfg.info.to_string() + "'" +
                                                       (why.empty() ? "" : ": " + why));
  }
  return caps ? caps : gst_caps_new_any();
}

static GstCaps *gst_tensor_decoder_transform_caps(GstBaseTransform *trans,
                                                  GstPadDirection direction, GstCaps *caps,
                                                  GstCaps *filter) {
  auto *self = GST_TENSOR_DECODER(trans);
  // The error value is made only on error (an eager gst_caps_new_empty() here leaked).
  GstCaps *out = nns::gst::guard(self, static_cast<GstCaps *>(nullptr), [&]() -> GstCaps * {
    GstCaps *result;
    if (direction == GST_PAD_SRC) {
      // Static and flexible input are decoded; sparse is not offered (the template keeps
      // NNStreamer's formats so linking behaves the same).
      result = gst_caps_from_string(
          "other/tensor, framerate = (fraction) [ 0, max ]; "
          "other/tensors, format = (string) static, framerate = (fraction) [ 0, max ]; "
          "other/tensors, format = (string) flexible, framerate = (fraction) [ 0, max ]");
    } else {
      auto *p = self->priv;
      std::lock_guard<std::mutex> l(p->lock);
      try {
        configure(p, GST_ELEMENT(self));
      } catch (const nns::Error &) {
        // Linking may query caps before the settings are complete; start() reports them.
        return gst_caps_new_any();
      }
      nns::gst::CapsPtr merged(gst_caps_new_empty());  // freed when out_caps_for throws
      for (guint i = 0; i < gst_caps_get_size(caps); ++i) {
        GstCaps *one = out_caps_for(p, gst_caps_get_structure(caps, i));
        merged.reset(gst_caps_merge(merged.release(), one));
      }
      result = merged.release();
    }
    if (filter) {
      GstCaps *r = gst_caps_intersect_full(filter, result, GST_CAPS_INTERSECT_FIRST);
      gst_caps_unref(result);
      result = r;
    }
    return result;
  });
  return out ? out : gst_caps_new_empty();
}

static GstCaps *gst_tensor_decoder_fixate_caps(GstBaseTransform *trans, GstPadDirection direction,
                                               GstCaps *caps, GstCaps *othercaps) {
  auto *self = GST_TENSOR_DECODER(trans);
  (void)direction;
  return nns::gst::guard(self, othercaps, [&]() -> GstCaps * {
    auto *p = self->priv;
    GstCaps *supposed;
    {
      std::lock_guard<std::mutex> l(p->lock);
      configure(p, GST_ELEMENT(self));
      GstCaps *fixed_in = gst_caps_fixate(gst_caps_ref(caps));
      supposed = out_caps_for(p, gst_caps_get_structure(fixed_in, 0));
      gst_caps_unref(fixed_in);
    }
    GstCaps *r = gst_caps_intersect(othercaps, supposed);
    gst_caps_unref(supposed);
    if (gst_caps_is_empty(r)) {
      gst_caps_unref(r);
      r = othercaps;
    } else {
      gst_caps_unref(othercaps);
    }
    return gst_caps_fixate(r);
  });
}

static gboolean gst_tensor_decoder_set_caps(GstBaseTransform *trans, GstCaps *incaps,
                                            GstCaps *outcaps) {
  auto *self = GST_TENSOR_DECODER(trans);
  (void)outcaps;
  return nns::gst::guard(self, FALSE, [&] {
    auto *p = self->priv;
    std::lock_guard<std::mutex> l(p->lock);
    configure(p, GST_ELEMENT(self));
    nns::TensorsConfig cfg = nns::gst::config_from_caps(incaps);
    if (cfg.info.format == nns::TensorFormat::kFlexible) {
      // Renegotiation (RECONFIGURE) with the flexible sink caps: use the last headers.
      if (!p->flex_known)
        throw nns::Error(nns::ErrorKind::kNegotiation,
                         "flexible input: no buffer has described the tensors yet");
      cfg = p->flex_cfg;
    }
    p->in_cfg = cfg;
    nns::to_c(p->in_cfg, p->in_config.get());
    p->raw_flexible = p->flexible && !p->custom && keeps_flexible_headers(p->mode);
    if (p->raw_flexible) p->in_config.get()->info.format = _NNS_TENSOR_FORMAT_FLEXIBLE;
    return TRUE;
  });
}

static gboolean gst_tensor_decoder_transform_size(GstBaseTransform *trans,
                                                  GstPadDirection direction, GstCaps *caps,
                                                  gsize size, GstCaps *othercaps,
                                                  gsize *othersize) {
  auto *self = GST_TENSOR_DECODER(trans);
  auto *p = self->priv;
  *othersize = 0;
  if (direction == GST_PAD_SRC) return FALSE;
  std::lock_guard<std::mutex> l(p->lock);
  if (p->def && p->def->getTransformSize)
    *othersize =
        p->def->getTransformSize(&p->pdata, p->in_config.get(), caps, size, othercaps, direction);
  return TRUE;
}

static GstFlowReturn gst_tensor_decoder_prepare_output_buffer(GstBaseTransform *trans,
                                                              GstBuffer *inbuf,
                                                              GstBuffer **outbuf) {
  auto *self = GST_TENSOR_DECODER(trans);
  auto *p = self->priv;
  gsize size = 0;
  {
    std::lock_guard<std::mutex> l(p->lock);
    if (p->def && p->def->getTransformSize) {
      GstCaps *in = gst_pad_get_current_caps(GST_BASE_TRANSFORM_SINK_PAD(trans));
      GstCaps *out = gst_pad_get_current_caps(GST_BASE_TRANSFORM_SRC_PAD(trans));
      size = p->def->getTransformSize(&p->pdata, p->in_config.get(), in, gst_buffer_get_size(inbuf),
                                      out, GST_PAD_SINK);
      if (in) gst_caps_unref(in);
      if (out) gst_caps_unref(out);
    }
  }
  *outbuf = size ? gst_buffer_new_allocate(nullptr, size, nullptr) : gst_buffer_new();
  gst_buffer_copy_into(*outbuf, inbuf, GST_BUFFER_COPY_METADATA, 0, -1);
  return GST_FLOW_OK;
}

static GstFlowReturn gst_tensor_decoder_transform(GstBaseTransform *trans, GstBuffer *inbuf,
                                                  GstBuffer *outbuf) {
  auto *self = GST_TENSOR_DECODER(trans);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&] {
    auto *p = self->priv;
    std::lock_guard<std::mutex> l(p->lock);
    configure(p, GST_ELEMENT(self));
    const auto &info = p->in_cfg.info;
    // Flexible buffers: one memory per tensor, its 128-byte header already checked against
    // in_cfg (submit_input_buffer); the decoder gets the payload only (the serialising modes:
    // the whole memory).
    const bool flex = p->flexible;
    const std::size_t skip = flex && !p->raw_flexible ? nns::kMetaHeaderSize : 0;
    std::size_t n = flex ? gst_buffer_n_memory(inbuf) : nns::gst::buffer_tensor_count(inbuf);
    if (!flex) nns::gst::check_static_buffer(inbuf, info);
    if (flex && n != info.tensors.size())
      throw nns::Error(nns::ErrorKind::kStream,
                       "flexible input buffer holds " + std::to_string(n) + " tensors, " +
                           std::to_string(info.tensors.size()) + " negotiated");
    if (n == 0 || n > NNS_TENSOR_SIZE_LIMIT)
      throw nns::Error(nns::ErrorKind::kStream,
                       "input buffer holds " + std::to_string(n) + " tensors");
    std::array<GstMapInfo, NNS_TENSOR_SIZE_LIMIT> maps{};
    std::array<GstMemory *, NNS_TENSOR_SIZE_LIMIT> mems{};
    std::array<GstTensorMemory, NNS_TENSOR_SIZE_LIMIT> tm{};
    std::size_t mapped = 0;
    auto unmap = [&] {
      for (std::size_t i = 0; i < mapped; ++i) {
        gst_memory_unmap(mems[i], &maps[i]);
        gst_memory_unref(mems[i]);
      }
    };
    for (; mapped < n; ++mapped) {
      mems[mapped] = flex ? gst_buffer_get_memory(inbuf, static_cast<guint>(mapped))
                          : nns::gst::buffer_get_tensor(inbuf, mapped);
      if (!gst_memory_map(mems[mapped], &maps[mapped], GST_MAP_READ)) {
        gst_memory_unref(mems[mapped]);
        unmap();
        throw nns::Error(nns::ErrorKind::kStream,
                         "cannot map input tensor " + std::to_string(mapped));
      }
      if (maps[mapped].size < skip) {
        ++mapped;
        unmap();
        throw nns::Error(nns::ErrorKind::kStream, "input tensor " + std::to_string(mapped - 1) +
                                                      ": flexible memory shorter than its header");
      }
      tm[mapped].data = maps[mapped].data + skip;
      tm[mapped].size = maps[mapped].size - skip;
    }
    GstFlowReturn ret = GST_FLOW_OK;
    std::string what;
    if (p->custom) {
      int r = p->custom->func(tm.data(), p->in_config.get(), p->custom->data, outbuf);
      if (r != 0) {
        ret = GST_FLOW_ERROR;
        what = "custom decoder '" + *p->options[0] + "' failed (" + std::to_string(r) + ")";
      }
    } else {
      ret = p->def->decode(&p->pdata, p->in_config.get(), tm.data(), outbuf);
      if (ret != GST_FLOW_OK) {
        std::string why = decoder_reason(p->pdata);
        what = "mode '" + p->mode + "' failed to decode a frame (flow " + gst_flow_get_name(ret) +
               ")" + (why.empty() ? "" : ": " + why);
      }
    }
    unmap();
    if (ret != GST_FLOW_OK && ret != GST_FLOW_FLUSHING && ret != GST_FLOW_EOS)
      throw nns::Error(nns::ErrorKind::kStream, what);
    return ret;
  });
}

static gboolean gst_tensor_decoder_start(GstBaseTransform *trans) {
  auto *self = GST_TENSOR_DECODER(trans);
  return nns::gst::guard(self, FALSE, [&] {
    std::lock_guard<std::mutex> l(self->priv->lock);
    self->priv->flexible = false;
    self->priv->flex_known = false;
    self->priv->drop_held();
    // Without a mode the element still starts (GstHarness tests and applications set it after
    // PLAYING, as with NNStreamer); the missing mode is reported when caps or data arrive.
    if (!self->priv->mode.empty()) configure(self->priv, GST_ELEMENT(self));
    return TRUE;
  });
}

// Static config of a flexible buffer, from its headers; throws naming the tensor and field.
static nns::TensorsConfig config_from_headers(GstBuffer *buf, int rate_n, int rate_d) {
  const guint n = gst_buffer_n_memory(buf);
  if (n == 0 || n > NNS_TENSOR_SIZE_LIMIT)
    throw nns::Error(nns::ErrorKind::kStream,
                     "flexible input buffer holds " + std::to_string(n) + " tensors");
  nns::TensorsConfig cfg;
  cfg.rate_n = rate_n;
  cfg.rate_d = rate_d;
  for (guint i = 0; i < n; ++i) {
    GstMemory *mem = gst_buffer_peek_memory(buf, i);
    const std::string who = "input tensor " + std::to_string(i) + ": ";
    nns::MetaHeader h;
    try {
      h = nns::gst::memory_header(mem);
    } catch (const nns::Error &e) {
      throw nns::Error(nns::ErrorKind::kStream, who + e.what());
    }
    if (h.format == nns::TensorFormat::kSparse)
      throw nns::Error(nns::ErrorKind::kStream,
                       who + "header format is sparse; decode it with tensor_sparse_dec first");
    if (nns::rank_of(h.dims) == 0)
      throw nns::Error(nns::ErrorKind::kStream, who + "flexible tensor header has no dimension");
    const gsize payload = gst_memory_get_sizes(mem, nullptr, nullptr) - nns::kMetaHeaderSize;
    if (payload != h.payload_size())
      throw nns::Error(nns::ErrorKind::kStream, who + "carries " + std::to_string(payload) +
                                                    " bytes after its header, the header (" +
                                                    h.info().to_string() + ") says " +
                                                    std::to_string(h.payload_size()));
    cfg.info.tensors.push_back(h.info());
  }
  return cfg;
}

static void forward_held_events(GstBaseTransform *trans) {
  auto *p = GST_TENSOR_DECODER(trans)->priv;
  std::vector<GstEvent *> held;
  {
    std::lock_guard<std::mutex> l(p->lock);
    held.swap(p->held);
  }
  for (GstEvent *e : held)
    GST_BASE_TRANSFORM_CLASS(gst_tensor_decoder_parent_class)->sink_event(trans, e);
}

// A flexible CAPS event is kept (not negotiated): the tensors are only known from the data.
static gboolean gst_tensor_decoder_sink_event(GstBaseTransform *trans, GstEvent *event) {
  auto *self = GST_TENSOR_DECODER(trans);
  auto *p = self->priv;
  const GstEventType type = GST_EVENT_TYPE(event);
  if (type == GST_EVENT_FLUSH_STOP) {
    std::lock_guard<std::mutex> l(p->lock);
    p->drop_held();
  }
  if (type == GST_EVENT_EOS) forward_held_events(trans);
  if (GST_EVENT_IS_STICKY(event) && type != GST_EVENT_CAPS && type != GST_EVENT_STREAM_START &&
      type != GST_EVENT_EOS) {
    std::lock_guard<std::mutex> l(p->lock);
    if (p->flexible && !p->flex_known) {
      p->held.push_back(event);
      return TRUE;
    }
  }
  if (type == GST_EVENT_CAPS) {
    GstCaps *caps = nullptr;
    gst_event_parse_caps(event, &caps);
    std::optional<nns::TensorsConfig> cfg;
    try {
      cfg = nns::gst::config_from_caps(caps);
    } catch (const nns::Error &) {
      // the base class negotiates and reports it
    }
    std::lock_guard<std::mutex> l(p->lock);
    p->flexible = cfg && cfg->info.format == nns::TensorFormat::kFlexible;
    p->flex_known = false;
    if (p->flexible) {
      p->flex_rate_n = cfg->rate_n;
      p->flex_rate_d = cfg->rate_d;
      gst_event_unref(event);
      return TRUE;
    }
  }
  return GST_BASE_TRANSFORM_CLASS(gst_tensor_decoder_parent_class)->sink_event(trans, event);
}

// Flexible input: reads the headers of each buffer and, when the tensors differ from the last
// ones (or for the first buffer), negotiates static caps for them through the base class, which
// asks the decoder for new output caps and sends them downstream.
static GstFlowReturn gst_tensor_decoder_submit_input_buffer(GstBaseTransform *trans,
                                                            gboolean is_discont, GstBuffer *inbuf) {
  auto *self = GST_TENSOR_DECODER(trans);
  auto *p = self->priv;
  GstFlowReturn ret = nns::gst::guard(self, GST_FLOW_ERROR, [&] {
    nns::gst::CapsPtr caps;
    {
      std::lock_guard<std::mutex> l(p->lock);
      if (!p->flexible) return GST_FLOW_OK;
      nns::TensorsConfig cfg = config_from_headers(inbuf, p->flex_rate_n, p->flex_rate_d);
      if (p->flex_known && cfg.info.tensors.size() == p->flex_cfg.info.tensors.size()) {
        bool same = true;
        for (std::size_t i = 0; i < cfg.info.tensors.size() && same; ++i)
          same = cfg.info.tensors[i].same_as(p->flex_cfg.info.tensors[i]);
        if (same) return GST_FLOW_OK;
      }
      p->flex_cfg = cfg;
      p->flex_known = true;
      caps.reset(gst_caps_new_full(nns::gst::structure_from_config(cfg), nullptr));
    }
    GST_DEBUG_OBJECT(self, "flexible input now %" GST_PTR_FORMAT, caps.get());
    if (!GST_BASE_TRANSFORM_CLASS(gst_tensor_decoder_parent_class)
             ->sink_event(trans, gst_event_new_caps(caps.get()))) {
      std::string c = nns::gst::caps_to_string(caps.get());
      throw nns::Error(nns::ErrorKind::kNegotiation,
                       "mode '" + p->mode + "' cannot produce output for flexible input " + c);
    }
    forward_held_events(trans);
    return GST_FLOW_OK;
  });
  if (ret != GST_FLOW_OK) {
    gst_buffer_unref(inbuf);
    return ret;
  }
  return GST_BASE_TRANSFORM_CLASS(gst_tensor_decoder_parent_class)
      ->submit_input_buffer(trans, is_discont, inbuf);
}

static void gst_tensor_decoder_finalize(GObject *object) {
  auto *self = GST_TENSOR_DECODER(object);
  self->priv->release();
  self->priv->drop_held();
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_decoder_parent_class)->finalize(object);
}

static void gst_tensor_decoder_init(GstTensorDecoder *self) {
  self->priv = new DecoderPriv();
  gst_base_transform_set_qos_enabled(GST_BASE_TRANSFORM(self), FALSE);
}

static void gst_tensor_decoder_class_init(GstTensorDecoderClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_decoder_debug, "tensor_decoder", 0, "tensor_decoder element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *trans_class = GST_BASE_TRANSFORM_CLASS(klass);
  gobject_class->set_property = gst_tensor_decoder_set_property;
  gobject_class->get_property = gst_tensor_decoder_get_property;
  gobject_class->finalize = gst_tensor_decoder_finalize;

  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Produce verbose output", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_MODE,
      g_param_spec_string("mode", "Mode",
                          "Decoder mode. Other options (option1 to optionN) depend on the "
                          "specified model. Available modes: see sub-plugins, or custom-code",
                          "", rw));
  static const char *const kNth[kNumOptions] = {"1st", "2nd", "3rd", "4th", "5th",
                                                "6th", "7th", "8th", "9th"};
  for (int i = 0; i < kNumOptions; ++i) {
    std::string name = "option" + std::to_string(i + 1);
    std::string blurb = std::string("option for specific decoder modes, ") + kNth[i] + " one.";
    g_object_class_install_property(
        gobject_class, PROP_OPTION1 + i,
        g_param_spec_string(g_intern_string(name.c_str()), g_intern_string(name.c_str()),
                            g_intern_string(blurb.c_str()), nullptr, rw));
  }
  g_object_class_install_property(
      gobject_class, PROP_SUBPLUGINS,
      g_param_spec_string("sub-plugins", "Sub-plugins", "Registrable sub-plugins list", "",
                          static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  g_object_class_install_property(
      gobject_class, PROP_CONFIG_FILE,
      g_param_spec_string("config-file", "Configuration file",
                          "Path to configuration file which contains plugins properties", "", rw));

  gst_element_class_set_static_metadata(
      element_class, "TensorDecoder", "Converter/Tensor",
      "Converts tensor stream of C-Array for neural network framework filters to audio or "
      "video stream",
      "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);

  trans_class->passthrough_on_same_caps = FALSE;
  trans_class->transform_ip_on_passthrough = FALSE;
  trans_class->start = gst_tensor_decoder_start;
  trans_class->sink_event = gst_tensor_decoder_sink_event;
  trans_class->submit_input_buffer = gst_tensor_decoder_submit_input_buffer;
  trans_class->transform_caps = gst_tensor_decoder_transform_caps;
  trans_class->fixate_caps = gst_tensor_decoder_fixate_caps;
  trans_class->set_caps = gst_tensor_decoder_set_caps;
  trans_class->transform_size = gst_tensor_decoder_transform_size;
  trans_class->prepare_output_buffer = gst_tensor_decoder_prepare_output_buffer;
  trans_class->transform = gst_tensor_decoder_transform;
}

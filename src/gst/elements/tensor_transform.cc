// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_transform
 *
 * Changes the shape, type or values of tensors (NNStreamer-compatible): `mode` picks the
 * operation (dimchg, typecast, arithmetic, transpose, stand, clamp, padding) and `option` its
 * parameters; `apply` limits it to some tensors (the others pass through, sharing memory).
 * Static and flexible streams are supported. The per-tensor plan (type/mode dispatch and
 * constants) is built when caps are set; each buffer only maps, runs and unmaps.
 * Grammars and semantics: docs/elements/tensor_transform.md.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=2 ! video/x-raw,format=RGB,width=224,height=224 !
 *       tensor_converter ! tensor_transform mode=arithmetic
 *       option=typecast:float32,add:-127.5,div:127.5 ! tensor_sink
 */
#include <gst/base/gstbasetransform.h>

#include <algorithm>
#include <atomic>
#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <vector>

#include "core/transform_kernels.h"
#include "gst/memory_recycler.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_transform_debug);
#define GST_CAT_DEFAULT tensor_transform_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_TRANSFORM (gst_tensor_transform_get_type())
G_DECLARE_FINAL_TYPE(GstTensorTransform, gst_tensor_transform, GST, TENSOR_TRANSFORM,
                     GstBaseTransform)
G_END_DECLS

namespace {

namespace tr = nns::transform;
using nns::Error;
using nns::ErrorKind;
using nns::TensorFormat;
using nns::TensorInfo;
using nns::TensorsConfig;

constexpr guint kTransposeRankLimit = 4;

struct Settings {
  int mode = -1;
  std::optional<std::string> option;
  bool acceleration = true;
  std::string apply;
  bool silent = true;
  // An option refused when set (as upstream, `option` keeps its previous value); start() posts
  // why, so the refusal is not silent.
  std::optional<std::string> refused_option;
  std::string refused_reason;
};

// What the settings mean, parsed (throws nns::Error naming the property).
struct Parsed {
  tr::Options opts;
  std::vector<uint32_t> apply;  // empty: every tensor
  bool accelerate = true;

  bool applied(std::size_t i) const {
    return apply.empty() ||
           std::find(apply.begin(), apply.end(), static_cast<uint32_t>(i)) != apply.end();
  }
};

Parsed parse_settings(const Settings &s) {
  Parsed p;
  p.opts = tr::parse_options(static_cast<tr::Mode>(s.mode), s.option ? s.option->c_str() : nullptr);
  p.apply = tr::parse_apply(s.apply);
  p.accelerate = s.acceleration;
  return p;
}

// Negotiated state; only the streaming thread touches it (set_caps and transform).
struct State {
  Parsed parsed;
  TensorsConfig in, out;
  bool in_flexible = false, out_flexible = false;
  std::vector<std::optional<tr::Plan>> plans;  // static: per tensor; flexible: cache per index
  // Output memories reused once downstream let them go (large tensors: no fresh pages per
  // buffer, src/gst/memory_recycler.h).
  std::shared_ptr<nns::gst::MemoryRecycler> recycler = std::make_shared<nns::gst::MemoryRecycler>();
};

struct TransformPriv {
  std::mutex lock;  // guards settings
  Settings settings;
  std::optional<State> state;
  bool caps_error_posted = false;
  // mode/option/apply/acceleration changed since the state was built. GstBaseTransform does not
  // call set_caps again when the renegotiated caps are equal to the old ones (e.g. add:.5 ->
  // mul:20), so transform() rebuilds the state itself then.
  std::atomic<bool> settings_changed{false};
};

enum {
  PROP_0,
  PROP_SILENT,
  PROP_MODE,
  PROP_OPTION,
  PROP_ACCELERATION,
  PROP_APPLY,
  PROP_TRANSPOSE_RANK_LIMIT
};

GType mode_enum_type() {
  static gsize type = 0;
  if (g_once_init_enter(&type)) {
    static const GEnumValue values[] = {
        {0, "Mode for changing tensor dimensions, option=FROM_DIM:TO_DIM", "dimchg"},
        {1, "Mode for casting type of tensor, option=TYPE", "typecast"},
        {2,
         "Mode for arithmetic operations with tensor, option=[typecast:TYPE,]"
         "[per-channel:(false|true@DIM),]add|mul|div:NUMBER[@CH_IDX], ...",
         "arithmetic"},
        {3, "Mode for transposing shape of tensor, option=D1':D2':D3':D4 (fixed to 3)",
         "transpose"},
        {4,
         "Mode for statistical standardization of tensor, "
         "option=(default|dc-average)[:TYPE][,per-channel:(false|true)]",
         "stand"},
        {5, "Mode for clamping all elements of tensor into the range, option=CLAMP_MIN:CLAMP_MAX",
         "clamp"},
        {6,
         "Mode for padding of tensor, "
         "option=left|right|top|bottom|front|back:NUMBER[,layout:(NCHW|NHWC)]",
         "padding"},
        {-1, "Unknown or not-implemented-yet mode", "unknown"},
        {0, nullptr, nullptr},
    };
    g_once_init_leave(&type, g_enum_register_static("gtt_mode_type", values));
  }
  return static_cast<GType>(type);
}

// Re-throws `e` with "tensor i: " in front, keeping its kind.
[[noreturn]] void fail_tensor(std::size_t i, const Error &e) {
  throw Error(e.kind(), "tensor " + std::to_string(i) + ": " + e.what());
}

nns::MetaHeader header_for(const TensorInfo &t) {
  return nns::flexible_header(t.type, t.dims);
}

// Caps of any tensor stream with the given rate: static (other/tensors and the legacy
// single-tensor other/tensor) and/or flexible.
GstCaps *any_tensor_caps(const TensorsConfig &c, bool with_static, bool with_flexible) {
  GstCaps *caps = gst_caps_new_empty();
  if (with_static) {
    caps =
        gst_caps_merge(caps, nns::gst::caps_for_format(TensorFormat::kStatic, c.rate_n, c.rate_d));
    caps = gst_caps_merge(caps, nns::gst::legacy_tensor_caps(c.rate_n, c.rate_d));
  }
  if (with_flexible)
    caps = gst_caps_merge(caps,
                          nns::gst::caps_for_format(TensorFormat::kFlexible, c.rate_n, c.rate_d));
  return caps;
}

// Caps on the other pad for the static reading of one structure (direction: the pad `s` is on).
GstCaps *transform_static_structure(const Parsed *parsed, GstPadDirection direction,
                                    TensorsConfig cfg) {
  const bool sink = direction == GST_PAD_SINK;
  if (!parsed || !cfg.info.valid()) return any_tensor_caps(cfg, true, sink);
  TensorsConfig other = cfg;
  try {
    for (std::size_t i = 0; i < cfg.info.size(); ++i)
      if (parsed->applied(i))
        other.info[i] = sink ? tr::output_info(parsed->opts, cfg.info[i])
                             : tr::input_info(parsed->opts, cfg.info[i]);
  } catch (const Error &) {
    // The input does not fit the option: let negotiation reach set_caps, which posts why.
    return sink ? any_tensor_caps(cfg, true, true) : gst_caps_new_empty();
  }
  GstCaps *out = nns::gst::caps_from_config(other, true);
  if (sink)  // a static input may also leave as flexible tensors
    out = gst_caps_merge(
        out, nns::gst::caps_for_format(TensorFormat::kFlexible, cfg.rate_n, cfg.rate_d));
  return out;
}

// Caps on the other pad for one structure of `caps` (direction: the pad `s` is on). A structure
// may allow both formats (format={static,flexible}, or no format field): each is answered.
GstCaps *transform_structure(const Parsed *parsed, GstPadDirection direction,
                             const GstStructure *s) {
  TensorsConfig cfg;
  try {
    cfg = nns::gst::config_from_structure(s);
  } catch (const Error &) {
    return any_tensor_caps(cfg, true, true);
  }
  const bool sink = direction == GST_PAD_SINK;
  GstCaps *out = gst_caps_new_empty();
  if (nns::gst::structure_allows_format(s, TensorFormat::kStatic)) {
    cfg.info.format = TensorFormat::kStatic;
    out = gst_caps_merge(out, transform_static_structure(parsed, direction, cfg));
  }
  if (nns::gst::structure_allows_format(s, TensorFormat::kFlexible))
    // flexible in -> flexible out; flexible out <- static or flexible in
    out = gst_caps_merge(out, any_tensor_caps(cfg, !sink, true));
  return out;
}

}  // namespace

struct _GstTensorTransform {
  GstBaseTransform parent;
  TransformPriv *priv;
};

G_DEFINE_TYPE(GstTensorTransform, gst_tensor_transform, GST_TYPE_BASE_TRANSFORM)
GST_ELEMENT_REGISTER_DEFINE(tensor_transform, "tensor_transform", GST_RANK_NONE,
                            GST_TYPE_TENSOR_TRANSFORM)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_TENSOR_CAPS_ANY_STR));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_TENSOR_CAPS_ANY_STR));

static Settings copy_settings(GstTensorTransform *self) {
  std::lock_guard<std::mutex> lk(self->priv->lock);
  return self->priv->settings;
}

static void gst_tensor_transform_set_property(GObject *object, guint id, const GValue *value,
                                              GParamSpec *pspec) {
  auto *self = GST_TENSOR_TRANSFORM(object);
  bool changed = false;
  std::string refused;
  {
    std::lock_guard<std::mutex> lk(self->priv->lock);
    Settings &s = self->priv->settings;
    switch (id) {
      case PROP_SILENT:
        s.silent = g_value_get_boolean(value);
        break;
      case PROP_MODE:
        changed = s.mode != g_value_get_enum(value);
        s.mode = g_value_get_enum(value);
        break;
      case PROP_OPTION: {
        const gchar *v = g_value_get_string(value);
        std::optional<std::string> next = v ? std::optional<std::string>(v) : std::nullopt;
        if (next && s.mode >= 0) {
          // Checked against the current mode now, as upstream: a refused option leaves the
          // previous one in place.
          try {
            tr::parse_options(static_cast<tr::Mode>(s.mode), next->c_str());
          } catch (const Error &e) {
            s.refused_option = next;
            s.refused_reason = e.what();
            refused = e.what();
            break;
          }
        }
        s.refused_option.reset();
        s.refused_reason.clear();
        changed = next != s.option;
        s.option = std::move(next);
        break;
      }
      case PROP_ACCELERATION:
        changed = s.acceleration != static_cast<bool>(g_value_get_boolean(value));
        s.acceleration = g_value_get_boolean(value);
        break;
      case PROP_APPLY: {
        const gchar *v = g_value_get_string(value);
        std::string next = v ? v : "";
        changed = next != s.apply;
        s.apply = std::move(next);
        break;
      }
      default:
        G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
    }
  }
  if (!refused.empty()) {
    GST_WARNING_OBJECT(self, "%s", refused.c_str());
    NNS_POST_WARNING(self, refused + " (refused: 'option' keeps its previous value)");
  }
  // A change while streaming takes effect from the next buffer: negotiate again.
  if (changed) {
    self->priv->settings_changed = true;
    gst_base_transform_reconfigure_src(GST_BASE_TRANSFORM(self));
  }
}

static void gst_tensor_transform_get_property(GObject *object, guint id, GValue *value,
                                              GParamSpec *pspec) {
  auto *self = GST_TENSOR_TRANSFORM(object);
  Settings s = copy_settings(self);
  switch (id) {
    case PROP_SILENT:
      g_value_set_boolean(value, s.silent);
      break;
    case PROP_MODE:
      g_value_set_enum(value, s.mode);
      break;
    case PROP_OPTION:
      g_value_set_string(value, s.option ? s.option->c_str() : nullptr);
      break;
    case PROP_ACCELERATION:
      g_value_set_boolean(value, s.acceleration);
      break;
    case PROP_APPLY:
      g_value_set_string(value, s.apply.c_str());
      break;
    case PROP_TRANSPOSE_RANK_LIMIT:
      g_value_set_uint(value, kTransposeRankLimit);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_transform_finalize(GObject *object) {
  delete GST_TENSOR_TRANSFORM(object)->priv;
  G_OBJECT_CLASS(gst_tensor_transform_parent_class)->finalize(object);
}

static gboolean gst_tensor_transform_start(GstBaseTransform *trans) {
  auto *self = GST_TENSOR_TRANSFORM(trans);
  self->priv->state.reset();
  self->priv->caps_error_posted = false;
  // Bad mode/option/apply stop the pipeline here, before any data flows. An unset mode does not:
  // GstHarness tests and applications set it after PLAYING (as with NNStreamer); it is reported,
  // naming the property, when caps arrive (set_caps).
  return nns::gst::guard(trans, FALSE, [&]() -> gboolean {
    Settings s = copy_settings(self);
    if (s.refused_option)
      throw Error(ErrorKind::kSettings,
                  s.refused_reason + " (refused when set; 'option' kept " +
                      (s.option ? "'" + *s.option + "'" : std::string("no value")) + ")");
    if (s.mode >= 0) parse_settings(s);
    return TRUE;
  });
}

static gboolean gst_tensor_transform_stop(GstBaseTransform *trans) {
  GST_TENSOR_TRANSFORM(trans)->priv->state.reset();
  return TRUE;
}

static GstCaps *gst_tensor_transform_transform_caps(GstBaseTransform *trans,
                                                    GstPadDirection direction, GstCaps *caps,
                                                    GstCaps *filter) {
  auto *self = GST_TENSOR_TRANSFORM(trans);
  std::optional<Parsed> parsed;
  try {
    parsed = parse_settings(copy_settings(self));
  } catch (const Error &) {
    // Reported by start()/set_caps(); here any tensor caps keep negotiation going.
  }
  GstCaps *result = gst_caps_new_empty();
  for (guint i = 0; i < gst_caps_get_size(caps); ++i)
    result = gst_caps_merge(result, transform_structure(parsed ? &*parsed : nullptr, direction,
                                                        gst_caps_get_structure(caps, i)));
  if (filter) {
    GstCaps *x = gst_caps_intersect_full(filter, result, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(result);
    result = x;
  }
  GST_DEBUG_OBJECT(trans, "transform_caps %s: %" GST_PTR_FORMAT " -> %" GST_PTR_FORMAT,
                   direction == GST_PAD_SINK ? "sink->src" : "src->sink", caps, result);
  return result;
}

static gboolean gst_tensor_transform_set_caps(GstBaseTransform *trans, GstCaps *incaps,
                                              GstCaps *outcaps) {
  auto *self = GST_TENSOR_TRANSFORM(trans);
  self->priv->settings_changed = false;  // the settings read below are the newest
  gboolean ok = nns::gst::guard(trans, FALSE, [&]() -> gboolean {
    State st;
    st.parsed = parse_settings(copy_settings(self));
    st.in = nns::gst::config_from_caps(incaps);
    st.out = nns::gst::config_from_caps(outcaps);
    st.in_flexible = st.in.info.format != TensorFormat::kStatic;
    st.out_flexible = st.out.info.format != TensorFormat::kStatic;
    const std::string how = st.parsed.opts.describe();
    if (const auto *a = std::get_if<tr::ArithOptions>(&st.parsed.opts.data))
      for (const std::string &w : a->warnings) NNS_POST_WARNING(trans, "property 'option': " + w);
    if (st.in_flexible) {
      if (!st.out_flexible)
        throw Error(ErrorKind::kNegotiation,
                    "flexible input tensors need flexible output caps, got " +
                        nns::gst::caps_to_string(outcaps));
      self->priv->state = std::move(st);
      return TRUE;
    }
    const std::size_t n = st.in.info.size();
    for (uint32_t a : st.parsed.apply)
      if (a >= n)
        throw Error(ErrorKind::kSettings, "property 'apply': tensor index " + std::to_string(a) +
                                              " is out of range, the stream has " +
                                              std::to_string(n) + " tensor(s) (" +
                                              st.in.info.to_string() + ")");
    TensorsConfig expected = st.in;
    st.plans.resize(n);
    for (std::size_t i = 0; i < n; ++i) {
      if (!st.parsed.applied(i)) continue;
      try {
        st.plans[i] = tr::make_plan(st.parsed.opts, st.in.info[i], st.parsed.accelerate);
      } catch (const Error &e) {
        fail_tensor(i, e);
      }
      expected.info[i] = st.plans[i]->out;
    }
    if (!st.out_flexible && !st.out.info.same_as(expected.info))
      throw Error(ErrorKind::kNegotiation, "output caps do not match " + how +
                                               " applied to the input " + st.in.info.to_string() +
                                               ": expected " + expected.info.to_string() +
                                               ", got " + st.out.info.to_string());
    // Flexible output caps carry no tensor description, but a peer (a capsfilter) may have added
    // static fields to them: they must not contradict what is pushed.
    if (st.out_flexible)
      nns::gst::check_flexible_caps_fields(outcaps, expected.info, how + " makes");
    st.out.info.tensors = expected.info.tensors;
    if (st.out_flexible) st.out.info.format = TensorFormat::kFlexible;
    GST_DEBUG_OBJECT(trans, "%s: %s -> %s", how.c_str(), st.in.info.to_string().c_str(),
                     expected.info.to_string().c_str());
    self->priv->state = std::move(st);
    return TRUE;
  });
  if (!ok) self->priv->caps_error_posted = true;
  return ok;
}

// A rejected CAPS event without an error of ours means downstream refused what the mode
// produces: say so on the bus (otherwise only a bare not-negotiated error would appear).
static gboolean gst_tensor_transform_sink_event(GstBaseTransform *trans, GstEvent *event) {
  auto *self = GST_TENSOR_TRANSFORM(trans);
  nns::gst::CapsPtr caps;
  if (GST_EVENT_TYPE(event) == GST_EVENT_CAPS) {
    GstCaps *c = nullptr;
    gst_event_parse_caps(event, &c);
    caps.reset(gst_caps_ref(c));
    self->priv->caps_error_posted = false;
  }
  gboolean ret =
      GST_BASE_TRANSFORM_CLASS(gst_tensor_transform_parent_class)->sink_event(trans, event);
  if (!ret && caps && !self->priv->caps_error_posted) {
    nns::gst::CapsPtr produced(
        gst_tensor_transform_transform_caps(trans, GST_PAD_SINK, caps.get(), nullptr));
    nns::gst::CapsPtr peer(gst_pad_peer_query_caps(GST_BASE_TRANSFORM_SRC_PAD(trans), nullptr));
    std::string how;
    try {
      how = parse_settings(copy_settings(self)).opts.describe();
    } catch (const Error &e) {
      how = e.what();
    }
    NNS_POST_ERROR(trans, ErrorKind::kNegotiation,
                   "cannot negotiate: " + how + " turns the input " +
                       nns::gst::caps_to_string(caps.get()) + " into " +
                       nns::gst::caps_to_string(produced.get()) + ", but downstream accepts only " +
                       nns::gst::caps_to_string(peer.get()));
    self->priv->caps_error_posted = true;
  }
  return ret;
}

static gboolean gst_tensor_transform_transform_size(GstBaseTransform *, GstPadDirection, GstCaps *,
                                                    gsize, GstCaps *, gsize *othersize) {
  *othersize = 0;  // memories are appended per tensor in transform()
  return TRUE;
}

static GstFlowReturn gst_tensor_transform_prepare_output_buffer(GstBaseTransform *trans,
                                                                GstBuffer *inbuf,
                                                                GstBuffer **outbuf) {
  *outbuf = gst_buffer_new();
  // GstBaseTransform's copy_metadata: flags, timestamps and the metas its transform_meta keeps
  // (those without tags, e.g. tensor_query's GstMetaQuery client id; not GstVideoMeta).
  if (!GST_BASE_TRANSFORM_GET_CLASS(trans)->copy_metadata(trans, inbuf, *outbuf)) {
    gst_buffer_unref(*outbuf);
    *outbuf = nullptr;
    return GST_FLOW_ERROR;
  }
  return GST_FLOW_OK;
}

// Output memory for one transformed tensor (header first when the output is flexible).
static GstMemory *run_plan(State &st, const tr::Plan &plan, const guint8 *src, bool flexible) {
  const gsize head = flexible ? nns::kMetaHeaderSize : 0;
  GstMemory *out = st.recycler->alloc(head + plan.out.byte_size());
  if (!out) throw Error(ErrorKind::kStream, "cannot allocate an output memory");
  nns::gst::MemoryMap map(out, GST_MAP_WRITE);
  if (!map.ok()) {
    gst_memory_unref(out);
    throw Error(ErrorKind::kStream, "cannot map an output memory for writing");
  }
  if (flexible) nns::write_meta_header(header_for(plan.out), map.data());
  plan.run(src, map.data() + head);
  return out;
}

static void transform_static(State &st, GstBuffer *inbuf, GstBuffer *outbuf) {
  const std::size_t n = st.in.info.size();
  const std::size_t got = nns::gst::buffer_tensor_count(inbuf);
  if (got != n)
    throw Error(ErrorKind::kStream, "the buffer has " + std::to_string(got) +
                                        " tensor memories, the caps say " + std::to_string(n) +
                                        " (" + st.in.info.to_string() + ")");
  for (std::size_t i = 0; i < n; ++i) {
    nns::gst::MemoryPtr mem(nns::gst::buffer_get_tensor(inbuf, i));
    const TensorInfo &in = st.in.info[i];
    gsize size = gst_memory_get_sizes(mem.get(), nullptr, nullptr);
    if (size != in.byte_size())
      throw Error(ErrorKind::kStream, "tensor " + std::to_string(i) + ": the buffer has " +
                                          std::to_string(size) + " bytes, the caps say " +
                                          std::to_string(in.byte_size()) + " (" + in.to_string() +
                                          ")");
    const auto &plan = st.plans[i];
    GstMemory *out;
    if (!plan || plan->identity) {  // unchanged bytes: share the memory
      out = st.out_flexible ? nns::gst::memory_with_header(header_for(st.out.info[i]), mem.get())
                            : mem.release();
    } else {
      nns::gst::MemoryMap map(mem.get(), GST_MAP_READ);
      if (!map.ok())
        throw Error(ErrorKind::kStream,
                    "tensor " + std::to_string(i) + ": cannot map the input memory");
      out = run_plan(st, *plan, map.data(), st.out_flexible);
    }
    nns::gst::buffer_append_tensor(outbuf, out, st.out.info[i]);
  }
}

static void transform_flexible(State &st, GstBuffer *inbuf, GstBuffer *outbuf) {
  const std::size_t n = nns::gst::buffer_tensor_count(inbuf);
  for (uint32_t a : st.parsed.apply)
    if (a >= n)
      throw Error(ErrorKind::kSettings, "property 'apply': tensor index " + std::to_string(a) +
                                            " is out of range, the buffer has " +
                                            std::to_string(n) + " tensor(s)");
  if (st.plans.size() < n) st.plans.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    nns::gst::MemoryPtr mem(nns::gst::buffer_get_tensor(inbuf, i));
    if (!st.parsed.applied(i)) {
      TensorInfo info;
      try {
        info = nns::gst::memory_header(mem.get()).info();
      } catch (const Error &e) {
        fail_tensor(i, e);
      }
      nns::gst::buffer_append_tensor(outbuf, mem.release(), info);
      continue;
    }
    nns::gst::MemoryMap map(mem.get(), GST_MAP_READ);
    if (!map.ok())
      throw Error(ErrorKind::kStream,
                  "tensor " + std::to_string(i) + ": cannot map the input memory");
    nns::MetaHeader h;
    try {
      h = nns::parse_meta_header(map.data(), map.size());
      if (h.format == TensorFormat::kSparse)
        throw Error(ErrorKind::kStream,
                    "is sparse; tensor_transform handles static and flexible "
                    "tensors only (decode it with tensor_sparse_dec first)");
      TensorInfo in = h.info();
      if (map.size() - nns::kMetaHeaderSize < in.byte_size())
        throw Error(ErrorKind::kStream,
                    "the memory has " + std::to_string(map.size() - nns::kMetaHeaderSize) +
                        " payload bytes, its header says " + std::to_string(in.byte_size()) + " (" +
                        in.to_string() + ")");
      auto &plan = st.plans[i];
      if (!plan || !plan->in.same_as(in) || plan->in.type != in.type)
        plan = tr::make_plan(st.parsed.opts, in,
                             st.parsed.accelerate);  // only when the header changes
    } catch (const Error &e) {
      fail_tensor(i, e);
    }
    const tr::Plan &plan = *st.plans[i];
    if (plan.identity && nns::dims_equal(plan.out.dims, plan.in.dims)) {
      nns::gst::buffer_append_tensor(outbuf, gst_memory_ref(mem.get()), plan.out);
      continue;
    }
    nns::gst::buffer_append_tensor(
        outbuf, run_plan(st, plan, map.data() + nns::kMetaHeaderSize, true), plan.out);
  }
}

static GstFlowReturn gst_tensor_transform_transform(GstBaseTransform *trans, GstBuffer *inbuf,
                                                    GstBuffer *outbuf) {
  auto *self = GST_TENSOR_TRANSFORM(trans);
  if (self->priv->state && self->priv->settings_changed) {
    nns::gst::CapsPtr in(gst_pad_get_current_caps(GST_BASE_TRANSFORM_SINK_PAD(trans)));
    nns::gst::CapsPtr out(gst_pad_get_current_caps(GST_BASE_TRANSFORM_SRC_PAD(trans)));
    if (in && out && !gst_tensor_transform_set_caps(trans, in.get(), out.get()))
      return GST_FLOW_NOT_NEGOTIATED;
  }
  return nns::gst::guard(trans, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    if (!self->priv->state) throw Error(ErrorKind::kNegotiation, "no caps were negotiated");
    State &st = *self->priv->state;
    if (st.in_flexible)
      transform_flexible(st, inbuf, outbuf);
    else
      transform_static(st, inbuf, outbuf);
    return GST_FLOW_OK;
  });
}

static void gst_tensor_transform_class_init(GstTensorTransformClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_transform_debug, "tensor_transform", 0,
                          "tensor_transform element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *trans_class = GST_BASE_TRANSFORM_CLASS(klass);
  gobject_class->set_property = gst_tensor_transform_set_property;
  gobject_class->get_property = gst_tensor_transform_get_property;
  gobject_class->finalize = gst_tensor_transform_finalize;

  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  const auto rw_playing = static_cast<GParamFlags>(rw | GST_PARAM_MUTABLE_PLAYING);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Produce verbose output ?", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_MODE,
      g_param_spec_enum("mode", "Mode", "Mode used for transforming tensor", mode_enum_type(), -1,
                        rw_playing));
  g_object_class_install_property(
      gobject_class, PROP_OPTION,
      g_param_spec_string("option", "Option", "Option for the tensor transform mode ?", nullptr,
                          rw_playing));
  g_object_class_install_property(
      gobject_class, PROP_ACCELERATION,
      g_param_spec_boolean("acceleration", "Acceleration",
                           "Orc acceleration (here: SIMD kernels; false runs the scalar "
                           "reference)",
                           TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_APPLY,
      g_param_spec_string("apply", "Apply",
                          "Select tensors to apply, separated with ',' in case of multiple "
                          "tensors. Default to apply all tensors.",
                          "", rw_playing));
  g_object_class_install_property(
      gobject_class, PROP_TRANSPOSE_RANK_LIMIT,
      g_param_spec_uint("transpose-rank-limit", "Transpose rank limit",
                        "The rank limit of transpose, which varies per version of nnstreamer "
                        "and may be lower than the global rank limit if it is over 4.",
                        0, nns::kRankLimit, kTransposeRankLimit,
                        static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));

  gst_element_class_set_static_metadata(
      element_class, "TensorTransform", "Filter/Tensor",
      "Transforms other/tensor dimensions for different models or frameworks", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);

  trans_class->passthrough_on_same_caps = FALSE;
  trans_class->start = gst_tensor_transform_start;
  trans_class->stop = gst_tensor_transform_stop;
  trans_class->transform_caps = gst_tensor_transform_transform_caps;
  trans_class->set_caps = gst_tensor_transform_set_caps;
  trans_class->sink_event = gst_tensor_transform_sink_event;
  trans_class->transform_size = gst_tensor_transform_transform_size;
  trans_class->prepare_output_buffer = gst_tensor_transform_prepare_output_buffer;
  trans_class->transform = gst_tensor_transform_transform;
}

static void gst_tensor_transform_init(GstTensorTransform *self) {
  self->priv = new TransformPriv();
  gst_base_transform_set_qos_enabled(GST_BASE_TRANSFORM(self), FALSE);
}

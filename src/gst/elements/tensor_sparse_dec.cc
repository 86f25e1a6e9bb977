// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_sparse_dec
 *
 * Decodes NNStreamer sparse tensors back into static tensors. The output caps come from the
 * first frame's headers (or from downstream when it fixes them); a later frame whose tensors
 * differ renegotiates, or posts an error naming the tensor when downstream fixed the caps.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=3 ! tensor_converter ! tensor_sparse_enc !
 *       tensor_sparse_dec ! tensor_sink
 */
#include <atomic>
#include <optional>

#include "core/sparse.h"
#include "gst/element_glue.h"
#include "gst/flow_util.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_sparse_dec_debug);
#define GST_CAT_DEFAULT tensor_sparse_dec_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_SPARSE_DEC (gst_tensor_sparse_dec_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSparseDec, gst_tensor_sparse_dec, GST, TENSOR_SPARSE_DEC, GstElement)
G_END_DECLS

namespace {

struct DecPriv {
  std::atomic<bool> silent{true};
  // Streaming-thread state.
  int rate_n = 0, rate_d = 1;
  bool have_caps = false;
  std::optional<nns::TensorsInfo> sent;  // tensors of the negotiated src caps
  bool downstream_fixed = false;         // downstream dictated the tensors
};

enum { PROP_0, PROP_SILENT };

}  // namespace

struct _GstTensorSparseDec {
  GstElement parent;
  GstPad *sinkpad;
  GstPad *srcpad;
  DecPriv *priv;
};

G_DEFINE_TYPE(GstTensorSparseDec, gst_tensor_sparse_dec, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_sparse_dec, "tensor_sparse_dec", GST_RANK_NONE,
                            GST_TYPE_TENSOR_SPARSE_DEC)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensors, format = (string) sparse, framerate = (fraction) [ 0, max ]"));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensors, format = (string) static, num_tensors = (int) [ 1, 256 ], "
                    "framerate = (fraction) [ 0, max ]"));

// A static config downstream insists on, if any.
static std::optional<nns::TensorsInfo> downstream_fixed(GstPad *src) {
  nns::gst::CapsPtr peer(gst_pad_peer_query_caps(src, nullptr));
  if (!peer || gst_caps_is_any(peer.get()) || gst_caps_is_empty(peer.get()) ||
      !nns::gst::is_tensor_caps(peer.get()))
    return std::nullopt;
  try {
    auto cfg = nns::gst::config_from_caps(peer.get());
    if (cfg.info.format == nns::TensorFormat::kStatic && cfg.info.valid()) return cfg.info;
  } catch (const nns::Error &) {
  }
  return std::nullopt;
}

static gboolean sparse_dec_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_SPARSE_DEC(parent);
  if (GST_EVENT_TYPE(event) != GST_EVENT_CAPS) return gst_pad_event_default(pad, parent, event);
  nns::gst::EventPtr owned(event);
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    GstCaps *caps;
    gst_event_parse_caps(event, &caps);
    auto cfg = nns::gst::config_from_caps(caps);
    auto *p = self->priv;
    p->rate_n = cfg.rate_n >= 0 ? cfg.rate_n : 0;
    p->rate_d = cfg.rate_d > 0 ? cfg.rate_d : 1;
    p->have_caps = true;
    p->sent.reset();
    // Downstream may fix the output right away (upstream's behaviour); otherwise the first
    // frame decides.
    if (auto fixed = downstream_fixed(self->srcpad)) {
      nns::TensorsConfig out{*fixed, p->rate_n, p->rate_d};
      nns::gst::set_src_caps(self->srcpad, out, "src");
      p->sent = *fixed;
      p->downstream_fixed = true;
    } else {
      p->downstream_fixed = false;
    }
    return TRUE;
  });
}

static GstFlowReturn sparse_dec_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_SPARSE_DEC(parent);
  nns::gst::BufferPtr in(buf);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = self->priv;
    if (!p->have_caps) nns::fail(nns::ErrorKind::kNegotiation, "buffer before caps");
    guint n = gst_buffer_n_memory(buf);
    if (n == 0) nns::fail(nns::ErrorKind::kStream, "sparse frame has no tensor memory");
    nns::TensorsInfo info;
    nns::gst::BufferPtr out(gst_buffer_new());
    for (guint i = 0; i < n; ++i) {
      nns::gst::MemoryMap m(gst_buffer_peek_memory(buf, i), GST_MAP_READ);
      if (!m.ok())
        nns::fail(nns::ErrorKind::kStream, "cannot map sparse tensor " + std::to_string(i));
      nns::MetaHeader h;
      try {
        h = nns::sparse_parse(m.data(), m.size());
      } catch (const nns::Error &e) {
        nns::fail(nns::ErrorKind::kStream, "tensor " + std::to_string(i) + ": " + e.what());
      }
      nns::TensorInfo t = h.info();
      GstMemory *dense = nns::gst::alloc_memory(t.byte_size());
      {
        nns::gst::MemoryMap w(dense, GST_MAP_WRITE);
        nns::sparse_decode(h, m.data(), w.data());
      }
      gst_buffer_append_memory(out.get(), dense);
      info.tensors.push_back(t);
    }
    if (!p->sent || !p->sent->same_as(info)) {
      if (p->sent && p->downstream_fixed) {
        std::string what = "decoded tensors " + info.to_string() +
                           " differ from the tensors downstream fixed, " + p->sent->to_string();
        nns::fail(nns::ErrorKind::kStream, what);
      }
      nns::gst::set_src_caps(self->srcpad, nns::TensorsConfig{info, p->rate_n, p->rate_d}, "src");
      p->sent = info;
    }
    gst_buffer_copy_into(out.get(), buf, GST_BUFFER_COPY_METADATA, 0, -1);
    return gst_pad_push(self->srcpad, out.release());
  });
}

static void gst_tensor_sparse_dec_set_property(GObject *object, guint id, const GValue *value,
                                               GParamSpec *pspec) {
  auto *self = GST_TENSOR_SPARSE_DEC(object);
  if (id == PROP_SILENT)
    self->priv->silent = g_value_get_boolean(value);
  else
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static void gst_tensor_sparse_dec_get_property(GObject *object, guint id, GValue *value,
                                               GParamSpec *pspec) {
  auto *self = GST_TENSOR_SPARSE_DEC(object);
  if (id == PROP_SILENT)
    g_value_set_boolean(value, self->priv->silent);
  else
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static GstStateChangeReturn sparse_dec_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_SPARSE_DEC(element);
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_sparse_dec_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) {
    self->priv->have_caps = false;
    self->priv->sent.reset();
  }
  return ret;
}

static void gst_tensor_sparse_dec_finalize(GObject *object) {
  delete GST_TENSOR_SPARSE_DEC(object)->priv;
  G_OBJECT_CLASS(gst_tensor_sparse_dec_parent_class)->finalize(object);
}

static void gst_tensor_sparse_dec_class_init(GstTensorSparseDecClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_sparse_dec_debug, "tensor_sparse_dec", 0, "tensor_sparse_dec");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_sparse_dec_set_property;
  gobject_class->get_property = gst_tensor_sparse_dec_get_property;
  gobject_class->finalize = gst_tensor_sparse_dec_finalize;
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log per-buffer details", TRUE,
                           static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS)));
  gst_element_class_set_static_metadata(element_class, "TensorSparseDec", "Filter/Tensor",
                                        "Decodes sparse tensors into static tensors",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->change_state = sparse_dec_change_state;
}

static void gst_tensor_sparse_dec_init(GstTensorSparseDec *self) {
  self->priv = new DecPriv();
  self->sinkpad = gst_pad_new_from_static_template(&sink_template, "sink");
  gst_pad_set_event_function(self->sinkpad, sparse_dec_sink_event);
  gst_pad_set_chain_function(self->sinkpad, sparse_dec_chain);
  gst_element_add_pad(GST_ELEMENT(self), self->sinkpad);
  self->srcpad = gst_pad_new_from_static_template(&src_template, "src");
  gst_pad_use_fixed_caps(self->srcpad);
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
}

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
#include "gst/sparse_glue.h"
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

static void on_caps(GstTensorSparseDec *self, GstCaps *caps) {
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
}

static void decode(GstTensorSparseDec *self, GstBuffer *buf, GstBuffer *out) {
  auto *p = self->priv;
  if (!p->have_caps) nns::fail(nns::ErrorKind::kNegotiation, "buffer before caps");
  guint n = gst_buffer_n_memory(buf);
  if (n == 0) nns::fail(nns::ErrorKind::kStream, "sparse frame has no tensor memory");
  nns::TensorsInfo info;
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
    nns::gst::sparse::append_written(out, t.byte_size(),
                                     [&](uint8_t *dst) { nns::sparse_decode(h, m.data(), dst); });
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
}

static gboolean sparse_dec_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_SPARSE_DEC(parent);
  return nns::gst::sparse::sink_event(GST_ELEMENT(self), pad, event,
                                      [self](GstCaps *caps) { on_caps(self, caps); });
}

static GstFlowReturn sparse_dec_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_SPARSE_DEC(parent);
  return nns::gst::sparse::chain(GST_ELEMENT(self), self->srcpad, buf,
                                 [self](GstBuffer *in, GstBuffer *out) { decode(self, in, out); });
}

static void gst_tensor_sparse_dec_set_property(GObject *object, guint id, const GValue *value,
                                               GParamSpec *pspec) {
  nns::gst::sparse::set_silent(object, id, value, pspec,
                               GST_TENSOR_SPARSE_DEC(object)->priv->silent);
}

static void gst_tensor_sparse_dec_get_property(GObject *object, guint id, GValue *value,
                                               GParamSpec *pspec) {
  nns::gst::sparse::get_silent(object, id, value, pspec,
                               GST_TENSOR_SPARSE_DEC(object)->priv->silent);
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
  nns::gst::sparse::class_init(gobject_class, element_class, "TensorSparseDec",
                               "Decodes sparse tensors into static tensors", &sink_template,
                               &src_template);
  element_class->change_state = sparse_dec_change_state;
}

static void gst_tensor_sparse_dec_init(GstTensorSparseDec *self) {
  self->priv = new DecPriv();
  nns::gst::sparse::add_pads(GST_ELEMENT(self), &sink_template, &src_template,
                             sparse_dec_sink_event, sparse_dec_chain, false, &self->sinkpad,
                             &self->srcpad);
}

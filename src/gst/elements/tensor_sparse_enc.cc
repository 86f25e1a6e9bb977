// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_sparse_enc
 *
 * Encodes static tensors into NNStreamer's sparse format: each memory becomes the 128-byte
 * header (format=sparse, nnz) + nnz values + nnz uint32 flat indices (src/core/sparse.h).
 * Timestamps are kept. At most 16 tensors per frame.
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

GST_DEBUG_CATEGORY_STATIC(tensor_sparse_enc_debug);
#define GST_CAT_DEFAULT tensor_sparse_enc_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_SPARSE_ENC (gst_tensor_sparse_enc_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSparseEnc, gst_tensor_sparse_enc, GST, TENSOR_SPARSE_ENC, GstElement)
G_END_DECLS

namespace {

struct EncPriv {
  std::atomic<bool> silent{true};
  std::optional<nns::TensorsConfig> in;  // streaming thread only
};

}  // namespace

struct _GstTensorSparseEnc {
  GstElement parent;
  GstPad *sinkpad;
  GstPad *srcpad;
  EncPriv *priv;
};

G_DEFINE_TYPE(GstTensorSparseEnc, gst_tensor_sparse_enc, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(tensor_sparse_enc, "tensor_sparse_enc", GST_RANK_NONE,
                            GST_TYPE_TENSOR_SPARSE_ENC)

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensors, format = (string) static, num_tensors = (int) [ 1, 256 ], "
                    "framerate = (fraction) [ 0, max ]"));
static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensors, format = (string) sparse, framerate = (fraction) [ 0, max ]"));

static void on_caps(GstTensorSparseEnc *self, GstCaps *caps) {
  auto cfg = nns::gst::config_from_caps(caps);
  if (!cfg.info.valid())
    nns::fail(nns::ErrorKind::kNegotiation,
              "sink caps need the dimensions and types of every tensor, got " +
                  nns::gst::caps_to_string(caps));
  if (cfg.info.size() > nns::kMemoryMax)
    nns::fail(
        nns::ErrorKind::kNegotiation,
        "sparse frames carry at most 16 tensors, the input has " + std::to_string(cfg.info.size()));
  nns::TensorsConfig out;
  out.info.format = nns::TensorFormat::kSparse;
  out.rate_n = cfg.rate_n;
  out.rate_d = cfg.rate_d;
  nns::gst::set_src_caps(self->srcpad, out, "src");
  self->priv->in = cfg;
}

static void encode(GstTensorSparseEnc *self, GstBuffer *buf, GstBuffer *out) {
  auto &cfg = self->priv->in;
  if (!cfg) nns::fail(nns::ErrorKind::kNegotiation, "buffer before caps");
  nns::gst::check_static_buffer(buf, cfg->info);
  nns::gst::TensorMaps maps(buf, cfg->info.size());
  for (std::size_t i = 0; i < maps.size(); ++i) {
    const auto &t = cfg->info[i];
    std::size_t nnz = nns::sparse_count_nonzero(t, maps.data(i));
    nns::gst::sparse::append_written(out, nns::sparse_encoded_size(t.type, nnz), [&](uint8_t *dst) {
      nns::sparse_encode(t, maps.data(i), dst);
    });
  }
  if (!self->priv->silent)
    GST_INFO_OBJECT(self, "encoded %zu tensor(s), %zu -> %zu bytes", maps.size(),
                    gst_buffer_get_size(buf), gst_buffer_get_size(out));
}

static gboolean sparse_enc_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_TENSOR_SPARSE_ENC(parent);
  return nns::gst::sparse::sink_event(GST_ELEMENT(self), pad, event,
                                      [self](GstCaps *caps) { on_caps(self, caps); });
}

static GstFlowReturn sparse_enc_chain(GstPad *, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_TENSOR_SPARSE_ENC(parent);
  return nns::gst::sparse::chain(GST_ELEMENT(self), self->srcpad, buf,
                                 [self](GstBuffer *in, GstBuffer *out) { encode(self, in, out); });
}

static void gst_tensor_sparse_enc_set_property(GObject *object, guint id, const GValue *value,
                                               GParamSpec *pspec) {
  nns::gst::sparse::set_silent(object, id, value, pspec,
                               GST_TENSOR_SPARSE_ENC(object)->priv->silent);
}

static void gst_tensor_sparse_enc_get_property(GObject *object, guint id, GValue *value,
                                               GParamSpec *pspec) {
  nns::gst::sparse::get_silent(object, id, value, pspec,
                               GST_TENSOR_SPARSE_ENC(object)->priv->silent);
}

static GstStateChangeReturn sparse_enc_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_SPARSE_ENC(element);
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_sparse_enc_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PAUSED_TO_READY) self->priv->in.reset();
  return ret;
}

static void gst_tensor_sparse_enc_finalize(GObject *object) {
  delete GST_TENSOR_SPARSE_ENC(object)->priv;
  G_OBJECT_CLASS(gst_tensor_sparse_enc_parent_class)->finalize(object);
}

static void gst_tensor_sparse_enc_class_init(GstTensorSparseEncClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_sparse_enc_debug, "tensor_sparse_enc", 0, "tensor_sparse_enc");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_sparse_enc_set_property;
  gobject_class->get_property = gst_tensor_sparse_enc_get_property;
  gobject_class->finalize = gst_tensor_sparse_enc_finalize;
  nns::gst::sparse::class_init(gobject_class, element_class, "TensorSparseEnc",
                               "Encodes static tensors into sparse tensors", &sink_template,
                               &src_template);
  element_class->change_state = sparse_enc_change_state;
}

static void gst_tensor_sparse_enc_init(GstTensorSparseEnc *self) {
  self->priv = new EncPriv();
  nns::gst::sparse::add_pads(GST_ELEMENT(self), &sink_template, &src_template,
                             sparse_enc_sink_event, sparse_enc_chain, true, &self->sinkpad,
                             &self->srcpad);
}

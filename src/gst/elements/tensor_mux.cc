// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_mux
 *
 * Combines N tensor streams into one other/tensors stream: each output frame carries the
 * tensors of every sink pad, in pad order (num_tensors is the sum). The tensors are not
 * copied: the output buffer holds the input buffers' memories. Which input buffers are put
 * together is decided by `sync-mode` (nosync, slowest (default), basepad, refresh) and
 * `sync-option`, as in NNStreamer; the output PTS is the time the policy picked (the latest
 * input PTS, or the base pad's). If any input is flexible, or the first caps downstream accepts
 * are flexible, the output is flexible; flexible caps downstream decorated with num_tensors /
 * types / dimensions are checked against what goes out (docs/elements/tensor_mux.md).
 *
 *   gst-launch-1.0 videotestsrc num-buffers=10 ! tensor_converter ! mux.sink_0 \
 *     videotestsrc num-buffers=10 ! tensor_converter ! mux.sink_1 \
 *     tensor_mux name=mux sync-mode=nosync ! tensor_sink
 */
#include <mutex>

#include "core/error.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_sync.h"

GST_DEBUG_CATEGORY_STATIC(tensor_mux_debug);
#define GST_CAT_DEFAULT tensor_mux_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_MUX (gst_tensor_mux_get_type())
G_DECLARE_FINAL_TYPE(GstTensorMux, gst_tensor_mux, GST, TENSOR_MUX, GstTensorSync)
G_END_DECLS

namespace {

// Negotiated per-input layout, set by configure() on the streaming thread.
struct MuxPriv {
  std::vector<nns::TensorsConfig> in;
  bool flexible_out = false;
  // Decorated flexible caps downstream asked for while some input is flexible: what the tensors
  // are is known only from each frame's headers, which are checked against it.
  nns::gst::CapsPtr decoration;
  std::string pads;  // "sink_0 + sink_1", for messages
};

enum { PROP_0, PROP_SILENT, PROP_SYNC_MODE, PROP_SYNC_OPTION };

}  // namespace

struct _GstTensorMux {
  GstTensorSync parent;
  MuxPriv *priv;
};

G_DEFINE_TYPE(GstTensorMux, gst_tensor_mux, GST_TYPE_TENSOR_SYNC)
GST_ELEMENT_REGISTER_DEFINE(tensor_mux, "tensor_mux", GST_RANK_NONE, GST_TYPE_TENSOR_MUX)

#define MUX_SINK_CAPS                                 \
  "other/tensor, framerate = (fraction) [ 0, max ]; " \
  "other/tensors, format = (string) { static, flexible }, framerate = (fraction) [ 0, max ]"
#define MUX_SRC_CAPS \
  "other/tensors, format = (string) { static, flexible }, framerate = (fraction) [ 0, max ]"

static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink_%u", GST_PAD_SINK, GST_PAD_REQUEST, GST_STATIC_CAPS(MUX_SINK_CAPS));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(MUX_SRC_CAPS));

namespace {

nns::TensorsConfig mux_configure(GstTensorSync *base, const std::vector<nns::TensorsConfig> &in,
                                 const std::vector<std::string> &names) {
  auto *self = GST_TENSOR_MUX(base);
  nns::TensorsConfig out;
  bool flexible = false;
  std::size_t total = 0;
  std::string per_pad;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i].info.format == nns::TensorFormat::kFlexible) flexible = true;
    total += in[i].info.size();
    per_pad += (i ? ", " : "") + (i < names.size() ? names[i] : "sink pad " + std::to_string(i)) +
               ": " + std::to_string(in[i].info.size());
  }
  if (total > nns::kTensorLimit)
    nns::fail(nns::ErrorKind::kNegotiation,
              "the sink pads carry " + std::to_string(total) + " tensors in all (" + per_pad +
                  "), more than the limit of " + std::to_string(nns::kTensorLimit));
  nns::TensorsInfo all;  // the static inputs' tensors, in pad order
  for (const auto &c : in)
    all.tensors.insert(all.tensors.end(), c.info.tensors.begin(), c.info.tensors.end());
  std::string pads;
  for (std::size_t i = 0; i < in.size(); ++i)
    pads += (i ? " + " : "") + (i < names.size() ? names[i] : "sink pad " + std::to_string(i));
  // As NNStreamer: the output is flexible when an input is, or when the first caps downstream
  // accepts are flexible (static inputs then get headers). Flexible caps downstream decorated
  // with num_tensors / types / dimensions must describe what goes out: checked here for static
  // inputs, per frame (from the headers) otherwise.
  nns::gst::CapsPtr decoration;
  GstPad *src = gst_element_get_static_pad(GST_ELEMENT(self), "src");
  nns::gst::CapsPtr peer(gst_pad_peer_query_caps(src, nullptr));
  gst_object_unref(src);
  bool peer_flexible = false;
  if (peer && !gst_caps_is_empty(peer.get()) && !gst_caps_is_any(peer.get())) {
    nns::gst::CapsPtr first(gst_caps_copy_nth(peer.get(), 0));
    const char *f = gst_structure_get_string(gst_caps_get_structure(first.get(), 0), "format");
    peer_flexible =
        gst_structure_has_name(gst_caps_get_structure(first.get(), 0), "other/tensors") && f &&
        std::string(f) == "flexible";
    if (peer_flexible && nns::gst::is_decorated_flexible(first.get()))
      decoration = std::move(first);
  }
  if (flexible || peer_flexible) {
    out.info.format = nns::TensorFormat::kFlexible;
    if (decoration && !flexible) {
      nns::gst::check_flexible_caps_fields(decoration.get(), all, pads + " give");
      decoration.reset();
    }
  } else {
    out.info = all;
  }
  nns::gst::sync_slowest_rate(in, &out.rate_n, &out.rate_d);
  MuxPriv *p = self->priv;
  p->in = in;
  p->flexible_out = flexible || peer_flexible;
  p->decoration = std::move(decoration);
  p->pads = pads;
  return out;
}

// Decorated flexible caps downstream against this frame's headers (flexible inputs).
void check_frame(MuxPriv *p, GstBuffer *out) {
  nns::TensorsInfo got;
  got.format = nns::TensorFormat::kFlexible;
  std::size_t n = nns::gst::buffer_tensor_count(out);
  for (std::size_t t = 0; t < n; ++t) {
    nns::gst::MemoryPtr m(nns::gst::buffer_get_tensor(out, t));
    got.tensors.push_back(nns::gst::memory_header(m.get()).info());
  }
  try {
    nns::gst::check_flexible_caps_fields(p->decoration.get(), got,
                                         "the frame from " + p->pads + " carries");
  } catch (const nns::Error &e) {
    nns::fail(nns::ErrorKind::kStream, e.what());
  }
}

GstBuffer *mux_combine(GstTensorSync *base, GstBuffer *const *in, std::size_t n) {
  auto *self = GST_TENSOR_MUX(base);
  MuxPriv *p = self->priv;
  nns::gst::BufferPtr out(gst_buffer_new());
  for (std::size_t i = 0; i < n; ++i) {
    const nns::TensorsInfo &info = p->in[i].info;
    if (info.format == nns::TensorFormat::kStatic) {
      std::size_t count = nns::gst::buffer_tensor_count(in[i]);
      if (count != info.size())
        nns::fail(nns::ErrorKind::kStream, nns::gst::sync_pad_name(base, i) + ": buffer has " +
                                               std::to_string(count) + " tensors, the caps say " +
                                               std::to_string(info.size()));
      for (std::size_t t = 0; t < count; ++t) {
        nns::gst::MemoryPtr mem(nns::gst::buffer_get_tensor(in[i], t));
        gsize size = gst_memory_get_sizes(mem.get(), nullptr, nullptr);
        if (size != info[t].byte_size())
          nns::fail(nns::ErrorKind::kStream,
                    nns::gst::sync_pad_name(base, i) + ": tensor " + std::to_string(t) + " has " +
                        std::to_string(size) + " bytes, expected " +
                        std::to_string(info[t].byte_size()) + " for " + info[t].to_string());
        if (p->flexible_out) {
          const nns::MetaHeader h = nns::flexible_header(info[t].type, info[t].dims);
          mem.reset(nns::gst::memory_with_header(h, mem.get()));
        }
        nns::gst::buffer_append_tensor(out.get(), mem.release(), info[t]);
      }
    } else {
      // Flexible memories carry their own headers: pass them on unchanged.
      for (guint m = 0; m < gst_buffer_n_memory(in[i]); ++m)
        gst_buffer_append_memory(out.get(), gst_buffer_get_memory(in[i], m));
    }
  }
  if (p->decoration) check_frame(p, out.get());
  return out.release();
}

}  // namespace

static void gst_tensor_mux_set_property(GObject *object, guint id, const GValue *value,
                                        GParamSpec *pspec) {
  if (!nns::gst::sync_set_property(GST_TENSOR_SYNC(object), PROP_SILENT, id, value))
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static void gst_tensor_mux_get_property(GObject *object, guint id, GValue *value,
                                        GParamSpec *pspec) {
  if (!nns::gst::sync_get_property(GST_TENSOR_SYNC(object), PROP_SILENT, id, value))
    G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static void gst_tensor_mux_finalize(GObject *object) {
  delete GST_TENSOR_MUX(object)->priv;
  G_OBJECT_CLASS(gst_tensor_mux_parent_class)->finalize(object);
}

static void gst_tensor_mux_class_init(GstTensorMuxClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_mux_debug, "tensor_mux", 0, "tensor_mux element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_mux_set_property;
  gobject_class->get_property = gst_tensor_mux_get_property;
  gobject_class->finalize = gst_tensor_mux_finalize;
  nns::gst::sync_install_properties(gobject_class, PROP_SILENT, "slowest");

  auto *sync_class = GST_TENSOR_SYNC_CLASS(klass);
  sync_class->configure = mux_configure;
  sync_class->combine = mux_combine;

  gst_element_class_set_static_metadata(element_class, "TensorMux", "Muxer/Tensor",
                                        "Combines tensor streams into one other/tensors stream",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template_with_gtype(element_class, &sink_template,
                                                       GST_TYPE_TENSOR_SYNC_PAD);
  gst_element_class_add_static_pad_template(element_class, &src_template);
}

static void gst_tensor_mux_init(GstTensorMux *self) {
  self->priv = new MuxPriv();
}

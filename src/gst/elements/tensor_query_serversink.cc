// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_query_serversink
 *
 * The answering half of a query server: each buffer must carry the GstMetaQuery that
 * tensor_query_serversrc (same `id`) attached; the buffer's memories go back to that client
 * only. Buffers without the meta (an element in between that drops metas) are counted;
 * `limit` of them in a row stop the pipeline with an error that says so.
 *
 *   gst-launch-1.0 tensor_query_serversrc ! tensor_query_serversink
 *
 * Answers for a client that has gone away are dropped (counted in `stats`), not an error:
 * the server keeps serving the others.
 */
#include <gst/base/gstbasesink.h>

#include <atomic>
#include <mutex>
#include <optional>

#include "gst/edge_glue.h"
#include "gst/edge_props.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/query_batch.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(query_serversink_debug);
#define GST_CAT_DEFAULT query_serversink_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_QUERY_SERVERSINK (gst_tensor_query_serversink_get_type())
G_DECLARE_FINAL_TYPE(GstTensorQueryServerSink, gst_tensor_query_serversink, GST,
                     TENSOR_QUERY_SERVERSINK, GstBaseSink)
G_END_DECLS

namespace {

struct ServerSinkPriv {
  std::mutex lock;
  nns::gst::ConnSettings conn;  // connect-type and timeout only
  guint id = 0;
  gint limit = 1;
  // streaming state
  std::shared_ptr<nns::gst::QueryServerShared> shared;
  bool tensor_caps = false;
  std::optional<nns::TensorsConfig> config;  // static tensor caps: checked against batches
  std::string refused;  // caps refused for max-batch (posted once, not at every retry)
  gint metaless = 0;
  std::atomic<guint64> sent{0}, dropped{0};
};

enum { PROP_0, PROP_ID, PROP_LIMIT, PROP_STATS, PROP_CONN_FIRST };

const nns::gst::ConnPropTable &conn_props() {
  using nns::gst::ConnProp;
  static const nns::gst::ConnPropTable t(
      PROP_CONN_FIRST, {{ConnProp::kConnectType, "Connect Type", "The connection type", nullptr, 0,
                         0, false, false, nns::gst::query_connect_type_get_type},
                        {ConnProp::kTimeout, "Timeout",
                         "The timeout as seconds to maintain connection", nullptr, 10, 3600}});
  return t;
}

}  // namespace

struct _GstTensorQueryServerSink {
  GstBaseSink parent;
  ServerSinkPriv *priv;
};

G_DEFINE_TYPE(GstTensorQueryServerSink, gst_tensor_query_serversink, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(tensor_query_serversink, "tensor_query_serversink", GST_RANK_NONE,
                            GST_TYPE_TENSOR_QUERY_SERVERSINK)

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void serversink_set_property(GObject *object, guint id, const GValue *value,
                                    GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_SERVERSINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().set(id, value, &p->conn)) return;
  switch (id) {
    case PROP_ID:
      p->id = g_value_get_uint(value);
      break;
    case PROP_LIMIT:
      p->limit = g_value_get_int(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void serversink_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_SERVERSINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().get(id, value, p->conn)) return;
  switch (id) {
    case PROP_ID:
      g_value_set_uint(value, p->id);
      break;
    case PROP_LIMIT:
      g_value_set_int(value, p->limit);
      break;
    case PROP_STATS:
      g_value_take_boxed(value, gst_structure_new("application/x-query-serversink-stats", "sent",
                                                  G_TYPE_UINT64, guint64(p->sent), "dropped",
                                                  G_TYPE_UINT64, guint64(p->dropped), nullptr));
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static gboolean serversink_start(GstBaseSink *bsink) {
  return nns::gst::guard(bsink, FALSE, [&]() -> gboolean {
    auto *p = GST_TENSOR_QUERY_SERVERSINK(bsink)->priv;
    guint id;
    {
      std::lock_guard<std::mutex> l(p->lock);
      nns::gst::require_tcp(p->conn.connect_type);
      id = p->id;
    }
    p->shared = nns::gst::query_server_get(id);
    {
      std::lock_guard<std::mutex> l(p->shared->lock);
      gst_object_replace(reinterpret_cast<GstObject **>(&p->shared->sink_pad),
                         GST_OBJECT(GST_BASE_SINK_PAD(bsink)));
    }
    p->metaless = 0;
    p->refused.clear();
    p->sent = 0;
    p->dropped = 0;
    return TRUE;
  });
}

static gboolean serversink_stop(GstBaseSink *bsink) {
  auto *p = GST_TENSOR_QUERY_SERVERSINK(bsink)->priv;
  if (p->shared) {
    std::lock_guard<std::mutex> l(p->shared->lock);
    gst_object_replace(reinterpret_cast<GstObject **>(&p->shared->sink_pad), nullptr);
  }
  p->shared.reset();
  return TRUE;
}

// With max-batch > 1 the answers are split per request along their outermost dimension:
// static answer caps that do not keep the batch there are refused now, naming the model that
// produced them, rather than at the first answer.
static void check_answer_batch(GstBaseSink *bsink, const nns::TensorsInfo &info, guint n) {
  if (const auto i = nns::gst::tensor_without_batch(info, n)) {
    const auto &t = info[*i];
    std::string from;
    if (GstElement *up = nns::gst::find_upstream(GST_ELEMENT(bsink), "model")) {
      gchar *model = nullptr;
      g_object_get(up, "model", &model, nullptr);
      from = " (from " + nns::gst::element_label(up) + ", model '" + (model ? model : "") + "')";
      g_free(model);
      gst_object_unref(up);
    }
    nns::fail(nns::ErrorKind::kNegotiation,
              "max-batch=" + std::to_string(n) + ": a batch of " + std::to_string(n) +
                  " requests (tensor_query_serversrc max-batch) cannot be split: answer tensor " +
                  std::to_string(*i) + " is " + t.to_string() + from +
                  ", its outermost dimension must be the batch (" + std::to_string(n) +
                  "); use a model that keeps the batch outermost in its outputs, or "
                  "max-batch=1");
  }
}

static gboolean serversink_set_caps(GstBaseSink *bsink, GstCaps *caps) {
  return nns::gst::guard(bsink, FALSE, [&]() -> gboolean {
    auto *p = GST_TENSOR_QUERY_SERVERSINK(bsink)->priv;
    p->tensor_caps = nns::gst::is_tensor_caps(caps);
    p->config.reset();
    if (p->tensor_caps && gst_caps_is_fixed(caps)) try {
        nns::TensorsConfig c = nns::gst::config_from_caps(caps);
        if (c.info.format == nns::TensorFormat::kStatic) p->config = c;
      } catch (const nns::Error &) {
      }
    guint n = 1;
    if (p->shared) {
      std::lock_guard<std::mutex> l(p->shared->lock);
      n = p->shared->max_batch;
    }
    if (n > 1 && p->config) {
      const std::string text = nns::gst::caps_to_string(caps);
      if (text == p->refused) return FALSE;
      p->refused = text;
      check_answer_batch(bsink, p->config->info, n);
      p->refused.clear();
    }
    return TRUE;
  });
}

static GstFlowReturn serversink_render(GstBaseSink *bsink, GstBuffer *buf) {
  return nns::gst::guard(bsink, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_TENSOR_QUERY_SERVERSINK(bsink)->priv;
    GstMetaQuery *meta = nns::gst::buffer_get_meta_query(buf);
    if (!meta) {
      ++p->dropped;
      gint limit;
      {
        std::lock_guard<std::mutex> l(p->lock);
        limit = p->limit;
      }
      if (++p->metaless >= limit)
        nns::fail(nns::ErrorKind::kStream,
                  std::to_string(p->metaless) +
                      " buffer(s) in a row arrived without the GstMetaQuery (client id) that "
                      "tensor_query_serversrc attaches (limit " +
                      std::to_string(limit) +
                      "): an element between serversrc and serversink drops buffer metas");
      GST_WARNING_OBJECT(bsink, "buffer without GstMetaQuery dropped");
      return GST_FLOW_OK;
    }
    p->metaless = 0;
    std::shared_ptr<nns::edge::ServerNode> node;
    {
      std::lock_guard<std::mutex> l(p->shared->lock);
      node = p->shared->node;
    }
    if (!node) {
      ++p->dropped;
      return GST_FLOW_OK;
    }
    nns::gst::FrameView view(buf, p->tensor_caps);
    std::string why;
    guint slots = 0;
    const auto clients = nns::gst::buffer_get_batch_meta(buf, &slots);
    if (!clients.empty()) {  // a batch (serversrc max-batch): slot i answers clients[i]
      const auto &mems = view.frame().mems;
      // Static caps say where the batch is: every answer tensor must keep it outermost (a
      // model that reduces over the batch would otherwise be split into garbage).
      if (p->config)
        if (const auto i = nns::gst::tensor_without_batch(p->config->info, slots))
          nns::fail(nns::ErrorKind::kStream,
                    "a batch of " + std::to_string(slots) +
                        " requests (tensor_query_serversrc max-batch) cannot be split: answer "
                        "tensor " +
                        std::to_string(*i) + " is " + p->config->info[*i].to_string() +
                        ", its outermost dimension must be the batch (" + std::to_string(slots) +
                        "); the model must keep the batch outermost");
      for (const auto &m : mems)
        if (slots == 0 || m.size % slots != 0 || clients.size() > slots)
          nns::fail(nns::ErrorKind::kStream,
                    "a batched answer of " + std::to_string(m.size) +
                        " bytes cannot be split into " + std::to_string(slots) +
                        " slots: the model's outputs must keep the batch as outermost dimension");
      for (std::size_t i = 0; i < clients.size(); ++i) {
        nns::edge::OutFrame f;
        f.meta = view.frame().meta;
        for (const auto &m : mems) {
          const std::size_t part = m.size / slots;
          f.mems.push_back({static_cast<const uint8_t *>(m.data) + i * part, part});
        }
        if (node->send_to(clients[i], f, &why)) {
          ++p->sent;
        } else {
          ++p->dropped;
          GST_INFO_OBJECT(bsink, "answer dropped: %s", why.c_str());
        }
      }
      return GST_FLOW_OK;
    }
    if (node->send_to(meta->client_id, view.frame(), &why)) {
      ++p->sent;
    } else {
      ++p->dropped;
      GST_INFO_OBJECT(bsink, "answer dropped: %s", why.c_str());
    }
    return GST_FLOW_OK;
  });
}

static void serversink_finalize(GObject *object) {
  auto *self = GST_TENSOR_QUERY_SERVERSINK(object);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_query_serversink_parent_class)->finalize(object);
}

static void gst_tensor_query_serversink_class_init(GstTensorQueryServerSinkClass *klass) {
  auto *gobject = G_OBJECT_CLASS(klass);
  auto *element = GST_ELEMENT_CLASS(klass);
  auto *basesink = GST_BASE_SINK_CLASS(klass);
  gobject->set_property = serversink_set_property;
  gobject->get_property = serversink_get_property;
  gobject->finalize = serversink_finalize;
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  conn_props().install(gobject);
  g_object_class_install_property(
      gobject, PROP_ID,
      g_param_spec_uint("id", "ID", "ID for distinguishing query servers.", 0, G_MAXUINT, 0, rw));
  g_object_class_install_property(
      gobject, PROP_LIMIT,
      g_param_spec_int("limit", "Limit",
                       "Limits of the number of the buffers that the server cannot handle. "
                       "e.g., If the received buffer does not have a GstMetaQuery, the server "
                       "cannot handle the buffer.",
                       0, 65535, 1, rw));
  g_object_class_install_property(
      gobject, PROP_STATS,
      g_param_spec_boxed(
          "stats", "Statistics", "Answers sent, and dropped (client gone or no GstMetaQuery)",
          GST_TYPE_STRUCTURE, static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  gst_element_class_add_static_pad_template(element, &sink_template);
  gst_element_class_set_static_metadata(element, "TensorQueryServerSink", "Sink/Tensor/Query",
                                        "Send tensor data as a server over the network",
                                        "nnstreamer-cpp");
  basesink->start = serversink_start;
  basesink->stop = serversink_stop;
  basesink->set_caps = serversink_set_caps;
  basesink->render = serversink_render;
  GST_DEBUG_CATEGORY_INIT(query_serversink_debug, "tensor_query_serversink", 0,
                          "Tensor Query Server Sink");
}

static void gst_tensor_query_serversink_init(GstTensorQueryServerSink *self) {
  self->priv = new ServerSinkPriv();
  self->priv->conn = conn_props().defaults();
  // Answers leave as soon as they are rendered; a processing deadline on a live server
  // pipeline only produces "please add queues" warnings (the source reports no latency).
  gst_base_sink_set_processing_deadline(GST_BASE_SINK(self), 0);
}

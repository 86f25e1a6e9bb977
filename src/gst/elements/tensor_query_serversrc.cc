// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_query_serversrc
 *
 * The receiving half of a query server: listens on host:port with nnstreamer-edge's TCP
 * protocol (docs/wire-edge-tcp.md), accepts any number of tensor_query_client peers and
 * pushes each request as a buffer carrying a GstMetaQuery with the client id, so that
 * tensor_query_serversink (same `id`) sends the answer back to the client that asked.
 * A live source by default (is-live=TRUE), so server pipelines never wait for preroll.
 *
 *   gst-launch-1.0 tensor_query_serversrc port=3000 ! \
 *     other/tensors,format=static,num_tensors=1,dimensions=3:224:224:1,types=uint8,\
 *     framerate=0/1 ! tensor_filter framework=onnxruntime model=m.onnx ! \
 *     tensor_query_serversink
 *
 * Only connect-type=TCP is implemented; HYBRID is accepted as a value and refused at start
 * with an error saying so.
 */
#include <gst/base/gstpushsrc.h>

#include <atomic>
#include <mutex>

#include "gst/edge_glue.h"
#include "gst/edge_props.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(query_serversrc_debug);
#define GST_CAT_DEFAULT query_serversrc_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_QUERY_SERVERSRC (gst_tensor_query_serversrc_get_type())
G_DECLARE_FINAL_TYPE(GstTensorQueryServerSrc, gst_tensor_query_serversrc, GST,
                     TENSOR_QUERY_SERVERSRC, GstPushSrc)
G_END_DECLS

namespace {

struct Settings {
  nns::gst::ConnSettings conn;
  guint id = 0;
};

struct ServerSrcPriv {
  std::mutex lock;  // settings
  Settings s;
  std::shared_ptr<nns::gst::QueryServerShared> shared;
  std::atomic<guint64> received{0};
};

enum { PROP_0, PROP_ID, PROP_IS_LIVE, PROP_CONN_FIRST };

const nns::gst::ConnPropTable &conn_props() {
  using nns::gst::ConnProp;
  static const nns::gst::ConnPropTable t(
      PROP_CONN_FIRST,
      {{ConnProp::kHost, "Host", "The hostname to listen as", "localhost"},
       {ConnProp::kPort, "Port", "The port to listen to (0=random available port)", nullptr, 3000},
       {ConnProp::kDestHost, "Destination Host", "The destination hostname to connect",
        "127.0.0.1"},
       {ConnProp::kDestPort, "Destination Port",
        "The destination port to connect to (0=random available port)", nullptr, 1883},
       {ConnProp::kConnectType, "Connect Type", "The connection type.", nullptr, 0, 0, false, false,
        nns::gst::query_connect_type_get_type},
       {ConnProp::kTimeout, "Timeout", "The timeout as seconds to maintain connection", nullptr, 10,
        3600},
       {ConnProp::kTopic, "Topic",
        "The main topic of the host and option if necessary. "
        "(topic)/(optional topic for main topic).",
        nullptr, 0, 0, true}});
  return t;
}

}  // namespace

struct _GstTensorQueryServerSrc {
  GstPushSrc parent;
  ServerSrcPriv *priv;
};

G_DEFINE_TYPE(GstTensorQueryServerSrc, gst_tensor_query_serversrc, GST_TYPE_PUSH_SRC)
GST_ELEMENT_REGISTER_DEFINE(tensor_query_serversrc, "tensor_query_serversrc", GST_RANK_NONE,
                            GST_TYPE_TENSOR_QUERY_SERVERSRC)

static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void serversrc_set_property(GObject *object, guint id, const GValue *value,
                                   GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().set(id, value, &p->s.conn)) return;
  switch (id) {
    case PROP_ID:
      p->s.id = g_value_get_uint(value);
      break;
    case PROP_IS_LIVE:
      gst_base_src_set_live(GST_BASE_SRC(object), g_value_get_boolean(value));
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void serversrc_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().get(id, value, p->s.conn)) return;
  switch (id) {
    case PROP_ID:
      g_value_set_uint(value, p->s.id);
      break;
    case PROP_IS_LIVE:
      g_value_set_boolean(value, gst_base_src_is_live(GST_BASE_SRC(object)));
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static gboolean serversrc_start(GstBaseSrc *bsrc) {
  return nns::gst::guard(bsrc, FALSE, [&]() -> gboolean {
    auto *self = GST_TENSOR_QUERY_SERVERSRC(bsrc);
    auto *p = self->priv;
    Settings s;
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->s;
    }
    nns::gst::require_tcp(s.conn.connect_type);
    auto shared = nns::gst::query_server_get(s.id);
    {
      std::lock_guard<std::mutex> l(shared->lock);
      if (shared->node)
        nns::fail(nns::ErrorKind::kSettings,
                  "another tensor_query_serversrc already serves id " + std::to_string(s.id));
      shared->requests.clear();
      shared->flushing = false;
      gst_object_replace(reinterpret_cast<GstObject **>(&shared->src_pad),
                         GST_OBJECT(GST_BASE_SRC_PAD(bsrc)));
    }
    nns::edge::NodeOptions o = s.conn.node_options(nns::edge::Role::kQueryServer);
    o.connect_timeout_ms = s.conn.timeout ? static_cast<int>(s.conn.timeout) * 1000 : -1;
    nns::edge::NodeCallbacks cb;
    std::weak_ptr<nns::gst::QueryServerShared> weak = shared;
    cb.on_data = [weak](nns::edge::Message &&m) {
      if (auto sh = weak.lock()) {
        std::lock_guard<std::mutex> l(sh->lock);
        sh->requests.push_back(std::move(m));
        sh->cv.notify_all();
      }
    };
    cb.on_warning = [self](const std::string &w) { NNS_POST_WARNING(self, w); };
    cb.on_connected = [self](int64_t id, const std::string &peer) {
      GST_INFO_OBJECT(self, "client %s connected, id %" G_GINT64_FORMAT, peer.c_str(), id);
    };
    cb.caps = [weak]() -> std::string {
      auto sh = weak.lock();
      return sh ? sh->capability() : std::string();
    };
    cb.alloc = nns::gst::gst_memory_allocator();
    std::shared_ptr<nns::edge::ServerNode> node =
        nns::edge::make_server(s.conn.type(), o, std::move(cb));
    node->start();
    GST_INFO_OBJECT(self, "query server %u listening on %s:%u", s.id, s.conn.host.c_str(),
                    node->port());
    {
      std::lock_guard<std::mutex> l(shared->lock);
      shared->node = node;
    }
    p->shared = shared;
    p->received = 0;
    return TRUE;
  });
}

static gboolean serversrc_stop(GstBaseSrc *bsrc) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
  if (!p->shared) return TRUE;
  std::shared_ptr<nns::edge::ServerNode> node;
  {
    std::lock_guard<std::mutex> l(p->shared->lock);
    node.swap(p->shared->node);
    p->shared->flushing = true;
    p->shared->cv.notify_all();
  }
  if (node) node->stop();
  {
    std::lock_guard<std::mutex> l(p->shared->lock);
    p->shared->requests.clear();
    gst_object_replace(reinterpret_cast<GstObject **>(&p->shared->src_pad), nullptr);
  }
  p->shared.reset();
  return TRUE;
}

static gboolean serversrc_unlock(GstBaseSrc *bsrc) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
  if (p->shared) {
    std::lock_guard<std::mutex> l(p->shared->lock);
    p->shared->flushing = true;
    p->shared->cv.notify_all();
  }
  return TRUE;
}

static gboolean serversrc_unlock_stop(GstBaseSrc *bsrc) {
  auto *p = GST_TENSOR_QUERY_SERVERSRC(bsrc)->priv;
  if (p->shared) {
    std::lock_guard<std::mutex> l(p->shared->lock);
    p->shared->flushing = false;
  }
  return TRUE;
}

static GstFlowReturn serversrc_create(GstPushSrc *psrc, GstBuffer **out) {
  return nns::gst::guard(psrc, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_TENSOR_QUERY_SERVERSRC(psrc)->priv;
    auto sh = p->shared;
    if (!sh) return GST_FLOW_FLUSHING;
    nns::edge::Message m;
    {
      std::unique_lock<std::mutex> l(sh->lock);
      sh->cv.wait(l, [&] { return sh->flushing || !sh->requests.empty(); });
      if (sh->flushing) return GST_FLOW_FLUSHING;
      m = std::move(sh->requests.front());
      sh->requests.pop_front();
    }
    const auto id_str = m.meta.get("client_id");
    const int64_t client_id = id_str ? g_ascii_strtoll(id_str->c_str(), nullptr, 10) : 0;
    GstBuffer *buf = nns::gst::buffer_from_message_for_pad(std::move(m), GST_BASE_SRC_PAD(psrc));
    nns::gst::buffer_add_meta_query(buf, client_id);
    ++p->received;
    *out = buf;
    return GST_FLOW_OK;
  });
}

static void serversrc_finalize(GObject *object) {
  auto *self = GST_TENSOR_QUERY_SERVERSRC(object);
  delete self->priv;
  G_OBJECT_CLASS(gst_tensor_query_serversrc_parent_class)->finalize(object);
}

static void gst_tensor_query_serversrc_class_init(GstTensorQueryServerSrcClass *klass) {
  auto *gobject = G_OBJECT_CLASS(klass);
  auto *element = GST_ELEMENT_CLASS(klass);
  auto *basesrc = GST_BASE_SRC_CLASS(klass);
  auto *pushsrc = GST_PUSH_SRC_CLASS(klass);
  gobject->set_property = serversrc_set_property;
  gobject->get_property = serversrc_get_property;
  gobject->finalize = serversrc_finalize;
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  conn_props().install(gobject);
  g_object_class_install_property(
      gobject, PROP_ID,
      g_param_spec_uint("id", "ID", "ID for distinguishing query servers.", 0, G_MAXUINT, 0, rw));
  g_object_class_install_property(
      gobject, PROP_IS_LIVE,
      g_param_spec_boolean("is-live", "Is Live",
                           "Synchronize the incoming buffers' timestamp with the current "
                           "running time",
                           TRUE, rw));
  gst_element_class_add_static_pad_template(element, &src_template);
  gst_element_class_set_static_metadata(element, "TensorQueryServerSrc", "Source/Tensor/Query",
                                        "Receive tensor data as a server over the network",
                                        "nnstreamer-cpp");
  basesrc->start = serversrc_start;
  basesrc->stop = serversrc_stop;
  basesrc->unlock = serversrc_unlock;
  basesrc->unlock_stop = serversrc_unlock_stop;
  pushsrc->create = serversrc_create;
  GST_DEBUG_CATEGORY_INIT(query_serversrc_debug, "tensor_query_serversrc", 0,
                          "Tensor Query Server Source");
}

static void gst_tensor_query_serversrc_init(GstTensorQueryServerSrc *self) {
  self->priv = new ServerSrcPriv();
  self->priv->s.conn = conn_props().defaults();
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
  gst_base_src_set_do_timestamp(GST_BASE_SRC(self), TRUE);
  gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
}

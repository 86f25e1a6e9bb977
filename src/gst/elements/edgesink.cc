// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-edgesink
 *
 * Publishes a stream of any caps to every edgesrc connected to host:port, with
 * nnstreamer-edge's TCP protocol (docs/wire-edge-tcp.md). Each subscriber gets the caps
 * string "@edge_sink_caps@<caps>" when it connects. Without subscribers buffers are dropped,
 * unless wait-connection=TRUE (then render waits up to connection-timeout ms, 0 = forever).
 *
 *   gst-launch-1.0 videotestsrc is-live=true ! video/x-raw,width=64,height=48 ! \
 *     edgesink port=3000
 *
 * Only connect-type=TCP is implemented: HYBRID, MQTT and CUSTOM are accepted as values and
 * refused at start with an error saying so.
 */
#include <gst/base/gstbasesink.h>

#include <chrono>
#include <condition_variable>
#include <mutex>

#include "gst/edge_glue.h"
#include "gst/edge_props.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(edgesink_debug);
#define GST_CAT_DEFAULT edgesink_debug

G_BEGIN_DECLS
#define GST_TYPE_EDGESINK (gst_edgesink_get_type())
G_DECLARE_FINAL_TYPE(GstEdgeSink, gst_edgesink, GST, EDGESINK, GstBaseSink)
G_END_DECLS

namespace {

struct Settings {
  nns::gst::ConnSettings conn;
  bool wait_connection = false;
  guint64 connection_timeout = 0;
};

struct EdgeSinkPriv {
  std::mutex lock;
  Settings s;
  std::unique_ptr<nns::edge::ServerNode> node;
  std::string caps;       // "@edge_sink_caps@..." once negotiated
  std::string caps_meta;  // connect-type MQTT: the caps, sent as "caps" metadata
  bool tensor_caps = false;
  std::mutex wlock;
  std::condition_variable wcv;
  bool unlocked = false;
  guint64 published = 0, dropped = 0;
};

enum { PROP_0, PROP_WAIT_CONNECTION, PROP_CONNECTION_TIMEOUT, PROP_CONN_FIRST };

// Upstream's edgesink connection properties. Upstream's init sets dest-host/dest-port to
// localhost/3000 while its specs say 127.0.0.1/1883: the specs' values are used.
const nns::gst::ConnPropTable &conn_props() {
  using nns::gst::ConnProp;
  static const nns::gst::ConnPropTable t(
      PROP_CONN_FIRST,
      {{ConnProp::kHost, "Host", "A self host address to accept connection from edgesrc",
        "localhost"},
       {ConnProp::kPort, "Port",
        "A self port address to accept connection from edgesrc. If the port is set to 0 then "
        "the available port is allocated. ",
        nullptr, 3000},
       nns::gst::edge_connect_type_prop(),
       {ConnProp::kDestHost, "Destination Host", "The destination hostname of the broker",
        "127.0.0.1"},
       {ConnProp::kDestPort, "Destination Port", "The destination port of the broker", nullptr,
        1883},
       nns::gst::edge_topic_prop(),
       nns::gst::edge_custom_lib_prop()});
  return t;
}

}  // namespace

struct _GstEdgeSink {
  GstBaseSink parent;
  EdgeSinkPriv *priv;
};

G_DEFINE_TYPE(GstEdgeSink, gst_edgesink, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(edgesink, "edgesink", GST_RANK_NONE, GST_TYPE_EDGESINK)

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void edgesink_set_property(GObject *object, guint id, const GValue *value,
                                  GParamSpec *pspec) {
  auto *p = GST_EDGESINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().set(id, value, &p->s.conn)) return;
  switch (id) {
    case PROP_WAIT_CONNECTION:
      p->s.wait_connection = g_value_get_boolean(value);
      break;
    case PROP_CONNECTION_TIMEOUT:
      p->s.connection_timeout = g_value_get_uint64(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void edgesink_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *p = GST_EDGESINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (conn_props().get(id, value, p->s.conn)) return;
  switch (id) {
    case PROP_WAIT_CONNECTION:
      g_value_set_boolean(value, p->s.wait_connection);
      break;
    case PROP_CONNECTION_TIMEOUT:
      g_value_set_uint64(value, p->s.connection_timeout);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static gboolean edgesink_start(GstBaseSink *bsink) {
  return nns::gst::guard(bsink, FALSE, [&]() -> gboolean {
    auto *self = GST_EDGESINK(bsink);
    auto *p = self->priv;
    Settings s;
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->s;
      p->caps.clear();
    }
    nns::edge::NodeOptions o = s.conn.node_options(nns::edge::Role::kPublisher);
    nns::edge::NodeCallbacks cb;
    cb.caps = [p]() {
      std::lock_guard<std::mutex> l(p->lock);
      return p->caps;
    };
    cb.on_connected = [self, p](int64_t id, const std::string &peer) {
      GST_INFO_OBJECT(self, "subscriber %s connected, id %" G_GINT64_FORMAT, peer.c_str(), id);
      std::lock_guard<std::mutex> l(p->wlock);
      p->wcv.notify_all();
    };
    cb.on_warning = [self](const std::string &w) { NNS_POST_WARNING(self, w); };
    p->node = nns::edge::make_server(s.conn.type(), o, std::move(cb));
    p->node->start();
    p->published = p->dropped = 0;
    return TRUE;
  });
}

static gboolean edgesink_stop(GstBaseSink *bsink) {
  auto *p = GST_EDGESINK(bsink)->priv;
  if (p->node) p->node->stop();
  p->node.reset();
  return TRUE;
}

static gboolean edgesink_unlock(GstBaseSink *bsink) {
  auto *p = GST_EDGESINK(bsink)->priv;
  std::lock_guard<std::mutex> l(p->wlock);
  p->unlocked = true;
  p->wcv.notify_all();
  return TRUE;
}

static gboolean edgesink_unlock_stop(GstBaseSink *bsink) {
  auto *p = GST_EDGESINK(bsink)->priv;
  std::lock_guard<std::mutex> l(p->wlock);
  p->unlocked = false;
  return TRUE;
}

static gboolean edgesink_set_caps(GstBaseSink *bsink, GstCaps *caps) {
  auto *p = GST_EDGESINK(bsink)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  const std::string cs = nns::gst::caps_to_string(caps);
  p->caps = "@edge_sink_caps@" + cs;
  const auto t = p->s.conn.type();
  p->caps_meta = t == nns::edge::ConnectType::kMqtt || t == nns::edge::ConnectType::kCustom
                     ? cs
                     : std::string();
  p->tensor_caps = nns::gst::is_tensor_caps(caps);
  return TRUE;
}

static GstFlowReturn edgesink_render(GstBaseSink *bsink, GstBuffer *buf) {
  return nns::gst::guard(bsink, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_EDGESINK(bsink)->priv;
    bool wait;
    guint64 timeout_ms;
    bool tensor;
    std::string caps_meta;
    bool mqtt;
    {
      std::lock_guard<std::mutex> l(p->lock);
      wait = p->s.wait_connection;
      timeout_ms = p->s.connection_timeout;
      tensor = p->tensor_caps;
      caps_meta = p->caps_meta;
      mqtt = p->s.conn.type() == nns::edge::ConnectType::kMqtt;
    }
    if (wait && p->node->client_count() == 0) {
      // Polled in short slices too: an MQTT broker link coming back does not notify wcv.
      std::unique_lock<std::mutex> l(p->wlock);
      auto ready = [&] { return p->unlocked || p->node->client_count() > 0; };
      const auto end = std::chrono::steady_clock::now() + std::chrono::milliseconds(timeout_ms);
      while (!ready()) {
        if (timeout_ms != 0 && std::chrono::steady_clock::now() >= end)
          nns::fail(nns::ErrorKind::kNotFound,
                    std::string(mqtt ? "no MQTT broker connection" : "no edgesrc connected") +
                        " within connection-timeout=" + std::to_string(timeout_ms) +
                        " ms (wait-connection=TRUE)");
        p->wcv.wait_for(l, std::chrono::milliseconds(100));
      }
      if (p->unlocked) return GST_FLOW_FLUSHING;
    }
    nns::gst::FrameView view(buf, tensor);
    if (!caps_meta.empty()) view.frame().meta.set("caps", caps_meta);
    if (p->node->broadcast(view.frame()) > 0)
      ++p->published;
    else
      ++p->dropped;
    return GST_FLOW_OK;
  });
}

static void edgesink_finalize(GObject *object) {
  auto *self = GST_EDGESINK(object);
  delete self->priv;
  G_OBJECT_CLASS(gst_edgesink_parent_class)->finalize(object);
}

static void gst_edgesink_class_init(GstEdgeSinkClass *klass) {
  auto *gobject = G_OBJECT_CLASS(klass);
  auto *element = GST_ELEMENT_CLASS(klass);
  auto *basesink = GST_BASE_SINK_CLASS(klass);
  gobject->set_property = edgesink_set_property;
  gobject->get_property = edgesink_get_property;
  gobject->finalize = edgesink_finalize;
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  conn_props().install(gobject);
  g_object_class_install_property(
      gobject, PROP_WAIT_CONNECTION,
      g_param_spec_boolean("wait-connection", "Wait connection to edgesrc",
                           "Wait connection to edgesrc. If FALSE, buffers are dropped until a "
                           "subscriber connects.",
                           FALSE, rw));
  g_object_class_install_property(
      gobject, PROP_CONNECTION_TIMEOUT,
      g_param_spec_uint64("connection-timeout", "Timeout for wait a connection",
                          "The timeout (in milliseconds) for waiting a connection to receiver. 0 "
                          "timeout (default) means infinite wait.",
                          0, G_MAXUINT64, 0, rw));
  gst_element_class_add_static_pad_template(element, &sink_template);
  gst_element_class_set_static_metadata(element, "EdgeSink", "Sink/Edge",
                                        "Publish incoming streams", "nnstreamer-cpp");
  basesink->start = edgesink_start;
  basesink->stop = edgesink_stop;
  basesink->unlock = edgesink_unlock;
  basesink->unlock_stop = edgesink_unlock_stop;
  basesink->set_caps = edgesink_set_caps;
  basesink->render = edgesink_render;
  GST_DEBUG_CATEGORY_INIT(edgesink_debug, "edgesink", 0, "Edge sink");
}

static void gst_edgesink_init(GstEdgeSink *self) {
  self->priv = new EdgeSinkPriv();
  self->priv->s.conn = conn_props().defaults();
}

// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-edgesrc
 *
 * Subscribes to an edgesink at dest-host:dest-port (nnstreamer-edge's TCP protocol) and
 * pushes what it publishes. The output caps are the publisher's ("@edge_sink_caps@<caps>"
 * in its capability) unless downstream fixes them.
 *
 *   gst-launch-1.0 edgesrc dest-host=127.0.0.1 dest-port=3000 ! videoconvert ! autovideosink
 *
 * When the publisher ends its stream (it stops and says goodbye) edgesrc sends EOS; when the
 * connection breaks or the publisher sends garbage, an error names it and what was wrong.
 * Only connect-type=TCP is implemented: HYBRID, MQTT and CUSTOM are refused at start.
 */
#include <gst/base/gstpushsrc.h>

#include <condition_variable>
#include <deque>
#include <mutex>

#include "gst/edge_glue.h"
#include "gst/edge_props.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(edgesrc_debug);
#define GST_CAT_DEFAULT edgesrc_debug

G_BEGIN_DECLS
#define GST_TYPE_EDGESRC (gst_edgesrc_get_type())
G_DECLARE_FINAL_TYPE(GstEdgeSrc, gst_edgesrc, GST, EDGESRC, GstPushSrc)
G_END_DECLS

namespace {

struct EdgeSrcPriv {
  std::mutex lock;
  nns::gst::ConnSettings s;
  std::unique_ptr<nns::edge::ClientNode> node;
  std::string publisher_caps;  // edge_sink_caps of the publisher, if it announced them
  std::string meta_caps;       // MQTT: the "caps" metadata last applied to the pad
  std::mutex qlock;
  std::condition_variable qcv;
  std::deque<nns::edge::Message> queue;
  bool flushing = false, closed = false, clean = false;
  std::string closed_why;
};

enum { PROP_0, PROP_CONN_FIRST };

// Upstream's edgesrc properties (host and port deprecated, without effect).
const nns::gst::ConnPropTable &conn_props() {
  using nns::gst::ConnProp;
  static const nns::gst::ConnPropTable t(
      PROP_CONN_FIRST,
      {{ConnProp::kHost, "Host", "A self host address (DEPRECATED, has no effect).", nullptr, 0,
        65535, true, true},
       {ConnProp::kPort, "Port", "A self port number (DEPRECATED, has no effect).", nullptr, 0,
        65535, false, true},
       {ConnProp::kDestHost, "Destination Host",
        "A host address of edgesink to receive the packets from edgesink", "localhost"},
       {ConnProp::kDestPort, "Destination Port",
        "A port of edgesink to receive the packets from edgesink", nullptr, 3000},
       nns::gst::edge_connect_type_prop(),
       nns::gst::edge_topic_prop(),
       nns::gst::edge_custom_lib_prop()});
  return t;
}

}  // namespace

struct _GstEdgeSrc {
  GstPushSrc parent;
  EdgeSrcPriv *priv;
};

G_DEFINE_TYPE(GstEdgeSrc, gst_edgesrc, GST_TYPE_PUSH_SRC)
GST_ELEMENT_REGISTER_DEFINE(edgesrc, "edgesrc", GST_RANK_NONE, GST_TYPE_EDGESRC)

static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void edgesrc_set_property(GObject *object, guint id, const GValue *value,
                                 GParamSpec *pspec) {
  auto *p = GST_EDGESRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (!conn_props().set(id, value, &p->s)) G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static void edgesrc_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *p = GST_EDGESRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  if (!conn_props().get(id, value, p->s)) G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
}

static gboolean edgesrc_start(GstBaseSrc *bsrc) {
  return nns::gst::guard(bsrc, FALSE, [&]() -> gboolean {
    auto *p = GST_EDGESRC(bsrc)->priv;
    nns::gst::ConnSettings s;
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->s;
    }
    {
      std::lock_guard<std::mutex> l(p->qlock);
      p->queue.clear();
      p->flushing = p->closed = p->clean = false;
      p->meta_caps.clear();
    }
    nns::edge::NodeOptions o = s.node_options(nns::edge::Role::kSubscriber);
    nns::edge::NodeCallbacks cb;
    cb.alloc = nns::gst::gst_memory_allocator();
    cb.on_data = [p](nns::edge::Message &&m) {
      std::lock_guard<std::mutex> l(p->qlock);
      p->queue.push_back(std::move(m));
      p->qcv.notify_all();
    };
    cb.on_warning = [bsrc](const std::string &w) { NNS_POST_WARNING(bsrc, w); };
    cb.on_closed = [p](const std::string &why, nns::edge::CloseKind kind) {
      std::lock_guard<std::mutex> l(p->qlock);
      p->closed = true;
      p->clean = kind == nns::edge::CloseKind::kGoodbye;
      p->closed_why = why;
      p->qcv.notify_all();
    };
    p->node = nns::edge::make_client(s.type(), o, std::move(cb));
    try {
      p->node->connect();
    } catch (const nns::Error &e) {
      nns::fail(nns::ErrorKind::kNotFound,
                std::string("cannot subscribe to the edgesink: ") + e.what());
    }
    const auto caps = nns::edge::caps_field(p->node->server_caps(), "edge_sink_caps");
    std::lock_guard<std::mutex> l(p->lock);
    p->publisher_caps = caps ? *caps : std::string();
    return TRUE;
  });
}

static gboolean edgesrc_stop(GstBaseSrc *bsrc) {
  auto *p = GST_EDGESRC(bsrc)->priv;
  p->node.reset();
  std::lock_guard<std::mutex> l(p->qlock);
  p->queue.clear();
  return TRUE;
}

static GstCaps *edgesrc_get_caps(GstBaseSrc *bsrc, GstCaps *filter) {
  auto *p = GST_EDGESRC(bsrc)->priv;
  GstCaps *caps = nullptr;
  {
    std::lock_guard<std::mutex> l(p->lock);
    if (!p->publisher_caps.empty()) caps = gst_caps_from_string(p->publisher_caps.c_str());
  }
  // Static tensors also in their '.'-joined spellings, so a capsfilter written so intersects.
  if (caps) caps = nns::gst::with_tensor_spellings(caps);
  if (!caps) caps = gst_pad_get_pad_template_caps(GST_BASE_SRC_PAD(bsrc));
  if (filter) {
    GstCaps *i = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    caps = i;
  }
  return caps;
}

// The default negotiation; when downstream takes none of the publisher's caps, an error naming
// both (basesrc alone would only say not-negotiated).
static gboolean edgesrc_negotiate(GstBaseSrc *bsrc) {
  if (GST_BASE_SRC_CLASS(gst_edgesrc_parent_class)->negotiate(bsrc)) return TRUE;
  auto *p = GST_EDGESRC(bsrc)->priv;
  std::string publisher;
  {
    std::lock_guard<std::mutex> l(p->lock);
    publisher = p->publisher_caps;
  }
  if (!publisher.empty()) {
    nns::gst::CapsPtr peer(gst_pad_peer_query_caps(GST_BASE_SRC_PAD(bsrc), nullptr));
    NNS_POST_ERROR(bsrc, nns::ErrorKind::kNegotiation,
                   "downstream accepts " + nns::gst::caps_to_string(peer.get()) +
                       " but the publisher's caps are " + publisher);
  }
  return FALSE;
}

static gboolean edgesrc_unlock(GstBaseSrc *bsrc) {
  auto *p = GST_EDGESRC(bsrc)->priv;
  std::lock_guard<std::mutex> l(p->qlock);
  p->flushing = true;
  p->qcv.notify_all();
  return TRUE;
}

static gboolean edgesrc_unlock_stop(GstBaseSrc *bsrc) {
  auto *p = GST_EDGESRC(bsrc)->priv;
  std::lock_guard<std::mutex> l(p->qlock);
  p->flushing = false;
  return TRUE;
}

// connect-type MQTT and CUSTOM have no capability exchange: our edgesink sends its caps as the
// "caps" metadata of each message. They become the pad's caps unless downstream fixed others
// (a capsfilter naming only some fields takes the publisher's full caps).
static void apply_meta_caps(GstPushSrc *psrc, EdgeSrcPriv *p, const nns::edge::Message &m) {
  const auto mc = m.meta.get("caps");
  if (!mc || *mc == p->meta_caps) return;
  GstPad *pad = GST_BASE_SRC_PAD(psrc);
  nns::gst::CapsPtr cur(gst_pad_get_current_caps(pad));
  nns::gst::CapsPtr caps(gst_caps_from_string(mc->c_str()));
  if (!caps || !gst_caps_is_fixed(caps.get()))
    nns::fail(nns::ErrorKind::kStream,
              "the publisher's caps metadata '" + *mc + "' is not a fixed caps string");
  // Negotiated with downstream: keep those, unless the publisher's refine them.
  if (cur && p->meta_caps.empty() &&
      (gst_caps_is_equal(caps.get(), cur.get()) || !gst_caps_is_subset(caps.get(), cur.get())))
    return;
  if (!gst_base_src_set_caps(GST_BASE_SRC(psrc), caps.get()))
    nns::fail(nns::ErrorKind::kNegotiation,
              "downstream does not accept the publisher's caps " + *mc);
  p->meta_caps = *mc;
}

static GstFlowReturn edgesrc_create(GstPushSrc *psrc, GstBuffer **out) {
  return nns::gst::guard(psrc, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_EDGESRC(psrc)->priv;
    nns::edge::Message m;
    {
      std::unique_lock<std::mutex> l(p->qlock);
      p->qcv.wait(l, [&] { return p->flushing || p->closed || !p->queue.empty(); });
      if (p->flushing) return GST_FLOW_FLUSHING;
      if (p->queue.empty()) {  // closed
        if (p->clean) return GST_FLOW_EOS;
        nns::fail(nns::ErrorKind::kStream, "subscription ended: " + p->closed_why);
      }
      m = std::move(p->queue.front());
      p->queue.pop_front();
    }
    apply_meta_caps(psrc, p, m);
    *out = nns::gst::buffer_from_message_for_pad(std::move(m), GST_BASE_SRC_PAD(psrc));
    return GST_FLOW_OK;
  });
}

static void edgesrc_finalize(GObject *object) {
  auto *self = GST_EDGESRC(object);
  delete self->priv;
  G_OBJECT_CLASS(gst_edgesrc_parent_class)->finalize(object);
}

static void gst_edgesrc_class_init(GstEdgeSrcClass *klass) {
  auto *gobject = G_OBJECT_CLASS(klass);
  auto *element = GST_ELEMENT_CLASS(klass);
  auto *basesrc = GST_BASE_SRC_CLASS(klass);
  auto *pushsrc = GST_PUSH_SRC_CLASS(klass);
  gobject->set_property = edgesrc_set_property;
  gobject->get_property = edgesrc_get_property;
  gobject->finalize = edgesrc_finalize;
  conn_props().install(gobject);
  gst_element_class_add_static_pad_template(element, &src_template);
  gst_element_class_set_static_metadata(element, "EdgeSrc", "Source/Edge",
                                        "Subscribe and push incoming streams", "nnstreamer-cpp");
  basesrc->start = edgesrc_start;
  basesrc->stop = edgesrc_stop;
  basesrc->get_caps = edgesrc_get_caps;
  basesrc->negotiate = edgesrc_negotiate;
  basesrc->unlock = edgesrc_unlock;
  basesrc->unlock_stop = edgesrc_unlock_stop;
  pushsrc->create = edgesrc_create;
  GST_DEBUG_CATEGORY_INIT(edgesrc_debug, "edgesrc", 0, "Edge source");
}

static void gst_edgesrc_init(GstEdgeSrc *self) {
  self->priv = new EdgeSrcPriv();
  self->priv->s = conn_props().defaults();
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
  gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
}

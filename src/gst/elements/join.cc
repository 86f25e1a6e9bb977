// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-join
 *
 * N-to-1 join: every buffer arriving on any request pad sink_%u is forwarded on src in arrival
 * order (no merging). When a different pad becomes active, its sticky events (segment, ...)
 * go downstream first. As upstream's join, the sink pads must carry the same caps: a CAPS event
 * that differs from the caps of the active pad (the first sink pad before any buffer) is refused
 * (negotiation fails, with a bus error naming both pads and both caps), while the active pad
 * itself may renegotiate; caps features are ignored (textoverlay's transient
 * video/x-raw(meta:GstVideoOverlayComposition)). EOS goes
 * out once every linked sink pad has ended; releasing a pad re-checks that. Not tensor
 * specific. Read-only properties: n-pads, active-pad.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=5 ! join.sink_0
 *     videotestsrc num-buffers=5 pattern=ball ! join.sink_1  join name=join ! fakesink
 */
#include <cstdio>
#include <map>
#include <mutex>
#include <string>

#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(join_debug);
#define GST_CAT_DEFAULT join_debug

G_BEGIN_DECLS
#define GST_TYPE_JOIN (gst_join_get_type())
G_DECLARE_FINAL_TYPE(GstJoin, gst_join, GST, JOIN, GstElement)
G_END_DECLS

namespace {

struct JoinPriv {
  std::mutex lock;               // pads, active, eos flags
  std::mutex push_lock;          // one buffer (with its pad switch) at a time
  std::map<GstPad *, bool> eos;  // sink pad -> received EOS
  GstPad *active = nullptr;      // not owned (the element owns its pads)
  bool eos_sent = false;
  guint next_index = 0;
};

enum { PROP_0, PROP_N_PADS, PROP_ACTIVE_PAD };
GParamSpec *pspec_active = nullptr;

}  // namespace

struct _GstJoin {
  GstElement parent;
  GstPad *srcpad;
  JoinPriv *priv;
};

G_DEFINE_TYPE(GstJoin, gst_join, GST_TYPE_ELEMENT)
GST_ELEMENT_REGISTER_DEFINE(join, "join", GST_RANK_NONE, GST_TYPE_JOIN)

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink_%u", GST_PAD_SINK, GST_PAD_REQUEST, GST_STATIC_CAPS_ANY);
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

// True when every linked sink pad got EOS (unlinked pads can never end, so they do not count).
static bool all_ended(JoinPriv *p) {
  bool any = false;
  for (auto &[pad, eos] : p->eos) {
    if (eos)
      any = true;
    else if (gst_pad_is_linked(pad))
      return false;
  }
  return any;
}

struct ForwardCtx {
  GstJoin *self;
};

static gboolean forward_sticky(GstPad *, GstEvent **event, gpointer user) {
  auto *self = static_cast<ForwardCtx *>(user)->self;
  GstEvent *ev = *event;
  if (GST_EVENT_TYPE(ev) == GST_EVENT_STREAM_START) {
    nns::gst::EventPtr have(gst_pad_get_sticky_event(self->srcpad, GST_EVENT_STREAM_START, 0));
    if (have) return TRUE;  // one stream-start downstream
  }
  if (GST_EVENT_TYPE(ev) == GST_EVENT_EOS) return TRUE;
  gst_pad_push_event(self->srcpad, gst_event_ref(ev));
  return TRUE;
}

static GstFlowReturn join_chain(GstPad *pad, GstObject *parent, GstBuffer *buf) {
  auto *self = GST_JOIN(parent);
  auto *p = self->priv;
  std::lock_guard<std::mutex> push(p->push_lock);
  bool switched = false;
  {
    std::lock_guard<std::mutex> l(p->lock);
    if (p->active != pad) {
      p->active = pad;
      switched = true;
    }
  }
  if (switched) {
    GST_DEBUG_OBJECT(self, "active pad is now %s", GST_PAD_NAME(pad));
    ForwardCtx ctx{self};
    gst_pad_sticky_events_foreach(pad, forward_sticky, &ctx);
    g_object_notify_by_pspec(G_OBJECT(self), pspec_active);
  }
  return gst_pad_push(self->srcpad, buf);
}

// Caps equal once their features (memory:..., meta:...) are set aside: textoverlay first offers
// video/x-raw(meta:GstVideoOverlayComposition), then the same caps without the feature.
static bool same_caps_but_features(GstCaps *a, GstCaps *b) {
  if (gst_caps_is_equal(a, b)) return true;
  auto plain = [](GstCaps *c) {
    GstCaps *out = gst_caps_copy(c);
    for (guint i = 0; i < gst_caps_get_size(out); ++i) gst_caps_set_features(out, i, nullptr);
    return nns::gst::CapsPtr(out);
  };
  nns::gst::CapsPtr pa = plain(a), pb = plain(b);
  return gst_caps_is_equal(pa.get(), pb.get());
}

// The pad upstream's join compares caps against: the active pad, or the first sink pad while no
// buffer went out yet. Caller holds p->lock.
static GstPad *reference_pad(GstJoin *self, JoinPriv *p) {
  if (p->active) return p->active;
  GstPad *first = nullptr;
  GST_OBJECT_LOCK(self);
  if (GST_ELEMENT(self)->sinkpads) first = GST_PAD(GST_ELEMENT(self)->sinkpads->data);
  GST_OBJECT_UNLOCK(self);
  return first;
}

// The sink pad (with its caps, owned) whose caps `caps` arriving on `pad` contradict, or nullptr.
// As upstream, caps are checked against the reference pad only, and that pad itself may
// renegotiate. A pad's first caps, while the reference pad has none, are checked against every
// other pad's caps. Features are ignored (transient caps such as textoverlay's).
static std::pair<GstPad *, GstCaps *> caps_clash(GstJoin *self, JoinPriv *p, GstPad *pad,
                                                 GstCaps *caps) {
  GstPad *ref = reference_pad(self, p);
  GstCaps *ref_caps = ref && ref != pad ? gst_pad_get_current_caps(ref) : nullptr;
  if (ref_caps) {
    if (same_caps_but_features(ref_caps, caps)) {
      gst_caps_unref(ref_caps);
      return {nullptr, nullptr};
    }
    return {ref, ref_caps};
  }
  if (ref == pad && gst_pad_has_current_caps(pad)) return {nullptr, nullptr};  // renegotiation
  for (auto &[other, eos] : p->eos) {
    if (other == pad) continue;
    GstCaps *have = gst_pad_get_current_caps(other);
    if (!have) continue;
    if (!same_caps_but_features(have, caps)) return {other, have};
    gst_caps_unref(have);
  }
  return {nullptr, nullptr};
}

static gboolean join_sink_event(GstPad *pad, GstObject *parent, GstEvent *event) {
  auto *self = GST_JOIN(parent);
  auto *p = self->priv;
  bool forward;
  if (GST_EVENT_TYPE(event) == GST_EVENT_CAPS) {
    GstCaps *caps = nullptr;
    gst_event_parse_caps(event, &caps);
    std::pair<GstPad *, GstCaps *> clash;
    {
      std::lock_guard<std::mutex> l(p->lock);
      clash = caps_clash(self, p, pad, caps);
    }
    if (clash.first) {
      nns::gst::CapsPtr have(clash.second);
      NNS_POST_ERROR(self, nns::ErrorKind::kNegotiation,
                     std::string("the caps of every sink pad must be the same: ") +
                         GST_PAD_NAME(pad) + " got " + nns::gst::caps_to_string(caps) + ", but " +
                         GST_PAD_NAME(clash.first) + " has " +
                         nns::gst::caps_to_string(have.get()));
      gst_event_unref(event);
      return FALSE;
    }
  }
  {
    std::lock_guard<std::mutex> l(p->lock);
    forward = (pad == p->active);
    switch (GST_EVENT_TYPE(event)) {
      case GST_EVENT_STREAM_START: {
        // Downstream gets one stream-start: from the first pad that has one.
        nns::gst::EventPtr have(gst_pad_get_sticky_event(self->srcpad, GST_EVENT_STREAM_START, 0));
        forward = !have;
        break;
      }
      case GST_EVENT_EOS:
        p->eos[pad] = true;
        forward = !p->eos_sent && all_ended(p);
        p->eos_sent = p->eos_sent || forward;
        break;
      case GST_EVENT_FLUSH_STOP:
        p->eos[pad] = false;
        p->eos_sent = false;
        break;
      default:
        break;
    }
  }
  if (!forward) {
    // Sticky events stay on the sink pad and go downstream when it becomes active.
    gst_event_unref(event);
    return TRUE;
  }
  if (GST_EVENT_IS_SERIALIZED(event) && GST_EVENT_TYPE(event) != GST_EVENT_EOS) {
    std::lock_guard<std::mutex> push(p->push_lock);
    return gst_pad_push_event(self->srcpad, event);
  }
  return gst_pad_push_event(self->srcpad, event);
}

static gboolean join_sink_query(GstPad *pad, GstObject *parent, GstQuery *query) {
  auto *self = GST_JOIN(parent);
  switch (GST_QUERY_TYPE(query)) {
    case GST_QUERY_CAPS:
    case GST_QUERY_ACCEPT_CAPS:
    case GST_QUERY_POSITION:
    case GST_QUERY_DURATION:
    case GST_QUERY_CONTEXT:
      // Every input may become active: ask downstream whatever the active pad.
      return gst_pad_peer_query(self->srcpad, query);
    case GST_QUERY_ALLOCATION: {
      std::lock_guard<std::mutex> l(self->priv->lock);
      if (pad != self->priv->active) return FALSE;
      break;
    }
    default:
      break;
  }
  return gst_pad_query_default(pad, parent, query);
}

static GstIterator *join_src_internal_links(GstPad *, GstObject *parent) {
  auto *self = GST_JOIN(parent);
  std::lock_guard<std::mutex> l(self->priv->lock);
  if (!self->priv->active) return nullptr;
  GValue v = G_VALUE_INIT;
  g_value_init(&v, GST_TYPE_PAD);
  g_value_set_object(&v, self->priv->active);
  GstIterator *it = gst_iterator_new_single(GST_TYPE_PAD, &v);
  g_value_unset(&v);
  return it;
}

static GstPad *join_request_new_pad(GstElement *element, GstPadTemplate *templ, const gchar *name,
                                    const GstCaps *) {
  auto *self = GST_JOIN(element);
  auto *p = self->priv;
  std::string pad_name;
  {
    std::lock_guard<std::mutex> l(p->lock);
    guint index = p->next_index;
    if (name && sscanf(name, "sink_%u", &index) == 1) {
      for (auto &[pad, eos] : p->eos)
        if (std::string(GST_PAD_NAME(pad)) == name) return nullptr;  // taken
    }
    if (index >= p->next_index) p->next_index = index + 1;
    pad_name = "sink_" + std::to_string(index);
  }
  GstPad *pad = gst_pad_new_from_template(templ, pad_name.c_str());
  gst_pad_set_chain_function(pad, join_chain);
  gst_pad_set_event_function(pad, join_sink_event);
  gst_pad_set_query_function(pad, join_sink_query);
  GST_OBJECT_FLAG_SET(pad, GST_PAD_FLAG_PROXY_CAPS);
  GST_OBJECT_FLAG_SET(pad, GST_PAD_FLAG_PROXY_ALLOCATION);
  {
    std::lock_guard<std::mutex> l(p->lock);
    p->eos[pad] = false;
  }
  gst_pad_set_active(pad, TRUE);
  gst_element_add_pad(element, pad);
  g_object_notify(G_OBJECT(self), "n-pads");
  return pad;
}

static void join_release_pad(GstElement *element, GstPad *pad) {
  auto *self = GST_JOIN(element);
  auto *p = self->priv;
  bool send_eos = false;
  {
    std::lock_guard<std::mutex> l(p->lock);
    p->eos.erase(pad);
    if (p->active == pad) p->active = nullptr;
    send_eos = !p->eos_sent && all_ended(p);
    p->eos_sent = p->eos_sent || send_eos;
  }
  gst_pad_set_active(pad, FALSE);
  gst_element_remove_pad(element, pad);
  g_object_notify(G_OBJECT(self), "n-pads");
  if (send_eos) gst_pad_push_event(self->srcpad, gst_event_new_eos());
}

static GstStateChangeReturn join_change_state(GstElement *element, GstStateChange t) {
  auto *p = GST_JOIN(element)->priv;
  if (t == GST_STATE_CHANGE_READY_TO_PAUSED) {
    std::lock_guard<std::mutex> l(p->lock);
    for (auto &[pad, eos] : p->eos) eos = false;
    p->eos_sent = false;
    p->active = nullptr;
  }
  return GST_ELEMENT_CLASS(gst_join_parent_class)->change_state(element, t);
}

static void gst_join_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *self = GST_JOIN(object);
  auto *p = self->priv;
  std::lock_guard<std::mutex> l(p->lock);
  switch (id) {
    case PROP_N_PADS:
      g_value_set_uint(value, static_cast<guint>(p->eos.size()));
      break;
    case PROP_ACTIVE_PAD:
      g_value_set_object(value, p->active);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_join_finalize(GObject *object) {
  delete GST_JOIN(object)->priv;
  G_OBJECT_CLASS(gst_join_parent_class)->finalize(object);
}

static void gst_join_class_init(GstJoinClass *klass) {
  GST_DEBUG_CATEGORY_INIT(join_debug, "join", 0, "join element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->get_property = gst_join_get_property;
  gobject_class->finalize = gst_join_finalize;
  g_object_class_install_property(
      gobject_class, PROP_N_PADS,
      g_param_spec_uint("n-pads", "Number of Pads", "The number of sink pads", 0, G_MAXUINT, 0,
                        static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
  pspec_active = g_param_spec_object(
      "active-pad", "Active pad", "The sink pad whose buffer went out last", GST_TYPE_PAD,
      static_cast<GParamFlags>(G_PARAM_READABLE | GST_PARAM_MUTABLE_PLAYING |
                               G_PARAM_STATIC_STRINGS));
  g_object_class_install_property(gobject_class, PROP_ACTIVE_PAD, pspec_active);
  gst_element_class_set_static_metadata(element_class, "Input join", "Generic",
                                        "N-to-1 input stream join", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->request_new_pad = join_request_new_pad;
  element_class->release_pad = join_release_pad;
  element_class->change_state = join_change_state;
}

static void gst_join_init(GstJoin *self) {
  self->priv = new JoinPriv();
  self->srcpad = gst_pad_new_from_static_template(&src_template, "src");
  gst_pad_set_iterate_internal_links_function(self->srcpad, join_src_internal_links);
  GST_OBJECT_FLAG_SET(self->srcpad, GST_PAD_FLAG_PROXY_CAPS);
  gst_element_add_pad(GST_ELEMENT(self), self->srcpad);
}

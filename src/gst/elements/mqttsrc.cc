// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-mqttsrc
 *
 * Subscribes to `sub-topic` and pushes one buffer per MQTT message published by NNStreamer's
 * (or our) mqttsink: the header's caps string becomes the src caps, its memory sizes the
 * buffer's memories, and its timestamps are moved from the sender's base time onto this
 * pipeline's (both carried as epoch ns), as upstream does. Messages sent before this
 * pipeline started get no timestamps and are dropped, like upstream's.
 *
 * A message that is not a valid NNStreamer MQTT message (short, a memory count above 16,
 * sizes that do not match the bytes, an unterminated or unparsable caps string) is an error
 * naming the topic and the problem; nothing of the claimed size is allocated. When the broker
 * goes away the client reconnects and subscribes again (bus warnings say so); `sub-timeout`
 * bounds the wait for each message.
 *
 *   gst-launch-1.0 mqttsrc sub-topic=edge/cam1 ! videoconvert ! autovideosink
 */
#include <gst/base/gstbasesrc.h>

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstring>
#include <deque>
#include <memory>
#include <mutex>

#include "core/error.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/mqtt_common.h"
#include "gst/tensor_caps.h"
#include "mqtt/mqtt_client.h"
#include "mqtt/mqtt_message.h"

GST_DEBUG_CATEGORY_STATIC(mqttsrc_debug);
#define GST_CAT_DEFAULT mqttsrc_debug

G_BEGIN_DECLS
#define GST_TYPE_MQTT_SRC (gst_mqtt_src_get_type())
G_DECLARE_FINAL_TYPE(GstMqttSrc, gst_mqtt_src, GST, MQTT_SRC, GstBaseSrc)
G_END_DECLS

namespace {

namespace mq = nns::gst::mqtt;

struct Settings : mq::CommonSettings {
  Settings() : mq::CommonSettings(mq::kSrcRole) {}
  bool is_live = true;
  std::string topic;
  gint64 sub_timeout = 10000000;  // us
};

struct Item {
  nns::mqtt::MessageHeader header;
  nns::gst::BufferPtr buffer;  // memories laid out, no timestamps yet
};

struct SrcPriv {
  std::mutex lock;  // guards settings, queue, error, flushing, accepting
  std::condition_variable cv;
  Settings settings;
  Settings run;
  std::unique_ptr<nns::mqtt::Client> client;
  std::deque<Item> queue;
  std::string error;  // a bad message: the streaming thread posts it
  bool flushing = false;
  bool accepting = false;  // started, and PLAYING when live
  // The pipeline's base time as an epoch (ns), measured again whenever the base time changes
  // (a live pipeline picks a new one once its sinks prerolled). Streaming thread only.
  GstClockTime base_time = GST_CLOCK_TIME_NONE;
  int64_t base_epoch = 0;
  std::string caps;  // caps string currently set on the pad
  uint64_t dumped = 0;
  // Set when the client reports the link lost; the first connect is not a reconnect.
  std::atomic<bool> link_down{false};
};

// debug, client-id, host, port, cleansession, keep-alive-interval, mqtt-qos: mq::CommonProp.
enum {
  PROP_IS_LIVE = mq::kPropFirstOwn,
  PROP_SUB_TOPIC,
  PROP_SUB_TIMEOUT,
};

}  // namespace

struct _GstMqttSrc {
  GstBaseSrc parent;
  SrcPriv *priv;
};

G_DEFINE_TYPE(GstMqttSrc, gst_mqtt_src, GST_TYPE_BASE_SRC)
GST_ELEMENT_REGISTER_DEFINE(mqttsrc, "mqttsrc", GST_RANK_NONE, GST_TYPE_MQTT_SRC)

static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void gst_mqtt_src_set_property(GObject *object, guint id, const GValue *value,
                                      GParamSpec *pspec) {
  auto *self = GST_MQTT_SRC(object);
  auto *p = self->priv;
  std::lock_guard<std::mutex> l(p->lock);
  Settings &s = p->settings;
  if (mq::set_common_property(s, id, value)) return;
  switch (id) {
    case PROP_IS_LIVE:
      s.is_live = g_value_get_boolean(value);
      gst_base_src_set_live(GST_BASE_SRC(self), s.is_live);
      break;
    case PROP_SUB_TOPIC:
      s.topic = mq::string_value(value);
      break;
    case PROP_SUB_TIMEOUT:
      s.sub_timeout = g_value_get_int64(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_mqtt_src_get_property(GObject *object, guint id, GValue *value, GParamSpec *pspec) {
  auto *p = GST_MQTT_SRC(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  const Settings &s = p->settings;
  if (mq::get_common_property(s, id, value)) return;
  switch (id) {
    case PROP_IS_LIVE:
      g_value_set_boolean(value, s.is_live);
      break;
    case PROP_SUB_TOPIC:
      g_value_set_string(value, s.topic.empty() ? nullptr : s.topic.c_str());
      break;
    case PROP_SUB_TIMEOUT:
      g_value_set_int64(value, s.sub_timeout);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

// libmosquitto's thread: check the message, copy it once into a buffer of its memories.
static void on_message(GstMqttSrc *self, const std::string &topic, const uint8_t *data,
                       std::size_t size) {
  auto *p = self->priv;
  {
    std::lock_guard<std::mutex> l(p->lock);
    if (!p->accepting || !p->error.empty()) return;
  }
  Item item;
  try {
    item.header = nns::mqtt::parse_message(data, size);
  } catch (const nns::Error &e) {
    std::lock_guard<std::mutex> l(p->lock);
    p->error = "topic '" + topic + "': message of " + std::to_string(size) +
               " bytes is not an NNStreamer MQTT message: " + e.what();
    p->cv.notify_all();
    return;
  }
  const std::size_t body = size - nns::mqtt::kHeaderSize;
  GstBuffer *buf = gst_buffer_new();
  if (body > 0) {
    GstMemory *all = gst_allocator_alloc(nullptr, body, nullptr);
    GstMapInfo map;
    if (!gst_memory_map(all, &map, GST_MAP_WRITE)) {
      gst_memory_unref(all);
      gst_buffer_unref(buf);
      return;
    }
    std::memcpy(map.data, data + nns::mqtt::kHeaderSize, body);
    gst_memory_unmap(all, &map);
    gsize off = 0;
    for (uint64_t s : item.header.mem_sizes) {
      if (s == 0) continue;
      gst_buffer_append_memory(
          buf, gst_memory_share(all, static_cast<gssize>(off), static_cast<gssize>(s)));
      off += s;
    }
    gst_memory_unref(all);
  }
  item.buffer.reset(buf);
  std::lock_guard<std::mutex> l(p->lock);
  p->queue.push_back(std::move(item));
  p->cv.notify_all();
}

static gboolean mqtt_src_start(GstBaseSrc *src) {
  return nns::gst::guard(src, FALSE, [&]() -> gboolean {
    auto *self = GST_MQTT_SRC(src);
    auto *p = self->priv;
    {
      std::lock_guard<std::mutex> l(p->lock);
      p->run = p->settings;
      p->queue.clear();
      p->error.clear();
      p->flushing = false;
      p->accepting = !p->run.is_live;
      p->caps.clear();
      p->dumped = 0;
    }
    p->base_time = GST_CLOCK_TIME_NONE;
    p->link_down = false;
    Settings &s = p->run;
    if (s.topic.empty())
      nns::fail(nns::ErrorKind::kSettings, "sub-topic is required (the topic to subscribe to)");
    const nns::mqtt::ClientOptions o = mq::client_options(s, mq::kSrcRole);
    GstElement *elem = GST_ELEMENT(src);
    p->client = std::make_unique<nns::mqtt::Client>(
        o,
        [self](const std::string &topic, const uint8_t *d, std::size_t n) {
          on_message(self, topic, d, n);
        },
        [elem, p](bool up, const std::string &why) {
          if (!up) {
            p->link_down = true;
            NNS_POST_WARNING(elem, "connection to the MQTT broker " + mq::broker_name(p->run) +
                                       " lost (" + why + "); reconnecting");
          } else if (p->link_down.exchange(false)) {
            NNS_POST_WARNING(elem, "reconnected to the MQTT broker " + mq::broker_name(p->run) +
                                       "; subscribing to '" + p->run.topic + "' again");
          }
        });
    p->client->subscribe(s.topic, s.qos);
    mq::connect_or_fail(p->client, s, " and subscribe to '" + s.topic + "'");
    return TRUE;
  });
}

static gboolean mqtt_src_stop(GstBaseSrc *src) {
  auto *p = GST_MQTT_SRC(src)->priv;
  {
    std::lock_guard<std::mutex> l(p->lock);
    p->accepting = false;
  }
  if (p->client) {
    p->client->stop();
    p->client.reset();
  }
  std::lock_guard<std::mutex> l(p->lock);
  p->queue.clear();
  return TRUE;
}

static gboolean mqtt_src_unlock(GstBaseSrc *src) {
  auto *p = GST_MQTT_SRC(src)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  p->flushing = true;
  p->cv.notify_all();
  return TRUE;
}

static gboolean mqtt_src_unlock_stop(GstBaseSrc *src) {
  auto *p = GST_MQTT_SRC(src)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  p->flushing = false;
  return TRUE;
}

static GstStateChangeReturn mqtt_src_change_state(GstElement *element, GstStateChange t) {
  auto *p = GST_MQTT_SRC(element)->priv;
  if (t == GST_STATE_CHANGE_PAUSED_TO_PLAYING) {
    p->base_time = GST_CLOCK_TIME_NONE;  // create() measures the base epoch again
    std::lock_guard<std::mutex> l(p->lock);
    if (p->client) p->accepting = true;
  }
  GstStateChangeReturn ret = GST_ELEMENT_CLASS(gst_mqtt_src_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PLAYING_TO_PAUSED) {
    std::lock_guard<std::mutex> l(p->lock);
    if (p->run.is_live) {
      p->accepting = false;  // upstream unsubscribes here
      p->queue.clear();
    }
  }
  return ret;
}

static void mqtt_src_get_times(GstBaseSrc *, GstBuffer *buf, GstClockTime *start,
                               GstClockTime *end) {
  GstClockTime ts = GST_BUFFER_DTS(buf);
  if (!GST_CLOCK_TIME_IS_VALID(ts)) ts = GST_BUFFER_PTS(buf);
  if (GST_CLOCK_TIME_IS_VALID(ts)) {
    *start = ts;
    if (GST_BUFFER_DURATION_IS_VALID(buf)) *end = ts + GST_BUFFER_DURATION(buf);
  }
}

// Why rebase() gave a message no timestamps (r.drop), in the receiver's terms.
static std::string drop_reason(const nns::mqtt::MessageHeader &h, const nns::mqtt::Rebased &r,
                               int64_t base_epoch) {
  using Drop = nns::mqtt::Rebased::Drop;
  const std::string bases = "sender base time epoch " + std::to_string(h.base_time_epoch) +
                            " ns, ours " + std::to_string(base_epoch) + " ns";
  switch (r.drop) {
    case Drop::kSentBeforeBase:
      return "sent " + std::to_string(base_epoch - h.sent_time_epoch) +
             " ns before this pipeline's base time";
    case Drop::kBeforeRunningZero:
      if (h.pts == nns::mqtt::kNoTime)
        return "without pts from a sender that started before this pipeline (" + bases + ")";
      return "whose pts lands " + std::to_string(-r.landed) +
             " ns before this pipeline's running time 0 (" + bases + ")";
    case Drop::kNone:
    case Drop::kNoTimestamps:
      break;
  }
  return "without timestamps";
}

static GstFlowReturn mqtt_src_create(GstBaseSrc *src, guint64, guint, GstBuffer **out) {
  return nns::gst::guard(src, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_MQTT_SRC(src)->priv;
    const auto timeout = std::chrono::microseconds(p->run.sub_timeout);
    for (;;) {
      Item item;
      {
        std::unique_lock<std::mutex> l(p->lock);
        const bool got = p->cv.wait_for(
            l, timeout, [&] { return p->flushing || !p->error.empty() || !p->queue.empty(); });
        if (p->flushing) return GST_FLOW_FLUSHING;
        if (!p->error.empty()) nns::fail(nns::ErrorKind::kStream, p->error);
        if (!got)
          nns::fail(nns::ErrorKind::kStream, "no message on topic '" + p->run.topic +
                                                 "' within sub-timeout (" +
                                                 std::to_string(p->run.sub_timeout) + " us)" +
                                                 (p->client && !p->client->connected()
                                                      ? "; the broker " + mq::broker_name(p->run) +
                                                            " is unreachable: " + p->client->why()
                                                      : "") +
                                                 (p->dumped ? "; " + std::to_string(p->dumped) +
                                                                  " earlier message(s) were "
                                                                  "dropped for their timestamps"
                                                            : ""));
        item = std::move(p->queue.front());
        p->queue.pop_front();
      }
      const auto &h = item.header;
      if (h.caps != p->caps) {
        if (h.caps.empty() && !p->caps.empty()) {
          // Keep the current caps.
        } else {
          nns::gst::CapsPtr caps(h.caps.empty() ? nullptr : gst_caps_from_string(h.caps.c_str()));
          if (!caps || !gst_caps_is_fixed(caps.get()))
            nns::fail(nns::ErrorKind::kStream, "topic '" + p->run.topic + "': the caps string '" +
                                                   h.caps + "' in the message header is not " +
                                                   "fixed caps");
          // Several tensors: in the spelling downstream takes ('.' between tensors or ',').
          caps.reset(nns::gst::caps_in_peer_spelling(GST_BASE_SRC_PAD(src), caps.get()));
          GstPad *pad = GST_BASE_SRC_PAD(src);
          if ((gst_pad_is_linked(pad) && !gst_pad_peer_query_accept_caps(pad, caps.get())) ||
              !gst_base_src_set_caps(src, caps.get())) {
            nns::gst::CapsPtr peer(gst_pad_peer_query_caps(GST_BASE_SRC_PAD(src), nullptr));
            nns::fail(nns::ErrorKind::kNegotiation,
                      "topic '" + p->run.topic + "': downstream does not accept the caps " +
                          h.caps + " of the received stream (it accepts " +
                          nns::gst::caps_to_string(peer.get()) + ")");
          }
          p->caps = h.caps;
        }
      }
      GstBuffer *buf = item.buffer.release();
      bool have_base = false;
      if (GST_STATE(src) == GST_STATE_PLAYING) {
        if (GstClock *clock = gst_element_get_clock(GST_ELEMENT(src))) {
          const GstClockTime bt = gst_element_get_base_time(GST_ELEMENT(src));
          if (bt != p->base_time) {
            p->base_epoch =
                nns::mqtt::base_time_epoch(g_get_real_time() * 1000, gst_clock_get_time(clock), bt);
            p->base_time = bt;
          }
          gst_object_unref(clock);
          have_base = true;
        }
      }
      if (have_base) {
        const nns::mqtt::Rebased r = nns::mqtt::rebase(h, p->base_epoch);
        if (!r.valid()) {
          // Upstream drops it without a word; a receiver that only ever gets such messages
          // would then wait out sub-timeout with nothing on the bus. Say why, once per run.
          const std::string why = drop_reason(h, r, p->base_epoch);
          if (++p->dumped == 1)
            NNS_POST_WARNING(src, "topic '" + p->run.topic + "': dropped a message " + why +
                                      " (as upstream, such messages are not pushed; further "
                                      "ones are only logged)");
          if (p->run.debug)
            GST_INFO_OBJECT(src, "%s: dropped a message %s (total %" G_GUINT64_FORMAT ")",
                            p->run.topic.c_str(), why.c_str(), p->dumped);
          gst_buffer_unref(buf);
          continue;
        }
        GST_BUFFER_PTS(buf) = r.pts;
        GST_BUFFER_DTS(buf) = r.dts;
        GST_BUFFER_DURATION(buf) = r.duration;
      } else {
        // Not PLAYING yet (is-live=false prerolls): the sender's timestamps as they are.
        GST_BUFFER_PTS(buf) = h.pts;
        GST_BUFFER_DTS(buf) = h.dts;
        GST_BUFFER_DURATION(buf) = h.duration;
      }
      *out = buf;
      return GST_FLOW_OK;
    }
  });
}

static gboolean mqtt_src_query(GstBaseSrc *src, GstQuery *query) {
  if (GST_QUERY_TYPE(query) == GST_QUERY_LATENCY) {
    gst_query_set_latency(query, TRUE, 0, GST_CLOCK_TIME_NONE);
    return TRUE;
  }
  return GST_BASE_SRC_CLASS(gst_mqtt_src_parent_class)->query(src, query);
}

static gboolean mqtt_src_is_seekable(GstBaseSrc *) {
  return FALSE;
}

static void gst_mqtt_src_finalize(GObject *object) {
  auto *self = GST_MQTT_SRC(object);
  delete self->priv;
  G_OBJECT_CLASS(gst_mqtt_src_parent_class)->finalize(object);
}

static void gst_mqtt_src_init(GstMqttSrc *self) {
  self->priv = new SrcPriv();
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
  gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
}

static void gst_mqtt_src_class_init(GstMqttSrcClass *klass) {
  GST_DEBUG_CATEGORY_INIT(mqttsrc_debug, "mqttsrc", 0, "MQTT source");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *src_class = GST_BASE_SRC_CLASS(klass);
  gobject_class->set_property = gst_mqtt_src_set_property;
  gobject_class->get_property = gst_mqtt_src_get_property;
  gobject_class->finalize = gst_mqtt_src_finalize;
  mq::install_common_properties(gobject_class, mq::kSrcRole);
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_IS_LIVE,
      g_param_spec_boolean("is-live", "Is Live",
                           "Synchronize the incoming buffers' timestamp with the current running "
                           "time",
                           TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_SUB_TIMEOUT,
      g_param_spec_int64("sub-timeout", "Timeout for receiving a message",
                         "The timeout (in microseconds) for receiving a message from subscribed "
                         "topic",
                         1000000, G_MAXINT64, 10000000, rw));
  g_object_class_install_property(
      gobject_class, PROP_SUB_TOPIC,
      g_param_spec_string("sub-topic", "Topic to Subscribe (mandatory)",
                          "The topic's name to subscribe", nullptr, rw));
  element_class->change_state = mqtt_src_change_state;
  src_class->start = mqtt_src_start;
  src_class->stop = mqtt_src_stop;
  src_class->unlock = mqtt_src_unlock;
  src_class->unlock_stop = mqtt_src_unlock_stop;
  src_class->get_times = mqtt_src_get_times;
  src_class->create = mqtt_src_create;
  src_class->query = mqtt_src_query;
  src_class->is_seekable = mqtt_src_is_seekable;
  gst_element_class_set_static_metadata(
      element_class, "MQTT source", "Source/MQTT",
      "Subscribe a MQTT topic and push incoming data to the GStreamer pipeline", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &src_template);
}

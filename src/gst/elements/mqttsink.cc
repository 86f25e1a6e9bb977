// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-mqttsink
 *
 * Publishes every buffer (any caps) as one MQTT message on `pub-topic`, in NNStreamer's
 * layout: a 1024-byte header (memory sizes, the pipeline's base time and the send time as
 * epoch ns, duration/dts/pts, the caps string) and the memories back to back
 * (src/mqtt/mqtt_message.h, docs/wire-mqtt.md), published with the retain flag as upstream.
 * With `ntp-sync` the epoch times come from the NTP servers of `ntp-srvs` (one query when the
 * pipeline goes to PLAYING; the offset is kept).
 *
 * When the broker goes away the client reconnects on its own; buffers that cannot be sent
 * within `pub-wait-timeout` seconds meanwhile are dropped, with a bus warning when the link
 * goes down and one giving the number dropped when it is back.
 *
 *   gst-launch-1.0 videotestsrc ! mqttsink pub-topic=edge/cam1 host=127.0.0.1 port=1883
 */
#include <gst/base/gstbasesink.h>

#include <atomic>
#include <chrono>
#include <memory>
#include <mutex>
#include <vector>

#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/mqtt_common.h"
#include "mqtt/mqtt_client.h"
#include "mqtt/mqtt_message.h"
#include "mqtt/ntp_client.h"

GST_DEBUG_CATEGORY_STATIC(mqttsink_debug);
#define GST_CAT_DEFAULT mqttsink_debug

G_BEGIN_DECLS
#define GST_TYPE_MQTT_SINK (gst_mqtt_sink_get_type())
G_DECLARE_FINAL_TYPE(GstMqttSink, gst_mqtt_sink, GST, MQTT_SINK, GstBaseSink)
G_END_DECLS

namespace {

namespace mq = nns::gst::mqtt;

struct Settings : mq::CommonSettings {
  Settings() : mq::CommonSettings(mq::kSinkRole) {}
  std::string topic = mq::kDefaultPubTopic;
  gulong pub_wait_timeout = 1;
  gulong max_buffer_size = 0;
  gint num_buffers = -1;
  bool ntp_sync = false;
  std::string ntp_servers = mq::kDefaultNtpServers;
};

struct SinkPriv {
  std::mutex lock;  // guards settings
  Settings settings;
  // Running state (start .. stop)
  Settings run;  // the settings start() took
  std::unique_ptr<nns::mqtt::Client> client;
  std::atomic<bool> flushing{false};
  // The pipeline's base time as an epoch (ns), measured again whenever the base time changes.
  std::atomic<GstClockTime> base_time{GST_CLOCK_TIME_NONE};
  int64_t base_epoch = 0;
  std::atomic<int64_t> epoch_offset_ns{0};  // NTP time - system real time
  std::string caps;
  std::vector<uint8_t> msg;
  gint remaining = -1;
  std::atomic<bool> link_down{false};
  std::atomic<bool> down_reported{false};
  std::atomic<uint64_t> dropped{0};
};

// debug, client-id, host, port, cleansession, keep-alive-interval, mqtt-qos: mq::CommonProp.
enum {
  PROP_PUB_TOPIC = mq::kPropFirstOwn,
  PROP_PUB_WAIT_TIMEOUT,
  PROP_MAX_BUFFER_SIZE,
  PROP_NUM_BUFFERS,
  PROP_NTP_SYNC,
  PROP_NTP_SRVS,
};

int64_t real_time_ns() {
  return g_get_real_time() * 1000;
}

}  // namespace

struct _GstMqttSink {
  GstBaseSink parent;
  SinkPriv *priv;
};

G_DEFINE_TYPE(GstMqttSink, gst_mqtt_sink, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(mqttsink, "mqttsink", GST_RANK_NONE, GST_TYPE_MQTT_SINK)

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS_ANY);

static void gst_mqtt_sink_set_property(GObject *object, guint id, const GValue *value,
                                       GParamSpec *pspec) {
  auto *p = GST_MQTT_SINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  Settings &s = p->settings;
  if (mq::set_common_property(s, id, value)) return;
  switch (id) {
    case PROP_PUB_TOPIC:
      s.topic = mq::string_value(value);
      break;
    case PROP_PUB_WAIT_TIMEOUT:
      s.pub_wait_timeout = g_value_get_ulong(value);
      break;
    case PROP_MAX_BUFFER_SIZE:
      s.max_buffer_size = g_value_get_ulong(value);
      break;
    case PROP_NUM_BUFFERS:
      s.num_buffers = g_value_get_int(value);
      break;
    case PROP_NTP_SYNC:
      s.ntp_sync = g_value_get_boolean(value);
      break;
    case PROP_NTP_SRVS:
      s.ntp_servers = mq::string_value(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_mqtt_sink_get_property(GObject *object, guint id, GValue *value,
                                       GParamSpec *pspec) {
  auto *p = GST_MQTT_SINK(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  const Settings &s = p->settings;
  if (mq::get_common_property(s, id, value)) return;
  switch (id) {
    case PROP_PUB_TOPIC:
      g_value_set_string(value, s.topic.c_str());
      break;
    case PROP_PUB_WAIT_TIMEOUT:
      g_value_set_ulong(value, s.pub_wait_timeout);
      break;
    case PROP_MAX_BUFFER_SIZE:
      g_value_set_ulong(value, s.max_buffer_size);
      break;
    case PROP_NUM_BUFFERS:
      g_value_set_int(value, s.num_buffers);
      break;
    case PROP_NTP_SYNC:
      g_value_set_boolean(value, s.ntp_sync);
      break;
    case PROP_NTP_SRVS:
      g_value_set_string(value, s.ntp_servers.c_str());
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static gboolean mqtt_sink_start(GstBaseSink *sink) {
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    auto *p = GST_MQTT_SINK(sink)->priv;
    {
      std::lock_guard<std::mutex> l(p->lock);
      p->run = p->settings;
    }
    Settings &s = p->run;
    const nns::mqtt::ClientOptions o = mq::client_options(s, mq::kSinkRole);
    if (s.topic == mq::kDefaultPubTopic) s.topic = s.client_id + "/topic";
    if (s.topic.empty()) nns::fail(nns::ErrorKind::kSettings, "pub-topic is empty");
    p->remaining = s.num_buffers;
    p->flushing = false;
    p->dropped = 0;
    p->link_down = false;
    p->down_reported = false;
    p->base_time = GST_CLOCK_TIME_NONE;
    p->base_epoch = real_time_ns();
    p->epoch_offset_ns = 0;
    GstElement *self = GST_ELEMENT(sink);
    p->client =
        std::make_unique<nns::mqtt::Client>(o, nullptr, [self, p](bool up, const std::string &why) {
          if (!up) {
            p->link_down = true;
            NNS_POST_WARNING(self, "connection to the MQTT broker " + mq::broker_name(p->run) +
                                       " lost (" + why + "); reconnecting");
          } else if (p->link_down.exchange(false)) {
            NNS_POST_WARNING(self, "reconnected to the MQTT broker " + mq::broker_name(p->run) +
                                       "; " + std::to_string(p->dropped.load()) +
                                       " buffers dropped so far while it was unreachable");
          }
        });
    mq::connect_or_fail(p->client, s, "");
    return TRUE;
  });
}

static gboolean mqtt_sink_stop(GstBaseSink *sink) {
  auto *p = GST_MQTT_SINK(sink)->priv;
  if (p->client) {
    p->client->flush(std::chrono::seconds(p->run.pub_wait_timeout));
    p->client->stop();
    p->client.reset();
  }
  p->msg.clear();
  p->msg.shrink_to_fit();
  return TRUE;
}

static gboolean mqtt_sink_unlock(GstBaseSink *sink) {
  GST_MQTT_SINK(sink)->priv->flushing = true;
  return TRUE;
}

static gboolean mqtt_sink_unlock_stop(GstBaseSink *sink) {
  GST_MQTT_SINK(sink)->priv->flushing = false;
  return TRUE;
}

static gboolean mqtt_sink_set_caps(GstBaseSink *sink, GstCaps *caps) {
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    auto *p = GST_MQTT_SINK(sink)->priv;
    nns::gst::GCharPtr str(gst_caps_to_string(caps));
    std::string c = str ? str.get() : "";
    if (c.size() >= nns::mqtt::kMaxCapsLen)
      nns::fail(nns::ErrorKind::kNegotiation,
                "caps string of " + std::to_string(c.size()) +
                    " bytes does not fit the 512-byte MQTT header field: " + c);
    p->caps = std::move(c);
    return TRUE;
  });
}

static GstStateChangeReturn mqtt_sink_change_state(GstElement *element, GstStateChange t) {
  auto *p = GST_MQTT_SINK(element)->priv;
  if (t == GST_STATE_CHANGE_PAUSED_TO_PLAYING) {
    bool ntp = false;
    std::string servers;
    {
      std::lock_guard<std::mutex> l(p->lock);
      ntp = p->settings.ntp_sync;
      servers = p->settings.ntp_servers;
    }
    if (ntp) {
      try {
        const int64_t ntp_ns = nns::mqtt::ntp_epoch_us(nns::mqtt::parse_ntp_servers(servers),
                                                       std::chrono::milliseconds(1000)) *
                               1000;
        p->epoch_offset_ns = ntp_ns - real_time_ns();
      } catch (const std::exception &e) {
        p->epoch_offset_ns = 0;
        NNS_POST_WARNING(element, std::string("ntp-sync: ") + e.what() + " (ntp-srvs='" + servers +
                                      "'); using the system clock");
      }
    }
    p->base_time = GST_CLOCK_TIME_NONE;  // render() measures the base epoch again
  }
  return GST_ELEMENT_CLASS(gst_mqtt_sink_parent_class)->change_state(element, t);
}

// Waits up to pub-wait-timeout for the link; false when it stays down or on flush.
static bool wait_link(SinkPriv *p) {
  const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(p->run.pub_wait_timeout);
  while (!p->client->connected()) {
    if (p->flushing || std::chrono::steady_clock::now() >= end) return false;
    p->client->wait_connected(std::chrono::milliseconds(50));
  }
  return true;
}

static GstFlowReturn mqtt_sink_render(GstBaseSink *sink, GstBuffer *buf) {
  return nns::gst::guard(sink, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = GST_MQTT_SINK(sink)->priv;
    const Settings &s = p->run;
    if (p->remaining == 0) return GST_FLOW_EOS;
    if (p->remaining > 0) --p->remaining;
    const gsize size = gst_buffer_get_size(buf);
    if (s.max_buffer_size != 0 && size > s.max_buffer_size)
      nns::fail(nns::ErrorKind::kStream, "buffer of " + std::to_string(size) +
                                             " bytes is larger than max-buffer-size (" +
                                             std::to_string(s.max_buffer_size) + ")");
    nns::mqtt::MessageHeader h;
    const guint n = gst_buffer_n_memory(buf);
    if (n <= nns::mqtt::kMaxMems) {
      for (guint i = 0; i < n; ++i) h.mem_sizes.push_back(gst_buffer_peek_memory(buf, i)->size);
    } else {
      // More memories than the header holds: the first 15 as they are, the rest as one.
      gsize rest = size;
      for (guint i = 0; i + 1 < nns::mqtt::kMaxMems; ++i) {
        h.mem_sizes.push_back(gst_buffer_peek_memory(buf, i)->size);
        rest -= gst_buffer_peek_memory(buf, i)->size;
      }
      h.mem_sizes.push_back(rest);
    }
    if (GstClock *clock = gst_element_get_clock(GST_ELEMENT(sink))) {
      const GstClockTime bt = gst_element_get_base_time(GST_ELEMENT(sink));
      if (bt != p->base_time) {
        p->base_epoch = nns::mqtt::base_time_epoch(real_time_ns() + p->epoch_offset_ns,
                                                   gst_clock_get_time(clock), bt);
        p->base_time = bt;
      }
      gst_object_unref(clock);
    }
    h.base_time_epoch = p->base_epoch;
    h.sent_time_epoch = real_time_ns() + p->epoch_offset_ns;
    h.duration = GST_BUFFER_DURATION(buf);
    h.dts = GST_BUFFER_DTS(buf);
    h.pts = GST_BUFFER_PTS(buf);
    h.caps = p->caps;
    p->msg.resize(nns::mqtt::kHeaderSize + size);
    nns::mqtt::write_header(h, p->msg.data());
    gst_buffer_extract(buf, 0, p->msg.data() + nns::mqtt::kHeaderSize, size);
    if (!wait_link(p) || !p->client->publish(s.topic, p->msg.data(), p->msg.size(), s.qos, true)) {
      if (p->flushing) return GST_FLOW_FLUSHING;
      const uint64_t d = ++p->dropped;
      if (!p->down_reported.exchange(true))
        NNS_POST_WARNING(sink, "MQTT broker " + mq::broker_name(s) + " unreachable (" +
                                   p->client->why() + "); dropping buffers until it is back");
      GST_DEBUG_OBJECT(sink, "dropped buffer %" G_GUINT64_FORMAT " on %s", d, s.topic.c_str());
      return GST_FLOW_OK;
    }
    p->down_reported = false;
    if (s.debug)
      GST_INFO_OBJECT(sink, "%s: published %zu bytes, pts %" GST_TIME_FORMAT, s.topic.c_str(),
                      p->msg.size(), GST_TIME_ARGS(GST_BUFFER_PTS(buf)));
    return GST_FLOW_OK;
  });
}

static gboolean mqtt_sink_query(GstBaseSink *sink, GstQuery *query) {
  if (GST_QUERY_TYPE(query) == GST_QUERY_SEEKING) {
    GstFormat fmt;
    gst_query_parse_seeking(query, &fmt, nullptr, nullptr, nullptr);
    gst_query_set_seeking(query, fmt, FALSE, 0, -1);
    return TRUE;
  }
  return GST_BASE_SINK_CLASS(gst_mqtt_sink_parent_class)->query(sink, query);
}

static void gst_mqtt_sink_finalize(GObject *object) {
  auto *self = GST_MQTT_SINK(object);
  delete self->priv;
  G_OBJECT_CLASS(gst_mqtt_sink_parent_class)->finalize(object);
}

static void gst_mqtt_sink_init(GstMqttSink *self) {
  self->priv = new SinkPriv();
  gst_base_sink_set_qos_enabled(GST_BASE_SINK(self), TRUE);
  gst_base_sink_set_sync(GST_BASE_SINK(self), FALSE);
}

static void gst_mqtt_sink_class_init(GstMqttSinkClass *klass) {
  GST_DEBUG_CATEGORY_INIT(mqttsink_debug, "mqttsink", 0, "MQTT sink");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *sink_class = GST_BASE_SINK_CLASS(klass);
  gobject_class->set_property = gst_mqtt_sink_set_property;
  gobject_class->get_property = gst_mqtt_sink_get_property;
  gobject_class->finalize = gst_mqtt_sink_finalize;
  mq::install_common_properties(gobject_class, mq::kSinkRole);
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_NTP_SYNC,
      g_param_spec_boolean("ntp-sync", "NTP Synchronization",
                           "Synchronize received streams to the NTP clock", FALSE, rw));
  g_object_class_install_property(
      gobject_class, PROP_NTP_SRVS,
      g_param_spec_string("ntp-srvs", "NTP Server Host Name and Port Pairs",
                          "NTP Servers' HOST_NAME:PORT pairs to use (valid only if ntp-sync is "
                          "true)\n\t\t\tUse ',' to separate each pair if there are more pairs "
                          "than one",
                          mq::kDefaultNtpServers, rw));
  g_object_class_install_property(
      gobject_class, PROP_PUB_TOPIC,
      g_param_spec_string("pub-topic", "Topic to Publish", "The topic's name to publish",
                          mq::kDefaultPubTopic, rw));
  g_object_class_install_property(
      gobject_class, PROP_PUB_WAIT_TIMEOUT,
      g_param_spec_ulong("pub-wait-timeout", "Timeout for Publish a message",
                         "Timeout for execution of the main thread with completed publication "
                         "of a message",
                         1UL, G_MAXULONG, 1UL, rw));
  g_object_class_install_property(
      gobject_class, PROP_MAX_BUFFER_SIZE,
      g_param_spec_ulong("max-buffer-size", "The maximum size of a message buffer",
                         "The maximum size in bytes of a message buffer (0 = dynamic buffer "
                         "size)",
                         0, G_MAXULONG, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_NUM_BUFFERS,
      g_param_spec_int("num-buffers", "Num Buffers",
                       "Number of (remaining) buffers to accept until sending EOS event (-1 = "
                       "no limit)",
                       -1, G_MAXINT32, -1, rw));
  element_class->change_state = mqtt_sink_change_state;
  sink_class->start = mqtt_sink_start;
  sink_class->stop = mqtt_sink_stop;
  sink_class->unlock = mqtt_sink_unlock;
  sink_class->unlock_stop = mqtt_sink_unlock_stop;
  sink_class->set_caps = mqtt_sink_set_caps;
  sink_class->render = mqtt_sink_render;
  sink_class->query = mqtt_sink_query;
  gst_element_class_set_static_metadata(element_class, "MQTT sink", "Sink/MQTT",
                                        "Publish incoming data streams as a MQTT topic",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
}

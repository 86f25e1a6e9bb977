// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_ros_src
 *
 * Subscribes to a ROS topic carrying nns_ros_bridge/Tensors messages (nnstreamer-ros's message,
 * see ros_tensors.h) and pushes each message as one tensor frame. The caps (other/tensors,
 * static; other/tensor for one tensor) come from the first message's layout; a later message
 * with other dimensions or types is an error. A live source: buffers are time-stamped on arrival.
 * No message within `timeout` seconds: an error before the first message, end of stream after.
 *
 *   gst-launch-1.0 tensor_ros_src topic=/camera/tensors ! tensor_sink
 */
#include <gst/base/gstpushsrc.h>

#include <atomic>
#include <mutex>

#include "gst/element_glue.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "ros/ros_elements.h"
#include "ros/ros_tensors.h"

GST_DEBUG_CATEGORY_STATIC(tensor_ros_src_debug);
#define GST_CAT_DEFAULT tensor_ros_src_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_ROS_SRC (gst_tensor_ros_src_get_type())
G_DECLARE_FINAL_TYPE(GstTensorRosSrc, gst_tensor_ros_src, GST, TENSOR_ROS_SRC, GstPushSrc)
G_END_DECLS

namespace {

constexpr uint32_t kQueueSize = 100;
constexpr double kDefaultRate = 1.0;
constexpr double kDefaultTimeout = 5.0;

struct RosSrcPriv {
  // Settings
  std::mutex lock;
  std::string topic;
  double rate = kDefaultRate;
  double timeout = kDefaultTimeout;
  std::atomic<bool> silent{true};
  bool load_rosbag = false;
  std::string location;
  // State
  nns::ros::MessageQueue queue{kQueueSize};
  std::unique_ptr<nns::ros::Subscriber> subscriber;
  std::unique_ptr<nns::ros::BagReader> bag;
  std::chrono::steady_clock::time_point next_bag_message;
  std::string resolved_topic;
  // From the first message. Written by the streaming thread (and start/stop) under config_lock;
  // get_caps reads it from other threads under the same lock.
  std::mutex config_lock;
  std::optional<nns::TensorsConfig> config;
  guint64 received = 0;
};

enum { PROP_0, PROP_SILENT, PROP_TOPIC, PROP_RATE, PROP_TIMEOUT, PROP_LOAD_ROSBAG, PROP_LOCATION };

}  // namespace

struct _GstTensorRosSrc {
  GstPushSrc parent;
  RosSrcPriv *priv;
};

G_DEFINE_TYPE(GstTensorRosSrc, gst_tensor_ros_src, GST_TYPE_PUSH_SRC)
GST_ELEMENT_REGISTER_DEFINE(tensor_ros_src, "tensor_ros_src", GST_RANK_NONE,
                            GST_TYPE_TENSOR_ROS_SRC)

static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensor, framerate = (fraction) [ 0, max ]; "
                    "other/tensors, format = (string) static, framerate = (fraction) [ 0, max ]"));

static void gst_tensor_ros_src_set_property(GObject *object, guint id, const GValue *value,
                                            GParamSpec *pspec) {
  RosSrcPriv *p = GST_TENSOR_ROS_SRC(object)->priv;
  std::lock_guard lock(p->lock);
  switch (id) {
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    case PROP_TOPIC: {
      const char *s = g_value_get_string(value);
      p->topic = s ? s : "";
      break;
    }
    case PROP_RATE:
      p->rate = g_value_get_double(value);
      break;
    case PROP_TIMEOUT:
      p->timeout = g_value_get_double(value);
      break;
    case PROP_LOAD_ROSBAG:
      p->load_rosbag = g_value_get_boolean(value);
      break;
    case PROP_LOCATION: {
      const char *s = g_value_get_string(value);
      p->location = s ? s : "";
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_ros_src_get_property(GObject *object, guint id, GValue *value,
                                            GParamSpec *pspec) {
  RosSrcPriv *p = GST_TENSOR_ROS_SRC(object)->priv;
  std::lock_guard lock(p->lock);
  switch (id) {
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    case PROP_TOPIC:
      g_value_set_string(value, p->topic.c_str());
      break;
    case PROP_RATE:
      g_value_set_double(value, p->rate);
      break;
    case PROP_TIMEOUT:
      g_value_set_double(value, p->timeout);
      break;
    case PROP_LOAD_ROSBAG:
      g_value_set_boolean(value, p->load_rosbag);
      break;
    case PROP_LOCATION:
      g_value_set_string(value, p->location.empty() ? nullptr : p->location.c_str());
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_ros_src_finalize(GObject *object) {
  delete GST_TENSOR_ROS_SRC(object)->priv;
  G_OBJECT_CLASS(gst_tensor_ros_src_parent_class)->finalize(object);
}

static gboolean gst_tensor_ros_src_start(GstBaseSrc *src) {
  RosSrcPriv *p = GST_TENSOR_ROS_SRC(src)->priv;
  return nns::gst::guard(src, FALSE, [&]() -> gboolean {
    std::string topic, location;
    bool load_rosbag;
    {
      std::lock_guard lock(p->lock);
      topic = p->topic;
      location = p->location;
      load_rosbag = p->load_rosbag;
    }
    {
      std::lock_guard lock(p->config_lock);
      p->config.reset();
    }
    p->received = 0;
    p->queue.clear();
    p->queue.relock();
    if (load_rosbag) {
      // nnstreamer-ros: every Tensors message of the bag, whatever its topic; no master needed.
      if (location.empty())
        nns::fail(nns::ErrorKind::kSettings,
                  "property 'location' is empty: enable-load-rosbag needs the rosbag file to read");
      p->bag = nns::ros::open_bag_reader(location);
      p->resolved_topic = location + " (rosbag)";
      p->next_bag_message = std::chrono::steady_clock::now();
      GST_INFO_OBJECT(src, "reading %s", p->resolved_topic.c_str());
      return TRUE;
    }
    if (topic.empty())
      nns::fail(nns::ErrorKind::kSettings,
                "property 'topic' is empty: give the ROS topic to subscribe to");
    RosSrcPriv *pp = p;
    p->subscriber = nns::ros::make_subscriber(topic, kQueueSize, [pp](nns::ros::WireMessage &&m) {
      if (pp->queue.push(std::move(m)))
        GST_DEBUG("queue full on %s: dropped the oldest message", pp->resolved_topic.c_str());
    });
    p->resolved_topic = p->subscriber->topic();
    GST_INFO_OBJECT(src, "subscribed to %s (%s) over %s", p->resolved_topic.c_str(),
                    nns::ros::kMessageType, nns::ros::transport_name());
    return TRUE;
  });
}

static gboolean gst_tensor_ros_src_stop(GstBaseSrc *src) {
  RosSrcPriv *p = GST_TENSOR_ROS_SRC(src)->priv;
  return nns::gst::guard(src, FALSE, [&]() -> gboolean {
    p->subscriber.reset();  // no callback runs after this
    p->bag.reset();
    p->queue.clear();
    {
      std::lock_guard lock(p->config_lock);
      p->config.reset();
    }
    return TRUE;
  });
}

static gboolean gst_tensor_ros_src_unlock(GstBaseSrc *src) {
  GST_TENSOR_ROS_SRC(src)->priv->queue.unlock();
  return TRUE;
}

static gboolean gst_tensor_ros_src_unlock_stop(GstBaseSrc *src) {
  GST_TENSOR_ROS_SRC(src)->priv->queue.relock();
  return TRUE;
}

static GstCaps *gst_tensor_ros_src_get_caps(GstBaseSrc *src, GstCaps *filter) {
  RosSrcPriv *p = GST_TENSOR_ROS_SRC(src)->priv;
  GstCaps *caps = nullptr;
  std::unique_lock lock(p->config_lock);
  if (p->config)
    caps = nns::gst::caps_from_config(*p->config);
  else
    caps = gst_pad_get_pad_template_caps(GST_BASE_SRC_PAD(src));
  lock.unlock();
  if (filter) {
    GstCaps *both = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    caps = both;
  }
  return caps;
}

// The caps are only known from the first message: negotiation waits for create().
static gboolean gst_tensor_ros_src_negotiate(GstBaseSrc *src) {
  RosSrcPriv *p = GST_TENSOR_ROS_SRC(src)->priv;
  {
    std::lock_guard lock(p->config_lock);
    if (!p->config) return TRUE;
  }
  return GST_BASE_SRC_CLASS(gst_tensor_ros_src_parent_class)->negotiate(src);
}

static std::string describe(const nns::TensorsInfo &info) {
  return "types " + info.types_string() + ", dimensions " + info.dims_string();
}

static std::string seconds(double s) {
  char text[32];
  g_snprintf(text, sizeof text, "%g", s);
  return text;
}

static nns::TensorsConfig config_for(const nns::TensorsInfo &info, double rate) {
  nns::TensorsConfig c;
  c.info = info;
  gint n = 0, d = 1;
  gst_util_double_to_fraction(rate, &n, &d);
  c.rate_n = n;
  c.rate_d = d;
  return c;
}

// Checks a received message against the caps (setting them from the first one) and wraps its
// tensors in a buffer without copying. Throws nns::Error naming the topic.
static GstBuffer *to_buffer(GstBaseSrc *src, RosSrcPriv *p, nns::ros::WireMessage &&msg,
                            double rate) {
  nns::TensorsInfo info = nns::ros::info_from_wire(msg, p->resolved_topic);
  if (!p->config) {
    {
      std::lock_guard lock(p->config_lock);
      p->config = config_for(info, rate);
    }
    if (!gst_base_src_negotiate(src)) {
      GstCaps *caps = nns::gst::caps_from_config(*p->config);
      std::string text = nns::gst::caps_to_string(caps);
      gst_caps_unref(caps);
      nns::fail(nns::ErrorKind::kNegotiation,
                "topic " + p->resolved_topic +
                    ": downstream refused the caps of the first message: " + text);
    }
  } else if (!info.same_as(p->config->info)) {
    nns::fail(nns::ErrorKind::kStream,
              "topic " + p->resolved_topic + ": message " + std::to_string(p->received) +
                  " carries " + describe(info) +
                  " but the caps were set from the first message to " + describe(p->config->info));
  }
  GstBuffer *buf = gst_buffer_new();
  for (std::size_t i = 0; i < msg.size(); ++i) {
    auto *bytes = new std::vector<uint8_t>(std::move(msg[i].data));
    const std::size_t offset = msg[i].data_offset;
    GstMemory *mem = gst_memory_new_wrapped(
        GST_MEMORY_FLAG_READONLY, bytes->data(), bytes->size(), offset, bytes->size() - offset,
        bytes, [](gpointer d) { delete static_cast<std::vector<uint8_t> *>(d); });
    nns::gst::buffer_append_tensor(buf, mem, info[i]);
  }
  ++p->received;
  if (!p->silent)
    GST_INFO_OBJECT(src, "message %" G_GUINT64_FORMAT " from %s: %s", p->received,
                    p->resolved_topic.c_str(), info.to_string().c_str());
  return buf;
}

// enable-load-rosbag: the bag's next message, one per 1/rate seconds; EOS at the end.
static GstFlowReturn next_from_bag(GstBaseSrc *src, RosSrcPriv *p, double rate, GstBuffer **out) {
  auto wait = std::chrono::duration_cast<std::chrono::milliseconds>(
      p->next_bag_message - std::chrono::steady_clock::now());
  nns::ros::WireMessage msg;
  if (wait.count() > 0 && p->queue.pop(msg, wait) == nns::ros::MessageQueue::PopResult::kUnlocked)
    return GST_FLOW_FLUSHING;  // the queue stays empty in bag mode: pop() is an interruptible sleep
  if (!p->bag->next(msg)) {
    if (!p->config)
      nns::fail(nns::ErrorKind::kNotFound,
                p->resolved_topic + " has no " + nns::ros::kMessageType + " message");
    GST_INFO_OBJECT(src, "end of %s after %" G_GUINT64_FORMAT " messages",
                    p->resolved_topic.c_str(), p->received);
    return GST_FLOW_EOS;
  }
  p->next_bag_message = std::chrono::steady_clock::now() +
                        std::chrono::microseconds(static_cast<int64_t>(1e6 / rate));
  *out = to_buffer(src, p, std::move(msg), rate);
  return GST_FLOW_OK;
}

static GstFlowReturn gst_tensor_ros_src_create(GstPushSrc *psrc, GstBuffer **out) {
  auto *src = GST_BASE_SRC(psrc);
  RosSrcPriv *p = GST_TENSOR_ROS_SRC(psrc)->priv;
  return nns::gst::guard(src, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    double timeout, rate;
    {
      std::lock_guard lock(p->lock);
      timeout = p->timeout;
      rate = p->rate;
    }
    nns::ros::WireMessage msg;
    if (p->bag) return next_from_bag(src, p, rate, out);
    auto r = p->queue.pop(msg, std::chrono::milliseconds(static_cast<int64_t>(timeout * 1000)));
    if (r == nns::ros::MessageQueue::PopResult::kUnlocked) return GST_FLOW_FLUSHING;
    if (r == nns::ros::MessageQueue::PopResult::kTimeout) {
      if (!p->config)
        nns::fail(nns::ErrorKind::kNotFound, "no message on topic " + p->resolved_topic +
                                                 " within " + seconds(timeout) +
                                                 " s (property 'timeout'): is a publisher of " +
                                                 nns::ros::kMessageType + " running?");
      GST_INFO_OBJECT(src, "no message on %s for %.1f s: end of stream", p->resolved_topic.c_str(),
                      timeout);
      return GST_FLOW_EOS;
    }
    *out = to_buffer(src, p, std::move(msg), rate);
    return GST_FLOW_OK;
  });
}

static void gst_tensor_ros_src_class_init(GstTensorRosSrcClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_ros_src_debug, "tensor_ros_src", 0, "tensor_ros_src element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *basesrc_class = GST_BASE_SRC_CLASS(klass);
  auto *pushsrc_class = GST_PUSH_SRC_CLASS(klass);
  gobject_class->set_property = gst_tensor_ros_src_set_property;
  gobject_class->get_property = gst_tensor_ros_src_get_property;
  gobject_class->finalize = gst_tensor_ros_src_finalize;
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                           GST_PARAM_MUTABLE_READY);

  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log every received message", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_TOPIC,
      g_param_spec_string("topic", "Topic",
                          "ROS Topic Name for subscription (relative names are in the root "
                          "namespace)",
                          "", rw));
  g_object_class_install_property(
      gobject_class, PROP_RATE,
      g_param_spec_double("rate", "Rate",
                          "Frame rate in Hz announced in the caps (messages are pushed as they "
                          "arrive)",
                          1.0, G_USEC_PER_SEC, kDefaultRate, rw));
  g_object_class_install_property(
      gobject_class, PROP_TIMEOUT,
      g_param_spec_double("timeout", "Timeout",
                          "Seconds to wait for the next message: an error before the first "
                          "message, end of stream after it",
                          1.0, 600.0, kDefaultTimeout, rw));

  g_object_class_install_property(
      gobject_class, PROP_LOAD_ROSBAG,
      g_param_spec_boolean("enable-load-rosbag", "Enable-load-rosbag",
                           "Load a rosbag file to generate tensor(s) streams (one message per "
                           "1/rate s; no ROS master needed)",
                           FALSE, rw));
  g_object_class_install_property(
      gobject_class, PROP_LOCATION,
      g_param_spec_string("location", "Location", "Location of the rosbag file to load", nullptr,
                          rw));

  gst_element_class_set_static_metadata(element_class, "TensorRosSrc", "Source/Tensor",
                                        "Source element to get the topic data from ROS node",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &src_template);
  basesrc_class->start = gst_tensor_ros_src_start;
  basesrc_class->stop = gst_tensor_ros_src_stop;
  basesrc_class->unlock = gst_tensor_ros_src_unlock;
  basesrc_class->unlock_stop = gst_tensor_ros_src_unlock_stop;
  basesrc_class->get_caps = gst_tensor_ros_src_get_caps;
  basesrc_class->negotiate = gst_tensor_ros_src_negotiate;
  pushsrc_class->create = gst_tensor_ros_src_create;
}

static void gst_tensor_ros_src_init(GstTensorRosSrc *self) {
  self->priv = new RosSrcPriv();
  gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
  gst_base_src_set_do_timestamp(GST_BASE_SRC(self), TRUE);
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
}

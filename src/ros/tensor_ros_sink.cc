// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_ros_sink
 *
 * Publishes every tensor frame as one nns_ros_bridge/Tensors message (nnstreamer-ros's message:
 * one std_msgs/UInt8MultiArray per tensor, see ros_tensors.h) on a ROS topic. The topic is the
 * `topic` property, or nnstreamer-ros's name /tensor_ros_sink/PID_<pid>/<element name> when it
 * is empty. Static tensors only. Like tensor_sink it also emits new-data / stream-start / eos.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=10 ! video/x-raw,format=RGB,width=4,height=4 ! \
 *       tensor_converter ! tensor_ros_sink topic=/camera/tensors
 */
#include <gst/base/gstbasesink.h>
#include <unistd.h>

#include <atomic>
#include <chrono>
#include <mutex>
#include <thread>

#include "gst/element_glue.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "ros/ros_elements.h"
#include "ros/ros_tensors.h"

GST_DEBUG_CATEGORY_STATIC(tensor_ros_sink_debug);
#define GST_CAT_DEFAULT tensor_ros_sink_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_ROS_SINK (gst_tensor_ros_sink_get_type())
G_DECLARE_FINAL_TYPE(GstTensorRosSink, gst_tensor_ros_sink, GST, TENSOR_ROS_SINK, GstBaseSink)
G_END_DECLS

namespace {

constexpr uint32_t kQueueSize = 100;
constexpr auto kWaitSubscribersLimit = std::chrono::seconds(10);
// roscpp writes queued messages from its own thread and drops what is still queued when the
// publisher goes away; it has no flush call. At EOS the sink keeps the connection this long
// before letting the pipeline stop, so the last frames reach connected subscribers.
constexpr auto kEosLinger = std::chrono::milliseconds(300);

struct RosSinkPriv {
  // Settings
  std::mutex lock;
  std::string topic;
  guint wait_subscribers = 0;
  std::atomic<guint> signal_rate{0};
  std::atomic<bool> emit_signal{true};
  std::atomic<bool> silent{true};
  std::atomic<bool> dummy{false};
  bool save_rosbag = false;
  std::string location;
  // State (streaming thread, start/stop)
  std::unique_ptr<nns::ros::Publisher> publisher;
  std::unique_ptr<nns::ros::BagWriter> bag;
  std::string resolved_topic;
  nns::TensorsInfo info;
  std::vector<std::vector<nns::ros::LayoutDim>> layouts;
  bool waited = false;
  std::atomic<bool> flushing{false};  // unlock(): stop waiting for subscribers
  GstClockTime last_signal = GST_CLOCK_TIME_NONE;
};

enum {
  PROP_0,
  PROP_TOPIC,
  PROP_WAIT_SUBSCRIBERS,
  PROP_SIGNAL_RATE,
  PROP_EMIT_SIGNAL,
  PROP_SILENT,
  PROP_DUMMY,
  PROP_SAVE_ROSBAG,
  PROP_LOCATION
};
enum { SIGNAL_NEW_DATA, SIGNAL_STREAM_START, SIGNAL_EOS, N_SIGNALS };
guint ros_sink_signals[N_SIGNALS];

}  // namespace

struct _GstTensorRosSink {
  GstBaseSink parent;
  RosSinkPriv *priv;
};

G_DEFINE_TYPE(GstTensorRosSink, gst_tensor_ros_sink, GST_TYPE_BASE_SINK)
GST_ELEMENT_REGISTER_DEFINE(tensor_ros_sink, "tensor_ros_sink", GST_RANK_NONE,
                            GST_TYPE_TENSOR_ROS_SINK)

// Static tensors only: a flexible frame has no fixed layout to announce.
static GstStaticPadTemplate sink_template = GST_STATIC_PAD_TEMPLATE(
    "sink", GST_PAD_SINK, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensor, framerate = (fraction) [ 0, max ]; "
                    "other/tensors, format = (string) static, framerate = (fraction) [ 0, max ]"));

static void gst_tensor_ros_sink_set_property(GObject *object, guint id, const GValue *value,
                                             GParamSpec *pspec) {
  RosSinkPriv *p = GST_TENSOR_ROS_SINK(object)->priv;
  switch (id) {
    case PROP_TOPIC: {
      std::lock_guard lock(p->lock);
      const char *s = g_value_get_string(value);
      p->topic = s ? s : "";
      break;
    }
    case PROP_WAIT_SUBSCRIBERS: {
      std::lock_guard lock(p->lock);
      p->wait_subscribers = g_value_get_uint(value);
      break;
    }
    case PROP_SIGNAL_RATE:
      p->signal_rate = g_value_get_uint(value);
      break;
    case PROP_EMIT_SIGNAL:
      p->emit_signal = g_value_get_boolean(value);
      break;
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    case PROP_DUMMY:
      p->dummy = g_value_get_boolean(value);
      break;
    case PROP_SAVE_ROSBAG: {
      std::lock_guard lock(p->lock);
      p->save_rosbag = g_value_get_boolean(value);
      break;
    }
    case PROP_LOCATION: {
      std::lock_guard lock(p->lock);
      const char *s = g_value_get_string(value);
      p->location = s ? s : "";
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_ros_sink_get_property(GObject *object, guint id, GValue *value,
                                             GParamSpec *pspec) {
  RosSinkPriv *p = GST_TENSOR_ROS_SINK(object)->priv;
  switch (id) {
    case PROP_TOPIC: {
      std::lock_guard lock(p->lock);
      g_value_set_string(value, p->topic.c_str());
      break;
    }
    case PROP_WAIT_SUBSCRIBERS: {
      std::lock_guard lock(p->lock);
      g_value_set_uint(value, p->wait_subscribers);
      break;
    }
    case PROP_SIGNAL_RATE:
      g_value_set_uint(value, p->signal_rate);
      break;
    case PROP_EMIT_SIGNAL:
      g_value_set_boolean(value, p->emit_signal);
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    case PROP_DUMMY:
      g_value_set_boolean(value, p->dummy);
      break;
    case PROP_SAVE_ROSBAG: {
      std::lock_guard lock(p->lock);
      g_value_set_boolean(value, p->save_rosbag);
      break;
    }
    case PROP_LOCATION: {
      std::lock_guard lock(p->lock);
      g_value_set_string(value, p->location.empty() ? nullptr : p->location.c_str());
      break;
    }
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_ros_sink_finalize(GObject *object) {
  delete GST_TENSOR_ROS_SINK(object)->priv;
  G_OBJECT_CLASS(gst_tensor_ros_sink_parent_class)->finalize(object);
}

static gboolean gst_tensor_ros_sink_start(GstBaseSink *sink) {
  auto *self = GST_TENSOR_ROS_SINK(sink);
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    RosSinkPriv *p = self->priv;
    std::string topic, location;
    bool save_rosbag;
    {
      std::lock_guard lock(p->lock);
      topic = p->topic;
      location = p->location;
      save_rosbag = p->save_rosbag;
    }
    gchar *name = gst_object_get_name(GST_OBJECT(sink));
    const std::string element_name = name;
    g_free(name);
    // nnstreamer-ros's name: /tensor_ros_sink/PID_<pid>/<element name>.
    if (topic.empty())
      topic = "/tensor_ros_sink/PID_" + std::to_string(getpid()) + "/" + element_name;
    p->waited = false;
    p->last_signal = GST_CLOCK_TIME_NONE;
    // nnstreamer-ros's default bag name: <element name>.bag in the working folder.
    if (save_rosbag)
      p->bag = nns::ros::open_bag_writer(location.empty() ? element_name + ".bag" : location);
    if (p->dummy) {
      p->resolved_topic = topic.front() == '/' ? topic : "/" + topic;
      GST_INFO_OBJECT(sink, "dummy mode: consuming without publishing (topic %s)", topic.c_str());
      return TRUE;
    }
    p->publisher = nns::ros::make_publisher(topic, kQueueSize);
    p->resolved_topic = p->publisher->topic();
    GST_INFO_OBJECT(sink, "publishing %s on %s over %s", nns::ros::kMessageType,
                    p->resolved_topic.c_str(), nns::ros::transport_name());
    return TRUE;
  });
}

static gboolean gst_tensor_ros_sink_stop(GstBaseSink *sink) {
  RosSinkPriv *p = GST_TENSOR_ROS_SINK(sink)->priv;
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    p->publisher.reset();
    p->bag.reset();  // closes the file
    p->layouts.clear();
    return TRUE;
  });
}

static gboolean gst_tensor_ros_sink_event(GstBaseSink *sink, GstEvent *event) {
  auto *self = GST_TENSOR_ROS_SINK(sink);
  if (GST_EVENT_TYPE(event) == GST_EVENT_EOS) {
    const auto &pub = self->priv->publisher;
    if (pub && pub->subscriber_count() > 0) std::this_thread::sleep_for(kEosLinger);
  }
  if (self->priv->emit_signal) {
    if (GST_EVENT_TYPE(event) == GST_EVENT_STREAM_START)
      g_signal_emit(self, ros_sink_signals[SIGNAL_STREAM_START], 0);
    else if (GST_EVENT_TYPE(event) == GST_EVENT_EOS)
      g_signal_emit(self, ros_sink_signals[SIGNAL_EOS], 0);
  }
  return GST_BASE_SINK_CLASS(gst_tensor_ros_sink_parent_class)->event(sink, event);
}

static gboolean gst_tensor_ros_sink_unlock(GstBaseSink *sink) {
  GST_TENSOR_ROS_SINK(sink)->priv->flushing = true;
  return TRUE;
}

static gboolean gst_tensor_ros_sink_unlock_stop(GstBaseSink *sink) {
  GST_TENSOR_ROS_SINK(sink)->priv->flushing = false;
  return TRUE;
}

static gboolean gst_tensor_ros_sink_set_caps(GstBaseSink *sink, GstCaps *caps) {
  RosSinkPriv *p = GST_TENSOR_ROS_SINK(sink)->priv;
  return nns::gst::guard(sink, FALSE, [&]() -> gboolean {
    auto config = nns::gst::config_from_caps(caps);
    if (config.info.format != nns::TensorFormat::kStatic || !config.info.valid())
      nns::fail(
          nns::ErrorKind::kNegotiation,
          "topic " + p->resolved_topic +
              ": static tensors with the dimensions and types of every tensor are needed, got " +
              nns::gst::caps_to_string(caps));
    std::vector<std::vector<nns::ros::LayoutDim>> layouts;
    for (const auto &t : config.info.tensors) layouts.push_back(nns::ros::layout_for(t));
    p->info = config.info;
    p->layouts = std::move(layouts);
    GST_DEBUG_OBJECT(sink, "publishing %s", p->info.to_string().c_str());
    return TRUE;
  });
}

// Waits (once) until `wait-subscribers` subscribers are connected, so the first frames are not
// published before anyone listens.
static bool wait_for_subscribers(GstTensorRosSink *self) {
  RosSinkPriv *p = self->priv;
  guint want;
  {
    std::lock_guard lock(p->lock);
    want = p->wait_subscribers;
  }
  p->waited = true;
  if (want == 0 || !p->publisher) return true;
  const auto deadline = std::chrono::steady_clock::now() + kWaitSubscribersLimit;
  while (p->publisher->subscriber_count() < want) {
    if (p->flushing) return false;
    if (std::chrono::steady_clock::now() > deadline)
      nns::fail(nns::ErrorKind::kStream,
                "property 'wait-subscribers': " + std::to_string(want) +
                    " subscriber(s) expected on topic " + p->resolved_topic + ", " +
                    std::to_string(p->publisher->subscriber_count()) + " connected after " +
                    std::to_string(kWaitSubscribersLimit.count()) + " s");
    std::this_thread::sleep_for(std::chrono::milliseconds(10));
  }
  return true;
}

static GstFlowReturn gst_tensor_ros_sink_render(GstBaseSink *sink, GstBuffer *buf) {
  auto *self = GST_TENSOR_ROS_SINK(sink);
  RosSinkPriv *p = self->priv;
  return nns::gst::guard(sink, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    if (p->layouts.empty())
      nns::fail(nns::ErrorKind::kNegotiation,
                "topic " + p->resolved_topic + ": buffer before caps");
    nns::gst::check_static_buffer(buf, p->info);
    if (!p->waited && !wait_for_subscribers(self)) {
      p->waited = false;
      return GST_FLOW_FLUSHING;
    }
    const std::size_t n = p->info.size();
    std::vector<GstMemory *> mems(n, nullptr);
    std::vector<GstMapInfo> maps(n);
    std::vector<nns::ros::TensorView> views(n);
    std::size_t mapped = 0;
    auto unmap_all = [&] {
      for (std::size_t i = 0; i < mapped; ++i) gst_memory_unmap(mems[i], &maps[i]);
      for (GstMemory *m : mems)
        if (m) gst_memory_unref(m);
    };
    try {
      for (std::size_t i = 0; i < n; ++i) {
        mems[i] = nns::gst::buffer_get_tensor(buf, i);
        if (!mems[i] || !gst_memory_map(mems[i], &maps[i], GST_MAP_READ))
          nns::fail(nns::ErrorKind::kStream,
                    "topic " + p->resolved_topic + ": cannot read tensor " + std::to_string(i));
        ++mapped;
        views[i] = nns::ros::TensorView{maps[i].data, maps[i].size, &p->layouts[i]};
      }
      if (p->publisher) p->publisher->publish(views);
      if (p->bag) p->bag->write(p->resolved_topic, views);
    } catch (...) {
      unmap_all();
      throw;
    }
    unmap_all();
    if (!p->silent)
      GST_INFO_OBJECT(self, "published %zu tensor(s), %" G_GSIZE_FORMAT " bytes on %s", n,
                      gst_buffer_get_size(buf), p->resolved_topic.c_str());
    if (p->emit_signal) {
      guint rate = p->signal_rate;
      GstClockTime now = g_get_monotonic_time() * GST_USECOND;
      if (rate == 0 || !GST_CLOCK_TIME_IS_VALID(p->last_signal) ||
          now >= p->last_signal + GST_SECOND / rate) {
        p->last_signal = now;
        g_signal_emit(self, ros_sink_signals[SIGNAL_NEW_DATA], 0, buf);
      }
    }
    return GST_FLOW_OK;
  });
}

static void gst_tensor_ros_sink_class_init(GstTensorRosSinkClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_ros_sink_debug, "tensor_ros_sink", 0, "tensor_ros_sink element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *sink_class = GST_BASE_SINK_CLASS(klass);
  gobject_class->set_property = gst_tensor_ros_sink_set_property;
  gobject_class->get_property = gst_tensor_ros_sink_get_property;
  gobject_class->finalize = gst_tensor_ros_sink_finalize;
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                           GST_PARAM_MUTABLE_READY);

  g_object_class_install_property(
      gobject_class, PROP_TOPIC,
      g_param_spec_string("topic", "Topic",
                          "ROS topic to publish on (relative names are in the root namespace); "
                          "empty: /tensor_ros_sink/PID_<pid>/<element name>",
                          "", rw));
  g_object_class_install_property(
      gobject_class, PROP_WAIT_SUBSCRIBERS,
      g_param_spec_uint("wait-subscribers", "Wait subscribers",
                        "Before the first message, wait (at most 10 s) until this many "
                        "subscribers are connected (0: publish at once)",
                        0, G_MAXUINT, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_SIGNAL_RATE,
      g_param_spec_uint("signal-rate", "Signal rate",
                        "New data signals per second (0 for unlimited, max 500)", 0, 500, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_EMIT_SIGNAL,
      g_param_spec_boolean("emit-signal", "Emit signal",
                           "Emit signal for new data, stream start, eos", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log every published message", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_DUMMY,
      g_param_spec_boolean("dummy", "Dummy",
                           "Consume the frames without connecting to ROS or publishing", FALSE,
                           rw));

  g_object_class_install_property(
      gobject_class, PROP_SAVE_ROSBAG,
      g_param_spec_boolean("enable-save-rosbag", "Enable-save-rosbag",
                           "Save a rosbag file with the contents of the publishing topic", FALSE,
                           rw));
  g_object_class_install_property(
      gobject_class, PROP_LOCATION,
      g_param_spec_string("location", "Location",
                          "Location of the rosbag file to save (default: <element name>.bag)",
                          nullptr, rw));

  ros_sink_signals[SIGNAL_NEW_DATA] =
      g_signal_new("new-data", G_TYPE_FROM_CLASS(klass), G_SIGNAL_RUN_LAST, 0, nullptr, nullptr,
                   nullptr, G_TYPE_NONE, 1, GST_TYPE_BUFFER | G_SIGNAL_TYPE_STATIC_SCOPE);
  ros_sink_signals[SIGNAL_STREAM_START] =
      g_signal_new("stream-start", G_TYPE_FROM_CLASS(klass), G_SIGNAL_RUN_LAST, 0, nullptr, nullptr,
                   nullptr, G_TYPE_NONE, 0);
  ros_sink_signals[SIGNAL_EOS] = g_signal_new("eos", G_TYPE_FROM_CLASS(klass), G_SIGNAL_RUN_LAST, 0,
                                              nullptr, nullptr, nullptr, G_TYPE_NONE, 0);

  gst_element_class_set_static_metadata(element_class, "TensorRosSink", "Sink/Tensor",
                                        "Sink element to publish a ROS topic for tensor stream",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  sink_class->start = gst_tensor_ros_sink_start;
  sink_class->stop = gst_tensor_ros_sink_stop;
  sink_class->event = gst_tensor_ros_sink_event;
  sink_class->set_caps = gst_tensor_ros_sink_set_caps;
  sink_class->unlock = gst_tensor_ros_sink_unlock;
  sink_class->unlock_stop = gst_tensor_ros_sink_unlock_stop;
  sink_class->render = gst_tensor_ros_sink_render;
}

static void gst_tensor_ros_sink_init(GstTensorRosSink *self) {
  self->priv = new RosSinkPriv();
  // nnstreamer-ros keeps GstBaseSink's defaults (sync on) and turns QoS on.
  gst_base_sink_set_qos_enabled(GST_BASE_SINK(self), TRUE);
}

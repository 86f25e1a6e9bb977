// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_src_iio
 *
 * Live source of Linux Industrial I/O (IIO) sensor samples as float32 tensors. The device is
 * found in `iio-base-dir` by `device` (its sysfs name) or `device-number`; at start the element
 * enables the chosen scan channels (`channels`), sets the trigger, the sampling `frequency` and
 * the buffer length (`buffer-capacity`), and at stop puts every setting back as it found it
 * (src/core/iio/iio_device.h).
 *
 * mode=continuous (default) reads the buffered character device `dev-dir`/iio:deviceN:
 * `buffer-capacity` scans per output buffer, each channel converted to float per its
 * scan_elements type (endianness, sign, bits, shift) as (raw + offset) * scale. With a trigger it
 * waits for data with poll (`poll-timeout` ms); without one it waits one buffer period.
 * mode=one-shot reads each channel's `<channel>_raw` sysfs value instead (upstream leaves this
 * mode unimplemented).
 *
 * Output: merge-channels-data=true gives one tensor "channels:buffer-capacity" (channel
 * innermost); false gives one tensor "1:buffer-capacity" per channel. framerate is
 * frequency/buffer-capacity; buffers carry running-time timestamps and their duration.
 *
 *   gst-launch-1.0 tensor_src_iio device=accel_3d buffer-capacity=10 ! tensor_sink
 */
#include <gst/base/gstbasesrc.h>
#include <poll.h>
#include <sys/eventfd.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <chrono>
#include <cstring>
#include <memory>
#include <mutex>
#include <utility>

#include "core/iio/iio_device.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_src_iio_debug);
#define GST_CAT_DEFAULT tensor_src_iio_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_SRC_IIO (gst_tensor_src_iio_get_type())
G_DECLARE_FINAL_TYPE(GstTensorSrcIIO, gst_tensor_src_iio, GST, TENSOR_SRC_IIO, GstBaseSrc)
G_END_DECLS

namespace {

using nns::ErrorKind;
using nns::fail;

struct Settings {
  nns::iio::DeviceSettings dev;
  std::string mode = "continuous";
  bool merge = true;
  int poll_timeout = 10000;  // ms, -1: forever
  bool silent = true;
};

// Run state, owned by the streaming side between start() and stop().
struct RunState {
  RunState() = default;
  RunState(RunState &&o) noexcept { *this = std::move(o); }
  RunState &operator=(RunState &&o) noexcept {
    if (this != &o) {
      close_fd();
      device = std::move(o.device);
      one_shot = o.one_shot;
      fd = std::exchange(o.fd, -1);
      regular_file = o.regular_file;
      config = std::move(o.config);
      raw = std::move(o.raw);
      samples = std::move(o.samples);
      period = o.period;
    }
    return *this;
  }
  ~RunState() { close_fd(); }
  void close_fd() {
    if (fd >= 0) ::close(fd);
    fd = -1;
  }

  std::unique_ptr<nns::iio::Device> device;
  bool one_shot = false;
  int fd = -1;
  bool regular_file = false;  // a file standing in for the device: its end ends the stream
  nns::TensorsConfig config;
  std::vector<uint8_t> raw;    // one buffer of scans, reused
  std::vector<float> samples;  // one-shot: one sample per channel, reused
  GstClockTime period = GST_CLOCK_TIME_NONE;
};

struct SrcIioPriv {
  std::mutex lock;  // guards settings and caps
  Settings settings;
  GstCaps *caps = nullptr;  // fixed output caps between start() and stop()
  RunState run;
  int wake_fd = -1;  // eventfd: unlock() wakes a waiting create()
  std::atomic<bool> flushing{false};
};

enum {
  PROP_0,
  PROP_MODE,
  PROP_SILENT,
  PROP_BASE_DIRECTORY,
  PROP_DEV_DIRECTORY,
  PROP_DEVICE,
  PROP_DEVICE_NUM,
  PROP_TRIGGER,
  PROP_TRIGGER_NUM,
  PROP_CHANNELS,
  PROP_BUFFER_CAPACITY,
  PROP_FREQUENCY,
  PROP_MERGE_CHANNELS,
  PROP_POLL_TIMEOUT
};

}  // namespace

struct _GstTensorSrcIIO {
  GstBaseSrc parent;
  SrcIioPriv *priv;
};

G_DEFINE_TYPE(GstTensorSrcIIO, gst_tensor_src_iio, GST_TYPE_BASE_SRC)
GST_ELEMENT_REGISTER_DEFINE(tensor_src_iio, "tensor_src_iio", GST_RANK_NONE,
                            GST_TYPE_TENSOR_SRC_IIO)

static GstStaticPadTemplate src_template = GST_STATIC_PAD_TEMPLATE(
    "src", GST_PAD_SRC, GST_PAD_ALWAYS,
    GST_STATIC_CAPS("other/tensor, framerate = (fraction) [ 0, max ]; "
                    "other/tensors, format = (string) static, num_tensors = (int) [ 1, 256 ], "
                    "framerate = (fraction) [ 0, max ]"));

// Settings change only in NULL/READY: the device is configured at start.
static bool settings_locked(GstTensorSrcIIO *self) {
  GstState state = GST_STATE(self);
  if (state == GST_STATE_PAUSED || state == GST_STATE_PLAYING) {
    GST_WARNING_OBJECT(self, "properties can only be set in NULL or READY state; ignored");
    return true;
  }
  return false;
}

static void set_absolute_dir(GstTensorSrcIIO *self, std::string &field, const gchar *v,
                             const char *prop) {
  if (!v || !g_path_is_absolute(v)) {
    NNS_POST_WARNING(self, std::string(prop) + " must be an absolute path, got '" +
                               (v ? v : "(null)") + "'; keeping " + field);
    return;
  }
  field = v;
}

static void gst_tensor_src_iio_set_property(GObject *object, guint id, const GValue *value,
                                            GParamSpec *pspec) {
  auto *self = GST_TENSOR_SRC_IIO(object);
  auto *p = self->priv;
  if (id != PROP_SILENT && settings_locked(self)) return;
  std::lock_guard<std::mutex> l(p->lock);
  auto &s = p->settings;
  switch (id) {
    case PROP_MODE: {
      const gchar *m = g_value_get_string(value);
      std::string mode = m ? m : "";
      if (mode != "continuous" && mode != "one-shot") {
        NNS_POST_WARNING(self, "mode must be 'continuous' or 'one-shot', got '" + mode +
                                   "'; keeping '" + s.mode + "'");
        break;
      }
      s.mode = mode;
      break;
    }
    case PROP_SILENT:
      s.silent = g_value_get_boolean(value);
      break;
    case PROP_BASE_DIRECTORY:
      set_absolute_dir(self, s.dev.base_dir, g_value_get_string(value), "iio-base-dir");
      break;
    case PROP_DEV_DIRECTORY:
      set_absolute_dir(self, s.dev.dev_dir, g_value_get_string(value), "dev-dir");
      break;
    case PROP_DEVICE: {
      const gchar *v = g_value_get_string(value);
      s.dev.device = v ? v : "";
      break;
    }
    case PROP_DEVICE_NUM:
      s.dev.device_number = g_value_get_int(value);
      break;
    case PROP_TRIGGER: {
      const gchar *v = g_value_get_string(value);
      s.dev.trigger = v ? v : "";
      break;
    }
    case PROP_TRIGGER_NUM:
      s.dev.trigger_number = g_value_get_int(value);
      break;
    case PROP_CHANNELS: {
      const gchar *v = g_value_get_string(value);
      try {
        nns::iio::parse_channels(v ? v : "auto", s.dev);
      } catch (const nns::Error &e) {
        NNS_POST_WARNING(self, std::string(e.what()) +
                                   "; keeping channels=" + nns::iio::channels_to_string(s.dev));
      }
      break;
    }
    case PROP_BUFFER_CAPACITY:
      s.dev.buffer_capacity = g_value_get_uint(value);
      break;
    case PROP_FREQUENCY:
      s.dev.frequency = g_value_get_ulong(value);
      break;
    case PROP_MERGE_CHANNELS:
      s.merge = g_value_get_boolean(value);
      break;
    case PROP_POLL_TIMEOUT:
      s.poll_timeout = g_value_get_int(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_src_iio_get_property(GObject *object, guint id, GValue *value,
                                            GParamSpec *pspec) {
  auto *p = GST_TENSOR_SRC_IIO(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  const auto &s = p->settings;
  auto str_or_null = [](const std::string &v) { return v.empty() ? nullptr : v.c_str(); };
  switch (id) {
    case PROP_MODE:
      g_value_set_string(value, s.mode.c_str());
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, s.silent);
      break;
    case PROP_BASE_DIRECTORY:
      g_value_set_string(value, s.dev.base_dir.c_str());
      break;
    case PROP_DEV_DIRECTORY:
      g_value_set_string(value, s.dev.dev_dir.c_str());
      break;
    case PROP_DEVICE:
      g_value_set_string(value, str_or_null(s.dev.device));
      break;
    case PROP_DEVICE_NUM:
      g_value_set_int(value, s.dev.device_number);
      break;
    case PROP_TRIGGER:
      g_value_set_string(value, str_or_null(s.dev.trigger));
      break;
    case PROP_TRIGGER_NUM:
      g_value_set_int(value, s.dev.trigger_number);
      break;
    case PROP_CHANNELS:
      g_value_set_string(value, nns::iio::channels_to_string(s.dev).c_str());
      break;
    case PROP_BUFFER_CAPACITY:
      g_value_set_uint(value, s.dev.buffer_capacity);
      break;
    case PROP_FREQUENCY:
      g_value_set_ulong(value, static_cast<gulong>(s.dev.frequency));
      break;
    case PROP_MERGE_CHANNELS:
      g_value_set_boolean(value, s.merge);
      break;
    case PROP_POLL_TIMEOUT:
      g_value_set_int(value, s.poll_timeout);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

// Tensors the configured channels produce (see the SECTION comment).
static nns::TensorsConfig make_config(const nns::iio::Device &dev, unsigned capacity, bool merge) {
  nns::TensorsConfig c;
  const auto &outs = dev.outputs();
  if (merge) {
    nns::TensorInfo t;
    t.type = nns::TensorType::kFloat32;
    t.dims = nns::make_dims({static_cast<uint32_t>(outs.size()), capacity});
    c.info.tensors.push_back(t);
  } else {
    if (outs.size() > nns::kTensorLimit)
      fail(ErrorKind::kSettings, "merge-channels-data=false: " + std::to_string(outs.size()) +
                                     " channels exceed the limit of " +
                                     std::to_string(nns::kTensorLimit) + " tensors");
    for (const auto *ch : outs) {
      nns::TensorInfo t;
      t.name = ch->name;
      t.type = nns::TensorType::kFloat32;
      t.dims = nns::make_dims({1, capacity});
      c.info.tensors.push_back(t);
    }
  }
  // framerate = frequency / capacity, reduced to fit a GStreamer fraction.
  uint64_t n = dev.frequency(), d = capacity;
  while (n > G_MAXINT || d > G_MAXINT) {
    n /= 2;
    d = std::max<uint64_t>(1, d / 2);
  }
  c.rate_n = static_cast<int>(n);
  c.rate_d = static_cast<int>(d);
  return c;
}

// One tensor (merged channels, or a single channel): the legacy other/tensor structure first, so
// a peer taking both gets other/tensor as NNStreamer's element gives (its tests read that name);
// other/tensors stays offered.
static GstCaps *legacy_first(GstCaps *caps) {
  if (gst_caps_get_size(caps) != 2 ||
      !gst_structure_has_name(gst_caps_get_structure(caps, 1), "other/tensor"))
    return caps;
  GstStructure *legacy = gst_caps_steal_structure(caps, 1);
  GstCaps *out = gst_caps_new_empty();
  gst_caps_append_structure(out, legacy);
  gst_caps_append(out, caps);
  return out;
}

static gboolean src_iio_start(GstBaseSrc *src) {
  auto *self = GST_TENSOR_SRC_IIO(src);
  auto *p = self->priv;
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    Settings s;
    {
      std::lock_guard<std::mutex> l(p->lock);
      s = p->settings;
    }
    // Built aside: when anything below throws, its Device puts the sysfs settings back.
    RunState r;
    r.device = std::make_unique<nns::iio::Device>(s.dev);
    r.one_shot = s.mode == "one-shot";
    if (r.one_shot) {
      r.device->configure_one_shot();
      r.samples.resize(r.device->outputs().size());
    } else {
      r.device->configure_buffered();
      r.fd = r.device->open_buffer();
      struct stat st {};
      r.regular_file = ::fstat(r.fd, &st) == 0 && S_ISREG(st.st_mode);
      r.raw.resize(r.device->scan_size() * s.dev.buffer_capacity);
    }
    r.config = make_config(*r.device, s.dev.buffer_capacity, s.merge);
    r.period = gst_util_uint64_scale(GST_SECOND, s.dev.buffer_capacity, r.device->frequency());
    {
      std::lock_guard<std::mutex> l(p->lock);
      gst_caps_take(&p->caps, legacy_first(nns::gst::caps_from_config(r.config)));
    }
    p->flushing = false;
    p->run = std::move(r);
    const RunState &run = p->run;
    if (!s.silent)
      GST_INFO_OBJECT(
          self, "IIO device '%s' (iio:device%d): %zu channels at %" G_GUINT64_FORMAT " Hz, %s",
          run.device->name().c_str(), run.device->number(), run.device->outputs().size(),
          run.device->frequency(), run.config.info.to_string().c_str());
    return TRUE;
  });
}

static gboolean src_iio_stop(GstBaseSrc *src) {
  auto *p = GST_TENSOR_SRC_IIO(src)->priv;
  p->run = RunState();  // closes the buffer; the Device puts the sysfs settings back
  std::lock_guard<std::mutex> l(p->lock);
  gst_caps_replace(&p->caps, nullptr);
  return TRUE;
}

static GstCaps *src_iio_get_caps(GstBaseSrc *src, GstCaps *filter) {
  auto *p = GST_TENSOR_SRC_IIO(src)->priv;
  GstCaps *caps = nullptr;
  {
    std::lock_guard<std::mutex> l(p->lock);
    if (p->caps) caps = gst_caps_ref(p->caps);
  }
  if (!caps) caps = gst_pad_get_pad_template_caps(GST_BASE_SRC_PAD(src));
  if (filter) {
    GstCaps *i = gst_caps_intersect_full(filter, caps, GST_CAPS_INTERSECT_FIRST);
    gst_caps_unref(caps);
    return i;
  }
  return caps;
}

static GstStateChangeReturn src_iio_change_state(GstElement *element, GstStateChange t) {
  auto *self = GST_TENSOR_SRC_IIO(element);
  auto *p = self->priv;
  auto buffer_enable = [&](bool on) {
    return nns::gst::guard(self, false, [&] {
      if (p->run.device && !p->run.one_shot) p->run.device->enable_buffer(on);
      return true;
    });
  };
  if (t == GST_STATE_CHANGE_PAUSED_TO_PLAYING && !buffer_enable(true))
    return GST_STATE_CHANGE_FAILURE;
  GstStateChangeReturn ret =
      GST_ELEMENT_CLASS(gst_tensor_src_iio_parent_class)->change_state(element, t);
  if (t == GST_STATE_CHANGE_PLAYING_TO_PAUSED && !buffer_enable(false))
    return GST_STATE_CHANGE_FAILURE;
  return ret;
}

static gboolean src_iio_unlock(GstBaseSrc *src) {
  auto *p = GST_TENSOR_SRC_IIO(src)->priv;
  p->flushing = true;
  uint64_t one = 1;
  if (::write(p->wake_fd, &one, sizeof one) < 0) GST_WARNING_OBJECT(src, "eventfd write failed");
  return TRUE;
}

static gboolean src_iio_unlock_stop(GstBaseSrc *src) {
  auto *p = GST_TENSOR_SRC_IIO(src)->priv;
  p->flushing = false;
  uint64_t v;
  while (::read(p->wake_fd, &v, sizeof v) > 0) {
  }
  return TRUE;
}

// Waits up to `ms` (-1: forever) for `fd` (or only for a wake-up when fd < 0).
// Returns 1 when fd is readable, 0 on time-out, -1 when flushing.
static int wait_readable(SrcIioPriv *p, int fd, int ms) {
  pollfd fds[2] = {{p->wake_fd, POLLIN, 0}, {fd, POLLIN, 0}};
  int n;
  do {
    n = ::poll(fds, fd >= 0 ? 2 : 1, ms);
  } while (n < 0 && errno == EINTR);
  if (p->flushing || (fds[0].revents & POLLIN)) return -1;
  if (n < 0) fail(ErrorKind::kStream, std::string("poll failed: ") + std::strerror(errno));
  return n == 0 ? 0 : 1;
}

// Fills r.raw with buffer-capacity scans. Returns GST_FLOW_OK, EOS or FLUSHING.
static GstFlowReturn read_scans(GstTensorSrcIIO *self, int poll_timeout) {
  auto *p = self->priv;
  RunState &r = p->run;
  const std::string path = r.device->buffer_path();
  std::size_t got = 0;
  auto deadline = std::chrono::steady_clock::now() + std::chrono::milliseconds(poll_timeout);
  bool waited = false;
  while (got < r.raw.size()) {
    if (r.device->has_trigger() || waited) {
      int left = poll_timeout < 0 ? -1
                                  : static_cast<int>(std::max<int64_t>(
                                        0, std::chrono::duration_cast<std::chrono::milliseconds>(
                                               deadline - std::chrono::steady_clock::now())
                                               .count()));
      int w = wait_readable(p, r.fd, left);
      if (w < 0) return GST_FLOW_FLUSHING;
      if (w == 0)
        fail(ErrorKind::kStream, "no data from " + path + " within poll-timeout=" +
                                     std::to_string(poll_timeout) + " ms (" + std::to_string(got) +
                                     " of " + std::to_string(r.raw.size()) + " bytes read)");
    } else {
      // No trigger: the device fills its buffer at the sampling frequency; wait one period.
      int ms = static_cast<int>(r.period / GST_MSECOND);
      if (ms > 0 && wait_readable(p, -1, ms) < 0) return GST_FLOW_FLUSHING;
    }
    waited = true;
    ssize_t n = ::read(r.fd, r.raw.data() + got, r.raw.size() - got);
    if (n < 0) {
      if (errno == EAGAIN || errno == EINTR) continue;
      fail(ErrorKind::kStream, "cannot read the buffer of IIO device '" + r.device->name() + "' (" +
                                   path + "): " + std::strerror(errno));
    }
    if (n == 0) {
      if (got == 0 && r.regular_file) return GST_FLOW_EOS;
      if (got == 0) continue;  // a FIFO without writer yet
      fail(ErrorKind::kStream, path + " ended inside a buffer: " + std::to_string(got) + " of " +
                                   std::to_string(r.raw.size()) + " bytes (" +
                                   std::to_string(r.device->scan_size()) + "-byte scans)");
    }
    got += static_cast<std::size_t>(n);
  }
  return GST_FLOW_OK;
}

static GstFlowReturn src_iio_create(GstBaseSrc *src, guint64, guint, GstBuffer **out) {
  auto *self = GST_TENSOR_SRC_IIO(src);
  auto *p = self->priv;
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    RunState &r = p->run;
    int poll_timeout;
    unsigned capacity;
    {
      std::lock_guard<std::mutex> l(p->lock);
      poll_timeout = p->settings.poll_timeout;
      capacity = p->settings.dev.buffer_capacity;
    }
    const auto &outs = r.device->outputs();
    const std::size_t nch = outs.size();
    nns::gst::BufferPtr buf(gst_buffer_new());
    std::vector<nns::gst::MemoryPtr> mems;
    for (const auto &t : r.config.info.tensors)
      mems.emplace_back(gst_allocator_alloc(nullptr, t.byte_size(), nullptr));
    {
      std::vector<std::unique_ptr<nns::gst::MemoryMap>> maps;
      for (auto &m : mems)
        maps.push_back(std::make_unique<nns::gst::MemoryMap>(m.get(), GST_MAP_WRITE));
      // Output position of sample `s` of channel `c`.
      auto at = [&](std::size_t s, std::size_t c) -> float * {
        if (mems.size() == 1) return reinterpret_cast<float *>(maps[0]->data()) + s * nch + c;
        return reinterpret_cast<float *>(maps[c]->data()) + s;
      };
      if (r.one_shot) {
        // One sample per device tick (1 / frequency).
        const int tick_ms = static_cast<int>(r.period / capacity / GST_MSECOND);
        for (unsigned s = 0; s < capacity; ++s) {
          if (tick_ms > 0 && wait_readable(p, -1, tick_ms) < 0) return GST_FLOW_FLUSHING;
          r.device->read_one_shot(r.samples.data());
          for (std::size_t c = 0; c < nch; ++c) *at(s, c) = r.samples[c];
        }
      } else {
        GstFlowReturn fr = read_scans(self, poll_timeout);
        if (fr != GST_FLOW_OK) return fr;
        const std::size_t scan = r.device->scan_size();
        for (unsigned s = 0; s < capacity; ++s)
          for (std::size_t c = 0; c < nch; ++c)
            *at(s, c) = nns::iio::decode_sample(*outs[c], r.raw.data() + s * scan);
      }
    }
    for (std::size_t i = 0; i < mems.size(); ++i)
      nns::gst::buffer_append_tensor(buf.get(), mems[i].release(), r.config.info[i]);
    GST_BUFFER_DURATION(buf.get()) = r.period;
    *out = buf.release();
    return GST_FLOW_OK;
  });
}

static void gst_tensor_src_iio_finalize(GObject *object) {
  auto *p = GST_TENSOR_SRC_IIO(object)->priv;
  if (p->wake_fd >= 0) ::close(p->wake_fd);
  gst_caps_replace(&p->caps, nullptr);
  delete p;
  G_OBJECT_CLASS(gst_tensor_src_iio_parent_class)->finalize(object);
}

static void gst_tensor_src_iio_class_init(GstTensorSrcIIOClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_src_iio_debug, "tensor_src_iio", 0, "tensor_src_iio");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *base_class = GST_BASE_SRC_CLASS(klass);
  gobject_class->set_property = gst_tensor_src_iio_set_property;
  gobject_class->get_property = gst_tensor_src_iio_get_property;
  gobject_class->finalize = gst_tensor_src_iio_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Produce verbose output", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_MODE,
      g_param_spec_string("mode", "Operating mode",
                          "Mode for the device to run in - one-shot or continuous", "continuous",
                          rw));
  g_object_class_install_property(
      gobject_class, PROP_BASE_DIRECTORY,
      g_param_spec_string("iio-base-dir", "IIO Base Dir", "Base directory for IIO devices",
                          "/sys/bus/iio/devices", rw));
  g_object_class_install_property(
      gobject_class, PROP_DEV_DIRECTORY,
      g_param_spec_string("dev-dir", "Dev Dir", "Directory for device files", "/dev", rw));
  g_object_class_install_property(
      gobject_class, PROP_DEVICE,
      g_param_spec_string("device", "Device Name", "Name of the device to be opened", nullptr, rw));
  g_object_class_install_property(
      gobject_class, PROP_DEVICE_NUM,
      g_param_spec_int("device-number", "Device Number",
                       "Number (numeric id) of the device to be opened", -1, G_MAXINT, -1, rw));
  g_object_class_install_property(
      gobject_class, PROP_TRIGGER,
      g_param_spec_string("trigger", "Trigger Name", "Name of the trigger to be used", nullptr,
                          rw));
  g_object_class_install_property(
      gobject_class, PROP_TRIGGER_NUM,
      g_param_spec_int("trigger-number", "Trigger Number",
                       "Number (numeric id) of the trigger to be opened", -1, G_MAXINT, -1, rw));
  g_object_class_install_property(
      gobject_class, PROP_CHANNELS,
      g_param_spec_string("channels", "Channels to be enabled",
                          "Specify channels to be enabled: 1) auto: enable all channels when no "
                          "channels are enabled automatically, 2) all: enable all channels, "
                          "3) x,y,z: list the idx of the channels to be enabled",
                          "auto", rw));
  g_object_class_install_property(
      gobject_class, PROP_BUFFER_CAPACITY,
      g_param_spec_uint("buffer-capacity", "Buffer Capacity", "Capacity of the data buffer", 1,
                        G_MAXUINT, 1, rw));
  g_object_class_install_property(
      gobject_class, PROP_FREQUENCY,
      g_param_spec_ulong("frequency", "Frequency", "Operating frequency of the device", 0,
                         G_MAXULONG, 0, rw));
  g_object_class_install_property(
      gobject_class, PROP_MERGE_CHANNELS,
      g_param_spec_boolean("merge-channels-data", "Merge Channels Data",
                           "Merge the data of channels into single tensor", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_POLL_TIMEOUT,
      g_param_spec_int("poll-timeout", "Poll Timeout", "Timeout for polling in milliseconds", -1,
                       G_MAXINT, 10000, rw));
  gst_element_class_set_static_metadata(element_class, "TensorSrcIIO", "Source/Tensor/Device",
                                        "Src element to support linux IIO", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &src_template);
  element_class->change_state = src_iio_change_state;
  base_class->start = src_iio_start;
  base_class->stop = src_iio_stop;
  base_class->get_caps = src_iio_get_caps;
  base_class->unlock = src_iio_unlock;
  base_class->unlock_stop = src_iio_unlock_stop;
  base_class->create = src_iio_create;
}

static void gst_tensor_src_iio_init(GstTensorSrcIIO *self) {
  self->priv = new SrcIioPriv();
  self->priv->wake_fd = ::eventfd(0, EFD_NONBLOCK | EFD_CLOEXEC);
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
  gst_base_src_set_live(GST_BASE_SRC(self), TRUE);
  gst_base_src_set_do_timestamp(GST_BASE_SRC(self), TRUE);
}

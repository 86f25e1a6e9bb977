// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_debug
 *
 * Passes other/tensors through untouched and logs what a developer needs to see at that point:
 * the caps and tensor descriptions (`capability`: disabled, updates, updates-full - also when
 * the dimensions inside flexible/sparse headers change -, always), and per-buffer metadata
 * (`metadata` flags: timestamp, queryserver). `output-method` flags choose where lines go
 * (upstream's values): console-info (stdout), console-warn / console-error (stderr),
 * gstdebug-info / -warn / -error (GStreamer debug log, category tensor_debug); circularbuf and
 * filewrite are not implemented (as upstream) and are reported once as a warning.
 *
 *   gst-launch-1.0 videotestsrc num-buffers=3 ! tensor_converter !
 *     tensor_debug output-method=console-info capability=always metadata=timestamp !
 *     tensor_sink
 */
#include <gst/base/gstbasetransform.h>

#include <mutex>

#include "core/tensor_debug_format.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"

GST_DEBUG_CATEGORY_STATIC(tensor_debug_debug);
#define GST_CAT_DEFAULT tensor_debug_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_DEBUG (gst_tensor_debug_get_type())
G_DECLARE_FINAL_TYPE(GstTensorDebug, gst_tensor_debug, GST, TENSOR_DEBUG, GstBaseTransform)
G_END_DECLS

namespace {

using nns::tdbg::Capability;
using nns::tdbg::Level;

struct DebugPriv {
  std::mutex lock;  // settings
  bool silent = true;
  guint output = nns::tdbg::kConsoleInfo;
  Capability cap = Capability::kUpdatesFull;
  guint meta = nns::tdbg::kMetaDisabled;
  // streaming state
  nns::TensorsConfig config;
  std::string caps_text;
  std::vector<nns::MetaHeader> last_headers;
  bool warned_unsupported = false;
  // Flexible caps decorated with num_tensors / types / dimensions (set_caps): they pass through
  // as they are; the first buffer whose headers contradict them is reported once.
  nns::gst::CapsPtr decoration;
  bool warned_decoration = false;
};

enum { PROP_0, PROP_SILENT, PROP_OUTPUT, PROP_CAP, PROP_META };

GType output_flags_get_type() {
  static GType type = 0;
  // As upstream: value_name holds the description, the nick is what pipelines use.
  static const GFlagsValue values[] = {
      {nns::tdbg::kOutputDisabled, "Disable log output and write", "disabled"},
      {nns::tdbg::kConsoleInfo, "Console output with info", "console-info"},
      {nns::tdbg::kConsoleWarn, "Console output with warning", "console-warn"},
      {nns::tdbg::kConsoleError, "Console output with error", "console-error"},
      {nns::tdbg::kGstInfo, "GStreamer debug log with info", "gstdebug-info"},
      {nns::tdbg::kGstWarn, "GStreamer debug log with warning", "gstdebug-warn"},
      {nns::tdbg::kGstError, "GStreamer debug log with error", "gstdebug-error"},
      {nns::tdbg::kCircularBuf, "Circular buffer for the application (not implemented)",
       "circularbuf"},
      {nns::tdbg::kFileWrite, "Write to a file (not implemented)", "filewrite"},
      {0, nullptr, nullptr}};
  if (g_once_init_enter(&type)) {
    GType t = g_flags_register_static("gtd_output", values);
    g_once_init_leave(&type, t);
  }
  return type;
}

GType cap_get_type() {
  static GType type = 0;
  static const GEnumValue values[] = {
      {0, "disabled", "Do not log stream capability"},
      {1, "updates", "Log stream capability if it is updated or initialized."},
      {2, "updates-full",
       "Log stream capability if the capability or dimensions of flexible/sparse tensors are "
       "updated. Logs dimension info of flexible/sparse tensors as well."},
      {3, "always", "Always, log stream capability and tensor dimension information."},
      {0, nullptr, nullptr}};
  if (g_once_init_enter(&type)) {
    GType t = g_enum_register_static("gtd_cap", values);
    g_once_init_leave(&type, t);
  }
  return type;
}

GType meta_flags_get_type() {
  static GType type = 0;
  static const GFlagsValue values[] = {
      {nns::tdbg::kMetaDisabled, "Do not log stream metadata", "disabled"},
      {nns::tdbg::kMetaTimestamp, "Log timestamps", "timestamp"},
      {nns::tdbg::kMetaQueryServer, "Log tensor-query-server information", "queryserver"},
      {0, nullptr, nullptr}};
  if (g_once_init_enter(&type)) {
    GType t = g_flags_register_static("gtd_meta", values);
    g_once_init_leave(&type, t);
  }
  return type;
}

struct Snapshot {
  nns::tdbg::Outputs out;
  Capability cap;
  guint meta;
};

}  // namespace

struct _GstTensorDebug {
  GstBaseTransform parent;
  DebugPriv *priv;
};

G_DEFINE_TYPE(GstTensorDebug, gst_tensor_debug, GST_TYPE_BASE_TRANSFORM)
GST_ELEMENT_REGISTER_DEFINE(tensor_debug, "tensor_debug", GST_RANK_NONE, GST_TYPE_TENSOR_DEBUG)

#define DBG_CAPS                                                                                \
  "other/tensors, format = (string) { static, flexible, sparse }, framerate = (fraction) [ 0, " \
  "max ]"

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink", GST_PAD_SINK, GST_PAD_ALWAYS, GST_STATIC_CAPS(DBG_CAPS));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(DBG_CAPS));

static Snapshot snapshot(DebugPriv *p) {
  std::lock_guard<std::mutex> l(p->lock);
  return {nns::tdbg::decode_outputs(p->output), p->cap, p->meta};
}

// Sends one line to every enabled output.
static void emit(GstTensorDebug *self, const nns::tdbg::Outputs &o, const std::string &text) {
  const gchar *name = GST_OBJECT_NAME(self);
  switch (o.console) {
    case Level::kInfo:
      g_print("[%s] %s\n", name, text.c_str());
      break;
    case Level::kWarn:
      g_printerr("[%s] WARNING: %s\n", name, text.c_str());
      break;
    case Level::kError:
      g_printerr("[%s] ERROR: %s\n", name, text.c_str());
      break;
    case Level::kNone:
      break;
  }
  switch (o.gst) {
    case Level::kInfo:
      GST_INFO_OBJECT(self, "%s", text.c_str());
      break;
    case Level::kWarn:
      GST_WARNING_OBJECT(self, "%s", text.c_str());
      break;
    case Level::kError:
      GST_ERROR_OBJECT(self, "%s", text.c_str());
      break;
    case Level::kNone:
      break;
  }
}

static gboolean tensor_debug_set_caps(GstBaseTransform *trans, GstCaps *in, GstCaps *) {
  auto *self = GST_TENSOR_DEBUG(trans);
  return nns::gst::guard(self, FALSE, [&]() -> gboolean {
    auto *p = self->priv;
    p->config = nns::gst::config_from_caps(in);
    p->caps_text = nns::gst::caps_to_string(in);
    p->last_headers.clear();
    p->decoration.reset(nns::gst::is_decorated_flexible(in) ? gst_caps_ref(in) : nullptr);
    p->warned_decoration = false;
    Snapshot s = snapshot(p);
    if (s.out.unsupported && !p->warned_unsupported) {
      p->warned_unsupported = true;
      NNS_POST_WARNING(self, "output-method circularbuf/filewrite is not implemented; ignored");
    }
    if (s.cap != Capability::kDisabled)
      emit(self, s.out,
           "caps: " + p->caps_text + " | " + nns::tdbg::describe_tensors(p->config.info));
    return TRUE;
  });
}

static std::vector<nns::MetaHeader> read_headers(GstBuffer *buf) {
  std::vector<nns::MetaHeader> hs;
  for (guint i = 0; i < gst_buffer_n_memory(buf); ++i)
    hs.push_back(nns::gst::memory_header(gst_buffer_peek_memory(buf, i)));
  return hs;
}

// Decorated flexible caps against the headers of `buf`: a WARNING (once per caps) naming the
// field, what the caps say and what the headers say. The stream goes on, as in NNStreamer,
// which does not look at these fields.
static void check_decoration(GstTensorDebug *self, DebugPriv *p, GstBuffer *buf) {
  nns::TensorsInfo got;
  got.format = nns::TensorFormat::kFlexible;
  for (const nns::MetaHeader &h : read_headers(buf)) got.tensors.push_back(h.info());
  try {
    nns::gst::check_flexible_caps_fields(p->decoration.get(), got,
                                         "the buffer's flexible headers say");
  } catch (const nns::Error &e) {
    p->warned_decoration = true;
    NNS_POST_WARNING(self, std::string("the stream contradicts its caps: ") + e.what());
  }
}

static GstFlowReturn tensor_debug_transform_ip(GstBaseTransform *trans, GstBuffer *buf) {
  auto *self = GST_TENSOR_DEBUG(trans);
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    auto *p = self->priv;
    if (p->decoration && !p->warned_decoration) check_decoration(self, p, buf);
    Snapshot s = snapshot(p);
    if (s.out.console == Level::kNone && s.out.gst == Level::kNone) return GST_FLOW_OK;
    bool flexible = p->config.info.format != nns::TensorFormat::kStatic;
    if (s.cap == Capability::kAlways) {
      std::string t = "caps: " + p->caps_text;
      t += " | " + (flexible ? nns::tdbg::describe_headers(read_headers(buf))
                             : nns::tdbg::describe_tensors(p->config.info));
      emit(self, s.out, t);
    } else if (s.cap == Capability::kUpdatesFull && flexible) {
      auto hs = read_headers(buf);
      if (!nns::tdbg::same_headers(hs, p->last_headers)) {
        emit(self, s.out, "tensors: " + nns::tdbg::describe_headers(hs));
        p->last_headers = std::move(hs);
      }
    }
    if (s.meta & nns::tdbg::kMetaTimestamp) {
      auto t = [](GstClockTime v) { return GST_CLOCK_TIME_IS_VALID(v) ? v : nns::tdbg::kNoTime; };
      guint64 off = GST_BUFFER_OFFSET(buf);
      emit(self, s.out,
           "meta: " + nns::tdbg::describe_timestamps(
                          t(GST_BUFFER_PTS(buf)), t(GST_BUFFER_DTS(buf)),
                          t(GST_BUFFER_DURATION(buf)),
                          off == GST_BUFFER_OFFSET_NONE ? nns::tdbg::kNoTime : off));
    }
    if (s.meta & nns::tdbg::kMetaQueryServer)
      emit(self, s.out, "meta: queryserver: no tensor_query metadata on this buffer");
    return GST_FLOW_OK;
  });
}

static gboolean tensor_debug_start(GstBaseTransform *trans) {
  auto *p = GST_TENSOR_DEBUG(trans)->priv;
  p->last_headers.clear();
  p->warned_unsupported = false;
  return TRUE;
}

static void gst_tensor_debug_set_property(GObject *object, guint id, const GValue *value,
                                          GParamSpec *pspec) {
  auto *p = GST_TENSOR_DEBUG(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  switch (id) {
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    case PROP_OUTPUT:
      p->output = g_value_get_flags(value);
      break;
    case PROP_CAP:
      p->cap = static_cast<Capability>(g_value_get_enum(value));
      break;
    case PROP_META:
      p->meta = g_value_get_flags(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_debug_get_property(GObject *object, guint id, GValue *value,
                                          GParamSpec *pspec) {
  auto *p = GST_TENSOR_DEBUG(object)->priv;
  std::lock_guard<std::mutex> l(p->lock);
  switch (id) {
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    case PROP_OUTPUT:
      g_value_set_flags(value, p->output);
      break;
    case PROP_CAP:
      g_value_set_enum(value, static_cast<int>(p->cap));
      break;
    case PROP_META:
      g_value_set_flags(value, p->meta);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_debug_finalize(GObject *object) {
  delete GST_TENSOR_DEBUG(object)->priv;
  G_OBJECT_CLASS(gst_tensor_debug_parent_class)->finalize(object);
}

static void gst_tensor_debug_class_init(GstTensorDebugClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_debug_debug, "tensor_debug", 0, "tensor_debug element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *trans_class = GST_BASE_TRANSFORM_CLASS(klass);
  gobject_class->set_property = gst_tensor_debug_set_property;
  gobject_class->get_property = gst_tensor_debug_get_property;
  gobject_class->finalize = gst_tensor_debug_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "silent", "Produce verbose output", TRUE, rw));
  g_object_class_install_property(
      gobject_class, PROP_OUTPUT,
      g_param_spec_flags("output-method", "output",
                         "Where debug lines go; several methods can be combined",
                         output_flags_get_type(), nns::tdbg::kConsoleInfo, rw));
  g_object_class_install_property(
      gobject_class, PROP_CAP,
      g_param_spec_enum("capability", "cap", "When to log the stream capability (GstCaps)",
                        cap_get_type(), 2, rw));
  g_object_class_install_property(
      gobject_class, PROP_META,
      g_param_spec_flags("metadata", "meta", "Which buffer metadata to log", meta_flags_get_type(),
                         nns::tdbg::kMetaDisabled, rw));
  gst_element_class_set_static_metadata(
      element_class, "TensorDebug", "Filter/Tensor",
      "Logs caps, tensor descriptions and timestamps of a tensor stream", "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &sink_template);
  gst_element_class_add_static_pad_template(element_class, &src_template);
  trans_class->passthrough_on_same_caps = TRUE;
  trans_class->transform_ip_on_passthrough = TRUE;
  trans_class->transform_ip = tensor_debug_transform_ip;
  trans_class->set_caps = tensor_debug_set_caps;
  trans_class->start = tensor_debug_start;
}

static void gst_tensor_debug_init(GstTensorDebug *self) {
  self->priv = new DebugPriv();
}

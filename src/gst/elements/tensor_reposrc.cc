// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_reposrc
 *
 * Outputs the buffers tensor_reposink hands to slot `slot-index` of the process-wide tensor
 * repository (src/gst/tensor_repo.h). `caps` is required: it fixes the output caps, and the
 * first buffer is a zero-filled frame of those caps so a cycle (RNN/LSTM state) can start.
 * When the sink stores caps that disagree with `caps`, an error names both. The source ends
 * when the slot gets EOS; flushing and state changes wake it, so shutdown never hangs.
 *
 *   gst-launch-1.0 tensor_reposrc slot-index=0 num-buffers=5 caps="other/tensors,
 *     format=static,num_tensors=1,dimensions=(string)4,types=(string)float32,
 *     framerate=(fraction)0/1" ! tensor_sink
 *
 * slot-index reads as 4294967295 until set (upstream's "unset" value); an unset index uses
 * slot 0, the tensor_reposink default.
 */
#include <gst/base/gstpushsrc.h>

#include <atomic>
#include <cstring>
#include <mutex>

#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_repo.h"

GST_DEBUG_CATEGORY_STATIC(tensor_reposrc_debug);
#define GST_CAT_DEFAULT tensor_reposrc_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_REPOSRC (gst_tensor_reposrc_get_type())
G_DECLARE_FINAL_TYPE(GstTensorRepoSrc, gst_tensor_reposrc, GST, TENSOR_REPOSRC, GstPushSrc)
G_END_DECLS

namespace {

struct RepoSrcPriv {
  std::mutex lock;                // guards caps
  GstCaps *caps = nullptr;        // the `caps` property
  nns::gst::RepoSlot slot{true};  // unset reads as slot 0
  std::atomic<bool> silent{true};
  // streaming thread
  bool started = false;  // the zero frame was sent
  nns::TensorsConfig config;
  GstCaps *checked = nullptr;  // last sink caps found compatible
};

enum { PROP_0, PROP_CAPS, PROP_SLOT, PROP_SILENT };

}  // namespace

struct _GstTensorRepoSrc {
  GstPushSrc parent;
  RepoSrcPriv *priv;
};

G_DEFINE_TYPE(GstTensorRepoSrc, gst_tensor_reposrc, GST_TYPE_PUSH_SRC)
GST_ELEMENT_REGISTER_DEFINE(tensor_reposrc, "tensor_reposrc", GST_RANK_NONE,
                            GST_TYPE_TENSOR_REPOSRC)

static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(NNS_REPO_CAPS));

static void gst_tensor_reposrc_set_property(GObject *object, guint id, const GValue *value,
                                            GParamSpec *pspec) {
  auto *p = GST_TENSOR_REPOSRC(object)->priv;
  switch (id) {
    case PROP_CAPS: {
      const GstCaps *c = gst_value_get_caps(value);
      std::lock_guard<std::mutex> l(p->lock);
      GstCaps *copy = c ? gst_caps_copy(c) : nullptr;
      gst_caps_replace(&p->caps, copy);
      if (copy) gst_caps_unref(copy);
      break;
    }
    case PROP_SLOT:
      p->slot.set_property(g_value_get_uint(value));
      break;
    case PROP_SILENT:
      p->silent = g_value_get_boolean(value);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_reposrc_get_property(GObject *object, guint id, GValue *value,
                                            GParamSpec *pspec) {
  auto *p = GST_TENSOR_REPOSRC(object)->priv;
  switch (id) {
    case PROP_CAPS: {
      std::lock_guard<std::mutex> l(p->lock);
      gst_value_set_caps(value, p->caps);
      break;
    }
    case PROP_SLOT:
      g_value_set_uint(value, p->slot.property());
      break;
    case PROP_SILENT:
      g_value_set_boolean(value, p->silent);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static GstCaps *reposrc_get_caps(GstBaseSrc *src, GstCaps *filter) {
  auto *p = GST_TENSOR_REPOSRC(src)->priv;
  nns::gst::CapsPtr tmpl(gst_pad_get_pad_template_caps(GST_BASE_SRC_PAD(src)));
  nns::gst::CapsPtr mine;
  {
    std::lock_guard<std::mutex> l(p->lock);
    mine.reset(p->caps ? gst_caps_intersect_full(p->caps, tmpl.get(), GST_CAPS_INTERSECT_FIRST)
                       : gst_caps_ref(tmpl.get()));
  }
  if (filter) return gst_caps_intersect_full(filter, mine.get(), GST_CAPS_INTERSECT_FIRST);
  return mine.release();
}

static gboolean reposrc_start(GstBaseSrc *src) {
  return nns::gst::guard(src, FALSE, [&]() -> gboolean {
    auto *p = GST_TENSOR_REPOSRC(src)->priv;
    std::lock_guard<std::mutex> l(p->lock);
    if (!p->caps || gst_caps_is_empty(p->caps) || gst_caps_is_any(p->caps))
      nns::fail(nns::ErrorKind::kSettings,
                "the caps property is required (e.g. caps=\"other/tensors,format=static,"
                "num_tensors=1,dimensions=(string)4,types=(string)float32,"
                "framerate=(fraction)0/1\")");
    auto cfg = nns::gst::config_from_caps(p->caps);
    if (!cfg.info.valid() || cfg.info.format != nns::TensorFormat::kStatic)
      nns::fail(nns::ErrorKind::kSettings,
                "caps property " + nns::gst::caps_to_string(p->caps) +
                    " must give format=static with the dimensions and types of every tensor");
    p->config = cfg;
    p->started = false;
    p->slot.unlock_stop();
    gst_caps_replace(&p->checked, nullptr);
    return TRUE;
  });
}

static gboolean reposrc_stop(GstBaseSrc *src) {
  auto *p = GST_TENSOR_REPOSRC(src)->priv;
  gst_caps_replace(&p->checked, nullptr);
  // Nobody reads the slot any more: drop what the writer left (the next run starts clean).
  nns::gst::TensorRepo::instance().reset(p->slot.slot());
  return TRUE;
}

static gboolean reposrc_unlock(GstBaseSrc *src) {
  GST_TENSOR_REPOSRC(src)->priv->slot.unlock();
  return TRUE;
}

static gboolean reposrc_unlock_stop(GstBaseSrc *src) {
  GST_TENSOR_REPOSRC(src)->priv->slot.unlock_stop();
  return TRUE;
}

// Zero-filled frame of the configured tensors.
static GstBuffer *zero_frame(const nns::TensorsConfig &cfg) {
  GstBuffer *buf = gst_buffer_new();
  for (const auto &t : cfg.info.tensors) {
    GstMemory *m = gst_allocator_alloc(nullptr, t.byte_size(), nullptr);
    nns::gst::MemoryMap w(m, GST_MAP_WRITE);
    std::memset(w.data(), 0, w.size());
    gst_buffer_append_memory(buf, m);
  }
  return buf;
}

static std::string describe(const nns::TensorsInfo &info) {
  std::string s;
  for (std::size_t i = 0; i < info.size(); ++i) s += (i ? ", " : "") + info[i].to_string();
  return s;
}

// Throws when the sink's caps cannot be this source's caps.
static void check_caps(GstTensorRepoSrc *self, guint slot, GstCaps *sink_caps) {
  auto *p = self->priv;
  if (!sink_caps || sink_caps == p->checked) return;
  auto got = nns::gst::config_from_caps(sink_caps);
  if (!got.info.same_as(p->config.info)) {
    nns::gst::CapsPtr mine;
    {
      std::lock_guard<std::mutex> l(p->lock);
      mine.reset(gst_caps_ref(p->caps));
    }
    nns::fail(nns::ErrorKind::kNegotiation,
              "slot " + std::to_string(slot) + ": caps property " +
                  nns::gst::caps_to_string(mine.get()) + " (" + describe(p->config.info) +
                  ") disagrees with the caps tensor_reposink stored, " +
                  nns::gst::caps_to_string(sink_caps) + " (" + describe(got.info) + ")");
  }
  gst_caps_replace(&p->checked, sink_caps);
}

// Throws when the tensors of `buf` are not those of the caps property (count, sizes): they would
// go downstream under caps that do not describe them.
static void check_tensors(GstTensorRepoSrc *self, guint slot, GstBuffer *buf) {
  auto *p = self->priv;
  try {
    nns::gst::check_static_buffer(buf, p->config.info);
  } catch (const nns::Error &e) {
    nns::gst::CapsPtr mine;
    {
      std::lock_guard<std::mutex> l(p->lock);
      mine.reset(gst_caps_ref(p->caps));
    }
    nns::fail(nns::ErrorKind::kStream, "slot " + std::to_string(slot) +
                                           ": the tensors that arrived do not match the caps " +
                                           "property " + nns::gst::caps_to_string(mine.get()) +
                                           " (" + describe(p->config.info) + "): " + e.what());
  }
}

static GstFlowReturn reposrc_create(GstPushSrc *src, GstBuffer **out) {
  auto *self = GST_TENSOR_REPOSRC(src);
  auto *p = self->priv;
  return nns::gst::guard(self, GST_FLOW_ERROR, [&]() -> GstFlowReturn {
    if (!p->started) {
      p->started = true;
      *out = zero_frame(p->config);
      return GST_FLOW_OK;
    }
    auto &repo = nns::gst::TensorRepo::instance();
    guint slot = 0;
    GstBuffer *buf = nullptr;
    GstCaps *caps = nullptr;
    // create runs under the pad's stream lock, which unlock_stop (GstBaseSrc) waits for.
    auto st = p->slot.wait(
        p->slot.ticket(),
        [&](uint32_t s, const std::function<bool()> &cancelled) {
          return repo.pop(s, &buf, &caps, cancelled);
        },
        &slot);
    if (st == nns::gst::TensorRepo::Status::kEos) return GST_FLOW_EOS;
    if (st == nns::gst::TensorRepo::Status::kCancelled) return GST_FLOW_FLUSHING;
    nns::gst::BufferPtr b(buf);
    nns::gst::CapsPtr c(caps);
    try {
      check_caps(self, slot, caps);
      check_tensors(self, slot, buf);
    } catch (...) {
      repo.set_eos(slot);  // the writer must not wait for a reader that stopped
      throw;
    }
    if (!p->silent)
      GST_INFO_OBJECT(self, "slot %u -> buffer pts %" GST_TIME_FORMAT, slot,
                      GST_TIME_ARGS(GST_BUFFER_PTS(buf)));
    *out = b.release();
    return GST_FLOW_OK;
  });
}

static void gst_tensor_reposrc_finalize(GObject *object) {
  auto *p = GST_TENSOR_REPOSRC(object)->priv;
  gst_caps_replace(&p->caps, nullptr);
  gst_caps_replace(&p->checked, nullptr);
  delete p;
  G_OBJECT_CLASS(gst_tensor_reposrc_parent_class)->finalize(object);
}

static void gst_tensor_reposrc_class_init(GstTensorRepoSrcClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_reposrc_debug, "tensor_reposrc", 0, "tensor_reposrc");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  auto *base_class = GST_BASE_SRC_CLASS(klass);
  auto *push_class = GST_PUSH_SRC_CLASS(klass);
  gobject_class->set_property = gst_tensor_reposrc_set_property;
  gobject_class->get_property = gst_tensor_reposrc_get_property;
  gobject_class->finalize = gst_tensor_reposrc_finalize;
  auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      gobject_class, PROP_CAPS,
      g_param_spec_boxed("caps", "Caps", "Caps of the frames in the slot (required)", GST_TYPE_CAPS,
                         rw));
  g_object_class_install_property(
      gobject_class, PROP_SLOT,
      g_param_spec_uint("slot-index", "Slot Index", "Repository slot to read", 0, G_MAXUINT - 1, 0,
                        rw));
  g_object_class_install_property(
      gobject_class, PROP_SILENT,
      g_param_spec_boolean("silent", "Silent", "Do not log each hand-off", TRUE, rw));
  gst_element_class_set_static_metadata(element_class, "TensorRepoSrc", "Source/Tensor/Repository",
                                        "Reads tensor frames from a repository slot",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template(element_class, &src_template);
  base_class->get_caps = reposrc_get_caps;
  base_class->start = reposrc_start;
  base_class->stop = reposrc_stop;
  base_class->unlock = reposrc_unlock;
  base_class->unlock_stop = reposrc_unlock_stop;
  push_class->create = reposrc_create;
}

static void gst_tensor_reposrc_init(GstTensorRepoSrc *self) {
  self->priv = new RepoSrcPriv();
  gst_base_src_set_format(GST_BASE_SRC(self), GST_FORMAT_TIME);
}

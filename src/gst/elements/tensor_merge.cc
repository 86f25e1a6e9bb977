// SPDX-License-Identifier: LGPL-2.1-only
/**
 * SECTION:element-tensor_merge
 *
 * Merges single-tensor streams into one tensor by concatenating them along one dimension
 * (`mode=linear`, `option=<dimension index>`, innermost first): `option=1` merges two
 * 3:640:480 tensors into 3:1280:480. The inputs need the same type and the same other
 * dimensions. Buffers are matched in time as in tensor_mux (`sync-mode`, default nosync).
 *
 *   gst-launch-1.0 videotestsrc num-buffers=10 ! video/x-raw,width=640,height=480 ! \
 *     tensor_converter ! m.sink_0 \
 *     videotestsrc num-buffers=10 ! video/x-raw,width=640,height=480 ! tensor_converter ! \
 *     m.sink_1 tensor_merge name=m mode=linear option=1 ! tensor_sink
 */
#include <charconv>
#include <mutex>

#include "core/error.h"
#include "core/tensor_concat.h"
#include "gst/element_glue.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_buffer.h"
#include "gst/tensor_caps.h"
#include "gst/tensor_sync.h"

GST_DEBUG_CATEGORY_STATIC(tensor_merge_debug);
#define GST_CAT_DEFAULT tensor_merge_debug

G_BEGIN_DECLS
#define GST_TYPE_TENSOR_MERGE (gst_tensor_merge_get_type())
G_DECLARE_FINAL_TYPE(GstTensorMerge, gst_tensor_merge, GST, TENSOR_MERGE, GstTensorSync)
G_END_DECLS

namespace {

struct MergePriv {
  // Settings
  std::mutex lock;
  std::string mode = "linear";
  std::string option;
  bool option_set = false;
  // State (streaming thread)
  std::size_t dim = 0;
  std::vector<nns::TensorInfo> in;
  nns::ConcatPlan plan;
};

enum { PROP_0, PROP_SILENT, PROP_SYNC_MODE, PROP_SYNC_OPTION, PROP_MODE, PROP_OPTION };

}  // namespace

struct _GstTensorMerge {
  GstTensorSync parent;
  MergePriv *priv;
};

G_DEFINE_TYPE(GstTensorMerge, gst_tensor_merge, GST_TYPE_TENSOR_SYNC)
GST_ELEMENT_REGISTER_DEFINE(tensor_merge, "tensor_merge", GST_RANK_NONE, GST_TYPE_TENSOR_MERGE)

#define MERGE_CAPS                                                   \
  "other/tensor, framerate = (fraction) [ 0, max ]; "                \
  "other/tensors, format = (string) static, num_tensors = (int) 1, " \
  "framerate = (fraction) [ 0, max ]"

static GstStaticPadTemplate sink_template =
    GST_STATIC_PAD_TEMPLATE("sink_%u", GST_PAD_SINK, GST_PAD_REQUEST, GST_STATIC_CAPS(MERGE_CAPS));
static GstStaticPadTemplate src_template =
    GST_STATIC_PAD_TEMPLATE("src", GST_PAD_SRC, GST_PAD_ALWAYS, GST_STATIC_CAPS(MERGE_CAPS));

namespace {

// mode must be linear; option is the dimension index (unset: 0, as upstream).
void merge_check_settings(GstTensorSync *base) {
  MergePriv *p = GST_TENSOR_MERGE(base)->priv;
  std::lock_guard<std::mutex> g(p->lock);
  if (g_ascii_strcasecmp(p->mode.c_str(), "linear") != 0)
    nns::fail(nns::ErrorKind::kSettings,
              "mode='" + p->mode + "' is not supported (the only mode is linear)");
  std::string opt = nns::trim(p->option);
  p->dim = 0;
  if (opt.empty()) return;
  unsigned v = 0;
  auto [end, ec] = std::from_chars(opt.data(), opt.data() + opt.size(), v);
  if (ec != std::errc() || end != opt.data() + opt.size() || v >= nns::kRankLimit)
    nns::fail(nns::ErrorKind::kSettings, "option='" + opt + "' must be a dimension index 0.." +
                                             std::to_string(nns::kRankLimit - 1) +
                                             " for mode=linear");
  p->dim = v;
}

nns::TensorsConfig merge_configure(GstTensorSync *base, const std::vector<nns::TensorsConfig> &in,
                                   const std::vector<std::string> &names) {
  MergePriv *p = GST_TENSOR_MERGE(base)->priv;
  std::vector<nns::TensorInfo> infos;
  for (std::size_t i = 0; i < in.size(); ++i) {
    if (in[i].info.format != nns::TensorFormat::kStatic || in[i].info.size() != 1)
      nns::fail(nns::ErrorKind::kNegotiation, names[i] + " carries " + in[i].info.to_string() +
                                                  "; tensor_merge needs one "
                                                  "static tensor per pad");
    infos.push_back(in[i].info[0]);
  }
  nns::TensorsConfig out;
  try {
    out.info.tensors.push_back(nns::concat_info(infos, p->dim, names));
  } catch (const nns::Error &e) {
    nns::fail(e.kind(), "option=" + std::to_string(p->dim) + ": " + e.what());
  }
  nns::gst::sync_slowest_rate(in, &out.rate_n, &out.rate_d);
  p->in = infos;
  p->plan = nns::plan_concat(infos, p->dim);
  return out;
}

GstBuffer *merge_combine(GstTensorSync *base, GstBuffer *const *in, std::size_t n) {
  MergePriv *p = GST_TENSOR_MERGE(base)->priv;
  GstMemory *out = gst_allocator_alloc(nullptr, p->plan.total, nullptr);
  nns::gst::MemoryPtr out_guard(out);
  // Maps every input; unmapped on every exit path.
  struct Maps {
    GstBuffer *const *bufs = nullptr;
    GstMapInfo info[nns::kTensorLimit];
    std::size_t count = 0;
    ~Maps() {
      for (std::size_t i = 0; i < count; ++i) gst_buffer_unmap(bufs[i], &info[i]);
    }
  } maps;
  maps.bufs = in;
  const uint8_t *src[nns::kTensorLimit];
  for (std::size_t i = 0; i < n; ++i) {
    if (!gst_buffer_map(in[i], &maps.info[i], GST_MAP_READ))
      nns::fail(nns::ErrorKind::kStream, nns::gst::sync_pad_name(base, i) + ": cannot map buffer");
    maps.count = i + 1;
    std::size_t want = p->plan.block[i] * p->plan.outer;
    if (maps.info[i].size != want)
      nns::fail(nns::ErrorKind::kStream, nns::gst::sync_pad_name(base, i) + ": buffer has " +
                                             std::to_string(maps.info[i].size) +
                                             " bytes, expected " + std::to_string(want) + " for " +
                                             p->in[i].to_string());
    src[i] = maps.info[i].data;
  }
  {
    nns::gst::MemoryMap dst(out, GST_MAP_WRITE);
    if (!dst.ok()) nns::fail(nns::ErrorKind::kStream, "cannot map the output memory");
    nns::run_concat(p->plan, src, dst.data());
  }
  GstBuffer *buf = gst_buffer_new();
  gst_buffer_append_memory(buf, out_guard.release());
  return buf;
}

}  // namespace

static void gst_tensor_merge_set_property(GObject *object, guint id, const GValue *value,
                                          GParamSpec *pspec) {
  auto *self = GST_TENSOR_MERGE(object);
  if (nns::gst::sync_set_property(GST_TENSOR_SYNC(object), PROP_SILENT, id, value)) return;
  std::lock_guard<std::mutex> g(self->priv->lock);
  const char *s = g_value_get_string(value);
  switch (id) {
    case PROP_MODE:
      self->priv->mode = s ? s : "linear";
      break;
    case PROP_OPTION:
      self->priv->option = s ? s : "";
      self->priv->option_set = s != nullptr;
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_merge_get_property(GObject *object, guint id, GValue *value,
                                          GParamSpec *pspec) {
  auto *self = GST_TENSOR_MERGE(object);
  if (nns::gst::sync_get_property(GST_TENSOR_SYNC(object), PROP_SILENT, id, value)) return;
  std::lock_guard<std::mutex> g(self->priv->lock);
  switch (id) {
    case PROP_MODE:
      g_value_set_string(value, self->priv->mode.c_str());
      break;
    case PROP_OPTION:
      g_value_set_string(value, self->priv->option_set ? self->priv->option.c_str() : nullptr);
      break;
    default:
      G_OBJECT_WARN_INVALID_PROPERTY_ID(object, id, pspec);
  }
}

static void gst_tensor_merge_finalize(GObject *object) {
  delete GST_TENSOR_MERGE(object)->priv;
  G_OBJECT_CLASS(gst_tensor_merge_parent_class)->finalize(object);
}

static void gst_tensor_merge_class_init(GstTensorMergeClass *klass) {
  GST_DEBUG_CATEGORY_INIT(tensor_merge_debug, "tensor_merge", 0, "tensor_merge element");
  auto *gobject_class = G_OBJECT_CLASS(klass);
  auto *element_class = GST_ELEMENT_CLASS(klass);
  gobject_class->set_property = gst_tensor_merge_set_property;
  gobject_class->get_property = gst_tensor_merge_get_property;
  gobject_class->finalize = gst_tensor_merge_finalize;
  nns::gst::sync_install_properties(gobject_class, PROP_SILENT, "nosync");
  auto flags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                        GST_PARAM_MUTABLE_READY);
  g_object_class_install_property(
      gobject_class, PROP_MODE,
      g_param_spec_string("mode", "Mode", "How tensors are merged; only linear exists", "linear",
                          flags));
  g_object_class_install_property(
      gobject_class, PROP_OPTION,
      g_param_spec_string("option", "Option",
                          "linear: index of the dimension to concatenate along (innermost "
                          "first; option=1 merges 3:640:480 twice into 3:1280:480)",
                          "", flags));

  auto *sync_class = GST_TENSOR_SYNC_CLASS(klass);
  sync_class->configure = merge_configure;
  sync_class->combine = merge_combine;
  sync_class->check_settings = merge_check_settings;

  gst_element_class_set_static_metadata(element_class, "TensorMerge", "Muxer/Tensor",
                                        "Concatenates tensor streams along one dimension",
                                        "nnstreamer-cpp");
  gst_element_class_add_static_pad_template_with_gtype(element_class, &sink_template,
                                                       GST_TYPE_TENSOR_SYNC_PAD);
  gst_element_class_add_static_pad_template(element_class, &src_template);
}

static void gst_tensor_merge_init(GstTensorMerge *self) {
  self->priv = new MergePriv();
}

// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/query_batch.h"

#include "core/error.h"
#include "gst/gst_ptr.h"
#include "gst/tensor_caps.h"

namespace nns::gst {

namespace {

const char *kBatchMeta = "GstQueryBatchMeta";

const GstMetaInfo *batch_meta_info() {
  static const GstMetaInfo *info = nullptr;
  if (g_once_init_enter(&info)) {
    static const gchar *tags[] = {nullptr};
    const GstMetaInfo *i = gst_meta_get_info(kBatchMeta);
    if (!i) i = gst_meta_register_custom(kBatchMeta, tags, nullptr, nullptr, nullptr);
    g_once_init_leave(&info, i);
  }
  return info;
}

// The config of one fixed tensor structure, or nullopt.
std::optional<TensorsConfig> structure_config(GstCaps *caps, guint i) {
  CapsPtr one(gst_caps_fixate(gst_caps_copy_nth(caps, i)));
  if (!is_tensor_caps(one.get())) return std::nullopt;
  try {
    TensorsConfig c = config_from_caps(one.get());
    if (c.info.format != TensorFormat::kStatic || !c.info.valid()) return std::nullopt;
    return c;
  } catch (const Error &) {
    return std::nullopt;
  }
}

}  // namespace

GstCaps *unbatch_caps(GstCaps *caps, guint n) {
  if (!caps || gst_caps_is_any(caps)) return caps ? gst_caps_ref(caps) : gst_caps_new_any();
  GstCaps *out = gst_caps_new_empty();
  for (guint i = 0; i < gst_caps_get_size(caps); ++i) {
    auto c = structure_config(caps, i);
    if (!c || tensor_without_batch(c->info, n)) continue;
    for (auto &t : c->info.tensors) t.dims[t.rank() - 1] = 1;
    // One other/tensors structure per config, no list of spellings nor other/tensor twin: fixed
    // caps stay fixed, as NNStreamer's client requires of the answer caps (else "out-caps from
    // tensor_query_serversink is not fixed" and no answers). Field order as upstream's.
    out = gst_caps_merge_structure(out, structure_from_config(*c));
  }
  return out;
}

std::optional<std::string> batch_caps_problem(GstCaps *caps, guint n) {
  const std::string got = caps_to_string(caps);
  if (!is_tensor_caps(caps) || !gst_caps_is_fixed(caps))
    return "batches need fixed tensor caps (other/tensors,format=static), got '" + got + "'";
  TensorsConfig c;
  try {
    c = config_from_caps(caps);
  } catch (const Error &e) {
    return std::string(e.what());
  }
  if (c.info.format != TensorFormat::kStatic)
    return "batches need static tensors (N fixed in the caps, unused slots are padding), got '" +
           got + "'";
  if (c.info.size() > 16)
    return "batches take at most 16 tensors, got " + std::to_string(c.info.size());
  if (const auto i = tensor_without_batch(c.info, n)) {
    const auto &t = c.info[*i];
    const std::size_t r = t.rank();
    return "tensor " + std::to_string(*i) + (t.name.empty() ? "" : " ('" + t.name + "')") + " is " +
           t.to_string() + ": its outermost dimension must be " + std::to_string(n) +
           " (the batch), got " + (r ? std::to_string(t.dims[r - 1]) : std::string("none"));
  }
  return std::nullopt;
}

std::optional<std::size_t> tensor_without_batch(const TensorsInfo &info, guint n) {
  for (std::size_t i = 0; i < info.size(); ++i) {
    const std::size_t r = info[i].rank();
    if (r == 0 || info[i].dims[r - 1] != n) return i;
  }
  return std::nullopt;
}

std::vector<std::size_t> slot_sizes(const TensorsInfo &info, guint n) {
  std::vector<std::size_t> out;
  for (const auto &t : info.tensors) out.push_back(t.byte_size() / n);
  return out;
}

void buffer_add_batch_meta(GstBuffer *buf, guint slots, const std::vector<int64_t> &clients) {
  batch_meta_info();
  GstCustomMeta *m = gst_buffer_add_custom_meta(buf, kBatchMeta);
  if (!m) fail(ErrorKind::kInternal, "cannot add the batch meta");
  std::string ids;
  for (auto id : clients) ids += (ids.empty() ? "" : ",") + std::to_string(id);
  gst_structure_set(gst_custom_meta_get_structure(m), "slots", G_TYPE_UINT, slots, "clients",
                    G_TYPE_STRING, ids.c_str(), nullptr);
}

std::vector<int64_t> buffer_get_batch_meta(GstBuffer *buf, guint *slots) {
  std::vector<int64_t> out;
  if (!batch_meta_info()) return out;
  GstCustomMeta *m = gst_buffer_get_custom_meta(buf, kBatchMeta);
  if (!m) return out;
  GstStructure *s = gst_custom_meta_get_structure(m);
  guint n = 0;
  gst_structure_get_uint(s, "slots", &n);
  if (slots) *slots = n;
  const char *ids = gst_structure_get_string(s, "clients");
  for (const char *p = ids; p && *p;) {
    char *end = nullptr;
    out.push_back(g_ascii_strtoll(p, &end, 10));
    p = (end && *end == ',') ? end + 1 : nullptr;
  }
  return out;
}

namespace {

// The only pad of `e` in direction `dir` (a new reference); nullptr when it has none or several.
GstPad *only_pad(GstElement *e, GstPadDirection dir) {
  GstPad *pad = nullptr;
  GST_OBJECT_LOCK(e);
  GList *pads = dir == GST_PAD_SINK ? e->sinkpads : e->srcpads;
  if (pads && !pads->next) pad = GST_PAD(gst_object_ref(pads->data));
  GST_OBJECT_UNLOCK(e);
  return pad;
}

}  // namespace

GstElement *find_along(GstPad *from, const char *property, std::string *first) {
  const GstPadDirection dir = GST_PAD_DIRECTION(from);
  GstPad *pad = GST_PAD(gst_object_ref(from));
  GstElement *found = nullptr;
  for (int hop = 0; hop < 8 && pad && !found; ++hop) {
    GstPad *peer = gst_pad_get_peer(pad);
    gst_object_unref(pad);
    pad = nullptr;
    if (!peer) break;
    GstElement *e = gst_pad_get_parent_element(peer);
    gst_object_unref(peer);
    if (!e) break;
    if (first && first->empty()) *first = GST_ELEMENT_NAME(e);
    if (g_object_class_find_property(G_OBJECT_GET_CLASS(e), property)) {
      found = e;
      break;
    }
    pad = only_pad(e, dir);
    gst_object_unref(e);
  }
  if (pad) gst_object_unref(pad);
  return found;
}

GstElement *find_upstream(GstElement *e, const char *property) {
  GstPad *sink = gst_element_get_static_pad(e, "sink");
  if (!sink) return nullptr;
  GstElement *found = find_along(sink, property, nullptr);
  gst_object_unref(sink);
  return found;
}

std::string element_label(GstElement *e) {
  GstElementFactory *f = gst_element_get_factory(e);
  return std::string(f ? GST_OBJECT_NAME(f) : "element") + " '" + GST_OBJECT_NAME(e) + "'";
}

std::optional<UpstreamBatch> upstream_batch(GstElement *e) {
  GstElement *up = find_upstream(e, "max-batch");
  if (!up) return std::nullopt;
  guint n = 1;
  GParamSpec *ps = g_object_class_find_property(G_OBJECT_GET_CLASS(up), "max-batch");
  if (ps->value_type == G_TYPE_UINT) g_object_get(up, "max-batch", &n, nullptr);
  UpstreamBatch b{element_label(up), n};
  gst_object_unref(up);
  if (n <= 1) return std::nullopt;
  return b;
}

}  // namespace nns::gst

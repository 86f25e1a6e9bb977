// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/converter_registry.h"

#include <cstdarg>

#include "core/nns_conf.h"

GST_DEBUG_CATEGORY_STATIC(nns_converter_registry_debug);
#define GST_CAT_DEFAULT nns_converter_registry_debug

namespace nns::gst {
namespace {

const char *converter_name(const void *t) {
  return static_cast<const NNStreamerExternalConverter *>(t)->name;
}

std::string check_converter(const void *t) {
  auto *ex = static_cast<const NNStreamerExternalConverter *>(t);
  if (!ex || !ex->name || !*ex->name) return "rejected: no name";
  if (!ex->convert || !ex->get_out_config || !ex->query_caps)
    return "'" + std::string(ex->name) +
           "' rejected: convert, get_out_config and query_caps are mandatory";
  // NNStreamer reserves these names (a converter can never be selected by them).
  if (g_ascii_strcasecmp(ex->name, "any") == 0 || g_ascii_strcasecmp(ex->name, "auto") == 0)
    return "'" + std::string(ex->name) + "' rejected: the name is reserved";
  return {};
}

}  // namespace

ConverterRegistry::ConverterRegistry()
    : reg_({SubpluginKind::kConverter, "converter", NNS_CONVERTER_SUBPLUGIN_ENTRY, converter_name,
            check_converter, reinterpret_cast<void *>(&registerExternalConverter),
            &nns_converter_registry_debug}) {}

ConverterRegistry &ConverterRegistry::instance() {
  static ConverterRegistry *r = [] {
    GST_DEBUG_CATEGORY_INIT(nns_converter_registry_debug, "nns_converter_registry", 0,
                            "tensor_converter sub-plugin registry");
    return new ConverterRegistry();
  }();
  return *r;
}

bool ConverterRegistry::add(const NNStreamerExternalConverter *ex) {
  if (!check_converter(ex).empty()) return reg_.add(ex);  // logs why and refuses
  // registerExternalConverter()'s caller may free or reuse its struct (NNStreamer's converters
  // often fill one on the stack): keep a copy, with our own copy of the name. Copies are never
  // freed (elements may still use them); the same registration again reuses its copy.
  const NNStreamerExternalConverter *kept = nullptr;
  {
    std::lock_guard<std::mutex> lock(copies_mutex_);
    for (const auto &c : copies_) {
      const NNStreamerExternalConverter &t = c->table;
      if (c->name == ex->name && t.convert == ex->convert &&
          t.get_out_config == ex->get_out_config && t.query_caps == ex->query_caps &&
          t.open == ex->open && t.close == ex->close)
        kept = &t;
    }
    if (!kept) {
      auto c = std::make_unique<OwnedConverter>();
      c->name = ex->name;
      c->table = *ex;
      c->table.name = c->name.c_str();
      copies_.push_back(std::move(c));
      kept = &copies_.back()->table;
    }
  }
  return reg_.add(kept);
}

bool ConverterRegistry::remove(std::string_view name) {
  return reg_.remove(name);
}

const NNStreamerExternalConverter *ConverterRegistry::find(std::string_view name) {
  return static_cast<const NNStreamerExternalConverter *>(reg_.find(name));
}

const NNStreamerExternalConverter *ConverterRegistry::find_for_media(std::string_view media_type) {
  std::lock_guard<std::recursive_mutex> lock(reg_.mutex());
  reg_.load_all_locked();
  for (const auto &e : reg_.tables_locked())
    if (e.first == media_type) return static_cast<const NNStreamerExternalConverter *>(e.second);
  const std::string media(media_type);
  for (const auto &e : reg_.tables_locked()) {
    auto *ex = static_cast<const NNStreamerExternalConverter *>(e.second);
    GstCaps *caps = ex->query_caps(nullptr);
    if (!caps) continue;
    bool match = false;
    for (guint i = 0; i < gst_caps_get_size(caps) && !match; ++i)
      match = gst_structure_has_name(gst_caps_get_structure(caps, i), media.c_str());
    gst_caps_unref(caps);
    if (match) return ex;
  }
  return nullptr;
}

std::vector<std::string> ConverterRegistry::names() {
  return reg_.names();
}

GstCaps *ConverterRegistry::all_caps() {
  std::lock_guard<std::recursive_mutex> lock(reg_.mutex());
  reg_.load_all_locked();
  if (!caps_cache_ || caps_generation_ != reg_.generation()) {
    GstCaps *all = gst_caps_new_empty();
    for (const auto &e : reg_.tables_locked()) {
      auto *ex = static_cast<const NNStreamerExternalConverter *>(e.second);
      if (GstCaps *c = ex->query_caps(nullptr)) all = gst_caps_merge(all, c);
    }
    if (caps_cache_) gst_caps_unref(caps_cache_);
    caps_cache_ = all;
    caps_generation_ = reg_.generation();
  }
  return gst_caps_ref(caps_cache_);
}

std::string ConverterRegistry::load_error(std::string_view name) {
  return reg_.load_error(name);
}

bool ConverterRegistry::set_property_descs(std::string_view name,
                                           SubpluginRegistry::PropertyDescs descs) {
  return reg_.set_property_descs(name, std::move(descs));
}

std::optional<SubpluginRegistry::PropertyDescs> ConverterRegistry::property_descs(
    std::string_view name) {
  return reg_.property_descs(name);
}

nns_converter_subplugin_last_error_fn ConverterRegistry::last_error_fn(
    const NNStreamerExternalConverter *ex) {
  return reinterpret_cast<nns_converter_subplugin_last_error_fn>(
      reg_.file_symbol(ex, NNS_CONVERTER_SUBPLUGIN_LAST_ERROR));
}

int ConverterRegistry::add_custom(const char *name, tensor_converter_custom func, void *data) {
  if (name && customs_.find(name)) GST_WARNING("custom converter '%s' is already registered", name);
  return customs_.add(name, CustomConverter{func, data}, func != nullptr);
}

int ConverterRegistry::remove_custom(const char *name) {
  return customs_.remove(name);
}

std::optional<CustomConverter> ConverterRegistry::find_custom(std::string_view name) {
  return customs_.find(name);
}

}  // namespace nns::gst

// ---- C API ---------------------------------------------------------------------------------

extern "C" {

const NNStreamerExternalConverter *nnstreamer_converter_find(const char *name) {
  if (!name) return nullptr;
  return nns::gst::ConverterRegistry::instance().find(name);
}

int registerExternalConverter(NNStreamerExternalConverter *ex) {
  return nns::gst::ConverterRegistry::instance().add(ex) ? TRUE : FALSE;
}

void unregisterExternalConverter(const char *name) {
  if (name) nns::gst::ConverterRegistry::instance().remove(name);
}

void nnstreamer_converter_set_custom_property_desc(const char *name, const char *prop, ...) {
  if (!name) return;
  va_list ap;
  va_start(ap, prop);
  auto descs = nns::gst::SubpluginRegistry::collect_descs(name, prop, ap);
  va_end(ap);
  nns::gst::ConverterRegistry::instance().set_property_descs(name, std::move(descs));
}

int nnstreamer_converter_custom_register(const gchar *name, tensor_converter_custom func,
                                         void *data) {
  return nns::gst::ConverterRegistry::instance().add_custom(name, func, data);
}

int nnstreamer_converter_custom_unregister(const gchar *name) {
  return nns::gst::ConverterRegistry::instance().remove_custom(name);
}

}  // extern "C"

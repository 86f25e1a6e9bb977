// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/converter_registry.h"

#include <dlfcn.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>

#include "core/nns_conf.h"

GST_DEBUG_CATEGORY_STATIC(nns_converter_registry_debug);
#define GST_CAT_DEFAULT nns_converter_registry_debug

namespace nns::gst {
namespace {

void init_debug() {
  static std::once_flag once;
  std::call_once(once, [] {
    GST_DEBUG_CATEGORY_INIT(nns_converter_registry_debug, "nns_converter_registry", 0,
                            "tensor_converter sub-plugin registry");
  });
}

// Makes the object holding this code export its symbols globally, so sub-plugins written the
// NNStreamer way (constructor calling registerExternalConverter) resolve against it. GStreamer
// loads plugins with local binding; re-opening with RTLD_NOLOAD | RTLD_GLOBAL promotes them.
void promote_self_global() {
  static std::once_flag once;
  std::call_once(once, [] {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void *>(&registerExternalConverter), &info) && info.dli_fname) {
      if (void *h = dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL)) {
        (void)h;  // keep the extra reference: the plugin stays loaded anyway
      }
    }
  });
}

}  // namespace

ConverterRegistry &ConverterRegistry::instance() {
  static ConverterRegistry *r = [] {
    init_debug();
    return new ConverterRegistry();
  }();
  return *r;
}

bool ConverterRegistry::add(const NNStreamerExternalConverter *ex) {
  if (!ex || !ex->name || !*ex->name) {
    GST_WARNING("converter sub-plugin rejected: no name");
    return false;
  }
  if (!ex->convert || !ex->get_out_config || !ex->query_caps) {
    GST_WARNING(
        "converter sub-plugin '%s' rejected: convert, get_out_config and query_caps are "
        "mandatory",
        ex->name);
    return false;
  }
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (const auto &e : converters_) {
    if (e.name == ex->name) {
      GST_WARNING("converter sub-plugin '%s' is already registered", ex->name);
      return false;
    }
  }
  converters_.push_back({ex->name, ex});
  ++generation_;
  GST_INFO("registered converter sub-plugin '%s'", ex->name);
  return true;
}

bool ConverterRegistry::remove(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  auto it = std::find_if(converters_.begin(), converters_.end(),
                         [&](const Entry &e) { return e.name == name; });
  if (it == converters_.end()) return false;
  converters_.erase(it);
  ++generation_;
  return true;
}

void ConverterRegistry::load_file(const std::string &name, const std::string &path) {
  if (std::find(tried_paths_.begin(), tried_paths_.end(), path) != tried_paths_.end()) return;
  tried_paths_.push_back(path);
  promote_self_global();
  void *handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char *err = dlerror();
    load_errors_.emplace_back(
        name, std::string("cannot load ") + path + ": " + (err ? err : "unknown dlopen error"));
    GST_WARNING("%s", load_errors_.back().second.c_str());
    return;
  }
  // NNStreamer-style objects registered themselves from a constructor during dlopen.
  for (const auto &e : converters_)
    if (e.name == name) return;
  auto entry = reinterpret_cast<nns_converter_subplugin_entry_fn>(
      dlsym(handle, NNS_CONVERTER_SUBPLUGIN_ENTRY));
  if (!entry) {
    load_errors_.emplace_back(name, path + " neither registered a converter named '" + name +
                                        "' nor exports " NNS_CONVERTER_SUBPLUGIN_ENTRY "()");
    GST_WARNING("%s", load_errors_.back().second.c_str());
    return;
  }
  const NNStreamerExternalConverter *ex = entry();
  if (!ex || !ex->name || name != ex->name) {
    load_errors_.emplace_back(name, path + ": " NNS_CONVERTER_SUBPLUGIN_ENTRY "() returned " +
                                        (ex && ex->name ? "'" + std::string(ex->name) + "'"
                                                        : std::string("no converter")) +
                                        ", expected '" + name + "'");
    GST_WARNING("%s", load_errors_.back().second.c_str());
    return;
  }
  if (!add(ex))
    load_errors_.emplace_back(name, path + ": the converter table lacks mandatory callbacks");
}

const NNStreamerExternalConverter *ConverterRegistry::find_locked(std::string_view name) {
  for (const auto &e : converters_)
    if (e.name == name) return e.ex;
  auto path = Conf::get().find_subplugin(SubpluginKind::kConverter, name);
  if (!path) return nullptr;
  load_file(std::string(name), *path);
  for (const auto &e : converters_)
    if (e.name == name) return e.ex;
  return nullptr;
}

const NNStreamerExternalConverter *ConverterRegistry::find(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  return find_locked(name);
}

void ConverterRegistry::load_all_locked() {
  // Folders are scanned once per configuration (Conf::reload() makes a new one).
  const Conf &conf = Conf::get();
  if (scanned_conf_ == &conf) return;
  scanned_conf_ = &conf;
  for (const auto &f : conf.subplugins(SubpluginKind::kConverter)) {
    bool have = std::any_of(converters_.begin(), converters_.end(),
                            [&](const Entry &e) { return e.name == f.name; });
    if (!have) load_file(f.name, f.path);
  }
}

const NNStreamerExternalConverter *ConverterRegistry::find_for_media(std::string_view media_type) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  load_all_locked();
  for (const auto &e : converters_)
    if (e.name == media_type) return e.ex;
  for (const auto &e : converters_) {
    GstCaps *caps = e.ex->query_caps(nullptr);
    if (!caps) continue;
    bool match = false;
    for (guint i = 0; i < gst_caps_get_size(caps) && !match; ++i)
      match =
          gst_structure_has_name(gst_caps_get_structure(caps, i), std::string(media_type).c_str());
    gst_caps_unref(caps);
    if (match) return e.ex;
  }
  return nullptr;
}

std::vector<std::string> ConverterRegistry::names() {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  std::vector<std::string> out;
  for (const auto &e : converters_) out.push_back(e.name);
  for (const auto &f : Conf::get().subplugins(SubpluginKind::kConverter)) out.push_back(f.name);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

GstCaps *ConverterRegistry::all_caps() {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  load_all_locked();
  if (!caps_cache_ || caps_generation_ != generation_) {
    GstCaps *all = gst_caps_new_empty();
    for (const auto &e : converters_) {
      if (GstCaps *c = e.ex->query_caps(nullptr)) all = gst_caps_merge(all, c);
    }
    if (caps_cache_) gst_caps_unref(caps_cache_);
    caps_cache_ = all;
    caps_generation_ = generation_;
  }
  return gst_caps_ref(caps_cache_);
}

std::string ConverterRegistry::load_error(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (auto it = load_errors_.rbegin(); it != load_errors_.rend(); ++it)
    if (it->first == name) return it->second;
  return {};
}

int ConverterRegistry::add_custom(const char *name, tensor_converter_custom func, void *data) {
  if (!name || !*name || !func) return -EINVAL;
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (const auto &c : customs_) {
    if (c.name == name) {
      GST_WARNING("custom converter '%s' is already registered", name);
      return -EINVAL;
    }
  }
  customs_.push_back({name, {func, data}});
  return 0;
}

int ConverterRegistry::remove_custom(const char *name) {
  if (!name) return -EINVAL;
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  auto it = std::find_if(customs_.begin(), customs_.end(),
                         [&](const Custom &c) { return c.name == name; });
  if (it == customs_.end()) return -EINVAL;
  customs_.erase(it);
  return 0;
}

std::optional<CustomConverter> ConverterRegistry::find_custom(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (const auto &c : customs_)
    if (c.name == name) return c.cb;
  return std::nullopt;
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
  // Descriptions are only informative; log them for gst-inspect users running with debug.
  va_list ap;
  va_start(ap, prop);
  for (const char *p = prop; p; p = va_arg(ap, const char *)) {
    const char *desc = va_arg(ap, const char *);
    GST_DEBUG("converter '%s' custom property '%s': %s", name ? name : "?", p, desc ? desc : "");
    if (!desc) break;
  }
  va_end(ap);
}

int nnstreamer_converter_custom_register(const gchar *name, tensor_converter_custom func,
                                         void *data) {
  return nns::gst::ConverterRegistry::instance().add_custom(name, func, data);
}

int nnstreamer_converter_custom_unregister(const gchar *name) {
  return nns::gst::ConverterRegistry::instance().remove_custom(name);
}

}  // extern "C"

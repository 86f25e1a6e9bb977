// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/subplugin_registry.h"

#include <dlfcn.h>

#include <algorithm>

#define GST_CAT_DEFAULT (*t_.category)

namespace nns::gst {
namespace {

// Sub-plugins written the NNStreamer way register from a constructor by calling a function of
// this object (registerExternalConverter, nnstreamer_decoder_probe). GStreamer loads plugins
// with local binding; re-opening the object holding `anchor` with RTLD_NOLOAD | RTLD_GLOBAL
// promotes it so those symbols resolve. The extra reference is kept (the plugin stays loaded).
void promote_self_global(void *anchor) {
  static std::once_flag once;
  std::call_once(once, [anchor] {
    Dl_info info{};
    if (dladdr(anchor, &info) && info.dli_fname) {
      if (void *h = dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL)) (void)h;
    }
  });
}

}  // namespace

bool SubpluginRegistry::add(const void *table) {
  std::string why = t_.check(table);
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (!why.empty()) {
    GST_WARNING("%s sub-plugin %s", t_.noun, why.c_str());
    rejections_.push_back(why);
    return false;
  }
  const char *name = t_.name_of(table);
  if (lookup_locked(name)) {
    GST_WARNING("%s sub-plugin '%s' is already registered", t_.noun, name);
    rejections_.push_back("'" + std::string(name) + "' is already registered");
    return false;
  }
  tables_.emplace_back(name, table);
  ++generation_;
  GST_INFO("registered %s sub-plugin '%s'", t_.noun, name);
  return true;
}

bool SubpluginRegistry::remove(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  auto it =
      std::find_if(tables_.begin(), tables_.end(), [&](const auto &e) { return e.first == name; });
  if (it == tables_.end()) return false;
  tables_.erase(it);
  std::erase_if(descs_, [&](const auto &d) { return d.first == name; });
  ++generation_;
  return true;
}

bool SubpluginRegistry::set_property_descs(std::string_view name, PropertyDescs descs) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  std::erase_if(descs_, [&](const auto &d) { return d.first == name; });
  if (!lookup_locked(name)) return false;
  if (!descs.empty()) descs_.emplace_back(std::string(name), std::move(descs));
  return true;
}

std::optional<SubpluginRegistry::PropertyDescs> SubpluginRegistry::property_descs(
    std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (const auto &d : descs_)
    if (d.first == name) return d.second;
  return std::nullopt;
}

SubpluginRegistry::PropertyDescs SubpluginRegistry::collect_descs(const char *owner,
                                                                  const char *prop, va_list ap) {
  PropertyDescs out;
  for (const char *p = prop; p; p = va_arg(ap, const char *)) {
    const char *desc = va_arg(ap, const char *);
    if (!desc) {
      g_message("sub-plugin '%s': custom property '%s' has no description: ignored",
                owner ? owner : "?", p);
      break;
    }
    out.emplace_back(p, desc);
  }
  return out;
}

const void *SubpluginRegistry::lookup_locked(std::string_view name) const {
  for (const auto &e : tables_)
    if (e.first == name) return e.second;
  return nullptr;
}

void SubpluginRegistry::fail_load(const std::string &name, std::string msg) {
  GST_WARNING("%s", msg.c_str());
  load_errors_.emplace_back(name, std::move(msg));
}

void SubpluginRegistry::load_file(const std::string &name, const std::string &path) {
  if (std::find(tried_paths_.begin(), tried_paths_.end(), path) != tried_paths_.end()) return;
  tried_paths_.push_back(path);
  promote_self_global(t_.anchor);
  const std::size_t rejected_before = rejections_.size();
  void *handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  if (!handle) {
    const char *err = dlerror();
    fail_load(name,
              std::string("cannot load ") + path + ": " + (err ? err : "unknown dlopen error"));
    return;
  }
  const std::string noun = t_.noun;
  const std::string entry_name = t_.entry_symbol;
  if (const void *table = lookup_locked(name)) {  // registered from a constructor
    handles_.emplace_back(table, handle);
    return;
  }
  auto entry = reinterpret_cast<const void *(*)()>(dlsym(handle, t_.entry_symbol));
  if (!entry && rejections_.size() > rejected_before) {
    // NNStreamer style: the constructor's registration was refused.
    std::string why;
    for (std::size_t i = rejected_before; i < rejections_.size(); ++i)
      why += (why.empty() ? "" : "; ") + rejections_[i];
    fail_load(name, path + ": the " + noun + " sub-plugin failed its probe: " + why);
    return;
  }
  if (!entry) {
    fail_load(name, path + " neither registered a " + noun + " named '" + name + "' nor exports " +
                        entry_name + "()");
    return;
  }
  const void *table = entry();
  const char *got = table ? t_.name_of(table) : nullptr;
  if (!got || name != got) {
    fail_load(name, path + ": " + entry_name + "() returned " +
                        (got ? "'" + std::string(got) + "'" : "no " + noun) + ", expected '" +
                        name + "'");
    return;
  }
  if (!add(table)) {
    fail_load(name, path + ": the " + noun + " table lacks mandatory callbacks");
    return;
  }
  handles_.emplace_back(table, handle);
}

const void *SubpluginRegistry::find(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (const void *t = lookup_locked(name)) return t;
  auto path = Conf::get().find_subplugin(t_.kind, name);
  if (!path) return nullptr;
  load_file(std::string(name), *path);
  return lookup_locked(name);
}

void SubpluginRegistry::load_all_locked() {
  // Folders are scanned once per configuration (Conf::reload() makes a new one).
  const Conf &conf = Conf::get();
  if (scanned_conf_ == &conf) return;
  scanned_conf_ = &conf;
  for (const auto &f : conf.subplugins(t_.kind))
    if (!lookup_locked(f.name)) load_file(f.name, f.path);
}

std::vector<std::string> SubpluginRegistry::names() {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  std::vector<std::string> out;
  for (const auto &e : tables_) out.push_back(e.first);
  for (const auto &f : Conf::get().subplugins(t_.kind)) out.push_back(f.name);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::string SubpluginRegistry::load_error(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (auto it = load_errors_.rbegin(); it != load_errors_.rend(); ++it)
    if (it->first == name) return it->second;
  return {};
}

void *SubpluginRegistry::file_symbol(const void *table, const char *symbol) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (const auto &h : handles_)
    if (h.first == table) return dlsym(h.second, symbol);
  return nullptr;
}

}  // namespace nns::gst

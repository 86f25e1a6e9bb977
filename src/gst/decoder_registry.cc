// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/decoder_registry.h"

#include <dlfcn.h>

#include <algorithm>
#include <cerrno>
#include <cstdarg>

#include "core/nns_conf.h"

GST_DEBUG_CATEGORY_STATIC(nns_decoder_registry_debug);
#define GST_CAT_DEFAULT nns_decoder_registry_debug

namespace nns::gst {
namespace {

// Sub-plugins written the NNStreamer way call nnstreamer_decoder_probe() from a constructor;
// promote the object holding this code to global binding so that symbol resolves.
void promote_self_global() {
  static std::once_flag once;
  std::call_once(once, [] {
    Dl_info info{};
    if (dladdr(reinterpret_cast<void *>(&nnstreamer_decoder_probe), &info) && info.dli_fname) {
      if (void *h = dlopen(info.dli_fname, RTLD_NOW | RTLD_NOLOAD | RTLD_GLOBAL)) (void)h;
    }
  });
}

}  // namespace

DecoderRegistry &DecoderRegistry::instance() {
  static DecoderRegistry *r = [] {
    GST_DEBUG_CATEGORY_INIT(nns_decoder_registry_debug, "nns_decoder_registry", 0,
                            "tensor_decoder sub-plugin registry");
    return new DecoderRegistry();
  }();
  return *r;
}

bool DecoderRegistry::add(const GstTensorDecoderDef *def) {
  if (!def || !def->modename || !*def->modename) {
    GST_WARNING("decoder sub-plugin rejected: no mode name");
    return false;
  }
  if (!def->init || !def->exit || !def->setOption || !def->getOutCaps || !def->decode) {
    GST_WARNING(
        "decoder sub-plugin '%s' rejected: init, exit, setOption, getOutCaps and decode "
        "are mandatory",
        def->modename);
    return false;
  }
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (lookup_locked(def->modename)) {
    GST_WARNING("decoder sub-plugin '%s' is already registered", def->modename);
    return false;
  }
  decoders_.emplace_back(def->modename, def);
  return true;
}

bool DecoderRegistry::remove(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  auto it = std::find_if(decoders_.begin(), decoders_.end(),
                         [&](const auto &e) { return e.first == name; });
  if (it == decoders_.end()) return false;
  decoders_.erase(it);
  return true;
}

const GstTensorDecoderDef *DecoderRegistry::lookup_locked(std::string_view name) const {
  for (const auto &e : decoders_)
    if (e.first == name) return e.second;
  return nullptr;
}

void DecoderRegistry::load_file(const std::string &name, const std::string &path) {
  if (std::find(tried_paths_.begin(), tried_paths_.end(), path) != tried_paths_.end()) return;
  tried_paths_.push_back(path);
  promote_self_global();
  void *handle = dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL);
  auto fail = [&](const std::string &msg) {
    load_errors_.emplace_back(name, msg);
    GST_WARNING("%s", msg.c_str());
  };
  if (!handle) {
    const char *err = dlerror();
    fail("cannot load " + path + ": " + (err ? err : "unknown dlopen error"));
    return;
  }
  if (lookup_locked(name)) return;  // registered from a constructor
  auto entry =
      reinterpret_cast<nns_decoder_subplugin_entry_fn>(dlsym(handle, NNS_DECODER_SUBPLUGIN_ENTRY));
  if (!entry) {
    fail(path + " neither registered a decoder named '" + name +
         "' nor exports " NNS_DECODER_SUBPLUGIN_ENTRY "()");
    return;
  }
  const GstTensorDecoderDef *def = entry();
  if (!def || !def->modename || name != def->modename) {
    fail(path + ": " NNS_DECODER_SUBPLUGIN_ENTRY "() returned " +
         (def && def->modename ? "'" + std::string(def->modename) + "'"
                               : std::string("no decoder")) +
         ", expected '" + name + "'");
    return;
  }
  if (!add(def)) fail(path + ": the decoder table lacks mandatory callbacks");
}

const GstTensorDecoderDef *DecoderRegistry::find(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  if (auto *d = lookup_locked(name)) return d;
  auto path = Conf::get().find_subplugin(SubpluginKind::kDecoder, name);
  if (!path) return nullptr;
  load_file(std::string(name), *path);
  return lookup_locked(name);
}

std::vector<std::string> DecoderRegistry::names() {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  std::vector<std::string> out;
  for (const auto &e : decoders_) out.push_back(e.first);
  for (const auto &f : Conf::get().subplugins(SubpluginKind::kDecoder)) out.push_back(f.name);
  std::sort(out.begin(), out.end());
  out.erase(std::unique(out.begin(), out.end()), out.end());
  return out;
}

std::string DecoderRegistry::load_error(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (auto it = load_errors_.rbegin(); it != load_errors_.rend(); ++it)
    if (it->first == name) return it->second;
  return {};
}

int DecoderRegistry::add_custom(const char *name, tensor_decoder_custom func, void *data) {
  if (!name || !*name || !func) return -EINVAL;
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (const auto &c : customs_)
    if (c.first == name) return -EINVAL;
  customs_.emplace_back(name, CustomDecoder{func, data});
  return 0;
}

int DecoderRegistry::remove_custom(const char *name) {
  if (!name) return -EINVAL;
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  auto it = std::find_if(customs_.begin(), customs_.end(),
                         [&](const auto &c) { return c.first == name; });
  if (it == customs_.end()) return -EINVAL;
  customs_.erase(it);
  return 0;
}

std::optional<CustomDecoder> DecoderRegistry::find_custom(std::string_view name) {
  std::lock_guard<std::recursive_mutex> lock(mutex_);
  for (const auto &c : customs_)
    if (c.first == name) return c.second;
  return std::nullopt;
}

}  // namespace nns::gst

extern "C" {

int nnstreamer_decoder_probe(GstTensorDecoderDef *decoder) {
  return nns::gst::DecoderRegistry::instance().add(decoder) ? TRUE : FALSE;
}

void nnstreamer_decoder_exit(const char *name) {
  if (name) nns::gst::DecoderRegistry::instance().remove(name);
}

const GstTensorDecoderDef *nnstreamer_decoder_find(const char *name) {
  if (!name) return nullptr;
  return nns::gst::DecoderRegistry::instance().find(name);
}

void nnstreamer_decoder_set_custom_property_desc(const char *name, const char *prop, ...) {
  // Informative only: logged for users running with GST_DEBUG.
  va_list ap;
  va_start(ap, prop);
  for (const char *p = prop; p; p = va_arg(ap, const char *)) {
    const char *desc = va_arg(ap, const char *);
    GST_DEBUG("decoder '%s' property '%s': %s", name ? name : "?", p, desc ? desc : "");
    if (!desc) break;
  }
  va_end(ap);
}

int nnstreamer_decoder_custom_register(const gchar *name, tensor_decoder_custom func, void *data) {
  return nns::gst::DecoderRegistry::instance().add_custom(name, func, data);
}

int nnstreamer_decoder_custom_unregister(const gchar *name) {
  return nns::gst::DecoderRegistry::instance().remove_custom(name);
}

}  // extern "C"

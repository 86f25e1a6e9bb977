// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_subplugin.h over nnstreamer-cpp's registries: filters through the 2.x filter
// registry (and our back ends for lookups), decoders and converters through theirs, the other
// kinds (easy custom filters, trainers, custom converters/decoders, tensor_if callbacks) in a
// plain table per kind, as NNStreamer keeps them.
#include "nnstreamer_subplugin.h"

#include <map>
#include <mutex>
#include <string>
#include <utility>
#include <vector>

#include "compat/compat_export.h"
#include "core/compat2x/filter2x.h"
#include "core/filter_registry.h"
#include "gst/converter_registry.h"
#include "gst/decoder_registry.h"
#include "nnstreamer_plugin_api_converter.h"
#include "nnstreamer_plugin_api_decoder.h"
#include "nnstreamer_plugin_api_filter.h"

namespace {

struct Table {
  std::mutex mu;
  std::map<std::pair<int, std::string>, const void *> data;  // kinds kept here
  std::map<std::pair<int, std::string>, GData *> desc;       // never freed (handed out)
};

Table &table() {
  static Table *t = new Table;
  return *t;
}

bool known_kind(subpluginType type) {
  return type >= NNS_SUBPLUGIN_FILTER && type < NNS_SUBPLUGIN_END &&
         type != static_cast<subpluginType>(NNSCONF_PATH_CUSTOM_FILTERS);
}

// Replaces the description list of (type, name) with copies of `pairs`.
void store_desc(Table &t, subpluginType type, const char *name,
                const std::vector<std::pair<std::string, std::string>> &pairs) {
  std::lock_guard lk(t.mu);
  GData *&dl = t.desc[{type, name}];
  g_datalist_clear(&dl);
  g_datalist_init(&dl);
  for (auto &[k, d] : pairs) g_datalist_set_data_full(&dl, k.c_str(), g_strdup(d.c_str()), g_free);
}

}  // namespace

NNS_COMPAT_API const void *get_subplugin(subpluginType type, const char *name) {
  if (!name || !known_kind(type)) return nullptr;
  try {
    switch (type) {
      case NNS_SUBPLUGIN_FILTER:
        return nnstreamer_filter_find(name);
      case NNS_SUBPLUGIN_DECODER:
        return nnstreamer_decoder_find(name);
      case NNS_SUBPLUGIN_CONVERTER:
        return nnstreamer_converter_find(name);
      default: {
        Table &t = table();
        std::lock_guard lk(t.mu);
        auto it = t.data.find({type, name});
        return it == t.data.end() ? nullptr : it->second;
      }
    }
  } catch (...) {
    return nullptr;
  }
}

NNS_COMPAT_API gchar **get_all_subplugins(subpluginType type) {
  std::vector<std::string> names;
  try {
    switch (type) {
      case NNS_SUBPLUGIN_FILTER:
        names = nns::FilterRegistry::get().available(*nns::current_filter_conf());
        break;
      case NNS_SUBPLUGIN_DECODER:
        names = nns::gst::DecoderRegistry::instance().names();
        break;
      case NNS_SUBPLUGIN_CONVERTER:
        names = nns::gst::ConverterRegistry::instance().names();
        break;
      default: {
        Table &t = table();
        std::lock_guard lk(t.mu);
        for (auto &[k, v] : t.data)
          if (k.first == type) names.push_back(k.second);
      }
    }
  } catch (...) {
    names.clear();
  }
  auto **out = g_new0(gchar *, names.size() + 1);
  for (std::size_t i = 0; i < names.size(); ++i) out[i] = g_strdup(names[i].c_str());
  return out;
}

NNS_COMPAT_API gboolean register_subplugin(subpluginType type, const char *name, const void *data) {
  if (!name || !data || !known_kind(type)) return FALSE;
  if (g_ascii_strcasecmp(name, "any") == 0 || g_ascii_strcasecmp(name, "auto") == 0) {
    g_critical("register_subplugin: the name '%s' is reserved", name);
    return FALSE;
  }
  try {
    switch (type) {
      case NNS_SUBPLUGIN_FILTER: {
        auto *fw = static_cast<GstTensorFilterFramework *>(const_cast<void *>(data));
        return nnstreamer_filter_probe(fw) ? TRUE : FALSE;
      }
      case NNS_SUBPLUGIN_DECODER: {
        auto *d = static_cast<GstTensorDecoderDef *>(const_cast<void *>(data));
        return nnstreamer_decoder_probe(d) ? TRUE : FALSE;
      }
      case NNS_SUBPLUGIN_CONVERTER: {
        auto *c = static_cast<NNStreamerExternalConverter *>(const_cast<void *>(data));
        return registerExternalConverter(c) ? TRUE : FALSE;
      }
      default: {
        Table &t = table();
        std::lock_guard lk(t.mu);
        if (!t.data.emplace(std::make_pair(int{type}, std::string(name)), data).second) {
          g_warning("register_subplugin: '%s' is already registered", name);
          return FALSE;
        }
        return TRUE;
      }
    }
  } catch (...) {
    return FALSE;
  }
}

NNS_COMPAT_API gboolean unregister_subplugin(subpluginType type, const char *name) {
  if (!name || !known_kind(type)) return FALSE;
  if (!get_subplugin(type, name)) return FALSE;
  try {
    switch (type) {
      case NNS_SUBPLUGIN_FILTER:
        nnstreamer_filter_exit(name);
        return nnstreamer_filter_find(name) == nullptr ? TRUE : FALSE;
      case NNS_SUBPLUGIN_DECODER:
        nnstreamer_decoder_exit(name);
        return TRUE;
      case NNS_SUBPLUGIN_CONVERTER:
        unregisterExternalConverter(name);
        return TRUE;
      default: {
        Table &t = table();
        std::lock_guard lk(t.mu);
        return t.data.erase({type, name}) ? TRUE : FALSE;
      }
    }
  } catch (...) {
    return FALSE;
  }
}

NNS_COMPAT_API void subplugin_set_custom_property_desc(subpluginType type, const char *name,
                                                       const gchar *prop, va_list varargs) {
  if (!name || !known_kind(type)) return;
  try {
    Table &t = table();
    std::vector<std::pair<std::string, std::string>> pairs;
    for (const gchar *p = prop; p; p = va_arg(varargs, const gchar *)) {
      const gchar *d = va_arg(varargs, const gchar *);
      if (!d) {
        g_warning("subplugin_set_custom_property_desc: no description for '%s'", p);
        break;
      }
      pairs.emplace_back(p, d);
    }
    store_desc(t, type, name, pairs);
    if (type == NNS_SUBPLUGIN_FILTER)
      nns::compat2x::Filter2xRegistry::get().set_custom_desc(name, std::move(pairs));
  } catch (...) {
  }
}

NNS_COMPAT_API GData *subplugin_get_custom_property_desc(subpluginType type, const char *name) {
  if (!name || !known_kind(type)) return nullptr;
  try {
    Table &t = table();
    if (type == NNS_SUBPLUGIN_FILTER) {  // also what nnstreamer_filter_set_custom_property_desc set
      auto pairs = nns::compat2x::Filter2xRegistry::get().custom_desc(name);
      if (!pairs.empty()) store_desc(t, type, name, pairs);
    }
    std::lock_guard lk(t.mu);
    auto it = t.desc.find({type, name});
    return it == t.desc.end() ? nullptr : it->second;
  } catch (...) {
    return nullptr;
  }
}

// SPDX-License-Identifier: LGPL-2.1-only
// Process-wide registry of tensor_converter extensions:
//   - converter sub-plugins (NNStreamerExternalConverter, nnstreamer_plugin_api_converter.h),
//     registered in-process or loaded on demand from libnnstreamer_converter_<name>.so in the
//     folders nns::Conf gives for SubpluginKind::kConverter;
//   - custom-code callbacks (tensor_converter_custom.h).
// Loaded objects are never unloaded (their tables may still be in use).
#pragma once

#include <gst/gst.h>

#include <memory>
#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gst/subplugin_registry.h"
#include "nnstreamer_plugin_api_converter.h"
#include "tensor_converter_custom.h"

namespace nns::gst {

struct CustomConverter {
  tensor_converter_custom func = nullptr;
  void *data = nullptr;
};

class ConverterRegistry {
 public:
  static ConverterRegistry &instance();

  // Sub-plugins. add() returns false (and logs why) for an invalid table or a taken name.
  bool add(const NNStreamerExternalConverter *ex);
  bool remove(std::string_view name);
  // Registered converter `name`; otherwise loads libnnstreamer_converter_<name>.so.
  const NNStreamerExternalConverter *find(std::string_view name);
  // Converter whose name or query_caps(NULL) structure name is `media_type` (loads all files).
  const NNStreamerExternalConverter *find_for_media(std::string_view media_type);
  // Names of registered and loadable converters, sorted, without duplicates.
  std::vector<std::string> names();
  // Union of query_caps(NULL) of every converter (loads all files); new reference.
  GstCaps *all_caps();
  // Why the last load of `name` failed ("" if none) — for error messages.
  std::string load_error(std::string_view name);
  // Custom-property descriptions of a registered converter (see SubpluginRegistry).
  bool set_property_descs(std::string_view name, SubpluginRegistry::PropertyDescs descs);
  std::optional<SubpluginRegistry::PropertyDescs> property_descs(std::string_view name);
  // The optional nns_converter_subplugin_last_error() export of the object `ex` came from
  // (nullptr if none): the reason of its last failed convert() on the calling thread.
  nns_converter_subplugin_last_error_fn last_error_fn(const NNStreamerExternalConverter *ex);

  // custom-code callbacks: 0 or -EINVAL, as NNStreamer.
  int add_custom(const char *name, tensor_converter_custom func, void *data);
  int remove_custom(const char *name);
  std::optional<CustomConverter> find_custom(std::string_view name);

 private:
  ConverterRegistry();

  struct OwnedConverter {
    std::string name;
    NNStreamerExternalConverter table;
  };
  std::mutex copies_mutex_;
  std::vector<std::unique_ptr<OwnedConverter>> copies_;  // what add() registered (never freed)
  SubpluginRegistry reg_;  // loader and table list shared with the decoder registry
  CustomCallbacks<CustomConverter> customs_;
  unsigned caps_generation_ = ~0u;
  GstCaps *caps_cache_ = nullptr;
};

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
// Process-wide registry of tensor_converter extensions:
//   - converter sub-plugins (NNStreamerExternalConverter, nnstreamer_plugin_api_converter.h),
//     registered in-process or loaded on demand from libnnstreamer_converter_<name>.so in the
//     folders nns::Conf gives for SubpluginKind::kConverter;
//   - custom-code callbacks (tensor_converter_custom.h).
// Loaded objects are never unloaded (their tables may still be in use).
#pragma once

#include <gst/gst.h>

#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

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

  // custom-code callbacks: 0 or -EINVAL, as NNStreamer.
  int add_custom(const char *name, tensor_converter_custom func, void *data);
  int remove_custom(const char *name);
  std::optional<CustomConverter> find_custom(std::string_view name);

 private:
  ConverterRegistry() = default;
  const NNStreamerExternalConverter *find_locked(std::string_view name);
  void load_file(const std::string &name, const std::string &path);
  void load_all_locked();

  std::recursive_mutex mutex_;  // a loaded object's constructor re-enters add()
  struct Entry {
    std::string name;
    const NNStreamerExternalConverter *ex;
  };
  std::vector<Entry> converters_;
  struct Custom {
    std::string name;
    CustomConverter cb;
  };
  std::vector<Custom> customs_;
  std::vector<std::string> tried_paths_;  // files already dlopen'ed (or failed)
  std::vector<std::pair<std::string, std::string>> load_errors_;
  const void *scanned_conf_ = nullptr;  // configuration whose folders were last loaded
  unsigned generation_ = 0;             // bumped on every add/remove
  unsigned caps_generation_ = ~0u;
  GstCaps *caps_cache_ = nullptr;
};

}  // namespace nns::gst

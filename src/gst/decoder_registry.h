// SPDX-License-Identifier: LGPL-2.1-only
// Process-wide registry of tensor_decoder extensions (the loader is shared with
// converter_registry.h: subplugin_registry.h):
//   - decoder sub-plugins (GstTensorDecoderDef, nnstreamer_plugin_api_decoder.h), registered
//     in-process (nnstreamer_decoder_probe) or loaded on demand from
//     libnnstreamer_decoder_<mode>.so in the folders nns::Conf gives for SubpluginKind::kDecoder
//     (constructor registration or the nns_decoder_subplugin_entry export);
//   - custom-code callbacks (tensor_decoder_custom.h).
// Loaded objects are never unloaded.
#pragma once

#include <gst/gst.h>

#include <mutex>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "gst/subplugin_registry.h"
#include "nnstreamer_plugin_api_decoder.h"
#include "tensor_decoder_custom.h"

namespace nns::gst {

struct CustomDecoder {
  tensor_decoder_custom func = nullptr;
  void *data = nullptr;
};

class DecoderRegistry {
 public:
  static DecoderRegistry &instance();

  bool add(const GstTensorDecoderDef *def);
  bool remove(std::string_view name);
  const GstTensorDecoderDef *find(std::string_view name);
  std::vector<std::string> names();  // registered and loadable, sorted, unique
  std::string load_error(std::string_view name);
  // Custom-property descriptions of a registered decoder (see SubpluginRegistry).
  bool set_property_descs(std::string_view name, SubpluginRegistry::PropertyDescs descs);
  std::optional<SubpluginRegistry::PropertyDescs> property_descs(std::string_view name);

  int add_custom(const char *name, tensor_decoder_custom func, void *data);
  int remove_custom(const char *name);
  std::optional<CustomDecoder> find_custom(std::string_view name);

 private:
  DecoderRegistry();

  SubpluginRegistry reg_;  // loader and table list shared with the converter registry
  CustomCallbacks<CustomDecoder> customs_;
};

}  // namespace nns::gst

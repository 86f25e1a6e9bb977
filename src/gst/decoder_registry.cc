// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/decoder_registry.h"

#include <cstdarg>

#include "core/nns_conf.h"

GST_DEBUG_CATEGORY_STATIC(nns_decoder_registry_debug);
#define GST_CAT_DEFAULT nns_decoder_registry_debug

namespace nns::gst {
namespace {

const char *decoder_name(const void *t) {
  return static_cast<const GstTensorDecoderDef *>(t)->modename;
}

std::string check_decoder(const void *t) {
  auto *def = static_cast<const GstTensorDecoderDef *>(t);
  if (!def || !def->modename || !*def->modename) return "rejected: no mode name";
  // As NNStreamer: exit, setOption and getTransformSize may be NULL.
  if (!def->init || !def->getOutCaps || !def->decode)
    return "'" + std::string(def->modename) +
           "' rejected: init, getOutCaps and decode are mandatory";
  if (g_ascii_strcasecmp(def->modename, "any") == 0 ||
      g_ascii_strcasecmp(def->modename, "auto") == 0)
    return "'" + std::string(def->modename) + "' rejected: the name is reserved";
  return {};
}

}  // namespace

DecoderRegistry::DecoderRegistry()
    : reg_({SubpluginKind::kDecoder, "decoder", NNS_DECODER_SUBPLUGIN_ENTRY, decoder_name,
            check_decoder, reinterpret_cast<void *>(&nnstreamer_decoder_probe),
            &nns_decoder_registry_debug}) {}

DecoderRegistry &DecoderRegistry::instance() {
  static DecoderRegistry *r = [] {
    GST_DEBUG_CATEGORY_INIT(nns_decoder_registry_debug, "nns_decoder_registry", 0,
                            "tensor_decoder sub-plugin registry");
    return new DecoderRegistry();
  }();
  return *r;
}

bool DecoderRegistry::add(const GstTensorDecoderDef *def) {
  return reg_.add(def);
}

bool DecoderRegistry::remove(std::string_view name) {
  return reg_.remove(name);
}

const GstTensorDecoderDef *DecoderRegistry::find(std::string_view name) {
  return static_cast<const GstTensorDecoderDef *>(reg_.find(name));
}

std::vector<std::string> DecoderRegistry::names() {
  return reg_.names();
}

std::string DecoderRegistry::load_error(std::string_view name) {
  return reg_.load_error(name);
}

bool DecoderRegistry::set_property_descs(std::string_view name,
                                         SubpluginRegistry::PropertyDescs descs) {
  return reg_.set_property_descs(name, std::move(descs));
}

std::optional<SubpluginRegistry::PropertyDescs> DecoderRegistry::property_descs(
    std::string_view name) {
  return reg_.property_descs(name);
}

int DecoderRegistry::add_custom(const char *name, tensor_decoder_custom func, void *data) {
  return customs_.add(name, CustomDecoder{func, data}, func != nullptr);
}

int DecoderRegistry::remove_custom(const char *name) {
  return customs_.remove(name);
}

std::optional<CustomDecoder> DecoderRegistry::find_custom(std::string_view name) {
  return customs_.find(name);
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
  if (!name) return;
  va_list ap;
  va_start(ap, prop);
  auto descs = nns::gst::SubpluginRegistry::collect_descs(name, prop, ap);
  va_end(ap);
  nns::gst::DecoderRegistry::instance().set_property_descs(name, std::move(descs));
}

int nnstreamer_decoder_custom_register(const gchar *name, tensor_decoder_custom func, void *data) {
  return nns::gst::DecoderRegistry::instance().add_custom(name, func, data);
}

int nnstreamer_decoder_custom_unregister(const gchar *name) {
  return nns::gst::DecoderRegistry::instance().remove_custom(name);
}

}  // extern "C"

/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * The C ABI of tensor_converter sub-plugins, modelled on NNStreamer's
 * nnstreamer_plugin_api_converter.h so its converters can be ported with few changes.
 *
 * A sub-plugin is a shared object named libnnstreamer_converter_<name>.so in a folder listed by
 * nnstreamer.ini's [converter] converters= key, NNSTREAMER_CONVERTERS (when enable_envvar is
 * set) or the built-in folders. tensor_converter loads it on demand and accepts two ways of
 * announcing the converter:
 *
 *   1. NNStreamer style: a constructor function calls registerExternalConverter(&table); the
 *      host makes these functions visible to the loaded object.
 *   2. Entry point (no link dependency on the host): the object exports
 *        const NNStreamerExternalConverter *nns_converter_subplugin_entry (void);
 *      returning its static table; the host registers it.
 *
 * The table's `name` must equal <name> of the file. The converter is chosen for an input
 * stream when the stream's media type equals `name` or a structure name of query_caps(NULL),
 * or explicitly by tensor_converter mode=custom-script:<path> (".py" selects "python3", other
 * extensions select the sub-plugin named like the extension).
 */
#ifndef NNSTREAMER_CPP_PLUGIN_API_CONVERTER_H_
#define NNSTREAMER_CPP_PLUGIN_API_CONVERTER_H_

#include <gst/gst.h>

#include "tensor_typedef.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef struct _NNStreamerExternalConverter {
  const char *name;

  /* Converts one input buffer. `in_buf` is borrowed; return a new buffer (one GstMemory per
   * tensor, or flexible memories with headers when config->info.format is flexible), or
   * in_buf itself to pass the data untouched. Fill `config` with what the buffer holds.
   * NULL means failure. Mandatory. */
  GstBuffer *(*convert)(GstBuffer *in_buf, GstTensorsConfig *config, void *priv_data);

  /* Output tensors for the input caps; TRUE on success. Mandatory. */
  gboolean (*get_out_config)(const GstCaps *in_caps, GstTensorsConfig *config);

  /* Input caps this converter accepts for the given output (NULL: everything it accepts).
   * Returns a new reference. Mandatory. */
  GstCaps *(*query_caps)(const GstTensorsConfig *config);

  /* custom-script mode: opens the script; *priv_data receives the instance. 0 or < 0.
   * May be NULL. */
  int (*open)(const gchar *script_path, void **priv_data);

  /* Releases what open() made and sets *priv_data to NULL. May be NULL. */
  void (*close)(void **priv_data);
} NNStreamerExternalConverter;

/* Name of the optional entry point and its type. */
#define NNS_CONVERTER_SUBPLUGIN_ENTRY "nns_converter_subplugin_entry"
typedef const NNStreamerExternalConverter *(*nns_converter_subplugin_entry_fn)(void);

/* Optional export of a converter sub-plugin object (nnstreamer-cpp extension; the table has no
 * error channel): why convert() last returned NULL on the calling thread ("" or NULL if it did
 * not fail). tensor_converter calls it right after a failed convert() and puts the text in its
 * bus error. */
#define NNS_CONVERTER_SUBPLUGIN_LAST_ERROR "nns_converter_subplugin_last_error"
typedef const char *(*nns_converter_subplugin_last_error_fn)(void);

/* The converter registered (or loadable) as `name`, or NULL. */
extern const NNStreamerExternalConverter *nnstreamer_converter_find(const char *name);

/* Registers a converter; TRUE when registered, FALSE when it lacks a name or one of the
 * mandatory callbacks, or the name is taken. */
extern int registerExternalConverter(NNStreamerExternalConverter *ex);

/* Removes the converter registered as `name` (no effect when there is none). */
extern void unregisterExternalConverter(const char *name);

/* Records descriptions of custom properties ("prop", "description", ..., NULL) for tools. */
extern void nnstreamer_converter_set_custom_property_desc(const char *name, const char *prop, ...);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_PLUGIN_API_CONVERTER_H_ */

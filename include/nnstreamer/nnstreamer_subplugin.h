/* SPDX-License-Identifier: LGPL-2.1-only */
/* NNStreamer 2.x's sub-plugin table (nnstreamer_subplugin.h). Filters, decoders and converters
 * go to nnstreamer-cpp's registries (the same ones nnstreamer_filter_probe(),
 * nnstreamer_decoder_probe() and registerExternalConverter() fill); the other kinds are kept in
 * a table per kind. Exported by libnnstreamer.so. */
#ifndef NNSTREAMER_SUBPLUGIN_H_
#define NNSTREAMER_SUBPLUGIN_H_

#include <stdarg.h>
#include <stdint.h>

#include "nnstreamer_conf.h"

G_BEGIN_DECLS

typedef enum {
  NNS_SUBPLUGIN_FILTER = NNSCONF_PATH_FILTERS,
  NNS_SUBPLUGIN_DECODER = NNSCONF_PATH_DECODERS,
  NNS_EASY_CUSTOM_FILTER = NNSCONF_PATH_EASY_CUSTOM_FILTERS,
  NNS_SUBPLUGIN_CONVERTER = NNSCONF_PATH_CONVERTERS,
  NNS_SUBPLUGIN_TRAINER = NNSCONF_PATH_TRAINERS,
  NNS_CUSTOM_CONVERTER,
  NNS_CUSTOM_DECODER,
  NNS_IF_CUSTOM,
  NNS_SUBPLUGIN_END,
} subpluginType;

#define NNS_SUBPLUGIN_CHECKER (0xdeadbeef)

/* The data registered as `name` (loading libnnstreamer_<kind>_<name>.so from the configured
 * folders for filters, decoders and converters), or NULL. */
extern const void *get_subplugin(subpluginType type, const char *name);
/* Every name registered or found in the folders; free with g_strfreev(). */
extern gchar **get_all_subplugins(subpluginType type);
/* FALSE for a NULL argument, an unknown kind, the names "any"/"auto", a taken name, or (filters,
 * decoders, converters) a table the registry refuses. */
extern gboolean register_subplugin(subpluginType type, const char *name, const void *data);
extern gboolean unregister_subplugin(subpluginType type, const char *name);
/* ("key", "description", ..., NULL) pairs after prop; replaces the previous list. */
extern void subplugin_set_custom_property_desc(subpluginType type, const char *name,
                                               const gchar *prop, va_list varargs);
/* The list set above (owned by the table), or NULL. */
extern GData *subplugin_get_custom_property_desc(subpluginType type, const char *name);

G_END_DECLS

#endif /* NNSTREAMER_SUBPLUGIN_H_ */

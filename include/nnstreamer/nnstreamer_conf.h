/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * nnstreamer.ini and environment access of NNStreamer's nnstreamer_conf.h (internal in
 * NNStreamer; installed here so sub-plugins written inside NNStreamer's tree build unchanged).
 * Exported by libnnstreamer-single.so, read through nnstreamer-cpp's own configuration reader,
 * so the file, NNSTREAMER_CONF, [common] enable_envvar / enable_symlink and the folder keys mean
 * the same for these functions and for the elements.
 */
#ifndef NNSTREAMER_CPP_NNSTREAMER_CONF_H_
#define NNSTREAMER_CPP_NNSTREAMER_CONF_H_

#include <glib.h>

G_BEGIN_DECLS

#define NNSTREAMER_SYS_ROOT_PATH_PREFIX "/"
#define NNSTREAMER_SO_FILE_EXTENSION ".so"
#define NNSTREAMER_DEFAULT_CONF_FILE "/etc/nnstreamer.ini"
#ifndef NNSTREAMER_CONF_FILE
#define NNSTREAMER_CONF_FILE NNSTREAMER_DEFAULT_CONF_FILE
#endif
#define NNSTREAMER_ENVVAR_CONF_FILE "NNSTREAMER_CONF"

typedef enum {
  NNSCONF_PATH_FILTERS = 0,
  NNSCONF_PATH_DECODERS,
  NNSCONF_PATH_CUSTOM_FILTERS,
  NNSCONF_PATH_EASY_CUSTOM_FILTERS,
  NNSCONF_PATH_CONVERTERS,
  NNSCONF_PATH_TRAINERS,

  NNSCONF_PATH_END,
} nnsconf_type_path;

/* Sub-plugins of one kind: parallel NULL-terminated lists. */
typedef struct {
  gchar **names;
  gchar **paths;
} subplugin_info_s;

/* Reads the configuration (again when force_reload). TRUE when a configuration is loaded. */
extern gboolean nnsconf_loadconf(gboolean force_reload);
/* Full path of sub-plugin `subpluginname` of the kind, or NULL. Owned by the library. */
extern const gchar *nnsconf_get_fullpath(const gchar *subpluginname, nnsconf_type_path type);
/* `fullpath` is a regular file (and no symlink unless enable_symlink) for a known kind. */
extern gboolean nnsconf_validate_file(nnsconf_type_path type, const gchar *fullpath);
/* "libnnstreamer_filter_", "libnnstreamer_decoder_", ...; "" for custom filters. */
extern const gchar *nnsconf_get_subplugin_name_prefix(nnsconf_type_path type);
/* Names and paths of the sub-plugins of the kind; returns their number. The lists belong to the
 * library (do not free them; they stay valid until the next reload). */
extern guint nnsconf_get_subplugin_info(nnsconf_type_path type, subplugin_info_s *info);
/* NNSTREAMER_<group>_<key> when environment variables are enabled, else [group] key of the
 * file; NULL when neither is set. g_free() the result. */
extern gchar *nnsconf_get_custom_value_string(const gchar *group, const gchar *key);
/* The same value read as a boolean (1/0, true/false, yes/no, on/off); `def` when unset. */
extern gboolean nnsconf_get_custom_value_bool(const gchar *group, const gchar *key, gboolean def);
/* Human-readable configuration summary into str[size]. */
extern void nnsconf_dump(gchar *str, gulong size);
/* The sub-plugin files found for each kind, into str[size]. */
extern void nnsconf_subplugin_dump(gchar *str, gulong size);

G_END_DECLS

#endif /* NNSTREAMER_CPP_NNSTREAMER_CONF_H_ */

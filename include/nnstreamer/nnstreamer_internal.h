/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * The few entry points NNStreamer 2.x installs for its own native APIs (the ML API library) and
 * sub-plugins beside the public plugin headers: configuration values, framework detection from
 * model files and the accelerator check. Names and signatures are NNStreamer's; exported by
 * libnnstreamer-single.so and the plugin (docs/compat-nnstreamer-2x.md).
 */
#ifndef NNSTREAMER_CPP_INTERNAL_H_
#define NNSTREAMER_CPP_INTERNAL_H_

#include <glib.h>

#include "nnstreamer_plugin_api_filter.h"

G_BEGIN_DECLS

/* nnstreamer.ini [group] key (or the NNSTREAMER_<group>_<key> variable); g_free() it. */
extern gchar *nnsconf_get_custom_value_string(const gchar *group, const gchar *key);
extern gboolean nnsconf_get_custom_value_bool(const gchar *group, const gchar *key, gboolean def);

/* The framework NNStreamer would pick for these model files (a new string, g_free() it), or
 * NULL: a folder gives "nnfw"; one file goes by its extension (with load_conf, nnstreamer.ini's
 * [filter] framework_priority_<ext> first: its first framework that is available), two files
 * give caffe2 (two different .pb) or vivante (.so and .nb). */
extern gchar *gst_tensor_filter_detect_framework(const gchar *const *model_files,
                                                 const guint num_models, const gboolean load_conf);

/* Whether framework `name` is available and can use accelerator `hw` (auto and default: always
 * when the framework is). `custom` is accepted and not used (no back end here takes an option
 * for this check). */
extern gboolean gst_tensor_filter_check_hw_availability(const gchar *name, const accl_hw hw,
                                                        const gchar *custom);

G_END_DECLS

#endif /* NNSTREAMER_CPP_INTERNAL_H_ */

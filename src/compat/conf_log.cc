// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_conf.h over nns::Conf (src/core/nns_conf.h: same file, variables and precedence as
// the elements use) and nnstreamer_log.h's backtrace and last-error buffer.
#include <execinfo.h>
#include <glib.h>

#include <cstdarg>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include "compat/compat_export.h"
#include "core/nns_conf.h"
#include "nnstreamer_conf.h"
#include "nnstreamer_log.h"

namespace {

// nnsconf kind -> our kind; false for NNSCONF_PATH_END and unknown values.
bool to_kind(nnsconf_type_path type, nns::SubpluginKind *kind) {
  switch (type) {
    case NNSCONF_PATH_FILTERS:
      *kind = nns::SubpluginKind::kFilter;
      return true;
    case NNSCONF_PATH_DECODERS:
      *kind = nns::SubpluginKind::kDecoder;
      return true;
    case NNSCONF_PATH_CUSTOM_FILTERS:
    case NNSCONF_PATH_EASY_CUSTOM_FILTERS:
      *kind = nns::SubpluginKind::kCustomFilter;
      return true;
    case NNSCONF_PATH_CONVERTERS:
      *kind = nns::SubpluginKind::kConverter;
      return true;
    case NNSCONF_PATH_TRAINERS:
      *kind = nns::SubpluginKind::kTrainer;
      return true;
    default:
      return false;
  }
}

// NULL-terminated name/path lists per kind, kept until the next reload. Old generations are
// kept alive too: callers may still hold pointers from before a reload.
struct Lists {
  std::vector<std::string> names, paths;
  std::vector<gchar *> name_ptrs, path_ptrs;
};

struct State {
  std::mutex mutex;
  bool loaded = false;
  std::vector<std::unique_ptr<Lists[]>> generations;  // back() is current (NNSCONF_PATH_END)
  Lists *current = nullptr;
};

State &state() {
  static State *s = new State;  // never destroyed: pointers handed out stay valid at exit
  return *s;
}

void fill_lists_locked(State &s) {
  auto lists = std::make_unique<Lists[]>(NNSCONF_PATH_END);
  const nns::Conf &conf = nns::Conf::get();
  for (int t = 0; t < NNSCONF_PATH_END; ++t) {
    nns::SubpluginKind kind;
    if (!to_kind(static_cast<nnsconf_type_path>(t), &kind)) continue;
    Lists &l = lists[t];
    for (const auto &f : conf.subplugins(kind)) {
      l.names.push_back(f.name);
      l.paths.push_back(f.path);
    }
    for (std::size_t i = 0; i < l.names.size(); ++i) {
      l.name_ptrs.push_back(l.names[i].data());
      l.path_ptrs.push_back(l.paths[i].data());
    }
    l.name_ptrs.push_back(nullptr);
    l.path_ptrs.push_back(nullptr);
  }
  s.current = lists.get();
  s.generations.push_back(std::move(lists));
  s.loaded = true;
}

Lists *lists_locked(State &s, nnsconf_type_path type) {
  if (!s.loaded) fill_lists_locked(s);
  return &s.current[type];
}

bool valid_type(nnsconf_type_path type) {
  return static_cast<int>(type) >= 0 && type < NNSCONF_PATH_END;
}

// Appends printf output at *pos of str[size], never past the end.
__attribute__((format(printf, 4, 5))) void append(gchar *str, gulong size, gulong *pos,
                                                  const char *fmt, ...) {
  if (*pos >= size) return;
  va_list ap;
  va_start(ap, fmt);
  int n = g_vsnprintf(str + *pos, size - *pos, fmt, ap);
  va_end(ap);
  if (n > 0) *pos = std::min<gulong>(size, *pos + static_cast<gulong>(n));
}

}  // namespace

NNS_COMPAT_API gboolean nnsconf_loadconf(gboolean force_reload) {
  State &s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  if (force_reload) {
    nns::Conf::reload();
    fill_lists_locked(s);
  } else if (!s.loaded) {
    fill_lists_locked(s);
  }
  return TRUE;
}

NNS_COMPAT_API guint nnsconf_get_subplugin_info(nnsconf_type_path type, subplugin_info_s *info) {
  if (!info) return 0;
  info->names = info->paths = nullptr;
  if (!valid_type(type)) return 0;
  State &s = state();
  std::lock_guard<std::mutex> lock(s.mutex);
  Lists *l = lists_locked(s, type);
  info->names = l->name_ptrs.data();
  info->paths = l->path_ptrs.data();
  return static_cast<guint>(l->names.size());
}

NNS_COMPAT_API const gchar *nnsconf_get_fullpath(const gchar *subpluginname,
                                                 nnsconf_type_path type) {
  subplugin_info_s info;
  guint n = nnsconf_get_subplugin_info(type, &info);
  for (guint i = 0; i < n; ++i)
    if (g_strcmp0(info.names[i], subpluginname) == 0) return info.paths[i];
  return nullptr;
}

NNS_COMPAT_API gboolean nnsconf_validate_file(nnsconf_type_path type, const gchar *fullpath) {
  if (!fullpath || !valid_type(type)) return FALSE;
  if (!g_file_test(fullpath, G_FILE_TEST_IS_REGULAR)) return FALSE;
  if (!nns::Conf::get().symlinks_enabled() && g_file_test(fullpath, G_FILE_TEST_IS_SYMLINK))
    return FALSE;
  return TRUE;
}

NNS_COMPAT_API const gchar *nnsconf_get_subplugin_name_prefix(nnsconf_type_path type) {
  nns::SubpluginKind kind;
  if (!to_kind(type, &kind)) return nullptr;
  return nns::kind_prefix(kind).data();  // string literals
}

NNS_COMPAT_API gchar *nnsconf_get_custom_value_string(const gchar *group, const gchar *key) {
  if (!group || !key) return nullptr;
  auto v = nns::Conf::get().value(group, key);
  return v ? g_strdup(v->c_str()) : nullptr;
}

NNS_COMPAT_API gboolean nnsconf_get_custom_value_bool(const gchar *group, const gchar *key,
                                                      gboolean def) {
  gchar *v = nnsconf_get_custom_value_string(group, key);
  gboolean r = v ? (nns::parse_bool(v, def != FALSE) ? TRUE : FALSE) : def;
  g_free(v);
  return r;
}

NNS_COMPAT_API void nnsconf_dump(gchar *str, gulong size) {
  if (!str || size == 0) return;
  str[0] = '\0';
  const nns::Conf &c = nns::Conf::get();
  const char *env_conf = g_getenv(NNSTREAMER_ENVVAR_CONF_FILE);
  gulong pos = 0;
  append(str, size, &pos,
         "Configuration Loaded: TRUE\n"
         "Configuration file path: %s\n"
         "    Candidates: envvar(NNSTREAMER_CONF): %s\n"
         "                hard-coded: %s\n"
         "[Common]\n"
         "  Enable envvar: %s\n"
         "  Enable sym-linked subplugins: %s\n",
         c.path().empty() ? "<no configuration file>" : c.path().c_str(),
         env_conf ? env_conf : "(null)", NNSTREAMER_DEFAULT_CONF_FILE,
         c.env_enabled() ? "TRUE" : "FALSE", c.symlinks_enabled() ? "TRUE" : "FALSE");
  append(str, size, &pos, "[Filter]\n  Filter paths:");
  for (const auto &d : c.subplugin_dirs(nns::SubpluginKind::kFilter))
    append(str, size, &pos, " %s", d.c_str());
  append(str, size, &pos, "\n");
}

NNS_COMPAT_API void nnsconf_subplugin_dump(gchar *str, gulong size) {
  if (!str || size == 0) return;
  str[0] = '\0';
  static const struct {
    nnsconf_type_path type;
    const char *title;
  } kinds[] = {{NNSCONF_PATH_FILTERS, "Filter"},
               {NNSCONF_PATH_DECODERS, "Decoder"},
               {NNSCONF_PATH_CONVERTERS, "Converter"},
               {NNSCONF_PATH_TRAINERS, "Trainer"}};
  gulong pos = 0;
  for (const auto &k : kinds) {
    append(str, size, &pos, "\n[%s]\n", k.title);
    subplugin_info_s info;
    guint n = nnsconf_get_subplugin_info(k.type, &info);
    for (guint i = 0; i < n; ++i) append(str, size, &pos, "  %s\n", info.names[i]);
  }
}

// nnstreamer_log.h ----------------------------------------------------------------------------

NNS_COMPAT_API char *_backtrace_to_string(void) {
  void *frames[20];
  int n = backtrace(frames, 20);
  char **lines = backtrace_symbols(frames, n);
  if (!lines) return nullptr;
  std::string text;
  for (int i = 0; i < n; ++i) {
    text += lines[i];
    text += '\n';
  }
  std::free(lines);
  return strdup(text.c_str());
}

namespace {

struct LastError {
  std::mutex mutex;
  char text[4096] = {0};
  bool reported = false;
};

LastError &last_error() {
  static LastError *e = new LastError;  // _nnstreamer_error() hands out its buffer
  return *e;
}

}  // namespace

NNS_COMPAT_API const char *_nnstreamer_error(void) {
  LastError &e = last_error();
  std::lock_guard<std::mutex> lock(e.mutex);
  if (e.reported || e.text[0] == '\0') return nullptr;
  e.reported = true;
  return e.text;
}

NNS_COMPAT_API void _nnstreamer_error_write(const char *fmt, ...) {
  LastError &e = last_error();
  std::lock_guard<std::mutex> lock(e.mutex);
  va_list ap;
  va_start(ap, fmt);
  std::vsnprintf(e.text, sizeof e.text, fmt, ap);
  va_end(ap);
  e.reported = false;
}

NNS_COMPAT_API void _nnstreamer_error_clean(void) {
  LastError &e = last_error();
  std::lock_guard<std::mutex> lock(e.mutex);
  e.text[0] = '\0';
}

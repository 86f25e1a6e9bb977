/* SPDX-License-Identifier: LGPL-2.1-only */
/*
 * Logging macros and the last-error buffer of NNStreamer's nnstreamer_log.h (NNStreamer keeps
 * this header internal; nnstreamer-cpp installs it so sub-plugins written inside NNStreamer's
 * tree build unchanged). The functions are exported by libnnstreamer-single.so.
 */
#ifndef NNSTREAMER_CPP_NNSTREAMER_LOG_H_
#define NNSTREAMER_CPP_NNSTREAMER_LOG_H_

#include <glib.h>
#include <stdlib.h>

#define TAG_NAME "nnstreamer"

#define ml_logi g_info
#define ml_logw g_warning
#define ml_loge g_critical
#define ml_logd g_debug
#define ml_logf g_error

#ifdef __cplusplus
extern "C" {
#endif

/* The calling thread's stack as text (malloc'ed; free() it), or NULL. */
extern char *_backtrace_to_string(void);

/* Posts an element error whose debug text is the current stack. */
#define GST_ELEMENT_ERROR_BTRACE(s, errtype, errcode, mesg)         \
  do {                                                              \
    char *btrace = _backtrace_to_string();                          \
    if (btrace) {                                                   \
      GST_ELEMENT_ERROR(s, errtype, errcode, mesg, ("%s", btrace)); \
      free(btrace);                                                 \
    }                                                               \
  } while (0)

#define ml_log_stacktrace(logfunc, ...)    \
  do {                                     \
    char *btrace = _backtrace_to_string(); \
    if (btrace) {                          \
      logfunc("%s\n", btrace);             \
      free(btrace);                        \
    }                                      \
    logfunc(__VA_ARGS__);                  \
  } while (0)
#define ml_logf_stacktrace(...) ml_log_stacktrace(ml_logf, __VA_ARGS__)
#define ml_loge_stacktrace(...) ml_log_stacktrace(ml_loge, __VA_ARGS__)

/* The last message written with _nnstreamer_error_write(), once (NULL afterwards and when
 * there is none). The text stays owned by the library. */
extern const char *_nnstreamer_error(void);
/* Replaces the last message (printf format, at most 4095 bytes kept). */
extern void _nnstreamer_error_write(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
/* Empties the last message. */
extern void _nnstreamer_error_clean(void);

#define nns_logi ml_logi
#define nns_logw ml_logw
#define nns_loge ml_loge
#define nns_logd ml_logd
#define nns_logf ml_logf

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_CPP_NNSTREAMER_LOG_H_ */

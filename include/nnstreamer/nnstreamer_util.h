/* SPDX-License-Identifier: LGPL-2.1-only */
/* Small macros NNStreamer extensions use (same names as NNStreamer's nnstreamer_util.h). */
#ifndef NNSTREAMER_CPP_NNSTREAMER_UTIL_H_
#define NNSTREAMER_CPP_NNSTREAMER_UTIL_H_

/* Marks a parameter as deliberately unused. */
#ifndef UNUSED
#define UNUSED(expr) \
  do {               \
    (void)(expr);    \
  } while (0)
#endif

/* g_memdup2() where GLib has it (define GLIB_USE_G_MEMDUP2 with GLib >= 2.68), else g_memdup(). */
#if defined(GLIB_USE_G_MEMDUP2)
#define _g_memdup(data, size) g_memdup2(data, size)
#else
#define _g_memdup(data, size) g_memdup(data, size)
#endif

#endif /* NNSTREAMER_CPP_NNSTREAMER_UTIL_H_ */

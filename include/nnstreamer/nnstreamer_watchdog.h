/* SPDX-License-Identifier: LGPL-2.1-only */
/* NNStreamer 2.x's watchdog (nnstreamer_watchdog.h): a thread with its own GMainContext that
 * runs one timeout callback, as tensor_filter's suspend= uses it. Exported by
 * libnnstreamer-single.so and libnnstreamer.so. */
#ifndef NNSTREAMER_WATCHDOG_H_
#define NNSTREAMER_WATCHDOG_H_

#include <glib.h>

G_BEGIN_DECLS

typedef void *nns_watchdog_h;

/* Starts the thread and waits (up to 5 s) until its loop runs. */
gboolean nnstreamer_watchdog_create(nns_watchdog_h *watchdog_h);
/* Releases the pending callback, stops and joins the thread, frees the handle. */
void nnstreamer_watchdog_destroy(nns_watchdog_h watchdog_h);
/* Cancels the pending callback, if any. */
void nnstreamer_watchdog_release(nns_watchdog_h watchdog_h);
/* Calls func(user_data) on the watchdog thread after `interval` ms (again while it returns
 * TRUE). */
gboolean nnstreamer_watchdog_feed(nns_watchdog_h watchdog_h, GSourceFunc func, guint interval,
                                  void *user_data);

G_END_DECLS

#endif /* NNSTREAMER_WATCHDOG_H_ */

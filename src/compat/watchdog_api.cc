// SPDX-License-Identifier: LGPL-2.1-only
// nnstreamer_watchdog.h: a GLib main loop on its own thread running one timeout source at a time.
// Feeding again replaces the pending callback (NNStreamer keeps the older one scheduled too, and
// loses its reference).
#include "nnstreamer_watchdog.h"

#include <mutex>
#include <new>

#include "compat/compat_export.h"

namespace {

struct Watchdog {
  GMainContext *context = nullptr;
  GMainLoop *loop = nullptr;
  GThread *thread = nullptr;
  std::mutex mu;  // guards source
  GSource *source = nullptr;
};

gpointer watchdog_thread(gpointer p) {
  auto *w = static_cast<Watchdog *>(p);
  g_main_context_push_thread_default(w->context);
  g_main_loop_run(w->loop);
  g_main_context_pop_thread_default(w->context);
  return nullptr;
}

}  // namespace

NNS_COMPAT_API void nnstreamer_watchdog_release(nns_watchdog_h h) {
  auto *w = static_cast<Watchdog *>(h);
  if (!w) return;
  std::lock_guard lk(w->mu);
  if (w->source) {
    g_source_destroy(w->source);
    g_source_unref(w->source);
    w->source = nullptr;
  }
}

NNS_COMPAT_API void nnstreamer_watchdog_destroy(nns_watchdog_h h) {
  auto *w = static_cast<Watchdog *>(h);
  if (!w) return;
  nnstreamer_watchdog_release(w);
  if (w->thread) {
    g_main_loop_quit(w->loop);
    g_thread_join(w->thread);
  }
  g_main_loop_unref(w->loop);
  g_main_context_unref(w->context);
  delete w;
}

NNS_COMPAT_API gboolean nnstreamer_watchdog_create(nns_watchdog_h *watchdog_h) {
  if (!watchdog_h) {
    g_critical("nnstreamer_watchdog_create: the handle pointer is NULL");
    return FALSE;
  }
  *watchdog_h = nullptr;
  auto *w = new (std::nothrow) Watchdog;
  if (!w) return FALSE;
  w->context = g_main_context_new();
  w->loop = g_main_loop_new(w->context, FALSE);
  GError *err = nullptr;
  w->thread = g_thread_try_new("nns_watchdog", watchdog_thread, w, &err);
  if (!w->thread) {
    g_critical("nnstreamer_watchdog_create: cannot start the thread: %s",
               err ? err->message : "unknown error");
    g_clear_error(&err);
    nnstreamer_watchdog_destroy(w);
    return FALSE;
  }
  // As NNStreamer: return once the loop runs (up to 5 s).
  for (int i = 0; i < 5000 && !g_main_loop_is_running(w->loop); ++i) g_usleep(1000);
  if (!g_main_loop_is_running(w->loop)) {
    g_critical("nnstreamer_watchdog_create: the watchdog loop did not start");
    nnstreamer_watchdog_destroy(w);
    return FALSE;
  }
  *watchdog_h = w;
  return TRUE;
}

NNS_COMPAT_API gboolean nnstreamer_watchdog_feed(nns_watchdog_h h, GSourceFunc func, guint interval,
                                                 void *user_data) {
  auto *w = static_cast<Watchdog *>(h);
  if (!w || !func) {
    g_critical("nnstreamer_watchdog_feed: the watchdog handle or func is NULL");
    return FALSE;
  }
  nnstreamer_watchdog_release(w);
  std::lock_guard lk(w->mu);
  w->source = g_timeout_source_new(interval);
  g_source_set_callback(w->source, func, user_data, nullptr);
  g_source_attach(w->source, w->context);
  return TRUE;
}

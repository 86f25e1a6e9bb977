// SPDX-License-Identifier: LGPL-2.1-only
// GObject shell of the nnsprofile tracer: parses "params", owns the Profiler and forwards the
// core's tracer hooks to it. No exception crosses into GLib (every hook catches).
#include "profile/tracer.h"

#include <gst/gsttracer.h>

#include <cstring>
#include <exception>

#include "profile/profiler.h"

GST_DEBUG_CATEGORY_STATIC(nns_profile_debug);
#define GST_CAT_DEFAULT nns_profile_debug

struct NnsProfileTracer {
  GstTracer parent;
  nns::profile::Profiler *prof;
};
struct NnsProfileTracerClass {
  GstTracerClass parent_class;
};

G_DEFINE_TYPE(NnsProfileTracer, nns_profile_tracer, GST_TYPE_TRACER)

namespace {

using nns::profile::Profiler;

Profiler *prof_of(GObject *self) {
  return reinterpret_cast<NnsProfileTracer *>(self)->prof;
}

template <typename F>
void safely(F &&f) noexcept {
  try {
    f();
  } catch (const std::exception &e) {
    GST_WARNING("nnsprofile: %s", e.what());
  } catch (...) {
    GST_WARNING("nnsprofile: unknown exception");
  }
}

int64_t ts_of(GstClockTime ts) {
  return static_cast<int64_t>(ts);
}

void on_push_pre(GObject *self, GstClockTime ts, GstPad *pad, GstBuffer *buf) {
  safely([&] { prof_of(self)->push_pre(ts_of(ts), pad, buf, 1, gst_buffer_get_size(buf)); });
}

void on_push_post(GObject *self, GstClockTime ts, GstPad *pad, GstFlowReturn) {
  safely([&] { prof_of(self)->push_post(ts_of(ts), pad); });
}

void on_push_list_pre(GObject *self, GstClockTime ts, GstPad *pad, GstBufferList *list) {
  safely([&] {
    const guint n = gst_buffer_list_length(list);
    prof_of(self)->push_pre(ts_of(ts), pad, n ? gst_buffer_list_get(list, 0) : nullptr, n,
                            gst_buffer_list_calculate_size(list));
  });
}

void on_pull_pre(GObject *self, GstClockTime ts, GstPad *pad, guint64, guint) {
  safely([&] { prof_of(self)->pull_pre(ts_of(ts), pad); });
}

void on_pull_post(GObject *self, GstClockTime ts, GstPad *pad, GstBuffer *buf, GstFlowReturn r) {
  safely([&] { prof_of(self)->pull_post(ts_of(ts), pad, r == GST_FLOW_OK ? buf : nullptr); });
}

void on_element_new(GObject *self, GstClockTime, GstElement *e) {
  safely([&] { prof_of(self)->element_new(e); });
}

void on_bin_add_post(GObject *self, GstClockTime, GstBin *, GstElement *e, gboolean ok) {
  if (ok) safely([&] { prof_of(self)->element_new(e); });
}

void on_change_state_pre(GObject *self, GstClockTime, GstElement *e, GstStateChange t) {
  safely([&] { prof_of(self)->state_change_pre(e, t); });
}

void on_change_state_post(GObject *self, GstClockTime, GstElement *e, GstStateChange t,
                          GstStateChangeReturn) {
  safely([&] { prof_of(self)->state_change_post(e, t); });
}

}  // namespace

static void nns_profile_tracer_constructed(GObject *object) {
  G_OBJECT_CLASS(nns_profile_tracer_parent_class)->constructed(object);
  auto *self = reinterpret_cast<NnsProfileTracer *>(object);
  gchar *params = nullptr;
  g_object_get(object, "params", &params, nullptr);
  try {
    if (nns::profile::active_profiler()) {
      g_warning("nnsprofile: a tracer is already active in this process; this one stays off");
    } else {
      self->prof = new Profiler(nns::profile::parse_params(params));
    }
  } catch (const std::exception &e) {
    g_warning("%s", e.what());
  }
  g_free(params);
  if (!self->prof) return;
  nns::profile::set_active_profiler(self->prof);
  GstTracer *t = GST_TRACER(object);
  gst_tracing_register_hook(t, "pad-push-pre", G_CALLBACK(on_push_pre));
  gst_tracing_register_hook(t, "pad-push-post", G_CALLBACK(on_push_post));
  gst_tracing_register_hook(t, "pad-push-list-pre", G_CALLBACK(on_push_list_pre));
  gst_tracing_register_hook(t, "pad-push-list-post", G_CALLBACK(on_push_post));
  gst_tracing_register_hook(t, "pad-pull-range-pre", G_CALLBACK(on_pull_pre));
  gst_tracing_register_hook(t, "pad-pull-range-post", G_CALLBACK(on_pull_post));
  gst_tracing_register_hook(t, "element-new", G_CALLBACK(on_element_new));
  gst_tracing_register_hook(t, "bin-add-post", G_CALLBACK(on_bin_add_post));
  gst_tracing_register_hook(t, "element-change-state-pre", G_CALLBACK(on_change_state_pre));
  gst_tracing_register_hook(t, "element-change-state-post", G_CALLBACK(on_change_state_post));
  GST_INFO("nnsprofile: writing %s", self->prof->params().file.c_str());
}

static void nns_profile_tracer_finalize(GObject *object) {
  auto *self = reinterpret_cast<NnsProfileTracer *>(object);
  if (self->prof) {
    if (nns::profile::active_profiler() == self->prof) nns::profile::set_active_profiler(nullptr);
    safely([&] { delete self->prof; });
    self->prof = nullptr;
  }
  G_OBJECT_CLASS(nns_profile_tracer_parent_class)->finalize(object);
}

static void nns_profile_tracer_class_init(NnsProfileTracerClass *klass) {
  GObjectClass *oc = G_OBJECT_CLASS(klass);
  oc->constructed = nns_profile_tracer_constructed;
  oc->finalize = nns_profile_tracer_finalize;
}

static void nns_profile_tracer_init(NnsProfileTracer *self) {
  self->prof = nullptr;
}

gboolean nns_profile_tracer_register(GstPlugin *plugin) {
  GST_DEBUG_CATEGORY_INIT(nns_profile_debug, "nnsprofile", 0, "nnsprofile tracer");
  return gst_tracer_register(plugin, "nnsprofile", nns_profile_tracer_get_type());
}

namespace nns::profile {

bool activate(const char *params) {
  if (active_profiler()) return true;
  GList *tracers = gst_tracing_get_active_tracers();
  bool other = false;
  for (GList *l = tracers; l; l = l->next)
    if (!std::strcmp(G_OBJECT_TYPE_NAME(l->data), "NnsProfileTracer")) other = true;
  g_list_free_full(tracers, gst_object_unref);
  if (other) return true;  // one from the plugin module (GST_PLUGIN_PATH) is running
  gpointer t = g_object_new(nns_profile_tracer_get_type(), "params", params, nullptr);
  gst_object_ref_sink(t);
  gst_object_unref(t);  // the core's hook table keeps it until gst_deinit()
  return active_profiler() != nullptr;
}

void activate_from_env() {
  const char *env = g_getenv("GST_TRACERS");
  if (!env) return;
  gchar **items = g_strsplit(env, ";", 0);
  for (gchar **it = items; *it; ++it) {
    std::string s = *it;
    if (s.rfind("nnsprofile", 0) != 0) continue;
    std::string rest = s.substr(std::strlen("nnsprofile"));
    if (!rest.empty() && rest.front() != '(') continue;
    std::string params;
    if (!rest.empty()) {
      params = rest.substr(1);
      if (!params.empty() && params.back() == ')') params.pop_back();
    }
    activate(params.empty() ? nullptr : params.c_str());
    break;
  }
  g_strfreev(items);
}

std::string snapshot() {
  Profiler *p = active_profiler();
  return p ? p->snapshot_json("request") : std::string();
}

bool write_snapshot(const char *reason) {
  Profiler *p = active_profiler();
  return p && p->write_file(reason);
}

}  // namespace nns::profile

// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/element_glue.h"

namespace nns::gst {
namespace {

void domain_code(ErrorKind kind, GQuark *domain, gint *code) {
  switch (kind) {
    case ErrorKind::kSettings:
      *domain = GST_RESOURCE_ERROR;
      *code = GST_RESOURCE_ERROR_SETTINGS;
      return;
    case ErrorKind::kNotFound:
      *domain = GST_RESOURCE_ERROR;
      *code = GST_RESOURCE_ERROR_NOT_FOUND;
      return;
    case ErrorKind::kNegotiation:
      *domain = GST_CORE_ERROR;
      *code = GST_CORE_ERROR_NEGOTIATION;
      return;
    case ErrorKind::kStream:
      *domain = GST_STREAM_ERROR;
      *code = GST_STREAM_ERROR_FAILED;
      return;
    case ErrorKind::kLibrary:
      *domain = GST_LIBRARY_ERROR;
      *code = GST_LIBRARY_ERROR_INIT;
      return;
    case ErrorKind::kInternal:
      *domain = GST_CORE_ERROR;
      *code = GST_CORE_ERROR_FAILED;
      return;
  }
}

}  // namespace

void post_error(GstElement *element, ErrorKind kind, const std::string &text, const char *file,
                const char *func, int line) {
  GQuark domain = GST_CORE_ERROR;
  gint code = GST_CORE_ERROR_FAILED;
  domain_code(kind, &domain, &code);
  gchar *name = gst_object_get_name(GST_OBJECT(element));
  // The user text carries the whole actionable message; debug repeats it with the location.
  gchar *msg = g_strdup_printf("%s: %s", name ? name : "?", text.c_str());
  gchar *dbg = g_strdup(text.c_str());
  g_free(name);
  gst_element_message_full(element, GST_MESSAGE_ERROR, domain, code, msg, dbg, file, func, line);
}

void post_warning(GstElement *element, const std::string &text, const char *file, const char *func,
                  int line) {
  gchar *name = gst_object_get_name(GST_OBJECT(element));
  gchar *msg = g_strdup_printf("%s: %s", name ? name : "?", text.c_str());
  g_free(name);
  gst_element_message_full(element, GST_MESSAGE_WARNING, GST_CORE_ERROR, GST_CORE_ERROR_FAILED, msg,
                           g_strdup(text.c_str()), file, func, line);
}

}  // namespace nns::gst

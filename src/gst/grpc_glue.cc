// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/grpc_glue.h"

namespace nns::gst::grpc {

void install_properties(GObjectClass *klass, const Role &role) {
  const auto rw = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS);
  g_object_class_install_property(
      klass, kPropSilent,
      g_param_spec_boolean("silent", "Silent", "Dont' produce verbose output", TRUE, rw));
  g_object_class_install_property(
      klass, kPropServer,
      g_param_spec_boolean("server", "Server", "Specify its working mode either server or client",
                           role.default_server, rw));
  g_object_class_install_property(
      klass, kPropBlocking,
      g_param_spec_boolean("blocking", "Blocking",
                           "Specify its working mode either blocking or non-blocking", TRUE, rw));
  g_object_class_install_property(
      klass, kPropIdl,
      g_param_spec_string("idl", "IDL",
                          "Specify Interface Description Language (IDL) for communication",
                          kDefaultIdl, rw));
  g_object_class_install_property(
      klass, kPropHost, g_param_spec_string("host", "Host", role.host_blurb, kDefaultHost, rw));
  g_object_class_install_property(
      klass, kPropPort,
      g_param_spec_int("port", "Port", role.port_blurb, 0, G_MAXUINT16, kDefaultPort, rw));
  g_object_class_install_property(
      klass, kPropOut,
      g_param_spec_uint("out", "Out", role.out_blurb, 0, G_MAXUINT, 0,
                        static_cast<GParamFlags>(G_PARAM_READABLE | G_PARAM_STATIC_STRINGS)));
}

bool set_property(Settings &s, guint id, const GValue *value) {
  switch (id) {
    case kPropServer:
      s.server = g_value_get_boolean(value);
      return true;
    case kPropBlocking:
      s.blocking = g_value_get_boolean(value);
      return true;
    case kPropIdl:
      s.idl = g_value_get_string(value) ? g_value_get_string(value) : "";
      return true;
    case kPropHost: {
      const gchar *h = g_value_get_string(value);
      if (!h) return true;  // NULL: ignored, as upstream
      if (g_strcmp0(h, "localhost") == 0 || g_hostname_is_ip_address(h)) {
        s.host = h;
        s.refused_host.clear();
      } else {
        s.refused_host = h;
      }
      return true;
    }
    case kPropPort:
      s.port = g_value_get_int(value);
      return true;
    case kPropSilent:
      s.silent = g_value_get_boolean(value);
      return true;
    default:
      return false;
  }
}

bool get_property(const Settings &s, guint out, guint id, GValue *value) {
  switch (id) {
    case kPropServer:
      g_value_set_boolean(value, s.server);
      return true;
    case kPropBlocking:
      g_value_set_boolean(value, s.blocking);
      return true;
    case kPropIdl:
      g_value_set_string(value, s.idl.c_str());
      return true;
    case kPropHost:
      g_value_set_string(value, s.host.c_str());
      return true;
    case kPropPort:
      g_value_set_int(value, s.port);
      return true;
    case kPropOut:
      g_value_set_uint(value, out);
      return true;
    case kPropSilent:
      g_value_set_boolean(value, s.silent);
      return true;
    default:
      return false;
  }
}

grpclink::LinkOptions link_options(const Settings &s, grpclink::Direction direction) {
  if (!s.refused_host.empty())
    fail(ErrorKind::kSettings, "host '" + s.refused_host +
                                   "' was refused: expected localhost or an IP address (as "
                                   "NNStreamer); 'host' kept '" +
                                   s.host + "'");
  grpclink::LinkOptions o;
  o.role = s.server ? grpclink::Role::kServer : grpclink::Role::kClient;
  o.direction = direction;
  o.idl = parse_idl(s.idl);
  o.host = s.host;
  o.port = s.port;
  return o;
}

void record_bound_port(std::mutex &lock, Settings &s, const grpclink::Link &link) {
  std::lock_guard<std::mutex> l(lock);
  s.port = link.bound_port();
}

}  // namespace nns::gst::grpc

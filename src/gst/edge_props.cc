// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/edge_props.h"

#include "gst/edge_glue.h"

namespace nns::gst {

namespace {

const char *prop_name(ConnProp p) {
  switch (p) {
    case ConnProp::kHost:
      return "host";
    case ConnProp::kPort:
      return "port";
    case ConnProp::kDestHost:
      return "dest-host";
    case ConnProp::kDestPort:
      return "dest-port";
    case ConnProp::kConnectType:
      return "connect-type";
    case ConnProp::kTopic:
      return "topic";
    case ConnProp::kTimeout:
      return "timeout";
    case ConnProp::kCustomLib:
      return "custom-lib";
  }
  return "?";
}

struct StrField {
  std::string *value;
  bool *set;  // nullptr: not a nullable field
};

StrField str_field(ConnProp p, ConnSettings *s) {
  switch (p) {
    case ConnProp::kHost:
      return {&s->host, &s->host_set};
    case ConnProp::kDestHost:
      return {&s->dest_host, nullptr};
    case ConnProp::kTopic:
      return {&s->topic, &s->topic_set};
    case ConnProp::kCustomLib:
      return {&s->custom_lib, &s->custom_lib_set};
    default:
      return {nullptr, nullptr};
  }
}

bool is_uint(ConnProp p) {
  return p == ConnProp::kPort || p == ConnProp::kDestPort || p == ConnProp::kTimeout;
}

guint *uint_field(ConnProp p, ConnSettings *s) {
  switch (p) {
    case ConnProp::kPort:
      return &s->port;
    case ConnProp::kDestPort:
      return &s->dest_port;
    case ConnProp::kTimeout:
      return &s->timeout;
    default:
      return nullptr;
  }
}

}  // namespace

ConnPropDesc edge_connect_type_prop() {
  return {ConnProp::kConnectType,
          "Connect Type",
          "The connections type between edgesink and edgesrc.",
          nullptr,
          0,
          0,
          false,
          false,
          edge_connect_type_get_type};
}

ConnPropDesc edge_topic_prop() {
  return {ConnProp::kTopic,
          "Topic",
          "The main topic of the host and option if necessary. "
          "(topic)/(optional topic for main topic).",
          nullptr,
          0,
          0,
          true};
}

ConnPropDesc edge_custom_lib_prop() {
  return {ConnProp::kCustomLib,
          "Custom connection lib path",
          "User defined custom connection lib path.",
          nullptr,
          0,
          0,
          true};
}

edge::NodeOptions ConnSettings::node_options(edge::Role role) const {
  edge::NodeOptions o;
  o.role = role;
  o.host = host;
  o.port = static_cast<uint16_t>(port);
  o.dest_host = dest_host;  // the peer (TCP) or the MQTT broker (MQTT, HYBRID)
  o.dest_port = static_cast<uint16_t>(dest_port);
  o.topic = topic;
  o.custom_lib = custom_lib;
  return o;
}

ConnPropTable::ConnPropTable(guint first_id, std::initializer_list<ConnPropDesc> props)
    : first_(first_id), props_(props) {}

const ConnPropDesc *ConnPropTable::find(guint id) const {
  if (id < first_ || id >= first_ + props_.size()) return nullptr;
  return &props_[id - first_];
}

void ConnPropTable::install(GObjectClass *klass) const {
  for (std::size_t i = 0; i < props_.size(); ++i) {
    const ConnPropDesc &d = props_[i];
    auto flags = static_cast<GParamFlags>(G_PARAM_READWRITE | G_PARAM_STATIC_STRINGS |
                                          (d.deprecated ? G_PARAM_DEPRECATED : 0));
    const char *name = prop_name(d.which);
    GParamSpec *spec = nullptr;
    if (d.which == ConnProp::kConnectType)
      spec = g_param_spec_enum(name, d.nick, d.blurb, d.enum_type(), 0, flags);
    else if (is_uint(d.which))
      spec = g_param_spec_uint(name, d.nick, d.blurb, 0, d.uint_max, d.uint_default, flags);
    else
      spec = g_param_spec_string(name, d.nick, d.blurb, d.str_default, flags);
    g_object_class_install_property(klass, first_ + static_cast<guint>(i), spec);
  }
}

ConnSettings ConnPropTable::defaults() const {
  ConnSettings s;
  for (const ConnPropDesc &d : props_) {
    if (guint *u = uint_field(d.which, &s)) *u = d.uint_default;
    if (StrField f = str_field(d.which, &s); f.value && d.str_default) *f.value = d.str_default;
  }
  return s;
}

bool ConnPropTable::set(guint id, const GValue *value, ConnSettings *s) const {
  const ConnPropDesc *d = find(id);
  if (!d) return false;
  if (d->which == ConnProp::kConnectType) {
    s->connect_type = g_value_get_enum(value);
  } else if (guint *u = uint_field(d->which, s)) {
    *u = g_value_get_uint(value);
  } else {
    StrField f = str_field(d->which, s);
    const gchar *v = g_value_get_string(value);
    if (d->nullable && f.set) {
      *f.set = v != nullptr;
      *f.value = v ? v : "";
    } else if (v) {
      *f.value = v;
    }
  }
  return true;
}

bool ConnPropTable::get(guint id, GValue *value, const ConnSettings &s) const {
  const ConnPropDesc *d = find(id);
  if (!d) return false;
  auto &m = const_cast<ConnSettings &>(s);  // the field helpers take a mutable pointer
  if (d->which == ConnProp::kConnectType) {
    g_value_set_enum(value, s.connect_type);
  } else if (guint *u = uint_field(d->which, &m)) {
    g_value_set_uint(value, *u);
  } else {
    StrField f = str_field(d->which, &m);
    const bool null = d->nullable && f.set && !*f.set;
    g_value_set_string(value, null ? nullptr : f.value->c_str());
  }
  return true;
}

}  // namespace nns::gst

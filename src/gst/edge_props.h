// SPDX-License-Identifier: LGPL-2.1-only
// The connection properties of the among-device elements (edgesrc, edgesink,
// tensor_query_client, tensor_query_serversrc, tensor_query_serversink): host, port,
// dest-host, dest-port, connect-type, topic, timeout, custom-lib. Each element lists the ones it
// has, with upstream's defaults, ranges and blurbs for that element, in a ConnPropTable; the
// table installs them and does set/get into a ConnSettings, so the elements keep only their
// own properties.
#pragma once

#include <gst/gst.h>

#include <initializer_list>
#include <string>
#include <vector>

#include "edge/edge_node.h"

namespace nns::gst {

enum class ConnProp {
  kHost,
  kPort,
  kDestHost,
  kDestPort,
  kConnectType,
  kTopic,
  kTimeout,
  kCustomLib
};

struct ConnSettings {
  std::string host, dest_host, topic, custom_lib;
  bool host_set = false, topic_set = false, custom_lib_set = false;  // nullable strings
  guint port = 0, dest_port = 0, timeout = 0;
  gint connect_type = 0;

  // host, port, dest-host, dest-port, topic and custom-lib for a node of `role`.
  edge::NodeOptions node_options(edge::Role role) const;
  edge::ConnectType type() const { return static_cast<edge::ConnectType>(connect_type); }
};

// One property of an element. Strings: `nullable` ones (default NULL) read back NULL until set
// and can be reset to NULL; the others ignore a NULL and read back `str_default` until set.
struct ConnPropDesc {
  ConnProp which;
  const char *nick;
  const char *blurb;
  const char *str_default = nullptr;
  guint uint_default = 0, uint_max = 65535;
  bool nullable = false;
  bool deprecated = false;
  GType (*enum_type)() = nullptr;  // connect-type: the element's GEnum
};

// connect-type, topic and custom-lib as edgesrc and edgesink both have them (same texts).
ConnPropDesc edge_connect_type_prop();
ConnPropDesc edge_topic_prop();
ConnPropDesc edge_custom_lib_prop();

class ConnPropTable {
 public:
  // The properties get the ids first_id, first_id + 1, ... in the order given.
  ConnPropTable(guint first_id, std::initializer_list<ConnPropDesc> props);
  void install(GObjectClass *klass) const;
  // The defaults of every listed property.
  ConnSettings defaults() const;
  // False when `id` is not one of the table's (the element handles it).
  bool set(guint id, const GValue *value, ConnSettings *s) const;
  bool get(guint id, GValue *value, const ConnSettings &s) const;

 private:
  const ConnPropDesc *find(guint id) const;
  guint first_;
  std::vector<ConnPropDesc> props_;
};

}  // namespace nns::gst

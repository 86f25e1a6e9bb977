// SPDX-License-Identifier: LGPL-2.1-only
// The transport interface of the among-device elements. A ServerNode is the query server or
// the publisher (edgesink); a ClientNode is the query client or the subscriber (edgesrc).
// make_server()/make_client() pick the implementation for a connect type: TCP lives in
// edge_tcp.cc, HYBRID (MQTT discovery + TCP) in edge_hybrid.cc, MQTT (publish/subscribe through
// a broker, publisher and subscriber only) in edge_mqtt.cc, CUSTOM (a connection library with
// nnstreamer-edge's custom ABI, publisher and subscriber only) in edge_custom.cc.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <string>

#include "edge/edge_io.h"

namespace nns::edge {

// Values of nnstreamer-edge's nns_edge_connect_type_e (and of the elements' enums).
enum class ConnectType { kTcp = 0, kMqtt = 1, kHybrid = 2, kCustom = 3 };
const char *connect_type_name(ConnectType t);

enum class Role { kQueryServer, kQueryClient, kPublisher, kSubscriber };

// How a client session ended: the server said goodbye (an ERROR command), the connection
// broke, or the server sent bytes that are not a valid frame.
enum class CloseKind { kGoodbye, kBroken, kProtocol };

struct NodeOptions {
  Role role = Role::kQueryServer;
  std::string host = "localhost";  // our listening address (servers, query client)
  uint16_t port = 0;               // 0: any free port
  std::string dest_host = "localhost";
  uint16_t dest_port = 0;
  std::string topic;
  Limits limits;
  int connect_timeout_ms = 5000;  // connecting and waiting for the handshake
  std::string custom_lib;         // CUSTOM: the connection library (dlopen path)
};

struct NodeCallbacks {
  // A TRANSFER_DATA frame; for servers `meta` carries "client_id" of the sender.
  std::function<void(Message &&)> on_data;
  // A peer misbehaved or went away; the text names the peer and what was wrong.
  std::function<void(const std::string &)> on_warning;
  // Client side: the session ended, and how.
  std::function<void(const std::string &, CloseKind)> on_closed;
  // Server side: a client completed the handshake.
  std::function<void(int64_t, const std::string &)> on_connected;
  // Server side: the capability string sent to each new client.
  std::function<std::string()> caps;
  // Client side: checks the server's capability string; returns an error text to refuse it.
  std::function<std::optional<std::string>(const std::string &)> accept_caps;
  // Where received memories are written (default: heap).
  Allocator alloc;
};

class ServerNode {
 public:
  virtual ~ServerNode() = default;
  virtual void start() = 0;  // throws nns::Error naming host:port
  virtual uint16_t port() const = 0;
  // Query server: the answer for one client. False when that client is gone.
  virtual bool send_to(int64_t client_id, const OutFrame &frame, std::string *why) = 0;
  // Publisher: every subscriber; returns how many got it.
  virtual std::size_t broadcast(const OutFrame &frame) = 0;
  virtual std::size_t client_count() const = 0;
  virtual void stop() = 0;
};

class ClientNode {
 public:
  virtual ~ClientNode() = default;
  // Opens a session (listener, connection, handshake). Throws nns::Error naming the server.
  virtual void connect() = 0;
  virtual bool connected() const = 0;
  virtual bool send(const OutFrame &frame, std::string *why) = 0;
  virtual int64_t client_id() const = 0;
  virtual std::string server_caps() const = 0;
  virtual std::string server_name() const = 0;  // "host:port"
  virtual void disconnect() = 0;
};

std::unique_ptr<ServerNode> make_server(ConnectType type, const NodeOptions &opts,
                                        NodeCallbacks cb);
std::unique_ptr<ClientNode> make_client(ConnectType type, const NodeOptions &opts,
                                        NodeCallbacks cb);

// HYBRID implementations (edge_hybrid.cc): MQTT discovery at dest-host:dest-port, TCP data.
std::unique_ptr<ServerNode> make_hybrid_server(const NodeOptions &opts, NodeCallbacks cb);
std::unique_ptr<ClientNode> make_hybrid_client(const NodeOptions &opts, NodeCallbacks cb);

// MQTT implementations (edge_mqtt.cc): broker at dest-host:dest-port, Role kPublisher /
// kSubscriber only.
std::unique_ptr<ServerNode> make_mqtt_server(const NodeOptions &opts, NodeCallbacks cb);
std::unique_ptr<ClientNode> make_mqtt_client(const NodeOptions &opts, NodeCallbacks cb);

// CUSTOM implementations (edge_custom.cc): opts.custom_lib, Role kPublisher / kSubscriber.
std::unique_ptr<ServerNode> make_custom_server(const NodeOptions &opts, NodeCallbacks cb);
std::unique_ptr<ClientNode> make_custom_client(const NodeOptions &opts, NodeCallbacks cb);

// TCP implementations (edge_tcp.cc).
std::unique_ptr<ServerNode> make_tcp_server(const NodeOptions &opts, NodeCallbacks cb);
std::unique_ptr<ClientNode> make_tcp_client(const NodeOptions &opts, NodeCallbacks cb);

}  // namespace nns::edge

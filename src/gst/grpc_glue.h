// SPDX-License-Identifier: LGPL-2.1-only
// What tensor_src_grpc and tensor_sink_grpc share: NNStreamer's defaults, the caps template, the
// properties both have (settings, install, set, get), the link options and the conversion
// between a negotiated tensors config and a gRPC frame.
#pragma once

#include <gst/gst.h>

#include <mutex>
#include <string>

#include "core/error.h"
#include "core/tensor_info.h"
#include "grpc/tensor_link.h"

namespace nns::gst::grpc {

inline constexpr char kDefaultHost[] = "localhost";
inline constexpr int kDefaultPort = 55115;
inline constexpr char kDefaultIdl[] = "protobuf";

#define NNS_GRPC_CAPS_STR                                                     \
  "other/tensor, framerate = (fraction) [ 0, max ]; "                         \
  "other/tensors, format = (string) static, num_tensors = (int) [ 1, 256 ], " \
  "framerate = (fraction) [ 0, max ]"

// How the two elements' properties differ (upstream's defaults and texts).
struct Role {
  bool default_server;
  const char *host_blurb;
  const char *port_blurb;
  const char *out_blurb;
};
inline constexpr Role kSinkRole{false, "The host/IP to send the packets to",
                                "The port to send the packets to",
                                "The number of output messages generated"};
inline constexpr Role kSrcRole{true, "The hostname to listen as or connect",
                               "The port to listen to (0=random available port) or connect",
                               "The number of output buffers generated"};

enum Prop : guint {
  kPropServer = 1,
  kPropBlocking,
  kPropIdl,
  kPropHost,
  kPropPort,
  kPropOut,
  kPropSilent
};

struct Settings {
  explicit Settings(const Role &r) : server(r.default_server) {}
  bool server;
  bool blocking = true;
  std::string idl = kDefaultIdl;
  std::string host = kDefaultHost;
  // A host that is neither "localhost" nor an IP address is refused when set, as NNStreamer
  // (host keeps its value); starting then fails naming it.
  std::string refused_host;
  int port = kDefaultPort;
  bool silent = true;
};

// Installs silent, server, blocking, idl, host, port and the read-only out.
void install_properties(GObjectClass *klass, const Role &role);
// Set / get a property of `s` (`out`: the element's counter); false for an unknown id.
bool set_property(Settings &s, guint id, const GValue *value);
bool get_property(const Settings &s, guint out, guint id, GValue *value);

// idl: protobuf or flatbuf (upstream's values).
inline grpclink::Idl parse_idl(const std::string &idl) {
  if (idl == "protobuf") return grpclink::Idl::kProtobuf;
  if (idl == "flatbuf") return grpclink::Idl::kFlatbuf;
  fail(ErrorKind::kSettings, "idl '" + idl + "' is not one of protobuf, flatbuf");
}

// The tensors config a received frame describes.
inline TensorsConfig config_of(const grpclink::Frame &f) {
  TensorsConfig c;
  c.info.format = TensorFormat::kStatic;
  for (const auto &t : f.tensors) {
    TensorInfo i;
    i.type = static_cast<TensorType>(t.type);
    for (std::size_t k = 0; k < t.dims.size() && k < kRankLimit; ++k) i.dims[k] = t.dims[k];
    c.info.tensors.push_back(i);
  }
  c.rate_n = f.rate_n;
  c.rate_d = f.rate_d > 0 ? f.rate_d : 1;
  return c;
}

// The link the settings ask for; throws nns::Error for a bad idl.
grpclink::LinkOptions link_options(const Settings &s, grpclink::Direction direction);

// After a server's start(): its `port` property shows the port bound (port=0 picks one).
void record_bound_port(std::mutex &lock, Settings &s, const grpclink::Link &link);

}  // namespace nns::gst::grpc

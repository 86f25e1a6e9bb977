// SPDX-License-Identifier: LGPL-2.1-only
// What tensor_src_grpc and tensor_sink_grpc share: NNStreamer's defaults, the caps template and
// the conversion between a negotiated tensors config and a gRPC frame.
#pragma once

#include <gst/gst.h>

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

}  // namespace nns::gst::grpc

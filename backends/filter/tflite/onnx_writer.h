// SPDX-License-Identifier: LGPL-2.1-only
// A minimal writer of ONNX ModelProto bytes (protobuf wire format), enough for the graphs the
// tflite back end builds in memory and hands to ONNX Runtime (CreateSessionFromArray). Field
// numbers are those of onnx.proto (a format fact); only the fields we emit are known here.
#pragma once

#include <cstdint>
#include <cstring>
#include <string>
#include <string_view>
#include <vector>

#include "../common/onnx_types.h"

namespace nns::onnx {

// Protobuf message under construction.
class Msg {
 public:
  Msg &varint(int field, uint64_t v) {
    key(field, 0);
    put_varint(v);
    return *this;
  }
  Msg &bytes(int field, std::string_view b) {
    key(field, 2);
    put_varint(b.size());
    buf_.append(b);
    return *this;
  }
  Msg &msg(int field, const Msg &m) { return bytes(field, m.buf_); }
  Msg &f32(int field, float f) {
    key(field, 5);
    char b[4];
    std::memcpy(b, &f, 4);
    buf_.append(b, 4);
    return *this;
  }
  const std::string &str() const { return buf_; }

 private:
  void key(int field, int wire) { put_varint((static_cast<uint64_t>(field) << 3) | wire); }
  void put_varint(uint64_t v) {
    while (v >= 0x80) {
      buf_.push_back(static_cast<char>((v & 0x7f) | 0x80));
      v >>= 7;
    }
    buf_.push_back(static_cast<char>(v));
  }
  std::string buf_;
};

// AttributeProto builders.
inline Msg attr_int(std::string_view name, int64_t v) {
  Msg a;
  a.bytes(1, name).varint(3, static_cast<uint64_t>(v)).varint(20, 2);  // INT
  return a;
}
inline Msg attr_float(std::string_view name, float v) {
  Msg a;
  a.bytes(1, name).f32(2, v).varint(20, 1);  // FLOAT
  return a;
}
inline Msg attr_str(std::string_view name, std::string_view v) {
  Msg a;
  a.bytes(1, name).bytes(4, v).varint(20, 3);  // STRING
  return a;
}
inline Msg attr_ints(std::string_view name, const std::vector<int64_t> &v) {
  Msg a;
  a.bytes(1, name);
  for (int64_t x : v) a.varint(8, static_cast<uint64_t>(x));
  a.varint(20, 7);  // INTS
  return a;
}

// GraphProto under construction plus the ModelProto wrapper.
class Graph {
 public:
  void node(std::string_view op, const std::vector<std::string> &in,
            const std::vector<std::string> &out, const std::vector<Msg> &attrs = {},
            std::string_view domain = {}) {
    Msg n;
    for (auto &s : in) n.bytes(1, s);
    for (auto &s : out) n.bytes(2, s);
    n.bytes(3, "n" + std::to_string(nodes_++));
    n.bytes(4, op);
    for (auto &a : attrs) n.msg(5, a);
    if (!domain.empty()) n.bytes(7, domain);
    g_.msg(1, n);
  }
  // Constant tensor (raw little-endian data).
  void initializer(const std::string &name, int type, const std::vector<int64_t> &dims,
                   const void *data, std::size_t bytes) {
    Msg t;
    for (int64_t d : dims) t.varint(1, static_cast<uint64_t>(d));
    t.varint(2, static_cast<uint64_t>(type));
    t.bytes(8, name);
    t.bytes(9, std::string_view(static_cast<const char *>(data), bytes));
    g_.msg(5, t);
  }
  // Graph input/output. dims < 0 are free (named), an empty `dims` with `known_rank` false
  // leaves the shape unspecified.
  void input(const std::string &name, int type, const std::vector<int64_t> &dims) {
    g_.msg(11, value_info(name, type, dims, true));
  }
  void output(const std::string &name, int type, const std::vector<int64_t> &dims,
              bool known_shape) {
    g_.msg(12, value_info(name, type, dims, known_shape));
  }
  // ModelProto bytes: ir_version 8, default domain at `opset`, com.microsoft at 1.
  std::string model(int opset) const {
    Msg g = g_;
    g.bytes(2, "tflite");
    Msg m;
    m.varint(1, 8);
    m.bytes(2, "nnstreamer-cpp tflite");
    m.msg(7, g);
    Msg os;
    os.bytes(1, "").varint(2, static_cast<uint64_t>(opset));
    m.msg(8, os);
    Msg ms;
    ms.bytes(1, "com.microsoft").varint(2, 1);
    m.msg(8, ms);
    return m.str();
  }

 private:
  static Msg value_info(const std::string &name, int type, const std::vector<int64_t> &dims,
                        bool known_shape) {
    Msg tt;
    tt.varint(1, static_cast<uint64_t>(type));
    if (known_shape) {
      Msg shape;
      int k = 0;
      for (int64_t d : dims) {
        Msg dim;
        if (d >= 0)
          dim.varint(1, static_cast<uint64_t>(d));
        else
          dim.bytes(2, name + "_d" + std::to_string(k));
        shape.msg(1, dim);
        ++k;
      }
      tt.msg(2, shape);
    }
    Msg type_proto;
    type_proto.msg(1, tt);
    Msg vi;
    vi.bytes(1, name).msg(2, type_proto);
    return vi;
  }
  Msg g_;
  int nodes_ = 0;
};

}  // namespace nns::onnx

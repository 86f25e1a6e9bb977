// SPDX-License-Identifier: LGPL-2.1-only
#include "onnx_model_info.h"

#include <fstream>
#include <iterator>
#include <set>
#include <stdexcept>
#include <string_view>

namespace nns::onnx {
namespace {

// A view over one protobuf message: iterates its fields.
class Reader {
 public:
  Reader(const uint8_t *p, std::size_t n) : p_(p), end_(p + n) {}

  // Reads the next field header; false at the end of the message.
  bool next(uint32_t &field, uint32_t &wire) {
    if (p_ >= end_) return false;
    uint64_t key = varint();
    field = static_cast<uint32_t>(key >> 3);
    wire = static_cast<uint32_t>(key & 7);
    return true;
  }
  uint64_t varint() {
    uint64_t v = 0;
    for (int shift = 0; shift < 64; shift += 7) {
      if (p_ >= end_) throw std::runtime_error("truncated varint");
      uint8_t b = *p_++;
      v |= static_cast<uint64_t>(b & 0x7f) << shift;
      if (!(b & 0x80)) return v;
    }
    throw std::runtime_error("varint too long");
  }
  Reader sub() {
    uint64_t n = varint();
    if (n > static_cast<uint64_t>(end_ - p_)) throw std::runtime_error("truncated field");
    Reader r(p_, n);
    p_ += n;
    return r;
  }
  std::string str() {
    Reader r = sub();
    return std::string(reinterpret_cast<const char *>(r.p_), r.end_ - r.p_);
  }
  void skip(uint32_t wire) {
    switch (wire) {
      case 0:
        varint();
        break;
      case 1:
        advance(8);
        break;
      case 2:
        sub();
        break;
      case 5:
        advance(4);
        break;
      default:
        throw std::runtime_error("unsupported protobuf wire type " + std::to_string(wire));
    }
  }

 private:
  void advance(std::size_t n) {
    if (n > static_cast<std::size_t>(end_ - p_)) throw std::runtime_error("truncated field");
    p_ += n;
  }
  const uint8_t *p_;
  const uint8_t *end_;
};

// TensorShapeProto.Dimension: dim_value = 1, dim_param = 2.
int64_t parse_dim(Reader r) {
  int64_t v = -1;
  uint32_t f, w;
  while (r.next(f, w)) {
    if (f == 1 && w == 0)
      v = static_cast<int64_t>(r.varint());
    else
      r.skip(w);
  }
  return v > 0 ? v : -1;
}

// TypeProto.Tensor: elem_type = 1, shape = 2 (TensorShapeProto: dim = 1).
void parse_tensor_type(Reader r, ValueInfo &vi) {
  uint32_t f, w;
  vi.is_tensor = true;
  while (r.next(f, w)) {
    if (f == 1 && w == 0) {
      vi.elem_type = static_cast<int32_t>(r.varint());
    } else if (f == 2 && w == 2) {
      Reader shape = r.sub();
      uint32_t sf, sw;
      while (shape.next(sf, sw)) {
        if (sf == 1 && sw == 2)
          vi.shape.push_back(parse_dim(shape.sub()));
        else
          shape.skip(sw);
      }
    } else {
      r.skip(w);
    }
  }
}

// ValueInfoProto: name = 1, type = 2 (TypeProto: tensor_type = 1).
ValueInfo parse_value_info(Reader r) {
  ValueInfo vi;
  uint32_t f, w;
  while (r.next(f, w)) {
    if (f == 1 && w == 2) {
      vi.name = r.str();
    } else if (f == 2 && w == 2) {
      Reader type = r.sub();
      uint32_t tf, tw;
      while (type.next(tf, tw)) {
        if (tf == 1 && tw == 2)
          parse_tensor_type(type.sub(), vi);
        else
          type.skip(tw);
      }
    } else {
      r.skip(w);
    }
  }
  return vi;
}

// TensorProto: name = 8.
std::string tensor_name(Reader r) {
  uint32_t f, w;
  std::string name;
  while (r.next(f, w)) {
    if (f == 8 && w == 2)
      name = r.str();
    else
      r.skip(w);
  }
  return name;
}

}  // namespace

GraphInfo parse_graph_info(const uint8_t *data, std::size_t size) {
  Reader model(data, size);
  uint32_t f, w;
  bool found = false;
  GraphInfo g;
  std::set<std::string> initializers;
  while (model.next(f, w)) {
    if (f != 7 || w != 2) {  // ModelProto.graph = 7
      model.skip(w);
      continue;
    }
    found = true;
    Reader graph = model.sub();
    uint32_t gf, gw;
    while (graph.next(gf, gw)) {
      if (gf == 11 && gw == 2)  // GraphProto.input
        g.inputs.push_back(parse_value_info(graph.sub()));
      else if (gf == 12 && gw == 2)  // GraphProto.output
        g.outputs.push_back(parse_value_info(graph.sub()));
      else if (gf == 5 && gw == 2)  // GraphProto.initializer
        initializers.insert(tensor_name(graph.sub()));
      else
        graph.skip(gw);
    }
  }
  if (!found) throw std::runtime_error("no graph in the ONNX model");
  std::erase_if(g.inputs, [&](const ValueInfo &v) { return initializers.count(v.name) > 0; });
  return g;
}

GraphInfo read_graph_info(const std::string &path) {
  std::ifstream f(path, std::ios::binary);
  if (!f) throw std::runtime_error(path + ": cannot open");
  std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(f)), {});
  try {
    return parse_graph_info(bytes.data(), bytes.size());
  } catch (const std::runtime_error &e) {
    throw std::runtime_error(path + ": not a readable ONNX model (" + e.what() + ")");
  }
}

}  // namespace nns::onnx

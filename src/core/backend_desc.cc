// SPDX-License-Identifier: LGPL-2.1-only
#include "core/backend_desc.h"

#include <cstring>

#include "core/error.h"

namespace nns {

std::size_t desc_rank(const nns_tensor_desc &d) {
  std::size_t r = 0;
  while (r < NNS_TENSOR_RANK_LIMIT && d.dims[r] != 0) ++r;
  return r;
}

bool desc_names_only(const nns_tensors_desc &d) {
  if (d.num_tensors == 0 || d.num_tensors > NNS_TENSOR_SIZE_LIMIT) return false;
  for (uint32_t i = 0; i < d.num_tensors; ++i)
    if (d.tensors[i].type < _NNS_END || desc_rank(d.tensors[i]) != 0) return false;
  return true;
}

TensorType desc_type(const nns_tensor_desc &d) {
  return d.type < kNumTypes ? static_cast<TensorType>(d.type) : TensorType::kEnd;
}

std::vector<int64_t> shape_of(const nns_tensor_desc &d, std::size_t rank) {
  std::size_t r = desc_rank(d);
  for (std::size_t i = rank; i < r; ++i)
    if (d.dims[i] != 1)
      fail(ErrorKind::kSettings, "tensor " + desc_string(d) + " has rank " + std::to_string(r) +
                                     " but the model's tensor has rank " + std::to_string(rank));
  std::vector<int64_t> shape(rank, 1);
  for (std::size_t i = 0; i < rank && i < r; ++i) shape[rank - 1 - i] = d.dims[i];
  return shape;
}

void set_dims(nns_tensor_desc &d, const std::vector<int64_t> &shape, uint32_t free_as) {
  std::memset(d.dims, 0, sizeof(d.dims));
  std::size_t rank = shape.size();
  if (rank > NNS_TENSOR_RANK_LIMIT)
    fail(ErrorKind::kSettings, "shape " + shape_string(shape) + " has rank " +
                                   std::to_string(rank) + ", the limit is " +
                                   std::to_string(NNS_TENSOR_RANK_LIMIT));
  for (std::size_t i = 0; i < rank; ++i) {
    int64_t v = shape[rank - 1 - i];
    d.dims[i] = v < 0 ? free_as : static_cast<uint32_t>(v);
  }
  // A rank-0 (scalar) tensor is one element.
  if (rank == 0) d.dims[0] = 1;
}

std::size_t desc_bytes(const nns_tensor_desc &d) {
  Dims dims{};
  std::memcpy(dims.data(), d.dims, sizeof(d.dims));
  return element_count(dims) * type_size(desc_type(d));
}

bool desc_dims_equal(const nns_tensor_desc &a, const nns_tensor_desc &b) {
  Dims x{}, y{};
  std::memcpy(x.data(), a.dims, sizeof(a.dims));
  std::memcpy(y.data(), b.dims, sizeof(b.dims));
  return dims_equal(x, y);
}

std::string desc_string(const nns_tensor_desc &d, bool with_name) {
  Dims dims{};
  std::memcpy(dims.data(), d.dims, sizeof(d.dims));
  std::string s = std::string(type_name(desc_type(d))) + " " + dims_to_string(dims);
  std::size_t n = strnlen(d.name, NNS_TENSOR_NAME_MAX);
  return n && with_name ? "'" + std::string(d.name, n) + "' " + s : s;
}

std::string desc_dims_string(const nns_tensor_desc &d) {
  Dims dims{};
  std::memcpy(dims.data(), d.dims, sizeof(d.dims));
  return dims_to_string(dims);
}

std::string shape_string(const std::vector<int64_t> &shape) {
  std::string s = "[";
  for (std::size_t i = 0; i < shape.size(); ++i) {
    if (i) s += ",";
    s += shape[i] < 0 ? std::string("?") : std::to_string(shape[i]);
  }
  return s + "]";
}

void set_name(nns_tensor_desc &d, const std::string &name) {
  std::memset(d.name, 0, sizeof(d.name));
  std::strncpy(d.name, name.c_str(), NNS_TENSOR_NAME_MAX - 1);
}

}  // namespace nns

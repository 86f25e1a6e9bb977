// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_concat.h"

#include <cstring>

#include "core/error.h"

namespace nns {
namespace {

uint32_t dim_at(const Dims &d, std::size_t i) {
  return d[i] == 0 ? 1 : d[i];
}

// Dims with every entry up to `upto` made explicit (0 -> 1), so the rank covers `upto`.
Dims extend(const Dims &d, std::size_t upto) {
  Dims out = d;
  for (std::size_t i = 0; i <= upto && i < kRankLimit; ++i) out[i] = dim_at(d, i);
  return out;
}

}  // namespace

TensorInfo concat_info(const std::vector<TensorInfo> &in, std::size_t dim,
                       const std::vector<std::string> &names) {
  if (in.empty()) fail(ErrorKind::kNegotiation, "no input tensors to concatenate");
  if (dim >= kRankLimit)
    fail(ErrorKind::kSettings, "dimension index " + std::to_string(dim) + " is outside 0.." +
                                   std::to_string(kRankLimit - 1));
  auto name = [&](std::size_t i) {
    return i < names.size() ? names[i] : "tensor " + std::to_string(i);
  };
  TensorInfo out;
  out.type = in[0].type;
  out.dims = extend(in[0].dims, dim);
  for (std::size_t k = 1; k < in.size(); ++k) {
    if (in[k].type != out.type)
      fail(ErrorKind::kNegotiation,
           name(k) + " has type " + std::string(type_name(in[k].type)) + " but " + name(0) +
               " has " + std::string(type_name(out.type)) + ": merged tensors need one type");
    for (std::size_t j = 0; j < kRankLimit; ++j) {
      if (j == dim) continue;
      if (dim_at(in[k].dims, j) != dim_at(in[0].dims, j))
        fail(ErrorKind::kNegotiation,
             name(k) + " has dimensions " + dims_to_string(in[k].dims) + " but " + name(0) +
                 " has " + dims_to_string(in[0].dims) + ": dimension " + std::to_string(j) +
                 " differs (" + std::to_string(dim_at(in[k].dims, j)) + " vs " +
                 std::to_string(dim_at(in[0].dims, j)) + "); only dimension " +
                 std::to_string(dim) + " may differ");
    }
    out.dims[dim] += dim_at(in[k].dims, dim);
  }
  return out;
}

ConcatPlan plan_concat(const std::vector<TensorInfo> &in, std::size_t dim) {
  ConcatPlan p;
  if (in.empty()) return p;
  for (std::size_t j = dim + 1; j < kRankLimit; ++j) p.outer *= dim_at(in[0].dims, j);
  for (const auto &t : in) {
    std::size_t b = type_size(t.type);
    for (std::size_t j = 0; j <= dim; ++j) b *= dim_at(t.dims, j);
    p.block.push_back(b);
    p.total += b * p.outer;
  }
  return p;
}

void run_concat(const ConcatPlan &plan, const uint8_t *const *src, uint8_t *dst) {
  const std::size_t n = plan.block.size();
  if (plan.outer == 1) {  // plain append
    for (std::size_t k = 0; k < n; ++k) {
      std::memcpy(dst, src[k], plan.block[k]);
      dst += plan.block[k];
    }
    return;
  }
  for (std::size_t o = 0; o < plan.outer; ++o)
    for (std::size_t k = 0; k < n; ++k) {
      const std::size_t b = plan.block[k];
      std::memcpy(dst, src[k] + o * b, b);
      dst += b;
    }
}

AggregatorPlan plan_aggregator(const TensorInfo &in, const AggregatorConfig &cfg) {
  const std::size_t fd = cfg.frames_dim;
  if (fd >= kRankLimit)
    fail(ErrorKind::kSettings,
         "frames-dim=" + std::to_string(fd) + " is outside 0.." + std::to_string(kRankLimit - 1));
  if (cfg.frames_in == 0 || cfg.frames_out == 0)
    fail(ErrorKind::kSettings, "frames-in and frames-out must be at least 1");
  const uint32_t count = (cfg.frames_out + cfg.frames_in - 1) / cfg.frames_in;
  if (static_cast<uint64_t>(cfg.frames_in) * count < cfg.frames_flush)
    fail(ErrorKind::kNegotiation,
         "frames-flush=" + std::to_string(cfg.frames_flush) + " is more than the " +
             std::to_string(static_cast<uint64_t>(cfg.frames_in) * count) +
             " frames held for one output (frames-in=" + std::to_string(cfg.frames_in) +
             ", frames-out=" + std::to_string(cfg.frames_out) + ")");
  Dims d = extend(in.dims, fd);
  if (d[fd] % cfg.frames_in != 0)
    fail(ErrorKind::kNegotiation,
         "frames-dim=" + std::to_string(fd) + ": dimension " + std::to_string(fd) +
             " of the input " + dims_to_string(in.dims) + " is " + std::to_string(d[fd]) +
             ", not a multiple of frames-in=" + std::to_string(cfg.frames_in));
  AggregatorPlan p;
  const uint32_t per_frame = d[fd] / cfg.frames_in;
  p.frame.type = p.out.type = in.type;
  p.frame.dims = d;
  p.frame.dims[fd] = per_frame;
  p.out.dims = d;
  p.out.dims[fd] = per_frame * cfg.frames_out;
  p.in_size = in.byte_size();
  p.frame_size = p.frame.byte_size();
  p.out_size = p.frame_size * cfg.frames_out;
  p.flush_size = p.frame_size * (cfg.frames_flush ? cfg.frames_flush : cfg.frames_out);
  if (cfg.concat && cfg.frames_out > 1)
    for (std::size_t j = fd + 1; j < kRankLimit; ++j)
      if (dim_at(p.frame.dims, j) > 1) p.reorder = true;
  if (p.reorder) p.concat = plan_concat(std::vector<TensorInfo>(cfg.frames_out, p.frame), fd);
  return p;
}

}  // namespace nns

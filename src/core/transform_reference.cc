// SPDX-License-Identifier: LGPL-2.1-only
// Scalar reference of every tensor_transform mode: one element at a time, written straight
// from the options and NNStreamer's definitions (its plain-C path), without sharing code with
// the accelerated plans. It is what `acceleration=false` runs and what the tests compare with.
#include <cmath>
#include <cstring>

#include "core/error.h"
#include "core/transform_kernels.h"

namespace nns::transform {
namespace {

uint32_t dim1(const TensorInfo &t, std::size_t i) {
  return i < t.rank() ? t.dims[i] : 1;
}

// One arithmetic step in type T, with C semantics: integers wrap, division truncates.
template <typename T>
T ref_apply(OpKind k, T a, T b) {
  if constexpr (std::is_same_v<T, Float16>) {
    float x = half_to_float(a.bits), y = half_to_float(b.bits);
    float r = k == OpKind::kAdd ? x + y : k == OpKind::kMul ? x * y : x / y;
    return Float16{float_to_half(r)};
  } else if constexpr (std::is_floating_point_v<T>) {
    return k == OpKind::kAdd ? a + b : k == OpKind::kMul ? a * b : a / b;
  } else {
    // Wide arithmetic, then wrap back to T.
    using W = std::conditional_t<std::is_signed_v<T>, int64_t, uint64_t>;
    W x = static_cast<W>(a), y = static_cast<W>(b);
    uint64_t ux = static_cast<uint64_t>(x), uy = static_cast<uint64_t>(y);
    switch (k) {
      case OpKind::kAdd:
        return static_cast<T>(ux + uy);
      case OpKind::kMul:
        return static_cast<T>(ux * uy);
      case OpKind::kDiv:
        if (y == 0) return a;  // refused at plan time; never reached from the element
        if constexpr (std::is_signed_v<T>)
          if (y == -1) return static_cast<T>(uint64_t{0} - ux);
        return static_cast<T>(x / y);
    }
    return a;
  }
}

template <typename T>
T operand(const Number &n) {
  return n.is_float ? cast_value<T>(n.f) : cast_value<T>(n.i);
}

void ref_permute(const Options &opts, const TensorInfo &in, const TensorInfo &out,
                 const uint8_t *src, uint8_t *dst) {
  std::array<uint32_t, kRankLimit> perm;
  std::size_t r = permutation(opts, in.rank(), perm);
  std::size_t es = type_size(in.type);
  std::size_t in_stride[kRankLimit];
  std::size_t s = 1;
  for (std::size_t a = 0; a < kRankLimit; ++a) {
    in_stride[a] = s;
    s *= dim1(in, a);
  }
  std::size_t n = out.element_count();
  for (std::size_t o = 0; o < n; ++o) {
    std::size_t rest = o, idx = 0;
    for (std::size_t k = 0; k < r; ++k) {
      std::size_t c = rest % dim1(out, k);
      rest /= dim1(out, k);
      idx += c * in_stride[perm[k]];
    }
    std::memcpy(dst + o * es, src + idx * es, es);
  }
}

void ref_arith(const Options &opts, const TensorInfo &in, const TensorInfo &out, const uint8_t *src,
               uint8_t *dst) {
  // typecast is arithmetic without operations.
  static const ArithOptions kNoOps;
  const ArithOptions &a = opts.mode == Mode::kArithmetic ? opts.get<ArithOptions>() : kNoOps;
  std::size_t ch_size = 1;
  for (std::size_t d = 0; d < a.ch_dim; ++d) ch_size *= dim1(in, d);
  std::size_t channels = dim1(in, a.ch_dim);
  std::size_t n = in.element_count();
  dispatch_type(in.type, [&](auto ti) {
    using In = typename decltype(ti)::type;
    dispatch_type(out.type, [&](auto to) {
      using T = typename decltype(to)::type;
      for (std::size_t i = 0; i < n; ++i) {
        In x;
        std::memcpy(&x, src + i * sizeof(In), sizeof(In));
        T v = cast_value<T>(x);
        int ch = a.per_channel ? static_cast<int>((i / ch_size) % channels) : -1;
        for (const auto &op : a.ops) {
          if (a.per_channel && op.channel >= 0 && op.channel != ch) continue;
          const Number &num =
              op.values.size() > 1 ? op.values[static_cast<std::size_t>(ch)] : op.values[0];
          v = ref_apply(op.kind, v, operand<T>(num));
        }
        std::memcpy(dst + i * sizeof(T), &v, sizeof(T));
      }
    });
  });
}

// Upstream's statistics: running mean, population standard deviation (1e-10 when it is 0).
void ref_stand(const Options &opts, const TensorInfo &in, const TensorInfo &out, const uint8_t *src,
               uint8_t *dst) {
  const auto &s = opts.get<StandOptions>();
  std::size_t n = in.element_count();
  std::size_t channels = s.per_channel ? dim1(in, 0) : 1;
  std::size_t per = n / channels;
  dispatch_type(in.type, [&](auto ti) {
    using In = typename decltype(ti)::type;
    dispatch_type(out.type, [&](auto to) {
      using Out = typename decltype(to)::type;
      auto value = [&](std::size_t i) {
        In x;
        std::memcpy(&x, src + i * sizeof(In), sizeof(In));
        return cast_value<double>(x);
      };
      for (std::size_t ch = 0; ch < channels; ++ch) {
        double mean = 0.0;
        for (std::size_t i = 0; i < per; ++i)
          mean = (value(i * channels + ch) - mean) / static_cast<double>(i + 1) + mean;
        double sd = 0.0;
        if (s.mode == StandMode::kDefault) {
          for (std::size_t i = 0; i < per; ++i)
            sd += std::pow(value(i * channels + ch) - mean, 2) / static_cast<double>(per);
          sd = sd != 0.0 ? std::sqrt(sd) : 1e-10;
        }
        for (std::size_t i = 0; i < per; ++i) {
          std::size_t e = i * channels + ch;
          double v = value(e) - mean;
          if (s.mode == StandMode::kDefault) v = std::fabs(v / sd);
          Out o = cast_value<Out>(v);
          std::memcpy(dst + e * sizeof(Out), &o, sizeof(Out));
        }
      }
    });
  });
}

void ref_clamp(const Options &opts, const TensorInfo &in, const uint8_t *src, uint8_t *dst) {
  const auto &c = opts.get<ClampOptions>();
  std::size_t n = in.element_count();
  dispatch_type(in.type, [&](auto ti) {
    using T = typename decltype(ti)::type;
    for (std::size_t i = 0; i < n; ++i) {
      T x;
      std::memcpy(&x, src + i * sizeof(T), sizeof(T));
      double v = cast_value<double>(x);
      v = v > c.max ? c.max : (v < c.min ? c.min : v);
      T o = cast_value<T>(v);
      std::memcpy(dst + i * sizeof(T), &o, sizeof(T));
    }
  });
}

void ref_padding(const Options &opts, const TensorInfo &in, const TensorInfo &out,
                 const uint8_t *src, uint8_t *dst) {
  const auto &p = opts.get<PaddingOptions>();
  std::size_t es = type_size(in.type);
  std::size_t n = out.element_count();
  for (std::size_t o = 0; o < n; ++o) {
    std::size_t rest = o, idx = 0, stride = 1;
    bool inside = true;
    for (std::size_t a = 0; a < 3; ++a) {
      std::size_t c = rest % dim1(out, a);
      rest /= dim1(out, a);
      if (c < p.pad[2 * a] || c >= p.pad[2 * a] + dim1(in, a)) inside = false;
      idx += (c - p.pad[2 * a]) * stride;
      stride *= dim1(in, a);
    }
    idx += rest * stride;  // dimensions from 3 on are not padded
    if (inside)
      std::memcpy(dst + o * es, src + idx * es, es);
    else
      std::memset(dst + o * es, 0, es);
  }
}

}  // namespace

void reference_transform(const Options &opts, const TensorInfo &in, const void *src_v,
                         void *dst_v) {
  const auto *src = static_cast<const uint8_t *>(src_v);
  auto *dst = static_cast<uint8_t *>(dst_v);
  TensorInfo out = output_info(opts, in);
  switch (opts.mode) {
    case Mode::kDimchg:
    case Mode::kTranspose:
      ref_permute(opts, in, out, src, dst);
      return;
    case Mode::kTypecast:
    case Mode::kArithmetic:
      ref_arith(opts, in, out, src, dst);
      return;
    case Mode::kStand:
      ref_stand(opts, in, out, src, dst);
      return;
    case Mode::kClamp:
      ref_clamp(opts, in, src, dst);
      return;
    case Mode::kPadding:
      ref_padding(opts, in, out, src, dst);
      return;
    case Mode::kUnknown:
      break;
  }
  fail(ErrorKind::kInternal, "reference_transform: no mode");
}

}  // namespace nns::transform

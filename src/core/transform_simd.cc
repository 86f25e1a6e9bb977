// SPDX-License-Identifier: LGPL-2.1-only
// Highway kernels, compiled once per SIMD target (foreach_target) and chosen at run time.
#include "core/transform_simd.h"

#include <algorithm>
#include <cstdint>

#ifdef NNS_HAVE_HWY
#undef HWY_TARGET_INCLUDE
#define HWY_TARGET_INCLUDE "core/transform_simd.cc"
#include <hwy/foreach_target.h>  // IWYU pragma: keep
#include <hwy/highway.h>

HWY_BEFORE_NAMESPACE();
namespace nns::transform::simd {
namespace HWY_NAMESPACE {
namespace hn = hwy::HWY_NAMESPACE;

using DF = hn::ScalableTag<float>;
using VF = hn::Vec<DF>;

HWY_INLINE VF LoadF32(DF df, const float *p) {
  return hn::LoadU(df, p);
}
HWY_INLINE VF LoadF32(DF df, const int32_t *p) {
  return hn::ConvertTo(df, hn::LoadU(hn::Rebind<int32_t, DF>(), p));
}
template <typename T>
HWY_INLINE VF LoadF32(DF df, const T *p) {  // 8/16-bit integers: widen to int32 first
  const hn::Rebind<int32_t, DF> di;
  return hn::ConvertTo(df, hn::PromoteTo(di, hn::LoadU(hn::Rebind<T, DF>(), p)));
}

HWY_INLINE VF Apply(DF df, VF v, const Op &op, std::size_t j) {
  const VF c = op.table ? hn::LoadU(df, op.table + j) : hn::Set(df, op.value);
  switch (op.kind) {
    case 0:
      return hn::Add(v, c);
    case 1:
      return hn::Mul(v, c);
    default:
      return hn::Div(v, c);
  }
}

HWY_INLINE float ApplyScalar(float v, const Op &op, std::size_t j) {
  const float c = op.table ? op.table[j] : op.value;
  switch (op.kind) {
    case 0:
      return v + c;
    case 1:
      return v * c;
    default:
      return v / c;
  }
}

template <int K>
HWY_INLINE VF OpK(VF v, VF c) {
  if constexpr (K == 0) return hn::Add(v, c);
  if constexpr (K == 1) return hn::Mul(v, c);
  if constexpr (K == 2) return hn::Div(v, c);
  return v;  // K == 3: no operation
}

template <int K>
HWY_INLINE float OpScalar(float v, float c) {
  if constexpr (K == 0) return v + c;
  if constexpr (K == 1) return v * c;
  if constexpr (K == 2) return v / c;
  return v;
}

// Uniform constants and at most two operations known at compile time: a straight-line loop,
// unrolled by two vectors, with the constants broadcast once.
template <typename In, int K0, int K1>
HWY_NOINLINE void ArithUniform2(const In *HWY_RESTRICT in, float *HWY_RESTRICT out, std::size_t n,
                                float c0, float c1) {
  const DF df;
  const std::size_t N = hn::Lanes(df);
  const VF v0 = hn::Set(df, c0), v1 = hn::Set(df, c1);
  std::size_t i = 0;
  for (; i + 2 * N <= n; i += 2 * N) {
    VF a = LoadF32(df, in + i), b = LoadF32(df, in + i + N);
    a = OpK<K1>(OpK<K0>(a, v0), v1);
    b = OpK<K1>(OpK<K0>(b, v0), v1);
    hn::StoreU(a, df, out + i);
    hn::StoreU(b, df, out + i + N);
  }
  for (; i + N <= n; i += N) hn::StoreU(OpK<K1>(OpK<K0>(LoadF32(df, in + i), v0), v1), df, out + i);
  for (; i < n; ++i) out[i] = OpScalar<K1>(OpScalar<K0>(static_cast<float>(in[i]), c0), c1);
}

template <typename In, int K0>
void Uniform2Second(const In *in, float *out, std::size_t n, int k1, float c0, float c1) {
  switch (k1) {
    case 0:
      return ArithUniform2<In, K0, 0>(in, out, n, c0, c1);
    case 1:
      return ArithUniform2<In, K0, 1>(in, out, n, c0, c1);
    case 2:
      return ArithUniform2<In, K0, 2>(in, out, n, c0, c1);
    default:
      return ArithUniform2<In, K0, 3>(in, out, n, c0, c1);
  }
}

template <typename In>
void Uniform2(const In *in, float *out, std::size_t n, int k0, int k1, float c0, float c1) {
  switch (k0) {
    case 0:
      return Uniform2Second<In, 0>(in, out, n, k1, c0, c1);
    case 1:
      return Uniform2Second<In, 1>(in, out, n, k1, c0, c1);
    case 2:
      return Uniform2Second<In, 2>(in, out, n, k1, c0, c1);
    default:
      return Uniform2Second<In, 3>(in, out, n, k1, c0, c1);
  }
}

template <typename In>
HWY_NOINLINE void ArithChain(const In *HWY_RESTRICT in, float *HWY_RESTRICT out, std::size_t n,
                             const Op *ops, std::size_t nops, std::size_t period) {
  if (period == 0 && nops <= 2) {  // the common case: straight-line code
    int k0 = nops > 0 ? ops[0].kind : 3, k1 = nops > 1 ? ops[1].kind : 3;
    float c0 = nops > 0 ? ops[0].value : 0.0f, c1 = nops > 1 ? ops[1].value : 0.0f;
    return Uniform2(in, out, n, k0, k1, c0, c1);
  }
  const DF df;
  const std::size_t N = hn::Lanes(df);
  const std::size_t chunk = period ? period : n;
  for (std::size_t base = 0; base < n; base += chunk) {
    const std::size_t m = std::min(chunk, n - base);
    const In *ip = in + base;
    float *op = out + base;
    std::size_t j = 0;
    if (nops == 0) {
      for (; j + N <= m; j += N) hn::StoreU(LoadF32(df, ip + j), df, op + j);
    } else if (nops == 1) {
      for (; j + N <= m; j += N) hn::StoreU(Apply(df, LoadF32(df, ip + j), ops[0], j), df, op + j);
    } else if (nops == 2) {
      for (; j + N <= m; j += N) {
        VF v = Apply(df, LoadF32(df, ip + j), ops[0], j);
        hn::StoreU(Apply(df, v, ops[1], j), df, op + j);
      }
    } else {
      for (; j + N <= m; j += N) {
        VF v = LoadF32(df, ip + j);
        for (std::size_t k = 0; k < nops; ++k) v = Apply(df, v, ops[k], j);
        hn::StoreU(v, df, op + j);
      }
    }
    for (; j < m; ++j) {
      float v = static_cast<float>(ip[j]);
      for (std::size_t k = 0; k < nops; ++k) v = ApplyScalar(v, ops[k], j);
      op[j] = v;
    }
  }
}

void ArithF32(int in_type, const void *in, float *out, std::size_t n, const Op *ops,
              std::size_t nops, std::size_t period) {
  switch (static_cast<TensorType>(in_type)) {
    case TensorType::kUInt8:
      return ArithChain(static_cast<const uint8_t *>(in), out, n, ops, nops, period);
    case TensorType::kInt8:
      return ArithChain(static_cast<const int8_t *>(in), out, n, ops, nops, period);
    case TensorType::kUInt16:
      return ArithChain(static_cast<const uint16_t *>(in), out, n, ops, nops, period);
    case TensorType::kInt16:
      return ArithChain(static_cast<const int16_t *>(in), out, n, ops, nops, period);
    case TensorType::kInt32:
      return ArithChain(static_cast<const int32_t *>(in), out, n, ops, nops, period);
    default:
      return ArithChain(static_cast<const float *>(in), out, n, ops, nops, period);
  }
}

// float32 -> int32 with x86 truncation semantics: NaN and out of range give INT32_MIN.
HWY_INLINE hn::Vec<hn::Rebind<int32_t, DF>> TruncI32(DF df, VF x) {
  const hn::Rebind<int32_t, DF> di;
  const auto ok =
      hn::And(hn::Ge(x, hn::Set(df, -2147483648.0f)), hn::Lt(x, hn::Set(df, 2147483648.0f)));
  const auto safe = hn::IfThenElseZero(ok, x);  // keeps ConvertTo in range
  return hn::IfThenElse(hn::RebindMask(di, ok), hn::ConvertTo(di, safe), hn::Set(di, INT32_MIN));
}

template <typename Out>
HWY_NOINLINE void F32ToInt(const float *HWY_RESTRICT in, Out *HWY_RESTRICT out, std::size_t n) {
  using U = hwy::MakeUnsigned<Out>;
  const DF df;
  const hn::Rebind<uint32_t, DF> du32;
  const hn::Rebind<U, DF> dout;
  const std::size_t N = hn::Lanes(df);
  std::size_t i = 0;
  for (; i + N <= n; i += N) {
    const auto u = hn::BitCast(du32, TruncI32(df, hn::LoadU(df, in + i)));
    if constexpr (sizeof(Out) == 4)
      hn::StoreU(u, du32, reinterpret_cast<uint32_t *>(out + i));
    else
      hn::StoreU(hn::TruncateTo(dout, u), dout, reinterpret_cast<U *>(out + i));
  }
  for (; i < n; ++i) {
    const float x = in[i];
    const int32_t v =
        (x >= -2147483648.0f && x < 2147483648.0f) ? static_cast<int32_t>(x) : INT32_MIN;
    out[i] = static_cast<Out>(v);
  }
}

bool F32ToIntAny(const float *in, int out_type, void *out, std::size_t n) {
  switch (static_cast<TensorType>(out_type)) {
    case TensorType::kInt8:
      F32ToInt(in, static_cast<int8_t *>(out), n);
      return true;
    case TensorType::kUInt8:
      F32ToInt(in, static_cast<uint8_t *>(out), n);
      return true;
    case TensorType::kInt16:
      F32ToInt(in, static_cast<int16_t *>(out), n);
      return true;
    case TensorType::kUInt16:
      F32ToInt(in, static_cast<uint16_t *>(out), n);
      return true;
    case TensorType::kInt32:
      F32ToInt(in, static_cast<int32_t *>(out), n);
      return true;
    case TensorType::kUInt32:
      F32ToInt(in, static_cast<uint32_t *>(out), n);
      return true;
    default:
      return false;
  }
}

template <typename T>
HWY_NOINLINE void Deinterleave(std::size_t channels, const T *HWY_RESTRICT in, T *HWY_RESTRICT out,
                               std::size_t n) {
  const hn::ScalableTag<T> d;
  using V = hn::Vec<decltype(d)>;
  const std::size_t N = hn::Lanes(d);
  T *p0 = out, *p1 = out + n, *p2 = out + 2 * n, *p3 = out + 3 * n;
  std::size_t i = 0;
  if (channels == 2) {
    for (; i + N <= n; i += N) {
      V a, b;
      hn::LoadInterleaved2(d, in + 2 * i, a, b);
      hn::StoreU(a, d, p0 + i);
      hn::StoreU(b, d, p1 + i);
    }
  } else if (channels == 3) {
    for (; i + N <= n; i += N) {
      V a, b, c;
      hn::LoadInterleaved3(d, in + 3 * i, a, b, c);
      hn::StoreU(a, d, p0 + i);
      hn::StoreU(b, d, p1 + i);
      hn::StoreU(c, d, p2 + i);
    }
  } else {
    for (; i + N <= n; i += N) {
      V a, b, c, e;
      hn::LoadInterleaved4(d, in + 4 * i, a, b, c, e);
      hn::StoreU(a, d, p0 + i);
      hn::StoreU(b, d, p1 + i);
      hn::StoreU(c, d, p2 + i);
      hn::StoreU(e, d, p3 + i);
    }
  }
  for (; i < n; ++i)
    for (std::size_t c = 0; c < channels; ++c) out[c * n + i] = in[i * channels + c];
}

void DeinterleaveAny(std::size_t esize, std::size_t channels, const void *in, void *out,
                     std::size_t n) {
  switch (esize) {
    case 1:
      return Deinterleave(channels, static_cast<const uint8_t *>(in), static_cast<uint8_t *>(out),
                          n);
    case 2:
      return Deinterleave(channels, static_cast<const uint16_t *>(in), static_cast<uint16_t *>(out),
                          n);
    case 4:
      return Deinterleave(channels, static_cast<const uint32_t *>(in), static_cast<uint32_t *>(out),
                          n);
    default:
      return Deinterleave(channels, static_cast<const uint64_t *>(in), static_cast<uint64_t *>(out),
                          n);
  }
}

int64_t Target() {
  return HWY_TARGET;
}

}  // namespace HWY_NAMESPACE
}  // namespace nns::transform::simd
HWY_AFTER_NAMESPACE();

#if HWY_ONCE
namespace nns::transform::simd {

HWY_EXPORT(ArithF32);
HWY_EXPORT(Target);
HWY_EXPORT(F32ToIntAny);
HWY_EXPORT(DeinterleaveAny);

bool f32_to_int(const float *in, TensorType out_type, void *out, std::size_t n) {
  return HWY_DYNAMIC_DISPATCH(F32ToIntAny)(in, static_cast<int>(out_type), out, n);
}

bool deinterleave(std::size_t esize, std::size_t channels, const void *in, void *out,
                  std::size_t n) {
  if (channels < 2 || channels > 4 || (esize != 1 && esize != 2 && esize != 4 && esize != 8))
    return false;
  HWY_DYNAMIC_DISPATCH(DeinterleaveAny)(esize, channels, in, out, n);
  return true;
}

bool supports_f32_input(TensorType t) {
  switch (t) {
    case TensorType::kUInt8:
    case TensorType::kInt8:
    case TensorType::kUInt16:
    case TensorType::kInt16:
    case TensorType::kInt32:
    case TensorType::kFloat32:
      return true;
    default:
      return false;
  }
}

void arith_f32(TensorType in_type, const void *in, float *out, std::size_t n, const Op *ops,
               std::size_t nops, std::size_t period) {
  HWY_DYNAMIC_DISPATCH(ArithF32)(static_cast<int>(in_type), in, out, n, ops, nops, period);
}

const char *target_name() {
  return hwy::TargetName(HWY_DYNAMIC_DISPATCH(Target)());
}

}  // namespace nns::transform::simd
#endif  // HWY_ONCE

#else   // !NNS_HAVE_HWY: plain loops (the build normally has libhwy-dev)
namespace nns::transform::simd {
namespace {
template <typename In>
void chain(const In *in, float *out, std::size_t n, const Op *ops, std::size_t nops,
           std::size_t period) {
  for (std::size_t i = 0; i < n; ++i) {
    float v = static_cast<float>(in[i]);
    std::size_t j = period ? i % period : 0;
    for (std::size_t k = 0; k < nops; ++k) {
      float c = ops[k].table ? ops[k].table[j] : ops[k].value;
      v = ops[k].kind == 0 ? v + c : ops[k].kind == 1 ? v * c : v / c;
    }
    out[i] = v;
  }
}
}  // namespace

bool supports_f32_input(TensorType t) {
  return t == TensorType::kUInt8 || t == TensorType::kInt8 || t == TensorType::kUInt16 ||
         t == TensorType::kInt16 || t == TensorType::kInt32 || t == TensorType::kFloat32;
}

void arith_f32(TensorType t, const void *in, float *out, std::size_t n, const Op *ops,
               std::size_t nops, std::size_t period) {
  switch (t) {
    case TensorType::kUInt8:
      return chain(static_cast<const uint8_t *>(in), out, n, ops, nops, period);
    case TensorType::kInt8:
      return chain(static_cast<const int8_t *>(in), out, n, ops, nops, period);
    case TensorType::kUInt16:
      return chain(static_cast<const uint16_t *>(in), out, n, ops, nops, period);
    case TensorType::kInt16:
      return chain(static_cast<const int16_t *>(in), out, n, ops, nops, period);
    case TensorType::kInt32:
      return chain(static_cast<const int32_t *>(in), out, n, ops, nops, period);
    default:
      return chain(static_cast<const float *>(in), out, n, ops, nops, period);
  }
}

bool f32_to_int(const float *, TensorType, void *, std::size_t) {
  return false;
}
bool deinterleave(std::size_t, std::size_t, const void *, void *, std::size_t) {
  return false;
}

const char *target_name() {
  return "scalar (built without Highway)";
}

}  // namespace nns::transform::simd
#endif  // NNS_HAVE_HWY

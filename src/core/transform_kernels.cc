// SPDX-License-Identifier: LGPL-2.1-only
// Accelerated tensor_transform plans. The type and mode are resolved here, once, into a
// function pointer over templates; per-buffer work is only the loops. Loops are written so the
// compiler vectorises them (this file is built with -O3, see src/CMakeLists.txt); the float32
// arithmetic/typecast hot path uses the Highway kernel (transform_simd.cc).
#include <algorithm>
#include <cstring>
#include <limits>
#include <numeric>

#include "core/error.h"
#include "core/transform_kernels.h"
#include "core/transform_simd.h"

namespace nns::transform {
namespace {

constexpr std::size_t kBlock = 1024;       // elements converted then operated on in L1
constexpr std::size_t kMaxPeriod = 65536;  // largest per-channel constant table
constexpr std::size_t kMaxSimdOps = 16;

uint32_t dim1(const TensorInfo &t, std::size_t i) {
  return i < t.rank() ? t.dims[i] : 1;
}

// Error text is built out of line: GCC 12 at -O3 warns falsely (-Wrestrict) on inlined
// std::string concatenation.
[[noreturn, gnu::noinline, gnu::cold]] void fail_div_zero(const Options &opts,
                                                          const std::string &token, TensorType t) {
  std::string msg = "property 'option' '";
  msg.append(opts.option).append("' for mode=").append(mode_name(opts.mode)).append(": '");
  msg.append(token);
  msg.append("' divides by zero (the value is 0 in ").append(type_name(t)).append(")");
  fail(ErrorKind::kSettings, msg);
}

// ---- element operations in the compute type (C semantics: integers wrap) -------------------

template <typename T>
inline T op_add(T a, T b) {
  if constexpr (std::is_same_v<T, Float16>) {
    return Float16{float_to_half(half_to_float(a.bits) + half_to_float(b.bits))};
  } else if constexpr (std::is_integral_v<T>) {
    using U = std::make_unsigned_t<T>;
    using W = std::conditional_t<(sizeof(T) < 4), uint32_t, U>;
    return static_cast<T>(static_cast<W>(static_cast<U>(a)) + static_cast<W>(static_cast<U>(b)));
  } else {
    return a + b;
  }
}

template <typename T>
inline T op_mul(T a, T b) {
  if constexpr (std::is_same_v<T, Float16>) {
    return Float16{float_to_half(half_to_float(a.bits) * half_to_float(b.bits))};
  } else if constexpr (std::is_integral_v<T>) {
    using U = std::make_unsigned_t<T>;
    using W = std::conditional_t<(sizeof(T) < 4), uint32_t, U>;
    return static_cast<T>(static_cast<W>(static_cast<U>(a)) * static_cast<W>(static_cast<U>(b)));
  } else {
    return a * b;
  }
}

template <typename T>
inline T op_div(T a, T b) {  // b != 0: refused when the plan is built
  if constexpr (std::is_same_v<T, Float16>) {
    return Float16{float_to_half(half_to_float(a.bits) / half_to_float(b.bits))};
  } else if constexpr (std::is_integral_v<T> && std::is_signed_v<T>) {
    using U = std::make_unsigned_t<T>;
    if (b == -1) return static_cast<T>(static_cast<U>(0) - static_cast<U>(a));  // MIN / -1 wraps
    return static_cast<T>(a / b);
  } else {
    return static_cast<T>(a / b);
  }
}

template <typename T>
void apply_uniform(T *__restrict x, std::size_t m, OpKind k, T c) {
  switch (k) {
    case OpKind::kAdd:
      for (std::size_t i = 0; i < m; ++i) x[i] = op_add(x[i], c);
      break;
    case OpKind::kMul:
      for (std::size_t i = 0; i < m; ++i) x[i] = op_mul(x[i], c);
      break;
    case OpKind::kDiv:
      for (std::size_t i = 0; i < m; ++i) x[i] = op_div(x[i], c);
      break;
  }
}

template <typename T>
void apply_table(T *__restrict x, std::size_t m, OpKind k, const T *__restrict c) {
  switch (k) {
    case OpKind::kAdd:
      for (std::size_t i = 0; i < m; ++i) x[i] = op_add(x[i], c[i]);
      break;
    case OpKind::kMul:
      for (std::size_t i = 0; i < m; ++i) x[i] = op_mul(x[i], c[i]);
      break;
    case OpKind::kDiv:
      for (std::size_t i = 0; i < m; ++i) x[i] = op_div(x[i], c[i]);
      break;
  }
}

template <typename In, typename T>
void convert(const In *__restrict in, T *__restrict out, std::size_t m) {
  for (std::size_t i = 0; i < m; ++i) out[i] = cast_value<T>(in[i]);
}

// ---- plan functions ---------------------------------------------------------------------

void run_reference(const Plan &p, const uint8_t *src, uint8_t *dst);

void run_copy(const Plan &p, const uint8_t *src, uint8_t *dst) {
  std::memcpy(dst, src, p.in.byte_size());
}

template <typename In, typename T>
void run_arith(const Plan &p, const uint8_t *src, uint8_t *dst) {
  const In *in = reinterpret_cast<const In *>(src);
  T *out = reinterpret_cast<T *>(dst);
  const std::size_t n = p.count;
  switch (p.layout) {
    case ArithLayout::kUniform:
      for (std::size_t base = 0; base < n; base += kBlock) {
        std::size_t m = std::min(kBlock, n - base);
        convert(in + base, out + base, m);
        for (const auto &op : p.ops) apply_uniform(out + base, m, op.kind, op.values.as<T>()[0]);
      }
      break;
    case ArithLayout::kPeriodic:
      for (std::size_t base = 0; base < n; base += p.period) {
        std::size_t m = std::min(p.period, n - base);
        convert(in + base, out + base, m);
        for (const auto &op : p.ops) apply_table(out + base, m, op.kind, op.values.as<T>());
      }
      break;
    case ArithLayout::kBlocked:
      for (std::size_t base = 0; base < n;) {
        for (std::size_t ch = 0; ch < p.channels; ++ch, base += p.ch_size) {
          convert(in + base, out + base, p.ch_size);
          for (const auto &op : p.ops)
            apply_uniform(out + base, p.ch_size, op.kind, op.values.as<T>()[ch]);
        }
      }
      break;
  }
}

void run_arith_simd(const Plan &p, const uint8_t *src, uint8_t *dst) {
  float *out = reinterpret_cast<float *>(dst);
  if (p.layout != ArithLayout::kBlocked) {
    simd::arith_f32(p.in.type, src, out, p.count, p.simd_ops.data(), p.simd_ops.size(),
                    p.layout == ArithLayout::kPeriodic ? p.period : 0);
    return;
  }
  simd::Op local[kMaxSimdOps];
  const std::size_t es = type_size(p.in.type), nops = p.ops.size();
  for (std::size_t base = 0; base < p.count;) {
    for (std::size_t ch = 0; ch < p.channels; ++ch, base += p.ch_size) {
      for (std::size_t k = 0; k < nops; ++k)
        local[k] = simd::Op{p.simd_ops[k].kind, p.ops[k].values.as<float>()[ch], nullptr};
      simd::arith_f32(p.in.type, src + base * es, out + base, p.ch_size, local, nops, 0);
    }
  }
}

void run_f32_to_int(const Plan &p, const uint8_t *src, uint8_t *dst) {
  simd::f32_to_int(reinterpret_cast<const float *>(src), p.out.type, dst, p.count);
}

// [outer][n][C] -> [outer][C][n] (e.g. HWC -> CHW): axes[0] = (n, stride C), axes[1] = (C, 1).
void run_deinterleave(const Plan &p, const uint8_t *src, uint8_t *dst) {
  const auto &ax = p.axes;
  const std::size_t es = type_size(p.in.type), n = ax[0].dim, C = ax[1].dim, nd = ax.size();
  const std::size_t outer = p.count / (n * C);
  std::size_t idx[kRankLimit] = {};
  std::size_t base = 0;
  for (std::size_t o = 0; o < outer; ++o) {
    simd::deinterleave(es, C, src + base * es, dst, n);
    dst += n * C * es;
    for (std::size_t k = 2; k < nd; ++k) {
      base += ax[k].in_stride;
      if (++idx[k] < ax[k].dim) break;
      base -= ax[k].in_stride * ax[k].dim;
      idx[k] = 0;
    }
  }
}

template <typename E>
void run_permute(const Plan &p, const uint8_t *src, uint8_t *dst) {
  const E *in = reinterpret_cast<const E *>(src);
  E *out = reinterpret_cast<E *>(dst);
  const auto &ax = p.axes;
  const std::size_t d0 = ax[0].dim, s0 = ax[0].in_stride, nd = ax.size();
  const std::size_t outer = p.count / d0;
  std::size_t idx[kRankLimit] = {};
  std::size_t base = 0;
  for (std::size_t o = 0; o < outer; ++o) {
    const E *ip = in + base;
    if (s0 == 1) {
      std::memcpy(out, ip, d0 * sizeof(E));
    } else {
      for (std::size_t j = 0; j < d0; ++j) out[j] = ip[j * s0];
    }
    out += d0;
    for (std::size_t k = 1; k < nd; ++k) {
      base += ax[k].in_stride;
      if (++idx[k] < ax[k].dim) break;
      base -= ax[k].in_stride * ax[k].dim;
      idx[k] = 0;
    }
  }
}

template <typename In, typename Out>
void run_stand(const Plan &p, const uint8_t *src, uint8_t *dst) {
  const In *__restrict in = reinterpret_cast<const In *>(src);
  Out *__restrict out = reinterpret_cast<Out *>(dst);
  const std::size_t C = p.stand_mean.size(), per = p.count / C;
  const bool full = p.stand_mode == StandMode::kDefault;
  // Channel by channel (C == 1 without per-channel), with local accumulators.
  for (std::size_t c = 0; c < C; ++c) {
    double sum = 0.0;
    for (std::size_t o = 0; o < per; ++o) sum += cast_value<double>(in[o * C + c]);
    const double mean = sum / static_cast<double>(per);
    double sd = 1.0;
    if (full) {
      double sq = 0.0;
      for (std::size_t o = 0; o < per; ++o) {
        double d = cast_value<double>(in[o * C + c]) - mean;
        sq += d * d;
      }
      sq /= static_cast<double>(per);
      sd = sq != 0.0 ? std::sqrt(sq) : 1e-10;
    }
    p.stand_mean[c] = mean;
    p.stand_std[c] = sd;
    if (full) {
      for (std::size_t o = 0; o < per; ++o)
        out[o * C + c] =
            cast_value<Out>(std::fabs((cast_value<double>(in[o * C + c]) - mean) / sd));
    } else {
      for (std::size_t o = 0; o < per; ++o)
        out[o * C + c] = cast_value<Out>(cast_value<double>(in[o * C + c]) - mean);
    }
  }
}

// Clamp through double, as upstream (64-bit integers and float16).
template <typename T>
void run_clamp_double(const Plan &p, const uint8_t *src, uint8_t *dst) {
  const T *__restrict in = reinterpret_cast<const T *>(src);
  T *__restrict out = reinterpret_cast<T *>(dst);
  const double lo = p.lo, hi = p.hi;
  for (std::size_t i = 0; i < p.count; ++i) {
    double v = cast_value<double>(in[i]);
    v = v > hi ? hi : (v < lo ? lo : v);
    out[i] = cast_value<T>(v);
  }
}

// Same results in the element type. float: comparing x with (float)hi decides like comparing
// with hi in double (hi rounds to the nearest float); integers up to 32 bits: x > hi iff
// x > floor(hi), x < lo iff x < ceil(lo).
template <typename T>
void run_clamp(const Plan &p, const uint8_t *src, uint8_t *dst) {
  const T *__restrict in = reinterpret_cast<const T *>(src);
  T *__restrict out = reinterpret_cast<T *>(dst);
  const T rh = cast_value<T>(p.hi), rl = cast_value<T>(p.lo);
  T th = rh, tl = rl;
  if constexpr (std::is_integral_v<T>) {
    const double fh = std::floor(p.hi), cl = std::ceil(p.lo);
    const double tmin = static_cast<double>(std::numeric_limits<T>::min());
    const double tmax = static_cast<double>(std::numeric_limits<T>::max());
    if (fh < tmin || cl > tmax) {  // every value is above hi (or below lo)
      std::fill(out, out + p.count, fh < tmin ? rh : rl);
      return;
    }
    th = static_cast<T>(std::min(fh, tmax));
    tl = static_cast<T>(std::max(cl, tmin));
  }
  for (std::size_t i = 0; i < p.count; ++i) {
    const T x = in[i];
    out[i] = x > th ? rh : (x < tl ? rl : x);
  }
}

void run_padding(const Plan &p, const uint8_t *src, uint8_t *dst) {
  const std::size_t es = type_size(p.in.type);
  std::memset(dst, 0, p.out.byte_size());
  const std::size_t row = p.pin[0] * es;
  if (p.pout[0] == p.pin[0]) {  // dimension 0 not padded: each plane's rows are contiguous
    for (std::size_t o = 0; o < p.pouter; ++o)
      for (std::size_t z = 0; z < p.pin[2]; ++z) {
        std::size_t oi =
            ((o * p.pout[2] + z + p.pbefore[2]) * p.pout[1] + p.pbefore[1]) * p.pout[0];
        std::size_t ii = (o * p.pin[2] + z) * p.pin[1] * p.pin[0];
        std::memcpy(dst + oi * es, src + ii * es, row * p.pin[1]);
      }
    return;
  }
  for (std::size_t o = 0; o < p.pouter; ++o)
    for (std::size_t z = 0; z < p.pin[2]; ++z)
      for (std::size_t y = 0; y < p.pin[1]; ++y) {
        std::size_t oi =
            ((o * p.pout[2] + z + p.pbefore[2]) * p.pout[1] + y + p.pbefore[1]) * p.pout[0] +
            p.pbefore[0];
        std::size_t ii = ((o * p.pin[2] + z) * p.pin[1] + y) * p.pin[0];
        std::memcpy(dst + oi * es, src + ii * es, row);
      }
}

// ---- plan construction --------------------------------------------------------------------

void plan_permute(Plan &p, const Options &opts) {
  std::array<uint32_t, kRankLimit> perm;
  std::size_t r = permutation(opts, p.in.rank(), perm);
  std::size_t in_stride[kRankLimit], s = 1;
  for (std::size_t a = 0; a < kRankLimit; ++a) {
    in_stride[a] = s;
    s *= dim1(p.in, a);
  }
  p.axes.clear();
  for (std::size_t k = 0; k < r; ++k) {
    std::size_t d = dim1(p.out, k);
    if (d == 1) continue;
    Plan::Axis a{d, in_stride[perm[k]]};
    if (!p.axes.empty() && p.axes.back().in_stride * p.axes.back().dim == a.in_stride)
      p.axes.back().dim *= d;  // contiguous in the input: one longer axis
    else
      p.axes.push_back(a);
  }
  if (p.axes.empty() || (p.axes.size() == 1 && p.axes[0].in_stride == 1)) {
    p.identity = true;
    p.fn = run_copy;
    return;
  }
  if (p.axes.size() >= 2 && p.axes[1].in_stride == 1 && p.axes[0].in_stride == p.axes[1].dim &&
      p.axes[1].dim >= 2 && p.axes[1].dim <= 4) {
    p.fn = run_deinterleave;  // interleaved channels to planes (HWC -> CHW)
    return;
  }
  switch (type_size(p.in.type)) {
    case 1:
      p.fn = run_permute<uint8_t>;
      break;
    case 2:
      p.fn = run_permute<uint16_t>;
      break;
    case 4:
      p.fn = run_permute<uint32_t>;
      break;
    default:
      p.fn = run_permute<uint64_t>;
      break;
  }
}

template <typename T>
T identity_of(OpKind k) {
  return k == OpKind::kAdd ? cast_value<T>(-0.0) : cast_value<T>(1);  // -0.0: x + -0 == x
}

template <typename T>
bool is_zero(T v) {
  if constexpr (std::is_same_v<T, Float16>)
    return (v.bits & 0x7fffu) == 0;
  else
    return v == T(0);
}

void plan_arith(Plan &p, const Options &opts, bool accelerate) {
  static const ArithOptions kNoOps;
  const ArithOptions &a = opts.mode == Mode::kArithmetic ? opts.get<ArithOptions>() : kNoOps;
  p.ch_size = 1;
  for (std::size_t d = 0; d < a.ch_dim; ++d) p.ch_size *= dim1(p.in, d);
  p.channels = dim1(p.in, a.ch_dim);
  bool per_ch = false;
  for (const auto &op : a.ops) per_ch = per_ch || op.channel >= 0 || op.values.size() > 1;
  per_ch = per_ch && a.per_channel;
  const std::size_t L = p.channels * p.ch_size;
  if (!per_ch) {
    p.layout = ArithLayout::kUniform;
  } else if (p.ch_size >= 64) {
    p.layout = ArithLayout::kBlocked;
  } else {
    std::size_t P = std::lcm(L, std::size_t{64});
    P *= (kBlock + P - 1) / P;
    p.layout = P <= kMaxPeriod ? ArithLayout::kPeriodic : ArithLayout::kBlocked;
    p.period = P;
  }
  const std::size_t len = p.layout == ArithLayout::kUniform   ? 1
                          : p.layout == ArithLayout::kBlocked ? p.channels
                                                              : p.period;
  dispatch_type(p.out.type, [&](auto to) {
    using T = typename decltype(to)::type;
    for (const auto &op : a.ops) {
      std::vector<T> c(len);
      for (std::size_t j = 0; j < len; ++j) {
        std::size_t ch = p.layout == ArithLayout::kPeriodic ? (j / p.ch_size) % p.channels : j;
        bool applies = !per_ch || op.channel < 0 || static_cast<std::size_t>(op.channel) == ch;
        const Number &num = op.values.size() > 1 ? op.values[ch] : op.values[0];
        T v = num.is_float ? cast_value<T>(num.f) : cast_value<T>(num.i);
        if (applies && op.kind == OpKind::kDiv && is_zero(v))
          fail_div_zero(opts, op.token, p.out.type);
        c[j] = applies ? v : identity_of<T>(op.kind);
      }
      p.ops.push_back(PlanOp{op.kind, ConstArray::make(std::move(c))});
    }
  });
  if (!accelerate) return;
  if (p.ops.empty() && p.in.type == p.out.type) {
    p.identity = true;
    p.fn = run_copy;
    return;
  }
  if (p.out.type == TensorType::kFloat32 && simd::supports_f32_input(p.in.type) &&
      p.ops.size() <= kMaxSimdOps) {
    for (const auto &op : p.ops)
      p.simd_ops.push_back(
          simd::Op{static_cast<int>(op.kind), op.values.as<float>()[0],
                   p.layout == ArithLayout::kPeriodic ? op.values.as<float>() : nullptr});
    p.fn = run_arith_simd;
    return;
  }
  if (p.ops.empty() && p.in.type == TensorType::kFloat32 &&
      simd::f32_to_int(nullptr, p.out.type, nullptr, 0)) {
    p.fn = run_f32_to_int;  // typecast float32 -> 8/16/32-bit integers
    return;
  }
  dispatch_type(p.in.type, [&](auto ti) {
    dispatch_type(p.out.type, [&](auto to) {
      p.fn = run_arith<typename decltype(ti)::type, typename decltype(to)::type>;
    });
  });
}

void run_reference(const Plan &p, const uint8_t *src, uint8_t *dst) {
  reference_transform(*p.opts, p.in, src, dst);
}

}  // namespace

Plan make_plan(const Options &opts, const TensorInfo &in, bool accelerate) {
  Plan p;
  p.in = in;
  p.out = output_info(opts, in);
  p.count = in.element_count();
  p.accelerated = accelerate;
  p.opts = std::make_shared<const Options>(opts);
  p.fn = run_reference;
  switch (opts.mode) {
    case Mode::kDimchg:
    case Mode::kTranspose:
      plan_permute(p, opts);
      break;
    case Mode::kTypecast:
    case Mode::kArithmetic:
      plan_arith(p, opts, accelerate);
      if (!accelerate) p.identity = opts.mode == Mode::kTypecast && p.in.type == p.out.type;
      break;
    case Mode::kStand: {
      const auto &s = opts.get<StandOptions>();
      p.stand_mode = s.mode;
      p.stand_per_channel = s.per_channel;
      std::size_t C = s.per_channel ? dim1(in, 0) : 1;
      p.stand_mean.assign(C, 0.0);
      p.stand_std.assign(C, 0.0);
      dispatch_type(in.type, [&](auto ti) {
        dispatch_type(p.out.type, [&](auto to) {
          p.fn = run_stand<typename decltype(ti)::type, typename decltype(to)::type>;
        });
      });
      break;
    }
    case Mode::kClamp:
      p.lo = opts.get<ClampOptions>().min;
      p.hi = opts.get<ClampOptions>().max;
      dispatch_type(in.type, [&](auto ti) {
        using T = typename decltype(ti)::type;
        if constexpr (std::is_same_v<T, Float16> || (sizeof(T) == 8 && std::is_integral_v<T>))
          p.fn = run_clamp_double<T>;
        else
          p.fn = run_clamp<T>;
      });
      break;
    case Mode::kPadding: {
      const auto &pd = opts.get<PaddingOptions>();
      for (std::size_t a = 0; a < 3; ++a) {
        p.pin[a] = dim1(in, a);
        p.pout[a] = dim1(p.out, a);
        p.pbefore[a] = pd.pad[2 * a];
      }
      p.pouter = p.count / (p.pin[0] * p.pin[1] * p.pin[2]);
      p.fn = run_padding;
      p.identity = p.out.byte_size() == p.in.byte_size();
      break;
    }
    case Mode::kUnknown:
      fail(ErrorKind::kSettings, "property 'mode' is not set");
  }
  if (!accelerate) p.fn = run_reference;
  return p;
}

}  // namespace nns::transform

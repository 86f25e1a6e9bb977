// SPDX-License-Identifier: LGPL-2.1-only
// tensor_transform compute: value conversion with NNStreamer's semantics, per-tensor execution
// plans (built once when caps are set, then run per buffer without allocating), and a scalar
// reference implementation the plans are tested against.
#pragma once

#include <cmath>
#include <cstdint>
#include <memory>
#include <type_traits>
#include <vector>

#include "core/float16.h"
#include "core/transform_options.h"
#include "core/transform_simd.h"

namespace nns::transform {

template <typename T>
struct TypeTag {
  using type = T;
};

// Calls f(TypeTag<C type of t>{}). float16 maps to nns::Float16.
template <typename F>
decltype(auto) dispatch_type(TensorType t, F &&f) {
  switch (t) {
    case TensorType::kInt32:
      return f(TypeTag<int32_t>{});
    case TensorType::kUInt32:
      return f(TypeTag<uint32_t>{});
    case TensorType::kInt16:
      return f(TypeTag<int16_t>{});
    case TensorType::kUInt16:
      return f(TypeTag<uint16_t>{});
    case TensorType::kInt8:
      return f(TypeTag<int8_t>{});
    case TensorType::kUInt8:
      return f(TypeTag<uint8_t>{});
    case TensorType::kFloat64:
      return f(TypeTag<double>{});
    case TensorType::kFloat32:
      return f(TypeTag<float>{});
    case TensorType::kInt64:
      return f(TypeTag<int64_t>{});
    case TensorType::kUInt64:
      return f(TypeTag<uint64_t>{});
    default:
      return f(TypeTag<Float16>{});
  }
}

template <typename T>
constexpr bool is_floating_v = std::is_floating_point_v<T> || std::is_same_v<T, Float16>;

// Float -> int32 / int64 the way x86-64 truncates (cvttss2si): NaN and out-of-range values give
// the minimum value. Written without undefined behaviour.
inline int32_t trunc_to_i32(double x) {
  return (x > -2147483649.0 && x < 2147483648.0) ? static_cast<int32_t>(x) : INT32_MIN;
}
// float overloads: the same results, without widening (so loops vectorise in float lanes).
inline int32_t trunc_to_i32(float x) {
  return (x >= -2147483648.0f && x < 2147483648.0f) ? static_cast<int32_t>(x) : INT32_MIN;
}
inline int64_t trunc_to_i64(float x) {
  return (x >= -9223372036854775808.0f && x < 9223372036854775808.0f) ? static_cast<int64_t>(x)
                                                                      : INT64_MIN;
}
inline int64_t trunc_to_i64(double x) {
  return (x >= -9223372036854775808.0 && x < 9223372036854775808.0) ? static_cast<int64_t>(x)
                                                                    : INT64_MIN;
}

// Converts one value with NNStreamer's C-cast semantics (gst_tensor_data_typecast on x86-64):
// integers wrap (two's complement); float -> int truncates toward zero, float -> unsigned goes
// through the signed type of the same width, and 8/16/32-bit results come from a 32-bit
// truncation (so NaN/out of range give INT32_MIN's low bits); int -> float rounds to nearest.
template <typename To, typename From>
inline To cast_value(From v) {
  if constexpr (std::is_same_v<To, From>) {
    return v;
  } else if constexpr (std::is_same_v<From, Float16>) {
    return cast_value<To>(half_to_float(v.bits));
  } else if constexpr (std::is_same_v<To, Float16>) {
    return Float16{float_to_half(static_cast<float>(v))};
  } else if constexpr (std::is_floating_point_v<To> || std::is_integral_v<From>) {
    return static_cast<To>(v);
  } else if constexpr (sizeof(To) == 8) {
    return static_cast<To>(trunc_to_i64(v));
  } else {
    return static_cast<To>(trunc_to_i32(v));
  }
}

// Type-erased, read-only array of constants in some element type.
struct ConstArray {
  std::shared_ptr<void> owner;
  const void *data = nullptr;
  template <typename T>
  const T *as() const {
    return static_cast<const T *>(data);
  }
  template <typename T>
  static ConstArray make(std::vector<T> v) {
    auto p = std::make_shared<std::vector<T>>(std::move(v));
    return ConstArray{p, p->data()};
  }
};

// One arithmetic step in the compute type: x = x op c[j] (c per element of a period) or a
// scalar when the plan is uniform.
struct PlanOp {
  OpKind kind = OpKind::kAdd;
  ConstArray values;  // compute type; length 1 (uniform), `period` or `channels`
};

// How per-channel constants are laid out.
enum class ArithLayout {
  kUniform,   // one constant per op
  kPeriodic,  // constants repeat every `period` elements (period is a multiple of 64)
  kBlocked,   // [outer][channels][ch_size]: one constant per channel and op
};

struct Plan {
  using Fn = void (*)(const Plan &, const uint8_t *, uint8_t *);

  TensorInfo in, out;
  Fn fn = nullptr;
  bool identity = false;  // output bytes equal input bytes: the memory can be shared
  bool accelerated = false;
  std::size_t count = 0;  // elements in the input tensor
  std::shared_ptr<const Options> opts;

  // dimchg / transpose: output axes (innermost first) with the input stride of each.
  struct Axis {
    std::size_t dim = 1, in_stride = 0;
  };
  std::vector<Axis> axes;

  // arithmetic / typecast
  ArithLayout layout = ArithLayout::kUniform;
  std::vector<PlanOp> ops;
  std::vector<simd::Op> simd_ops;  // the same ops for the Highway kernel (float32 output)
  std::size_t period = 0, channels = 1, ch_size = 1;

  // stand: scratch for per-channel statistics (sized at plan time; the plan is used by one
  // streaming thread at a time).
  StandMode stand_mode = StandMode::kDefault;
  bool stand_per_channel = false;
  mutable std::vector<double> stand_mean, stand_std;

  // clamp
  double lo = 0, hi = 0;

  // padding: [outer][d2][d1][d0] with the offset of the copied block.
  std::size_t pin[3]{}, pout[3]{}, pbefore[3]{}, pouter = 1;

  void run(const void *src, void *dst) const {
    fn(*this, static_cast<const uint8_t *>(src), static_cast<uint8_t *>(dst));
  }
};

// Builds the plan for one tensor. `accelerate` selects the SIMD kernels (Highway /
// auto-vectorised loops); otherwise the scalar reference runs. Throws nns::Error
// (kNegotiation) when the tensor does not fit the option, (kSettings) for a division by zero
// in the compute type.
Plan make_plan(const Options &opts, const TensorInfo &in, bool accelerate);

// The scalar reference: element by element, straight from the options, with upstream's
// semantics (exact division, running mean for stand). `dst` holds output_info(opts, in).
void reference_transform(const Options &opts, const TensorInfo &in, const void *src, void *dst);

}  // namespace nns::transform

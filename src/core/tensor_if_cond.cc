// SPDX-License-Identifier: LGPL-2.1-only
#include "core/tensor_if_cond.h"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstdlib>
#include <cstring>
#include <type_traits>

#include "core/error.h"

namespace nns::tif {
namespace {

[[noreturn]] void bad(std::string_view what, const std::string &msg) {
  fail(ErrorKind::kSettings, std::string(what) + ": " + msg);
}

int64_t parse_int(std::string_view tok, std::string_view what, std::string_view whole) {
  std::string t(trim(tok));
  if (t.empty()) bad(what, "empty entry in '" + std::string(whole) + "'");
  char *end = nullptr;
  errno = 0;
  long long v = std::strtoll(t.c_str(), &end, 10);
  if (errno == ERANGE || *end != '\0')
    bad(what, "'" + t + "' in '" + std::string(whole) + "' is not an integer");
  return v;
}

uint32_t parse_index(std::string_view tok, std::string_view what, std::string_view whole) {
  int64_t v = parse_int(tok, what, whole);
  if (v < 0 || v > int64_t(UINT32_MAX))
    bad(what, "index " + std::to_string(v) + " in '" + std::string(whole) + "' is negative");
  return static_cast<uint32_t>(v);
}

// IEEE half <-> float (round to nearest even on the way down).
float half_to_float(uint16_t h) {
  uint32_t sign = uint32_t(h & 0x8000) << 16;
  uint32_t exp = (h >> 10) & 0x1f;
  uint32_t man = h & 0x3ff;
  float f;
  if (exp == 0) {
    f = std::ldexp(static_cast<float>(man), -24);
  } else if (exp == 31) {
    f = man ? std::nanf("") : INFINITY;
  } else {
    f = std::ldexp(static_cast<float>(man | 0x400), int(exp) - 25);
  }
  return sign ? -f : f;
}

template <typename T>
T from_sv(bool is_float, double f, int64_t i) {
  if constexpr (std::is_floating_point_v<T>) {
    return is_float ? static_cast<T>(f) : static_cast<T>(i);
  } else {
    // Like a C cast of the int64/double supplied value to the element type.
    return is_float ? static_cast<T>(static_cast<int64_t>(f)) : static_cast<T>(i);
  }
}

template <typename T>
bool compare(T cv, T a, T b, Op op) {
  switch (op) {
    case Op::kEq:
      return cv == a;
    case Op::kNe:
      return cv != a;
    case Op::kGt:
      return cv > a;
    case Op::kGe:
      return cv >= a;
    case Op::kLt:
      return cv < a;
    case Op::kLe:
      return cv <= a;
    case Op::kRangeInclusive:
      return a <= cv && cv <= b;
    case Op::kRangeExclusive:
      return a < cv && cv < b;
    case Op::kNotInRangeInclusive:
      return cv < a || b < cv;
    case Op::kNotInRangeExclusive:
      return cv <= a || b <= cv;
  }
  return false;
}

// Supplied operands as bytes of the element's type (float for float16).
template <typename T>
void store_operands(const SuppliedValue &sv, Condition::Operands *o) {
  for (int k = 0; k < 2; ++k) {
    std::size_t j = std::min<std::size_t>(k, sv.size() - 1);
    T v = from_sv<T>(sv.is_float, sv.is_float ? sv.f[j] : 0.0, sv.is_float ? 0 : sv.i[j]);
    if constexpr (std::is_floating_point_v<T>) {
      o->f[k] = static_cast<double>(v);
    } else if constexpr (std::is_signed_v<T>) {
      o->i[k] = static_cast<int64_t>(v);
    } else {
      o->u[k] = static_cast<uint64_t>(v);
    }
  }
}

template <typename T>
T operand(const Condition::Operands &o, int k) {
  if constexpr (std::is_floating_point_v<T>) {
    return static_cast<T>(o.f[k]);
  } else if constexpr (std::is_signed_v<T>) {
    return static_cast<T>(o.i[k]);
  } else {
    return static_cast<T>(o.u[k]);
  }
}

template <typename T>
T load(const uint8_t *p) {
  T v;
  std::memcpy(&v, p, sizeof v);
  return v;
}

template <typename T>
bool eval_elem(const uint8_t *p, Op op, const Condition::Operands &o) {
  return compare<T>(load<T>(p), operand<T>(o, 0), operand<T>(o, 1), op);
}
bool eval_elem_f16(const uint8_t *p, Op op, const Condition::Operands &o) {
  return compare<float>(half_to_float(load<uint16_t>(p)), operand<float>(o, 0),
                        operand<float>(o, 1), op);
}

template <typename T>
bool eval_avg(const uint8_t *p, std::size_t n, Op op, const Condition::Operands &o) {
  double sum = 0;
  for (std::size_t k = 0; k < n; ++k) sum += static_cast<double>(load<T>(p + k * sizeof(T)));
  double avg = n ? sum / static_cast<double>(n) : 0.0;
  T cv = from_sv<T>(true, avg, 0);  // the average is cast to the element type
  return compare<T>(cv, operand<T>(o, 0), operand<T>(o, 1), op);
}
bool eval_avg_f16(const uint8_t *p, std::size_t n, Op op, const Condition::Operands &o) {
  double sum = 0;
  for (std::size_t k = 0; k < n; ++k) sum += half_to_float(load<uint16_t>(p + 2 * k));
  float cv = static_cast<float>(n ? sum / static_cast<double>(n) : 0.0);
  return compare<float>(cv, operand<float>(o, 0), operand<float>(o, 1), op);
}

template <typename T>
void bind(const SuppliedValue &sv, Condition::Operands *o, Condition::EvalFn *e,
          Condition::AvgFn *a) {
  store_operands<T>(sv, o);
  *e = eval_elem<T>;
  *a = eval_avg<T>;
}

void bind_type(TensorType t, const SuppliedValue &sv, Condition::Operands *o, Condition::EvalFn *e,
               Condition::AvgFn *a) {
  switch (t) {
    case TensorType::kInt32:
      return bind<int32_t>(sv, o, e, a);
    case TensorType::kUInt32:
      return bind<uint32_t>(sv, o, e, a);
    case TensorType::kInt16:
      return bind<int16_t>(sv, o, e, a);
    case TensorType::kUInt16:
      return bind<uint16_t>(sv, o, e, a);
    case TensorType::kInt8:
      return bind<int8_t>(sv, o, e, a);
    case TensorType::kUInt8:
      return bind<uint8_t>(sv, o, e, a);
    case TensorType::kFloat64:
      return bind<double>(sv, o, e, a);
    case TensorType::kFloat32:
      return bind<float>(sv, o, e, a);
    case TensorType::kInt64:
      return bind<int64_t>(sv, o, e, a);
    case TensorType::kUInt64:
      return bind<uint64_t>(sv, o, e, a);
    case TensorType::kFloat16:
      store_operands<float>(sv, o);
      *e = eval_elem_f16;
      *a = eval_avg_f16;
      return;
    case TensorType::kEnd:
      break;
  }
  fail(ErrorKind::kNegotiation, "tensor_if: input tensor has no element type");
}

}  // namespace

const char *op_name(Op op) {
  static const char *const names[] = {"EQ",
                                      "NE",
                                      "GT",
                                      "GE",
                                      "LT",
                                      "LE",
                                      "RANGE_INCLUSIVE",
                                      "RANGE_EXCLUSIVE",
                                      "NOT_IN_RANGE_INCLUSIVE",
                                      "NOT_IN_RANGE_EXCLUSIVE"};
  int i = static_cast<int>(op);
  return i >= 0 && i < 10 ? names[i] : "?";
}

bool op_needs_two(Op op) {
  return static_cast<int>(op) >= static_cast<int>(Op::kRangeInclusive);
}

SuppliedValue parse_supplied_value(std::string_view s) {
  constexpr std::string_view what = "supplied-value";
  SuppliedValue sv;
  auto toks = split(s, ",");
  if (toks.empty())
    fail(ErrorKind::kSettings,
         "supplied-value is not set; give one value, or two for a range operator");
  if (toks.size() > 2)
    bad(what,
        "'" + std::string(s) + "' has " + std::to_string(toks.size()) + " values, expected 1 or 2");
  sv.is_float = s.find_first_of(".eE") != std::string_view::npos;
  for (const auto &t : toks) {
    if (t.empty()) bad(what, "empty entry in '" + std::string(s) + "'");
    if (sv.is_float) {
      char *end = nullptr;
      double v = std::strtod(t.c_str(), &end);
      if (*end != '\0') bad(what, "'" + t + "' in '" + std::string(s) + "' is not a number");
      sv.f.push_back(v);
    } else {
      sv.i.push_back(parse_int(t, what, s));
    }
  }
  return sv;
}

ElementRef parse_a_value_option(std::string_view s) {
  constexpr std::string_view what = "compared-value-option";
  auto parts = split(s, ",");
  if (parts.size() != 2)
    bad(what, "'" + std::string(s) +
                  "' is not '<d0:d1:...>,<tensor index>' as A_VALUE needs (e.g. 0:0:0:0,0)");
  ElementRef r;
  for (const auto &t : split(parts[0], ":")) r.index.push_back(parse_index(t, what, s));
  if (r.index.empty() || r.index.size() > kRankLimit)
    bad(what, "'" + std::string(s) + "' gives " + std::to_string(r.index.size()) +
                  " element indices, expected 1.." + std::to_string(kRankLimit));
  r.tensor = parse_index(parts[1], what, s);
  return r;
}

uint32_t parse_tensor_index(std::string_view s, std::string_view what) {
  auto toks = split(s, ",:");
  if (toks.size() != 1)
    bad(what, "'" + std::string(s) +
                  "' must be one tensor index for TENSOR_AVERAGE_VALUE (several tensors are not "
                  "supported)");
  return parse_index(toks[0], what, s);
}

std::vector<uint32_t> parse_pick(std::string_view s, std::string_view what) {
  std::vector<uint32_t> out;
  for (const auto &t : split(s, ",")) out.push_back(parse_index(t, what, s));
  return out;
}

Condition::Condition(Compared kind, std::string_view option, Op op, const SuppliedValue &sv,
                     const TensorsInfo &in)
    : kind_(kind), op_(op) {
  if (sv.size() == 0)
    fail(ErrorKind::kSettings, "supplied-value is not set; operator " + std::string(op_name(op)) +
                                   " needs " + (op_needs_two(op) ? "two values" : "a value"));
  if (op_needs_two(op) && sv.size() != 2)
    fail(ErrorKind::kSettings, std::string("operator ") + op_name(op) +
                                   " needs two supplied values (e.g. supplied-value=10,20), got " +
                                   std::to_string(sv.size()));
  std::string opt(option);
  if (kind == Compared::kAValue) {
    ElementRef r = parse_a_value_option(option);
    if (r.tensor >= in.size())
      fail(ErrorKind::kSettings, "compared-value-option='" + opt + "' names tensor " +
                                     std::to_string(r.tensor) + " but the input has " +
                                     std::to_string(in.size()) + " tensor(s)");
    const TensorInfo &t = in[r.tensor];
    std::size_t off = 0, stride = 1;
    for (std::size_t d = 0; d < kRankLimit; ++d) {
      uint32_t extent = t.dims[d] ? t.dims[d] : 1;
      uint32_t idx = d < r.index.size() ? r.index[d] : 0;
      if (idx >= extent)
        fail(ErrorKind::kSettings, "compared-value-option='" + opt + "': index " +
                                       std::to_string(idx) + " of dimension " + std::to_string(d) +
                                       " is outside tensor " + std::to_string(r.tensor) + " (" +
                                       t.to_string() + ")");
      off += idx * stride;
      stride *= extent;
    }
    tensor_ = r.tensor;
    byte_offset_ = off * type_size(t.type);
  } else if (kind == Compared::kTensorAverage) {
    tensor_ = parse_tensor_index(option, "compared-value-option");
    if (tensor_ >= in.size())
      fail(ErrorKind::kSettings, "compared-value-option='" + opt + "' names tensor " +
                                     std::to_string(tensor_) + " but the input has " +
                                     std::to_string(in.size()) + " tensor(s)");
    count_ = in[tensor_].element_count();
  } else {
    fail(ErrorKind::kInternal, "tensor_if: custom conditions are evaluated by the element");
  }
  bind_type(in[tensor_].type, sv, &sv_, &eval_, &avg_);
}

bool Condition::evaluate(const uint8_t *const *tensors) const {
  if (kind_ == Compared::kAValue) return eval_(tensors[tensor_] + byte_offset_, op_, sv_);
  return avg_(tensors[tensor_], count_, op_, sv_);
}

TensorsInfo action_output(Action a, const std::vector<uint32_t> &pick, const TensorsInfo &in,
                          std::string_view what) {
  if (a != Action::kTensorPick) return in;
  if (pick.empty())
    fail(ErrorKind::kSettings,
         std::string(what) + " is empty; TENSORPICK needs tensor indices (e.g. 0,2)");
  TensorsInfo out;
  out.format = in.format;
  for (uint32_t i : pick) {
    if (i >= in.size())
      fail(ErrorKind::kSettings, std::string(what) + " picks tensor " + std::to_string(i) +
                                     " but the input has " + std::to_string(in.size()) +
                                     " tensor(s)");
    out.tensors.push_back(in[i]);
  }
  return out;
}

}  // namespace nns::tif

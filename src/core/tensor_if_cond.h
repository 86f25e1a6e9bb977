// SPDX-License-Identifier: LGPL-2.1-only
// tensor_if condition logic (GStreamer-free): option grammars of NNStreamer's tensor_if and a
// condition evaluator prepared once per negotiated input.
//
//   compared-value=A_VALUE              compared-value-option="d0:d1:...:dk,<tensor index>"
//   compared-value=TENSOR_AVERAGE_VALUE compared-value-option="<tensor index>"
//   supplied-value="V" or "V1,V2"  (float if it contains '.', 'e' or 'E', else int64)
//   then-option / else-option (TENSORPICK) = "i,j,..." tensor indices
//
// The compared value keeps the tensor's element type; the supplied values are cast to that type
// before comparing (an average is computed in double and then cast, as upstream does).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

#include "core/tensor_info.h"

namespace nns::tif {

// Numbering of NNStreamer's GEnums (part of the pipeline-string compatibility).
enum class Compared : int { kAValue = 0, kTensorAverage = 3, kCustom = 5 };
enum class Op : int {
  kEq = 0,
  kNe,
  kGt,
  kGe,
  kLt,
  kLe,
  kRangeInclusive,
  kRangeExclusive,
  kNotInRangeInclusive,
  kNotInRangeExclusive,
};
enum class Action : int { kPassthrough = 0, kSkip = 1, kTensorPick = 7 };

const char *op_name(Op op);  // "EQ", "RANGE_INCLUSIVE", ...
bool op_needs_two(Op op);    // the range operators

struct SuppliedValue {
  bool is_float = false;
  std::vector<double> f;   // when is_float
  std::vector<int64_t> i;  // otherwise
  std::size_t size() const { return is_float ? f.size() : i.size(); }
};
// Throws nns::Error(kSettings) naming "supplied-value" and the bad token.
SuppliedValue parse_supplied_value(std::string_view s);

struct ElementRef {
  std::vector<uint32_t> index;  // innermost first; missing trailing entries are 0
  uint32_t tensor = 0;
};
// "d0:d1:d2:d3,n". Throws nns::Error(kSettings) naming "compared-value-option".
ElementRef parse_a_value_option(std::string_view s);
// "n" for TENSOR_AVERAGE_VALUE.
uint32_t parse_tensor_index(std::string_view s, std::string_view what);
// "i,j,k" tensor indices for TENSORPICK; `what` names the property.
std::vector<uint32_t> parse_pick(std::string_view s, std::string_view what);

// A condition bound to the negotiated input tensors. Construction validates the options
// against `in` and throws nns::Error(kSettings) naming the option and both values when they
// disagree (tensor index past the tensor count, element index outside the dimensions, a range
// operator with one supplied value, ...). evaluate() then only reads memory.
class Condition {
 public:
  Condition(Compared kind, std::string_view option, Op op, const SuppliedValue &sv,
            const TensorsInfo &in);
  // `tensors[i]` points at tensor i's bytes (in[i].byte_size() long).
  bool evaluate(const uint8_t *const *tensors) const;

  struct Operands {
    double f[2];
    int64_t i[2];
    uint64_t u[2];
  };
  using EvalFn = bool (*)(const uint8_t *elem, Op op, const Operands &sv);
  using AvgFn = bool (*)(const uint8_t *data, std::size_t n, Op op, const Operands &sv);

 private:
  Compared kind_;
  Op op_;
  uint32_t tensor_ = 0;
  std::size_t byte_offset_ = 0;  // A_VALUE
  std::size_t count_ = 0;        // TENSOR_AVERAGE_VALUE: element count
  Operands sv_{};
  EvalFn eval_ = nullptr;
  AvgFn avg_ = nullptr;
};

// Output tensors for an action: all tensors (PASSTHROUGH) or the picked ones. Throws
// nns::Error(kSettings) when a picked index is not below in.size().
TensorsInfo action_output(Action a, const std::vector<uint32_t> &pick, const TensorsInfo &in,
                          std::string_view what);

}  // namespace nns::tif

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_transform's `mode` / `option` / `apply` grammars (NNStreamer-compatible) and the shape
// and type each mode gives a tensor. GStreamer-free; errors are nns::Error quoting the bad token.
//
//   dimchg      FROM:TO                 move dimension FROM to position TO (0..15)
//   typecast    TYPE                    int8..uint64, float16/32/64
//   arithmetic  [typecast:TYPE,][per-channel:(false|true@DIM),](add|mul|div):N[:N...][@CH],...
//   transpose   A:B:C:3                 permutation of 0..2, then 3 (rank 4)
//   stand       (default|dc-average)[:TYPE][,per-channel:(true|false)]
//   clamp       MIN:MAX
//   padding     (left|right|top|bottom|front|back):N[,...][,layout:(NCHW|NHWC)]
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/tensor_info.h"

namespace nns::transform {

// Same numbering as NNStreamer's GEnum "gtt_mode_type".
enum class Mode : int {
  kUnknown = -1,
  kDimchg = 0,
  kTypecast = 1,
  kArithmetic = 2,
  kTranspose = 3,
  kStand = 4,
  kClamp = 5,
  kPadding = 6,
};
std::string_view mode_name(Mode m);  // "dimchg", ..., "unknown"

// A number from an option: integer unless it has '.', 'e' or 'E' (as upstream decides).
struct Number {
  bool is_float = false;
  double f = 0.0;
  int64_t i = 0;
  std::string text;
};

enum class OpKind { kAdd, kMul, kDiv };
std::string_view op_name(OpKind k);

struct ArithOp {
  OpKind kind = OpKind::kAdd;
  std::vector<Number> values;  // one value, or one per channel (needs per-channel)
  int channel = -1;            // @CH: only this channel; -1 = every channel
  std::string token;           // the option token, for messages
};

struct DimchgOptions {
  uint32_t from = 0, to = 0;
};
struct TypecastOptions {
  TensorType to = TensorType::kEnd;
};
struct ArithOptions {
  std::optional<TensorType> out_type;
  bool per_channel = false;
  uint32_t ch_dim = 0;
  std::vector<ArithOp> ops;
  // Accepted as upstream reads them, but worth telling the user (e.g. add:1:2 without
  // per-channel uses 1).
  std::vector<std::string> warnings;
};
struct TransposeOptions {
  std::array<uint32_t, 4> order{0, 1, 2, 3};
};
enum class StandMode { kDefault, kDcAverage };
struct StandOptions {
  StandMode mode = StandMode::kDefault;
  std::optional<TensorType> out_type;
  bool per_channel = false;
};
struct ClampOptions {
  double min = 0.0, max = 0.0;
};
struct PaddingOptions {
  // Pads before/after each of the three innermost dimensions: pad[2*axis], pad[2*axis+1].
  // NCHW (default): left/right -> dim 0, top/bottom -> dim 1, front/back -> dim 2.
  // NHWC: front/back -> dim 0, top/bottom -> dim 1, left/right -> dim 2 (as upstream).
  std::array<uint32_t, 6> pad{};
  bool nhwc = false;
};

struct Options {
  Mode mode = Mode::kUnknown;
  std::string option;
  std::variant<std::monostate, DimchgOptions, TypecastOptions, ArithOptions, TransposeOptions,
               StandOptions, ClampOptions, PaddingOptions>
      data;

  template <typename T>
  const T &get() const {
    return std::get<T>(data);
  }
  std::string describe() const;  // "mode=arithmetic option='add:1'"
};

// Parses `option` for `mode`. Throws nns::Error(kSettings) naming the property (mode or
// option), quoting the bad token and saying what was expected. `option` may be null.
Options parse_options(Mode mode, const char *option);

// Parses `apply` ("0,2"): tensor indices, empty = all. Throws nns::Error(kSettings).
std::vector<uint32_t> parse_apply(std::string_view apply);

// The tensor `in` becomes (sink -> src). Throws nns::Error(kNegotiation) when the tensor does
// not fit the option (e.g. per-channel index beyond the channel count).
TensorInfo output_info(const Options &opts, const TensorInfo &in);
// What input gives `out` (src -> sink), where derivable: fields that cannot be derived are left
// unknown (type kEnd, dims all 0).
TensorInfo input_info(const Options &opts, const TensorInfo &out);

// Axis permutation of dimchg/transpose for a tensor of rank `rank` (>= the axes the option
// names): output axis k takes input axis perm[k]. Returns the rank used.
std::size_t permutation(const Options &opts, std::size_t rank,
                        std::array<uint32_t, kRankLimit> &perm);

}  // namespace nns::transform

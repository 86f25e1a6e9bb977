// SPDX-License-Identifier: LGPL-2.1-only
#include "core/transform_options.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <limits>

#include "core/error.h"

namespace nns::transform {
namespace {

constexpr std::array<std::string_view, 7> kModeNames = {
    "dimchg", "typecast", "arithmetic", "transpose", "stand", "clamp", "padding"};

std::string lower(std::string_view s) {
  std::string out(s);
  for (auto &c : out) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
  return out;
}

std::string quote(std::string_view s) {
  return "'" + std::string(s) + "'";
}

bool all_digits(std::string_view s) {
  return !s.empty() && std::all_of(s.begin(), s.end(), [](char c) { return c >= '0' && c <= '9'; });
}

// Error about the option string of the current mode.
struct Ctx {
  Mode mode;
  std::string option;

  [[noreturn]] void bad(const std::string &msg) const {
    fail(ErrorKind::kSettings, "property 'option' " + quote(option) +
                                   " for mode=" + std::string(mode_name(mode)) + ": " + msg);
  }
};

// [-+]?[0-9]*\.?[0-9]+([eE][-+]?[0-9]+)?  (upstream's number grammar)
bool is_number(std::string_view s) {
  std::size_t i = 0, n = s.size();
  auto digits = [&] {
    std::size_t start = i;
    while (i < n && s[i] >= '0' && s[i] <= '9') ++i;
    return i - start;
  };
  if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
  std::size_t int_digits = digits();
  if (i < n && s[i] == '.') {
    ++i;
    if (digits() == 0) return false;
  } else if (int_digits == 0) {
    return false;
  }
  if (i < n && (s[i] == 'e' || s[i] == 'E')) {
    ++i;
    if (i < n && (s[i] == '+' || s[i] == '-')) ++i;
    if (digits() == 0) return false;
  }
  return i == n;
}

Number parse_number(const Ctx &c, std::string_view s, std::string_view token) {
  if (!is_number(s))
    c.bad("bad number " + quote(s) + " in " + quote(token) +
          " (expected a decimal number such as 2, -127.5 or 1e-3)");
  Number num;
  num.text = std::string(s);
  num.is_float = s.find_first_of(".eE") != std::string_view::npos;
  std::string_view digits = s[0] == '+' ? s.substr(1) : s;
  const char *end = digits.data() + digits.size();
  if (num.is_float) {
    auto [p, ec] = std::from_chars(digits.data(), end, num.f);
    if (ec != std::errc() || p != end) c.bad("number " + quote(s) + " is out of range");
    num.i = 0;
  } else {
    auto [p, ec] = std::from_chars(digits.data(), end, num.i);
    if (ec != std::errc() || p != end) c.bad("integer " + quote(s) + " is out of the int64 range");
    num.f = static_cast<double>(num.i);
  }
  return num;
}

TensorType parse_type_token(const Ctx &c, std::string_view s, std::string_view token) {
  if (auto t = type_from_name(lower(s))) return *t;
  c.bad("unknown type " + quote(s) + " in " + quote(token) +
        " (expected one of int8, int16, int32, int64, uint8, uint16, uint32, uint64, float16, "
        "float32, float64)");
}

// Splits the option on ','; a single trailing ',' is allowed (upstream's regex allows it).
std::vector<std::string> split_tokens(const Ctx &c, std::string_view s) {
  auto tokens = split(s, ",", true);
  if (!tokens.empty() && tokens.back().empty()) tokens.pop_back();
  for (const auto &t : tokens)
    if (t.empty()) c.bad("empty item between ',' separators");
  if (tokens.empty()) c.bad("the option is empty");
  return tokens;
}

DimchgOptions parse_dimchg(const Ctx &c) {
  auto parts = split(c.option, ":", false);
  auto dim = [&](const std::string &p) -> uint32_t {
    bool ok = (p.size() == 1 && all_digits(p)) ||
              (p.size() == 2 && p[0] == '1' && p[1] <= '5' && p[1] >= '0');
    if (!ok) c.bad("bad dimension index " + quote(p) + " (expected FROM:TO with indices 0..15)");
    return static_cast<uint32_t>(std::stoul(p));
  };
  if (parts.size() != 2) c.bad("expected FROM:TO with dimension indices 0..15, e.g. 0:2");
  return DimchgOptions{dim(parts[0]), dim(parts[1])};
}

ArithOptions parse_arithmetic(const Ctx &c) {
  ArithOptions a;
  auto tokens = split_tokens(c, c.option);
  std::size_t idx = 0;
  auto key_of = [](const std::string &t) { return lower(t.substr(0, t.find(':'))); };
  if (key_of(tokens[0]) == "typecast") {
    auto parts = split(tokens[0], ":", false);
    if (parts.size() != 2) c.bad("expected typecast:TYPE, got " + quote(tokens[0]));
    a.out_type = parse_type_token(c, parts[1], tokens[0]);
    ++idx;
  }
  if (idx < tokens.size() && key_of(tokens[idx]) == "per-channel") {
    const std::string &t = tokens[idx];
    std::string v = lower(t.substr(t.find(':') + 1));
    if (v == "false") {
      a.per_channel = false;
    } else if (v.rfind("true@", 0) == 0 && all_digits(v.substr(5))) {
      std::string d = v.substr(5);
      d.erase(0, std::min(d.find_first_not_of('0'), d.size() - 1));  // 0*([0-9]|1[0-5])
      if (d.size() > 2 || std::stoul(d) >= kRankLimit)
        c.bad("channel dimension " + quote(v.substr(5)) + " in " + quote(t) +
              " is out of range (expected 0..15)");
      a.per_channel = true;
      a.ch_dim = static_cast<uint32_t>(std::stoul(d));
    } else {
      c.bad("bad " + quote(t) +
            " (expected per-channel:false or per-channel:true@DIM with DIM "
            "0..15)");
    }
    ++idx;
  }
  for (; idx < tokens.size(); ++idx) {
    const std::string &t = tokens[idx];
    std::string key = key_of(t);
    if (key == "typecast") {
      // Upstream removes later typecast:TYPE items and ignores them; only the last item can go
      // without leaving an empty item behind (which its grammar refuses), so only that one is
      // accepted here, with a warning.
      auto parts = split(t, ":", false);
      if (idx + 1 == tokens.size() && parts.size() == 2 && a.ops.size() > 0) {
        parse_type_token(c, parts[1], t);
        a.warnings.push_back(quote(t) +
                             " is ignored: only a typecast:TYPE given first sets the output "
                             "type (put it first to cast the result)");
        continue;
      }
      c.bad(quote(t) +
            " must be the first item (typecast:TYPE,...) so the output is allocated "
            "once");
    }
    if (key == "per-channel")
      c.bad(quote(t) + " must come before the operations (after an optional typecast:TYPE)");
    ArithOp op;
    op.token = t;
    if (key == "add")
      op.kind = OpKind::kAdd;
    else if (key == "mul")
      op.kind = OpKind::kMul;
    else if (key == "div")
      op.kind = OpKind::kDiv;
    else
      c.bad("unknown operation " + quote(key) + " in " + quote(t) +
            " (expected add, mul or div, e.g. add:-127.5)");
    std::string body = t;
    if (auto at = t.find('@'); at != std::string::npos) {
      std::string ch = t.substr(at + 1);
      if (!all_digits(ch) || ch.size() > 9)
        c.bad("bad channel index " + quote(ch) + " in " + quote(t) + " (expected @CH, e.g. @0)");
      op.channel = std::stoi(ch);
      body = t.substr(0, at);
    }
    auto parts = split(body, ":", false);
    if (parts.size() < 2)
      c.bad("operation " + quote(t) + " has no value (expected " + key + ":NUMBER)");
    for (std::size_t i = 1; i < parts.size(); ++i)
      op.values.push_back(parse_number(c, parts[i], t));
    if (op.channel >= 0 && !a.per_channel)
      c.bad(quote(t) + " names channel " + std::to_string(op.channel) +
            " but per-channel is not enabled (add per-channel:true@DIM first)");
    if (op.values.size() > 1 && !a.per_channel) {
      // Upstream reads only the first value here: so do we, and say so.
      a.warnings.push_back(quote(t) + " has " + std::to_string(op.values.size()) +
                           " values but per-channel is not enabled: only the first (" + parts[1] +
                           ") is used (per-channel:true@DIM gives one per channel)");
      op.values.resize(1);
    }
    if (op.values.size() > 1 && op.channel >= 0)
      c.bad(quote(t) + " gives both one value per channel and a channel index @" +
            std::to_string(op.channel));
    a.ops.push_back(std::move(op));
  }
  if (a.ops.empty()) c.bad("no add/mul/div operation (e.g. typecast:float32,add:-127.5,div:127.5)");
  return a;
}

TransposeOptions parse_transpose(const Ctx &c) {
  auto parts = split(c.option, ":", false);
  const char *expect = " (expected a permutation of 0,1,2 followed by :3, e.g. 1:2:0:3)";
  if (parts.size() != 4) c.bad("expected 4 indices, got " + std::to_string(parts.size()) + expect);
  TransposeOptions t;
  bool seen[3] = {false, false, false};
  for (std::size_t i = 0; i < 3; ++i) {
    const auto &p = parts[i];
    if (p.size() != 1 || p[0] < '0' || p[0] > '2') c.bad("bad index " + quote(p) + expect);
    uint32_t v = static_cast<uint32_t>(p[0] - '0');
    if (seen[v]) c.bad("index " + quote(p) + " is repeated" + expect);
    seen[v] = true;
    t.order[i] = v;
  }
  if (parts[3] != "3") c.bad("the last index must be 3, got " + quote(parts[3]) + expect);
  return t;
}

StandOptions parse_stand(const Ctx &c) {
  StandOptions s;
  auto tokens = split(c.option, ",", true);
  const char *expect = " (expected (default|dc-average)[:TYPE][,per-channel:(true|false)])";
  if (tokens.empty() || tokens.size() > 2) c.bad("expected one or two items" + std::string(expect));
  auto parts = split(tokens[0], ":", false);
  std::string m = lower(parts[0]);
  if (m == "default")
    s.mode = StandMode::kDefault;
  else if (m == "dc-average")
    s.mode = StandMode::kDcAverage;
  else
    c.bad("unknown stand mode " + quote(parts[0]) + expect);
  if (parts.size() == 2)
    s.out_type = parse_type_token(c, parts[1], tokens[0]);
  else if (parts.size() > 2)
    c.bad("bad " + quote(tokens[0]) + expect);
  if (tokens.size() == 2) {
    std::string t = lower(tokens[1]);
    if (t == "per-channel:true")
      s.per_channel = true;
    else if (t == "per-channel:false")
      s.per_channel = false;
    else
      c.bad("bad " + quote(tokens[1]) + expect);
  }
  return s;
}

ClampOptions parse_clamp(const Ctx &c) {
  auto parts = split(c.option, ":", false);
  if (parts.size() != 2) c.bad("expected MIN:MAX, e.g. 0:255 or -1.5:1e3");
  ClampOptions o;
  o.min = parse_number(c, parts[0], c.option).f;
  o.max = parse_number(c, parts[1], c.option).f;
  if (o.min > o.max) c.bad("MIN " + quote(parts[0]) + " is larger than MAX " + quote(parts[1]));
  return o;
}

PaddingOptions parse_padding(const Ctx &c) {
  PaddingOptions p;
  auto tokens = split_tokens(c, c.option);
  const char *expect =
      " (expected (left|right|top|bottom|front|back):N[,...][,layout:(NCHW|NHWC)])";
  bool any_pad = false;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    const auto &t = tokens[i];
    auto kv = split(t, ":", false);
    if (kv.size() != 2) c.bad("bad item " + quote(t) + expect);
    std::string key = lower(kv[0]);
    if (key == "layout") {
      std::string v = lower(kv[1]);
      if (v != "nchw" && v != "nhwc") c.bad("bad layout " + quote(kv[1]) + expect);
      if (i + 1 != tokens.size()) c.bad(quote(t) + " must be the last item" + expect);
      p.nhwc = v == "nhwc";
      continue;
    }
    static constexpr std::array<std::string_view, 6> kKeys = {"left",   "right", "top",
                                                              "bottom", "front", "back"};
    auto it = std::find(kKeys.begin(), kKeys.end(), key);
    if (it == kKeys.end()) c.bad("unknown padding side " + quote(kv[0]) + expect);
    if (!all_digits(kv[1]) || kv[1].size() > 10 || std::stoull(kv[1]) > UINT32_MAX)
      c.bad("bad padding size " + quote(kv[1]) + " in " + quote(t) +
            " (expected an integer 0..4294967295)");
    p.pad[static_cast<std::size_t>(it - kKeys.begin())] = static_cast<uint32_t>(std::stoull(kv[1]));
    any_pad = true;
  }
  if (!any_pad) c.bad("no padding side given" + std::string(expect));
  for (std::size_t a = 0; a < 3; ++a)
    if (static_cast<uint64_t>(p.pad[2 * a]) + p.pad[2 * a + 1] > UINT32_MAX)
      c.bad("the pads of dimension " + std::to_string(a) + " add up to more than 4294967295");
  if (p.nhwc) {  // upstream swaps left/right with front/back for NHWC
    std::swap(p.pad[0], p.pad[4]);
    std::swap(p.pad[1], p.pad[5]);
  }
  return p;
}

uint32_t dim_or_1(const TensorInfo &t, std::size_t i) {
  return i < t.rank() ? t.dims[i] : 1;
}

}  // namespace

std::string_view mode_name(Mode m) {
  int i = static_cast<int>(m);
  return i >= 0 && i < static_cast<int>(kModeNames.size()) ? kModeNames[i]
                                                           : std::string_view("unknown");
}

std::string_view op_name(OpKind k) {
  switch (k) {
    case OpKind::kAdd:
      return "add";
    case OpKind::kMul:
      return "mul";
    case OpKind::kDiv:
      return "div";
  }
  return "?";
}

std::string Options::describe() const {
  return "mode=" + std::string(mode_name(mode)) + " option=" + quote(option);
}

Options parse_options(Mode mode, const char *option) {
  Options o;
  o.mode = mode;
  if (mode == Mode::kUnknown)
    fail(ErrorKind::kSettings,
         "property 'mode' is not set (expected one of dimchg, typecast, arithmetic, transpose, "
         "stand, clamp, padding)");
  if (static_cast<int>(mode) < -1 || static_cast<int>(mode) > 6)
    fail(ErrorKind::kSettings,
         "property 'mode' has the unknown value " + std::to_string(static_cast<int>(mode)));
  if (!option || !*option)
    fail(ErrorKind::kSettings,
         "property 'option' is not set; mode=" + std::string(mode_name(mode)) +
             " needs one (see the element "
             "documentation for its grammar)");
  o.option = option;
  Ctx c{mode, o.option};
  switch (mode) {
    case Mode::kDimchg:
      o.data = parse_dimchg(c);
      break;
    case Mode::kTypecast:
      o.data = TypecastOptions{parse_type_token(c, trim(o.option), o.option)};
      break;
    case Mode::kArithmetic:
      o.data = parse_arithmetic(c);
      break;
    case Mode::kTranspose:
      o.data = parse_transpose(c);
      break;
    case Mode::kStand:
      o.data = parse_stand(c);
      break;
    case Mode::kClamp:
      o.data = parse_clamp(c);
      break;
    case Mode::kPadding:
      o.data = parse_padding(c);
      break;
    case Mode::kUnknown:
      break;
  }
  return o;
}

std::vector<uint32_t> parse_apply(std::string_view apply) {
  std::vector<uint32_t> out;
  if (trim(apply).empty()) return out;
  for (const auto &t : split(apply, ",", true)) {
    if (!all_digits(t) || t.size() > 3 || std::stoul(t) >= kTensorLimit)
      fail(ErrorKind::kSettings, "property 'apply' " + quote(apply) + ": " + quote(t) +
                                     " is not a tensor index (expected integers 0..255 "
                                     "separated by ',')");
    out.push_back(static_cast<uint32_t>(std::stoul(t)));
  }
  return out;
}

std::size_t permutation(const Options &opts, std::size_t rank,
                        std::array<uint32_t, kRankLimit> &perm) {
  for (uint32_t k = 0; k < kRankLimit; ++k) perm[k] = k;
  if (opts.mode == Mode::kDimchg) {
    const auto &d = opts.get<DimchgOptions>();
    std::size_t r = std::max<std::size_t>({rank, d.from + 1u, d.to + 1u});
    if (d.from < d.to) {
      for (uint32_t k = d.from; k < d.to; ++k) perm[k] = k + 1;
    } else {
      for (uint32_t k = d.to + 1; k <= d.from; ++k) perm[k] = k - 1;
    }
    perm[d.to] = d.from;
    return r;
  }
  if (opts.mode == Mode::kTranspose) {
    const auto &t = opts.get<TransposeOptions>();
    for (std::size_t k = 0; k < 4; ++k) perm[k] = t.order[k];
    return std::max<std::size_t>(rank, 4);
  }
  return rank;
}

TensorInfo output_info(const Options &opts, const TensorInfo &in) {
  TensorInfo out = in;
  auto bad = [&](const std::string &msg) {
    fail(ErrorKind::kNegotiation, opts.describe() + " does not fit " + in.to_string() + ": " + msg);
  };
  switch (opts.mode) {
    case Mode::kDimchg:
    case Mode::kTranspose: {
      std::array<uint32_t, kRankLimit> perm;
      std::size_t r = permutation(opts, in.rank(), perm);
      for (std::size_t k = 0; k < r; ++k) out.dims[k] = dim_or_1(in, perm[k]);
      break;
    }
    case Mode::kTypecast:
      out.type = opts.get<TypecastOptions>().to;
      break;
    case Mode::kArithmetic: {
      const auto &a = opts.get<ArithOptions>();
      if (a.out_type) out.type = *a.out_type;
      if (a.per_channel) {
        uint32_t channels = dim_or_1(in, a.ch_dim);
        for (const auto &op : a.ops) {
          if (op.channel >= 0 && static_cast<uint32_t>(op.channel) >= channels)
            bad(quote(op.token) + " names channel " + std::to_string(op.channel) +
                " but dimension " + std::to_string(a.ch_dim) + " has " + std::to_string(channels) +
                " channels");
          if (op.values.size() > 1 && op.values.size() != channels)
            bad(quote(op.token) + " has " + std::to_string(op.values.size()) +
                " values but dimension " + std::to_string(a.ch_dim) + " has " +
                std::to_string(channels) + " channels");
        }
      }
      break;
    }
    case Mode::kStand: {
      const auto &s = opts.get<StandOptions>();
      if (s.out_type) out.type = *s.out_type;
      break;
    }
    case Mode::kClamp:
      break;
    case Mode::kPadding: {
      const auto &p = opts.get<PaddingOptions>();
      std::size_t padded_rank = 0;
      for (std::size_t a = 0; a < 3; ++a)
        if (p.pad[2 * a] + static_cast<uint64_t>(p.pad[2 * a + 1]) > 0) padded_rank = a + 1;
      for (std::size_t a = 0; a < std::max(padded_rank, std::min<std::size_t>(in.rank(), 3)); ++a) {
        uint64_t d = static_cast<uint64_t>(dim_or_1(in, a)) + p.pad[2 * a] + p.pad[2 * a + 1];
        if (d > UINT32_MAX)
          bad("padded dimension " + std::to_string(a) + " would be " + std::to_string(d) +
              ", larger than 4294967295");
        out.dims[a] = static_cast<uint32_t>(d);
      }
      break;
    }
    case Mode::kUnknown:
      bad("no mode");
  }
  return out;
}

TensorInfo input_info(const Options &opts, const TensorInfo &out) {
  TensorInfo in = out;
  switch (opts.mode) {
    case Mode::kDimchg:
    case Mode::kTranspose: {
      if (out.rank() == 0) break;
      std::array<uint32_t, kRankLimit> perm;
      std::size_t r = permutation(opts, out.rank(), perm);
      Dims d{};
      for (std::size_t k = 0; k < r; ++k) d[perm[k]] = dim_or_1(out, k);
      in.dims = d;
      break;
    }
    case Mode::kTypecast:
      in.type = TensorType::kEnd;
      break;
    case Mode::kArithmetic:
      if (opts.get<ArithOptions>().out_type) in.type = TensorType::kEnd;
      break;
    case Mode::kStand:
      if (opts.get<StandOptions>().out_type) in.type = TensorType::kEnd;
      break;
    case Mode::kClamp:
    case Mode::kUnknown:
      break;
    case Mode::kPadding: {
      if (out.rank() == 0) break;
      const auto &p = opts.get<PaddingOptions>();
      for (std::size_t a = 0; a < 3; ++a) {
        uint64_t pads = static_cast<uint64_t>(p.pad[2 * a]) + p.pad[2 * a + 1];
        uint32_t d = dim_or_1(out, a);
        if (pads == 0) continue;
        if (d <= pads) return TensorInfo{out.name, in.type, Dims{}};
        in.dims[a] = static_cast<uint32_t>(d - pads);
      }
      break;
    }
  }
  return in;
}

}  // namespace nns::transform

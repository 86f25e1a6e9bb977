// SPDX-License-Identifier: LGPL-2.1-only
#include "gst/tensor_caps.h"

#include <algorithm>

#include "core/error.h"
#include "gst/gst_ptr.h"

namespace nns::gst {
namespace {

constexpr const char *kTensors = "other/tensors";
constexpr const char *kTensor = "other/tensor";

void read_rate(const GstStructure *s, TensorsConfig &c) {
  int n, d;
  if (gst_structure_get_fraction(s, "framerate", &n, &d)) {
    c.rate_n = n;
    c.rate_d = d;
  }
}

void set_rate(GstStructure *s, int n, int d) {
  if (n >= 0 && d > 0)
    gst_structure_set(s, "framerate", GST_TYPE_FRACTION, n, d, nullptr);
  else
    gst_structure_set(s, "framerate", GST_TYPE_FRACTION_RANGE, 0, 1, G_MAXINT, 1, nullptr);
}

// Sets `field` to one string, or to a list of strings when there are alternatives.
void set_string_or_list(GstStructure *s, const char *field, const std::vector<std::string> &v) {
  if (v.size() == 1) {
    gst_structure_set(s, field, G_TYPE_STRING, v[0].c_str(), nullptr);
    return;
  }
  GValue list = G_VALUE_INIT;
  gst_value_list_init(&list, v.size());
  for (const auto &x : v) {
    GValue item = G_VALUE_INIT;
    g_value_init(&item, G_TYPE_STRING);
    g_value_set_string(&item, x.c_str());
    gst_value_list_append_and_take_value(&list, &item);
  }
  gst_structure_take_value(s, field, &list);
}

// All combinations of per-tensor spellings, joined with `sep`; at most `limit` of them.
std::vector<std::string> dims_variants(const TensorsInfo &info, std::size_t limit, char sep) {
  std::vector<std::string> out{""};
  for (std::size_t i = 0; i < info.size(); ++i) {
    auto sp = dim_spellings(info[i].dims);
    if (out.size() * sp.size() > limit) sp.resize(1);
    std::vector<std::string> next;
    for (const auto &prefix : out)
      for (const auto &x : sp) next.push_back(i ? prefix + sep + x : x);
    out = std::move(next);
  }
  return out;
}

}  // namespace

bool is_tensor_structure(const GstStructure *s) {
  return gst_structure_has_name(s, kTensors) || gst_structure_has_name(s, kTensor);
}

bool is_tensor_caps(const GstCaps *caps) {
  if (!caps || gst_caps_is_empty(caps) || gst_caps_is_any(caps)) return false;
  for (guint i = 0; i < gst_caps_get_size(caps); ++i)
    if (!is_tensor_structure(gst_caps_get_structure(caps, i))) return false;
  return true;
}

bool structure_allows_format(const GstStructure *s, TensorFormat format) {
  if (gst_structure_has_name(s, kTensor)) return format == TensorFormat::kStatic;
  if (!gst_structure_has_name(s, kTensors)) return false;
  const GValue *v = gst_structure_get_value(s, "format");
  if (!v) return true;
  const std::string want(format_name(format));
  if (G_VALUE_HOLDS_STRING(v)) return want == g_value_get_string(v);
  if (GST_VALUE_HOLDS_LIST(v)) {
    for (guint i = 0; i < gst_value_list_get_size(v); ++i) {
      const GValue *e = gst_value_list_get_value(v, i);
      if (G_VALUE_HOLDS_STRING(e) && want == g_value_get_string(e)) return true;
    }
  }
  return false;
}

void check_flexible_caps_fields(const GstCaps *caps, const TensorsInfo &info,
                                const std::string &who) {
  if (!caps || gst_caps_is_empty(caps) || gst_caps_is_any(caps)) return;
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  if (!gst_structure_has_name(s, kTensors)) return;
  // Read the static fields as if the structure were static.
  GstStructure *copy = gst_structure_copy(s);
  gst_structure_set(copy, "format", G_TYPE_STRING, "static", nullptr);
  const bool has_num = gst_structure_has_field(copy, "num_tensors");
  const char *types = gst_structure_get_string(copy, "types");
  const char *dims = gst_structure_get_string(copy, "dimensions");
  std::string problem;
  try {
    if (has_num || types || dims) {
      TensorsConfig c = config_from_structure(copy);
      const std::string caps_text = caps_to_string(caps);
      if (c.info.size() != info.size()) {
        problem = "the output caps " + caps_text + " describe " + std::to_string(c.info.size()) +
                  " tensor(s), but " + who + " " + std::to_string(info.size()) + " (" +
                  info.to_string() + ")";
      } else {
        for (std::size_t i = 0; i < info.size() && problem.empty(); ++i) {
          if (types && c.info[i].type != info[i].type)
            problem = "the output caps " + caps_text + " say types=" + types + ", but " + who +
                      " " + info.types_string();
          else if (dims && !dims_equal(c.info[i].dims, info[i].dims))
            problem = "the output caps " + caps_text + " say dimensions=" + dims + ", but " + who +
                      " " + info.dims_string();
        }
      }
    }
  } catch (const Error &e) {
    problem = std::string("the output caps have bad static fields: ") + e.what();
  }
  gst_structure_free(copy);
  if (!problem.empty()) fail(ErrorKind::kNegotiation, problem);
}

bool is_decorated_flexible(const GstCaps *caps) {
  if (!caps || gst_caps_is_empty(caps) || gst_caps_is_any(caps)) return false;
  const GstStructure *s = gst_caps_get_structure(caps, 0);
  if (!gst_structure_has_name(s, kTensors)) return false;
  const char *f = gst_structure_get_string(s, "format");
  if (!f || std::string(f) != "flexible") return false;
  return gst_structure_has_field(s, "num_tensors") || gst_structure_has_field(s, "types") ||
         gst_structure_has_field(s, "dimensions");
}

TensorsConfig config_from_structure(const GstStructure *s) {
  TensorsConfig c;
  read_rate(s, c);
  if (gst_structure_has_name(s, kTensor)) {
    TensorInfo t;
    if (const char *d = gst_structure_get_string(s, "dimension")) t.dims = parse_dims(d);
    if (const char *ty = gst_structure_get_string(s, "type")) t.type = parse_type(ty);
    c.info.tensors.push_back(t);
    return c;
  }
  if (!gst_structure_has_name(s, kTensors))
    fail(ErrorKind::kNegotiation,
         std::string("expected other/tensors caps, got ") + gst_structure_get_name(s));
  if (const char *f = gst_structure_get_string(s, "format")) {
    auto fmt = format_from_name(f);
    if (!fmt)
      fail(ErrorKind::kNegotiation,
           std::string("caps field format='") + f + "' is not static, flexible or sparse");
    c.info.format = *fmt;
  }
  if (c.info.format != TensorFormat::kStatic) return c;
  int num = 0;
  bool has_num = gst_structure_get_int(s, "num_tensors", &num);
  const char *dims = gst_structure_get_string(s, "dimensions");
  const char *types = gst_structure_get_string(s, "types");
  std::vector<Dims> dl;
  std::vector<TensorType> tl;
  try {
    if (dims) dl = parse_dims_list(dims, "caps field dimensions");
    if (types) tl = parse_types_list(types, "caps field types");
  } catch (const Error &e) {
    fail(ErrorKind::kNegotiation, e.what());
  }
  std::size_t n = has_num ? static_cast<std::size_t>(num) : std::max(dl.size(), tl.size());
  if (has_num && (num < 1 || static_cast<std::size_t>(num) > kTensorLimit))
    fail(ErrorKind::kNegotiation, "caps field num_tensors=" + std::to_string(num) +
                                      " is outside 1.." + std::to_string(kTensorLimit));
  if (dims && dl.size() != n)
    fail(ErrorKind::kNegotiation, "caps field num_tensors=" + std::to_string(n) +
                                      " but dimensions='" + dims + "' lists " +
                                      std::to_string(dl.size()));
  if (types && tl.size() != n)
    fail(ErrorKind::kNegotiation, "caps field num_tensors=" + std::to_string(n) + " but types='" +
                                      types + "' lists " + std::to_string(tl.size()));
  c.info.tensors.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (i < dl.size()) c.info.tensors[i].dims = dl[i];
    if (i < tl.size()) c.info.tensors[i].type = tl[i];
  }
  return c;
}

TensorsConfig config_from_caps(const GstCaps *caps) {
  if (!caps || gst_caps_is_empty(caps) || gst_caps_is_any(caps))
    fail(ErrorKind::kNegotiation, "no tensor caps to read");
  return config_from_structure(gst_caps_get_structure(caps, 0));
}

std::vector<std::string> dim_spellings(const Dims &d) {
  std::size_t r = rank_of(d);
  if (r == 0) return {""};
  std::size_t minr = r;
  while (minr > 1 && d[minr - 1] == 1) --minr;
  std::size_t maxr = std::max<std::size_t>(r, 4);
  // The spelling as given comes first, so fixation picks it when the peer does not care.
  std::vector<std::string> out{dims_to_string(d)};
  for (std::size_t k = minr; k <= maxr; ++k) {
    if (k == r) continue;
    std::string s;
    for (std::size_t i = 0; i < k; ++i) {
      if (i) s += ':';
      s += std::to_string(i < r ? d[i] : 1);
    }
    out.push_back(s);
  }
  return out;
}

GstStructure *structure_from_config(const TensorsConfig &config) {
  const auto &info = config.info;
  GstStructure *s = gst_structure_new(kTensors, "format", G_TYPE_STRING,
                                      std::string(format_name(info.format)).c_str(), nullptr);
  if (info.format == TensorFormat::kStatic && !info.tensors.empty()) {
    gst_structure_set(s, "num_tensors", G_TYPE_INT, static_cast<int>(info.size()), nullptr);
    bool dims_known = true, types_known = true;
    for (const auto &t : info.tensors) {
      dims_known = dims_known && t.rank() > 0;
      types_known = types_known && t.type != TensorType::kEnd;
    }
    if (dims_known)
      gst_structure_set(s, "dimensions", G_TYPE_STRING, info.dims_string().c_str(), nullptr);
    if (types_known)
      gst_structure_set(s, "types", G_TYPE_STRING, info.types_string().c_str(), nullptr);
  }
  set_rate(s, config.rate_n, config.rate_d);
  return s;
}

GstCaps *caps_from_config(const TensorsConfig &config, bool dim_variants) {
  const auto &info = config.info;
  GstStructure *s = structure_from_config(config);
  bool static_known = info.format == TensorFormat::kStatic && info.valid();
  // Dimension spellings are offered whenever every dimension is known, even if a type is not
  // (e.g. the sink caps of a typecast derived from its src caps).
  bool dims_known = info.format == TensorFormat::kStatic && !info.tensors.empty() &&
                    std::all_of(info.tensors.begin(), info.tensors.end(),
                                [](const TensorInfo &t) { return t.rank() > 0; });
  if (dim_variants && dims_known) {
    // Several tensors: also the '.'-joined lists (upstream's tests and gst-launch lines write
    // them so, a ',' inside a field needing quotes there). Ours (',') stay first.
    auto dl = dims_variants(info, 32, ',');
    if (info.size() > 1) {
      auto dot = dims_variants(info, 32, '.');
      dl.insert(dl.end(), dot.begin(), dot.end());
    }
    set_string_or_list(s, "dimensions", dl);
  }
  bool types_known = info.format == TensorFormat::kStatic && !info.tensors.empty() &&
                     std::all_of(info.tensors.begin(), info.tensors.end(),
                                 [](const TensorInfo &t) { return t.type != TensorType::kEnd; });
  if (dim_variants && types_known && info.size() > 1) {
    std::string dot;
    for (std::size_t i = 0; i < info.size(); ++i)
      dot += (i ? "." : "") + std::string(type_name(info[i].type));
    set_string_or_list(s, "types", {info.types_string(), dot});
  }
  GstCaps *caps = gst_caps_new_full(s, nullptr);
  if (static_known && info.size() == 1) {
    GstStructure *legacy = gst_structure_new(kTensor, "type", G_TYPE_STRING,
                                             std::string(type_name(info[0].type)).c_str(), nullptr);
    if (dim_variants)
      set_string_or_list(legacy, "dimension", dim_spellings(info[0].dims));
    else
      gst_structure_set(legacy, "dimension", G_TYPE_STRING, dims_to_string(info[0].dims).c_str(),
                        nullptr);
    set_rate(legacy, config.rate_n, config.rate_d);
    gst_caps_append_structure(caps, legacy);
  }
  return caps;
}

GstCaps *with_tensor_spellings(GstCaps *caps) {
  if (!is_tensor_caps(caps) || !gst_caps_is_fixed(caps)) return caps;
  try {
    TensorsConfig cfg = config_from_caps(caps);
    // Without a framerate the rebuilt caps would offer any rate: keep those as they are.
    if (cfg.info.format != TensorFormat::kStatic || !cfg.info.valid() || cfg.info.size() < 2 ||
        cfg.rate_n < 0)
      return caps;
    gst_caps_unref(caps);
    return caps_from_config(cfg, true);
  } catch (const Error &) {
    return caps;  // not readable as a config: offered as they are
  }
}

GstCaps *caps_in_peer_spelling(GstPad *srcpad, GstCaps *caps) {
  GstCaps *variants = with_tensor_spellings(gst_caps_ref(caps));
  if (variants == caps) return variants;
  CapsPtr own(variants);
  CapsPtr peer(gst_pad_peer_query_caps(srcpad, variants));
  if (!peer || gst_caps_is_empty(peer.get()) || gst_caps_can_intersect(peer.get(), caps))
    return gst_caps_ref(caps);
  return gst_caps_fixate(peer.release());
}

GstCaps *caps_for_format(TensorFormat format, int rate_n, int rate_d) {
  TensorsConfig c;
  c.info.format = format;
  c.rate_n = rate_n;
  c.rate_d = rate_d;
  return gst_caps_new_full(structure_from_config(c), nullptr);
}

GstCaps *legacy_tensor_caps(int rate_n, int rate_d) {
  GstStructure *s = gst_structure_new_empty(kTensor);
  set_rate(s, rate_n, rate_d);
  return gst_caps_new_full(s, nullptr);
}

std::string caps_to_string(const GstCaps *caps) {
  if (!caps) return "(none)";
  GCharPtr s(gst_caps_to_string(caps));
  return s ? std::string(s.get()) : std::string("(none)");
}

}  // namespace nns::gst

// SPDX-License-Identifier: LGPL-2.1-only
// tensor_data.h: NNStreamer 2.x's typed single values and raw statistics. Values are C casts as
// NNStreamer makes them (integers wrap, float to unsigned goes through the signed type of the
// same width); float16 is supported (NNStreamer needs its FLOAT16_SUPPORT build for it).
#include "tensor_data.h"

#include <cmath>
#include <cstring>

#include "compat/compat_export.h"
#include "core/float16.h"
#include "nnstreamer_plugin_api_util.h"

namespace {

std::size_t size_of(tensor_type t) {
  return t < _NNS_END ? gst_tensor_get_element_size(t) : 0;
}

bool is_float(tensor_type t) {
  return t == _NNS_FLOAT16 || t == _NNS_FLOAT32 || t == _NNS_FLOAT64;
}

double float_of(const tensor_data_s &td) {
  switch (td.type) {
    case _NNS_FLOAT16:
      return nns::half_to_float(td.data._uint16_t);
    case _NNS_FLOAT32:
      return td.data._float;
    default:
      return td.data._double;
  }
}

// The source as a 64-bit integer pattern (signed sources sign-extended).
uint64_t int_of(const tensor_data_s &td) {
  switch (td.type) {
    case _NNS_INT8:
      return static_cast<uint64_t>(int64_t{td.data._int8_t});
    case _NNS_UINT8:
      return td.data._uint8_t;
    case _NNS_INT16:
      return static_cast<uint64_t>(int64_t{td.data._int16_t});
    case _NNS_UINT16:
      return td.data._uint16_t;
    case _NNS_INT32:
      return static_cast<uint64_t>(int64_t{td.data._int32_t});
    case _NNS_UINT32:
      return td.data._uint32_t;
    case _NNS_INT64:
      return static_cast<uint64_t>(td.data._int64_t);
    default:
      return td.data._uint64_t;
  }
}

bool is_signed_int(tensor_type t) {
  return t == _NNS_INT8 || t == _NNS_INT16 || t == _NNS_INT32 || t == _NNS_INT64;
}

// A float cast to a signed integer as x86 does it (out of range and NaN: the minimum).
int64_t trunc_s64(double v) {
  if (std::isnan(v) || v >= 9223372036854775808.0 || v < -9223372036854775808.0) return INT64_MIN;
  return static_cast<int64_t>(v);
}

}  // namespace

NNS_COMPAT_API gboolean gst_tensor_data_set(tensor_data_s *td, tensor_type type, gpointer value) {
  if (!td || !value) return FALSE;
  td->data._int64_t = 0;
  td->type = _NNS_END;
  std::size_t n = size_of(type);
  if (!n) return FALSE;
  std::memcpy(&td->data, value, n);
  td->type = type;
  return TRUE;
}

NNS_COMPAT_API gboolean gst_tensor_data_get(tensor_data_s *td, gpointer value) {
  if (!td || !value) return FALSE;
  std::size_t n = size_of(td->type);
  if (!n) return FALSE;
  std::memcpy(value, &td->data, n);
  return TRUE;
}

NNS_COMPAT_API gboolean gst_tensor_data_typecast(tensor_data_s *td, tensor_type type) {
  if (!td) return FALSE;
  if (td->type == type) return TRUE;
  if (!size_of(td->type) || !size_of(type)) return FALSE;
  const bool from_float = is_float(td->type);
  const double f = from_float ? float_of(*td) : 0.0;
  const uint64_t i = from_float ? static_cast<uint64_t>(trunc_s64(f)) : int_of(*td);
  const bool from_signed = is_signed_int(td->type);
  auto as_double = [&]() -> double {
    if (from_float) return f;
    return from_signed ? static_cast<double>(static_cast<int64_t>(i)) : static_cast<double>(i);
  };
  tensor_element out;
  out._int64_t = 0;
  switch (type) {
    case _NNS_INT8:
    case _NNS_UINT8:
      out._uint8_t = static_cast<uint8_t>(i);
      break;
    case _NNS_INT16:
    case _NNS_UINT16:
      out._uint16_t = static_cast<uint16_t>(i);
      break;
    case _NNS_INT32:
    case _NNS_UINT32:
      out._uint32_t = static_cast<uint32_t>(i);
      break;
    case _NNS_INT64:
    case _NNS_UINT64:
      out._uint64_t = i;
      break;
    case _NNS_FLOAT16:
      out._uint16_t = nns::float_to_half(static_cast<float>(as_double()));
      break;
    case _NNS_FLOAT32:
      out._float = static_cast<float>(as_double());
      break;
    case _NNS_FLOAT64:
      out._double = as_double();
      break;
    default:
      return FALSE;
  }
  td->data = out;
  td->type = type;
  return TRUE;
}

NNS_COMPAT_API gboolean gst_tensor_data_raw_typecast(gpointer input, tensor_type in_type,
                                                     gpointer output, tensor_type out_type) {
  if (!input || !output || in_type == _NNS_END || out_type == _NNS_END) return FALSE;
  tensor_data_s td;
  if (!gst_tensor_data_set(&td, in_type, input)) return FALSE;
  if (!gst_tensor_data_typecast(&td, out_type)) return FALSE;
  return gst_tensor_data_get(&td, output);
}

namespace {

double value_at(const uint8_t *raw, std::size_t idx, tensor_type type, std::size_t es) {
  double v = 0.0;
  gst_tensor_data_raw_typecast(const_cast<uint8_t *>(raw + idx * es), type, &v, _NNS_FLOAT64);
  return v;
}

// Per channel (stride channels, channel ch) running average or deviation around mean; channels
// = 1 for the whole buffer.
gboolean stats(gpointer raw, gsize length, tensor_type type, std::size_t channels,
               const gdouble *means, gdouble **out) {
  std::size_t es = size_of(type);
  if (!raw || !length || !es || !channels || !out) return FALSE;
  std::size_t num = length / es / channels;
  *out = static_cast<gdouble *>(g_try_malloc0(sizeof(gdouble) * channels));
  if (!*out) return FALSE;
  const auto *p = static_cast<const uint8_t *>(raw);
  for (std::size_t ch = 0; ch < channels; ++ch) {
    double acc = 0.0;
    for (std::size_t i = 0; i < num; ++i) {
      double v = value_at(p, i * channels + ch, type, es);
      if (means)
        acc += std::pow(v - means[ch], 2) / static_cast<double>(num);
      else
        acc = (v - acc) / static_cast<double>(i + 1) + acc;
    }
    if (means) acc = acc != 0.0 ? std::sqrt(acc) : 1e-10;
    (*out)[ch] = acc;
  }
  return TRUE;
}

}  // namespace

NNS_COMPAT_API gboolean gst_tensor_data_raw_average(gpointer raw, gsize length, tensor_type type,
                                                    gdouble **result) {
  return stats(raw, length, type, 1, nullptr, result);
}

NNS_COMPAT_API gboolean gst_tensor_data_raw_average_per_channel(gpointer raw, gsize length,
                                                                tensor_type type, tensor_dim dim,
                                                                gdouble **results) {
  return dim ? stats(raw, length, type, dim[0], nullptr, results) : FALSE;
}

NNS_COMPAT_API gboolean gst_tensor_data_raw_std(gpointer raw, gsize length, tensor_type type,
                                                gdouble *average, gdouble **result) {
  return average ? stats(raw, length, type, 1, average, result) : FALSE;
}

NNS_COMPAT_API gboolean gst_tensor_data_raw_std_per_channel(gpointer raw, gsize length,
                                                            tensor_type type, tensor_dim dim,
                                                            gdouble *averages, gdouble **results) {
  return dim && averages ? stats(raw, length, type, dim[0], averages, results) : FALSE;
}

// SPDX-License-Identifier: LGPL-2.1-only
// NNStreamer 2.x's element-wise helpers (nnstreamer-orc.h): nns_orc_add_c_* / mul_c_* / div_c_*
// (in place, with a constant) and nns_orc_conv_<from>_to_<to> for the ten tensor types. NNStreamer
// builds them with ORC; here they are plain loops with ORC's per-opcode results, so the values
// are the same: integer add and mul saturate (64-bit add wraps; 64-bit mul first saturates the
// element to 32 bits, as NNStreamer's programs do), conversions go through NNStreamer's chains of
// ORC steps (sign/zero extension, truncation, or saturation at each width; float to integer
// truncates toward zero and saturates at the 32-bit limits).
#include <cmath>
#include <cstdint>
#include <limits>

#include "compat/compat_export.h"
#include "nnstreamer-orc.h"

namespace {

template <typename To, typename From>
To sat(From v) {
  if (v < static_cast<From>(std::numeric_limits<To>::min())) return std::numeric_limits<To>::min();
  if (v > static_cast<From>(std::numeric_limits<To>::max())) return std::numeric_limits<To>::max();
  return static_cast<To>(v);
}

// ORC's width steps (names as ORC's opcodes). Arguments are bit patterns of the given width.
int16_t convsbw(int8_t v) {
  return v;
}
uint16_t convubw(uint8_t v) {
  return v;
}
int32_t convswl(int16_t v) {
  return v;
}
uint32_t convuwl(uint16_t v) {
  return v;
}
int64_t convslq(int32_t v) {
  return v;
}
uint64_t convulq(uint32_t v) {
  return v;
}
uint8_t convwb(uint16_t v) {
  return static_cast<uint8_t>(v);
}
uint16_t convlw(uint32_t v) {
  return static_cast<uint16_t>(v);
}
uint32_t convql(uint64_t v) {
  return static_cast<uint32_t>(v);
}
int8_t convssswb(int16_t v) {
  return sat<int8_t>(v);
}
int16_t convssslw(int32_t v) {
  return sat<int16_t>(v);
}
int32_t convsssql(int64_t v) {
  return sat<int32_t>(v);
}
[[maybe_unused]] uint8_t convuuswb(uint16_t v) {
  return sat<uint8_t>(v);
}
[[maybe_unused]] uint16_t convuuslw(uint32_t v) {
  return sat<uint16_t>(v);
}
[[maybe_unused]] uint32_t convuusql(uint64_t v) {
  return sat<uint32_t>(v);
}
float convlf(int32_t v) {
  return static_cast<float>(v);
}
double convld(int32_t v) {
  return static_cast<double>(v);
}
template <typename F>
int32_t to_s32(F v) {  // truncation toward zero, saturated; NaN as x86 gives it, then ORC's fix-up
  if (std::isnan(v)) return std::signbit(v) ? INT32_MIN : INT32_MAX;
  if (v >= 2147483648.0) return INT32_MAX;
  if (v < -2147483648.0) return INT32_MIN;
  return static_cast<int32_t>(v);
}
int32_t convfl(float v) {
  return to_s32(v);
}
int32_t convdl(double v) {
  return to_s32(v);
}
double convfd(float v) {
  return v;
}
float convdf(double v) {
  return static_cast<float>(v);
}

// In-place arithmetic with a constant.
int8_t add_s8(int8_t d, int p) {
  return sat<int8_t>(int{d} + static_cast<int8_t>(p));
}
uint8_t add_u8(uint8_t d, int p) {
  return sat<uint8_t>(int{d} + static_cast<uint8_t>(p));
}
int16_t add_s16(int16_t d, int p) {
  return sat<int16_t>(int{d} + static_cast<int16_t>(p));
}
uint16_t add_u16(uint16_t d, int p) {
  return sat<uint16_t>(int{d} + static_cast<uint16_t>(p));
}
int32_t add_s32(int32_t d, int p) {
  return sat<int32_t>(int64_t{d} + p);
}
uint32_t add_u32(uint32_t d, int p) {
  return sat<uint32_t>(uint64_t{d} + static_cast<uint32_t>(p));
}
int64_t add_s64(int64_t d, int p) {
  return static_cast<int64_t>(static_cast<uint64_t>(d) + static_cast<uint64_t>(int64_t{p}));
}
uint64_t add_u64(uint64_t d, int p) {
  return d + static_cast<uint32_t>(p);
}
float add_f32(float d, float p) {
  return d + p;
}
double add_f64(double d, double p) {
  return d + p;
}

int8_t mul_s8(int8_t d, int p) {
  return convssswb(static_cast<int16_t>(d * static_cast<int8_t>(p)));
}
uint8_t mul_u8(uint8_t d, int p) {
  return sat<uint8_t>(static_cast<uint16_t>(d * static_cast<uint8_t>(p)));
}
int16_t mul_s16(int16_t d, int p) {
  return convssslw(d * static_cast<int16_t>(p));
}
uint16_t mul_u16(uint16_t d, int p) {
  return sat<uint16_t>(uint32_t{d} * static_cast<uint16_t>(p));
}
int32_t mul_s32(int32_t d, int p) {
  return convsssql(int64_t{d} * p);
}
uint32_t mul_u32(uint32_t d, int p) {
  return sat<uint32_t>(uint64_t{d} * static_cast<uint32_t>(p));
}
int64_t mul_s64(int64_t d, int p) {
  return int64_t{convsssql(d)} * p;
}
uint64_t mul_u64(uint64_t d, int p) {
  return uint64_t{static_cast<uint32_t>(convsssql(static_cast<int64_t>(d)))} *
         static_cast<uint32_t>(p);
}
float mul_f32(float d, float p) {
  return d * p;
}
double mul_f64(double d, double p) {
  return d * p;
}
float div_f32(float d, float p) {
  return d / p;
}
double div_f64(double d, double p) {
  return d / p;
}

}  // namespace

NNS_COMPAT_API void nns_orc_add_c_s8(int8_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_s8(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_s8(int8_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_s8(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_s8_to_s8(int8_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int8_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s8_to_u8(uint8_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint8_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s8_to_s16(int16_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int16_t>(convsbw(static_cast<int8_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s8_to_u16(uint16_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint16_t>(convsbw(static_cast<int8_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s8_to_s32(int32_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<int32_t>(convswl(static_cast<int16_t>(convsbw(static_cast<int8_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s8_to_u32(uint32_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint32_t>(convswl(static_cast<int16_t>(convsbw(static_cast<int8_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s8_to_s64(int64_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int64_t>(convslq(
        static_cast<int32_t>(convswl(static_cast<int16_t>(convsbw(static_cast<int8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_s8_to_u64(uint64_t *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint64_t>(convslq(
        static_cast<int32_t>(convswl(static_cast<int16_t>(convsbw(static_cast<int8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_s8_to_f32(float *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<float>(convlf(
        static_cast<int32_t>(convswl(static_cast<int16_t>(convsbw(static_cast<int8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_s8_to_f64(double *d1, const int8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<double>(convld(
        static_cast<int32_t>(convswl(static_cast<int16_t>(convsbw(static_cast<int8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_add_c_u8(uint8_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_u8(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_u8(uint8_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_u8(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_u8_to_s8(int8_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int8_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u8_to_u8(uint8_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint8_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u8_to_s16(int16_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int16_t>(convubw(static_cast<uint8_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u8_to_u16(uint16_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint16_t>(convubw(static_cast<uint8_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u8_to_s32(int32_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<int32_t>(convuwl(static_cast<uint16_t>(convubw(static_cast<uint8_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u8_to_u32(uint32_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint32_t>(convuwl(static_cast<uint16_t>(convubw(static_cast<uint8_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u8_to_s64(int64_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int64_t>(convulq(static_cast<uint32_t>(
        convuwl(static_cast<uint16_t>(convubw(static_cast<uint8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_u8_to_u64(uint64_t *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint64_t>(convulq(static_cast<uint32_t>(
        convuwl(static_cast<uint16_t>(convubw(static_cast<uint8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_u8_to_f32(float *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<float>(convlf(static_cast<int32_t>(
        convuwl(static_cast<uint16_t>(convubw(static_cast<uint8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_u8_to_f64(double *d1, const uint8_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<double>(convld(static_cast<int32_t>(
        convuwl(static_cast<uint16_t>(convubw(static_cast<uint8_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_add_c_s16(int16_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_s16(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_s16(int16_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_s16(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_s16_to_s8(int8_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int8_t>(convssswb(static_cast<int16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s16_to_u8(uint8_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint8_t>(convwb(static_cast<uint16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s16_to_s16(int16_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int16_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s16_to_u16(uint16_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint16_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s16_to_s32(int32_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(convswl(static_cast<int16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s16_to_u32(uint32_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(convswl(static_cast<int16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s16_to_s64(int64_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<int64_t>(convslq(static_cast<int32_t>(convswl(static_cast<int16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s16_to_u64(uint64_t *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint64_t>(convslq(static_cast<int32_t>(convswl(static_cast<int16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s16_to_f32(float *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<float>(convlf(static_cast<int32_t>(convswl(static_cast<int16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s16_to_f64(double *d1, const int16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<double>(convld(static_cast<int32_t>(convswl(static_cast<int16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_add_c_u16(uint16_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_u16(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_u16(uint16_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_u16(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_u16_to_s8(int8_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int8_t>(convssswb(static_cast<int16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u16_to_u8(uint8_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint8_t>(convwb(static_cast<uint16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u16_to_s16(int16_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int16_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u16_to_u16(uint16_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint16_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u16_to_s32(int32_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(convuwl(static_cast<uint16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u16_to_u32(uint32_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(convuwl(static_cast<uint16_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u16_to_s64(int64_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<int64_t>(convulq(static_cast<uint32_t>(convuwl(static_cast<uint16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u16_to_u64(uint64_t *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint64_t>(
        convulq(static_cast<uint32_t>(convuwl(static_cast<uint16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u16_to_f32(float *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<float>(convlf(static_cast<int32_t>(convuwl(static_cast<uint16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u16_to_f64(double *d1, const uint16_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<double>(convld(static_cast<int32_t>(convuwl(static_cast<uint16_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_add_c_s32(int32_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_s32(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_s32(int32_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_s32(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_s32_to_s8(int8_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int8_t>(
        convssswb(static_cast<int16_t>(convssslw(static_cast<int32_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s32_to_u8(uint8_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint8_t>(convwb(static_cast<uint16_t>(convlw(static_cast<uint32_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s32_to_s16(int16_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int16_t>(convssslw(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s32_to_u16(uint16_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint16_t>(convssslw(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s32_to_s32(int32_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s32_to_u32(uint32_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s32_to_s64(int64_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int64_t>(convslq(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s32_to_u64(uint64_t *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint64_t>(convslq(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s32_to_f32(float *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<float>(convlf(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s32_to_f64(double *d1, const int32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<double>(convld(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_add_c_u32(uint32_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_u32(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_u32(uint32_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_u32(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_u32_to_s8(int8_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int8_t>(
        convssswb(static_cast<int16_t>(convssslw(static_cast<int32_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u32_to_u8(uint8_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint8_t>(convwb(static_cast<uint16_t>(convlw(static_cast<uint32_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u32_to_s16(int16_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int16_t>(convssslw(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u32_to_u16(uint16_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint16_t>(convssslw(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u32_to_s32(int32_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u32_to_u32(uint32_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u32_to_s64(int64_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int64_t>(convulq(static_cast<uint32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u32_to_u64(uint64_t *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint64_t>(convulq(static_cast<uint32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u32_to_f32(float *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<float>(convlf(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u32_to_f64(double *d1, const uint32_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<double>(convld(static_cast<int32_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_add_c_s64(int64_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_s64(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_s64(int64_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_s64(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_s64_to_s8(int8_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int8_t>(convssswb(static_cast<int16_t>(
        convssslw(static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_s64_to_u8(uint8_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint8_t>(convwb(static_cast<uint16_t>(
        convlw(static_cast<uint32_t>(convql(static_cast<uint64_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_s64_to_s16(int16_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int16_t>(
        convssslw(static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s64_to_u16(uint16_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint16_t>(
        convssslw(static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s64_to_s32(int32_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s64_to_u32(uint32_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(convsssql(static_cast<int64_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_s64_to_s64(int64_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int64_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s64_to_u64(uint64_t *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint64_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_s64_to_f32(float *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<float>(convlf(static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_s64_to_f64(double *d1, const int64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<double>(convld(static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_add_c_u64(uint64_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_u64(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_u64(uint64_t *d1, int p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_u64(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_u64_to_s8(int8_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int8_t>(convwb(static_cast<uint16_t>(
        convlw(static_cast<uint32_t>(convql(static_cast<uint64_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_u64_to_u8(uint8_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint8_t>(convwb(static_cast<uint16_t>(
        convlw(static_cast<uint32_t>(convql(static_cast<uint64_t>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_u64_to_s16(int16_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int16_t>(
        convssslw(static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u64_to_u16(uint16_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint16_t>(convlw(static_cast<uint32_t>(convql(static_cast<uint64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u64_to_s32(int32_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(convsssql(static_cast<int64_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u64_to_u32(uint32_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(convsssql(static_cast<int64_t>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_u64_to_s64(int64_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int64_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u64_to_u64(uint64_t *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint64_t>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_u64_to_f32(float *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<float>(convlf(static_cast<int32_t>(convql(static_cast<uint64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_u64_to_f64(double *d1, const uint64_t *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<double>(convld(static_cast<int32_t>(convql(static_cast<uint64_t>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_add_c_f32(float *d1, float p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_f32(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_f32(float *d1, float p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_f32(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_div_c_f32(float *d1, float p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = div_f32(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_f32_to_s8(int8_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int8_t>(convssswb(
        static_cast<int16_t>(convssslw(static_cast<int32_t>(convfl(static_cast<float>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_u8(uint8_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint8_t>(convwb(
        static_cast<uint16_t>(convlw(static_cast<uint32_t>(convfl(static_cast<float>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_s16(int16_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<int16_t>(convssslw(static_cast<int32_t>(convfl(static_cast<float>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_u16(uint16_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint16_t>(convssslw(static_cast<int32_t>(convfl(static_cast<float>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_s32(int32_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(convfl(static_cast<float>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_u32(uint32_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(convfl(static_cast<float>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_s64(int64_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int64_t>(convslq(static_cast<int32_t>(convfl(static_cast<float>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_u64(uint64_t *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint64_t>(convslq(static_cast<int32_t>(convfl(static_cast<float>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f32_to_f32(float *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<float>(s1[i]);
}

NNS_COMPAT_API void nns_orc_conv_f32_to_f64(double *d1, const float *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<double>(convfd(static_cast<float>(s1[i])));
}

NNS_COMPAT_API void nns_orc_add_c_f64(double *d1, double p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = add_f64(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_mul_c_f64(double *d1, double p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = mul_f64(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_div_c_f64(double *d1, double p1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = div_f64(d1[i], p1);
}

NNS_COMPAT_API void nns_orc_conv_f64_to_s8(int8_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int8_t>(convssswb(
        static_cast<int16_t>(convssslw(static_cast<int32_t>(convdl(static_cast<double>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_u8(uint8_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<uint8_t>(convwb(
        static_cast<uint16_t>(convlw(static_cast<uint32_t>(convdl(static_cast<double>(s1[i])))))));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_s16(int16_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<int16_t>(convssslw(static_cast<int32_t>(convdl(static_cast<double>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_u16(uint16_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint16_t>(convssslw(static_cast<int32_t>(convdl(static_cast<double>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_s32(int32_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<int32_t>(convdl(static_cast<double>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_u32(uint32_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<uint32_t>(convdl(static_cast<double>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_s64(int64_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] = static_cast<int64_t>(convslq(static_cast<int32_t>(convdl(static_cast<double>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_u64(uint64_t *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i)
    d1[i] =
        static_cast<uint64_t>(convslq(static_cast<int32_t>(convdl(static_cast<double>(s1[i])))));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_f32(float *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<float>(convdf(static_cast<double>(s1[i])));
}

NNS_COMPAT_API void nns_orc_conv_f64_to_f64(double *d1, const double *s1, int n) {
  for (int i = 0; i < n; ++i) d1[i] = static_cast<double>(s1[i]);
}

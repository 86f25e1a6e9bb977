/* SPDX-License-Identifier: LGPL-2.1-only */
/* NNStreamer 2.x's element-wise helpers, as its ORC-generated nnstreamer-orc.h declares them:
 * nns_orc_add_c_<t> / nns_orc_mul_c_<t> (d1[i] = d1[i] op p1, integers saturating),
 * nns_orc_div_c_f32/_f64, and nns_orc_conv_<from>_to_<to> (d1[i] = s1[i] converted) for
 * s8, u8, s16, u16, s32, u32, s64, u64, f32, f64. Exported by libnnstreamer.so. */
#ifndef NNSTREAMER_ORC_H_
#define NNSTREAMER_ORC_H_

#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

extern void nns_orc_add_c_s8(int8_t *d1, int p1, int n);
extern void nns_orc_mul_c_s8(int8_t *d1, int p1, int n);
extern void nns_orc_conv_s8_to_s8(int8_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_u8(uint8_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_s16(int16_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_u16(uint16_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_s32(int32_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_u32(uint32_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_s64(int64_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_u64(uint64_t *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_f32(float *d1, const int8_t *s1, int n);
extern void nns_orc_conv_s8_to_f64(double *d1, const int8_t *s1, int n);
extern void nns_orc_add_c_u8(uint8_t *d1, int p1, int n);
extern void nns_orc_mul_c_u8(uint8_t *d1, int p1, int n);
extern void nns_orc_conv_u8_to_s8(int8_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_u8(uint8_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_s16(int16_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_u16(uint16_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_s32(int32_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_u32(uint32_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_s64(int64_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_u64(uint64_t *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_f32(float *d1, const uint8_t *s1, int n);
extern void nns_orc_conv_u8_to_f64(double *d1, const uint8_t *s1, int n);
extern void nns_orc_add_c_s16(int16_t *d1, int p1, int n);
extern void nns_orc_mul_c_s16(int16_t *d1, int p1, int n);
extern void nns_orc_conv_s16_to_s8(int8_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_u8(uint8_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_s16(int16_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_u16(uint16_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_s32(int32_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_u32(uint32_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_s64(int64_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_u64(uint64_t *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_f32(float *d1, const int16_t *s1, int n);
extern void nns_orc_conv_s16_to_f64(double *d1, const int16_t *s1, int n);
extern void nns_orc_add_c_u16(uint16_t *d1, int p1, int n);
extern void nns_orc_mul_c_u16(uint16_t *d1, int p1, int n);
extern void nns_orc_conv_u16_to_s8(int8_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_u8(uint8_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_s16(int16_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_u16(uint16_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_s32(int32_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_u32(uint32_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_s64(int64_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_u64(uint64_t *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_f32(float *d1, const uint16_t *s1, int n);
extern void nns_orc_conv_u16_to_f64(double *d1, const uint16_t *s1, int n);
extern void nns_orc_add_c_s32(int32_t *d1, int p1, int n);
extern void nns_orc_mul_c_s32(int32_t *d1, int p1, int n);
extern void nns_orc_conv_s32_to_s8(int8_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_u8(uint8_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_s16(int16_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_u16(uint16_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_s32(int32_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_u32(uint32_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_s64(int64_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_u64(uint64_t *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_f32(float *d1, const int32_t *s1, int n);
extern void nns_orc_conv_s32_to_f64(double *d1, const int32_t *s1, int n);
extern void nns_orc_add_c_u32(uint32_t *d1, int p1, int n);
extern void nns_orc_mul_c_u32(uint32_t *d1, int p1, int n);
extern void nns_orc_conv_u32_to_s8(int8_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_u8(uint8_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_s16(int16_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_u16(uint16_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_s32(int32_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_u32(uint32_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_s64(int64_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_u64(uint64_t *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_f32(float *d1, const uint32_t *s1, int n);
extern void nns_orc_conv_u32_to_f64(double *d1, const uint32_t *s1, int n);
extern void nns_orc_add_c_s64(int64_t *d1, int p1, int n);
extern void nns_orc_mul_c_s64(int64_t *d1, int p1, int n);
extern void nns_orc_conv_s64_to_s8(int8_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_u8(uint8_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_s16(int16_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_u16(uint16_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_s32(int32_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_u32(uint32_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_s64(int64_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_u64(uint64_t *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_f32(float *d1, const int64_t *s1, int n);
extern void nns_orc_conv_s64_to_f64(double *d1, const int64_t *s1, int n);
extern void nns_orc_add_c_u64(uint64_t *d1, int p1, int n);
extern void nns_orc_mul_c_u64(uint64_t *d1, int p1, int n);
extern void nns_orc_conv_u64_to_s8(int8_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_u8(uint8_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_s16(int16_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_u16(uint16_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_s32(int32_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_u32(uint32_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_s64(int64_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_u64(uint64_t *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_f32(float *d1, const uint64_t *s1, int n);
extern void nns_orc_conv_u64_to_f64(double *d1, const uint64_t *s1, int n);
extern void nns_orc_add_c_f32(float *d1, float p1, int n);
extern void nns_orc_mul_c_f32(float *d1, float p1, int n);
extern void nns_orc_div_c_f32(float *d1, float p1, int n);
extern void nns_orc_conv_f32_to_s8(int8_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_u8(uint8_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_s16(int16_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_u16(uint16_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_s32(int32_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_u32(uint32_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_s64(int64_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_u64(uint64_t *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_f32(float *d1, const float *s1, int n);
extern void nns_orc_conv_f32_to_f64(double *d1, const float *s1, int n);
extern void nns_orc_add_c_f64(double *d1, double p1, int n);
extern void nns_orc_mul_c_f64(double *d1, double p1, int n);
extern void nns_orc_div_c_f64(double *d1, double p1, int n);
extern void nns_orc_conv_f64_to_s8(int8_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_u8(uint8_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_s16(int16_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_u16(uint16_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_s32(int32_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_u32(uint32_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_s64(int64_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_u64(uint64_t *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_f32(float *d1, const double *s1, int n);
extern void nns_orc_conv_f64_to_f64(double *d1, const double *s1, int n);

#ifdef __cplusplus
}
#endif

#endif /* NNSTREAMER_ORC_H_ */

#pragma once
// The four-lane layer (simd4.h) on armhf: NEON intrinsics. Included by simd4.h only.

#include <arm_neon.h>

#include <cstdint>

#include "kernels/common.h"

namespace sb {
namespace simd4 {

struct F4 {
  float32x4_t v;
};
struct I4 {
  int32x4_t v;
};
struct M4 {
  uint32x4_t v;  // all ones (true) or zero per lane
};
inline F4 splat(float s) { return {vdupq_n_f32(s)}; }
inline F4 make4(float x, float y, float z, float w) {
  const float a[4] = {x, y, z, w};
  return {vld1q_f32(a)};
}
inline F4 load(const float* p) { return {vld1q_f32(p)}; }
inline void store(float* p, F4 a) { vst1q_f32(p, a.v); }
inline F4 operator+(F4 a, F4 b) { return {vaddq_f32(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {vsubq_f32(a.v, b.v)}; }
inline F4 operator*(F4 a, F4 b) { return {vmulq_f32(a.v, b.v)}; }
inline F4 operator/(F4 a, F4 b) {  // ARMv7 NEON has no division: one VFP division per lane
  float x[4], y[4];
  vst1q_f32(x, a.v);
  vst1q_f32(y, b.v);
  for (int i = 0; i < 4; ++i) x[i] /= y[i];
  return {vld1q_f32(x)};
}
template <int i>
inline float lane(F4 a) {
  return vgetq_lane_f32(a.v, i);
}
template <int i>
inline F4 broadcast(F4 a) {
  return {i < 2 ? vdupq_lane_f32(vget_low_f32(a.v), i & 1) : vdupq_lane_f32(vget_high_f32(a.v), i & 1)};
}
inline F4 pairSum(F4 a, F4 b) {
  return {vcombine_f32(vpadd_f32(vget_low_f32(a.v), vget_high_f32(a.v)),
                       vpadd_f32(vget_low_f32(b.v), vget_high_f32(b.v)))};
}
inline F4 pick01(F4 a, F4 b) { return {vcombine_f32(vget_low_f32(a.v), vget_low_f32(b.v))}; }
inline F4 pick23(F4 a, F4 b) { return {vcombine_f32(vget_high_f32(a.v), vget_high_f32(b.v))}; }
inline F4 pick12(F4 a, F4 b) {
  return {vcombine_f32(vget_low_f32(vextq_f32(a.v, a.v, 1)), vget_low_f32(vextq_f32(b.v, b.v, 1)))};
}
inline F4 weights0(F4 one, F4 f) {
  const float32x2_t u = vzip_f32(vget_low_f32(one.v), vget_low_f32(f.v)).val[0];
  return {vcombine_f32(u, u)};
}
inline F4 weights1(F4 one, F4 f) {
  const float32x2_t u = vzip_f32(vget_low_f32(one.v), vget_low_f32(f.v)).val[1];
  return {vcombine_f32(u, u)};
}
inline F4 weights2(F4 one, F4 f) {
  const float32x2_t u = vzip_f32(vget_high_f32(one.v), vget_high_f32(f.v)).val[0];
  return {vcombine_f32(u, u)};
}
inline bool insideXyz(F4 a, F4 lo, F4 hi) {
  uint32x4_t m = vandq_u32(vcgeq_f32(a.v, lo.v), vcltq_f32(a.v, hi.v));
  m = vsetq_lane_u32(0xffffffffu, m, 3);
  uint32x2_t h = vand_u32(vget_low_u32(m), vget_high_u32(m));
  return (vget_lane_u32(h, 0) & vget_lane_u32(h, 1)) != 0;
}
inline float min012(F4 a) { return sbFmin(lane<0>(a), sbFmin(lane<1>(a), lane<2>(a))); }
inline F4 tsdfOf(int16x8_t pairs) {
  const int32x4_t w = vreinterpretq_s32_s16(pairs);
  return {vcvtq_f32_s32(vshrq_n_s32(vshlq_n_s32(w, 16), 16))};
}
inline F4 tsdf4(const int16_t* p) { return tsdfOf(vld1q_s16(p)); }
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) {
  return tsdfOf(vcombine_s16(vld1_s16(a), vld1_s16(b)));
}
inline I4 truncate(F4 a) { return {vcvtq_s32_f32(a.v)}; }
inline F4 toFloat(I4 a) { return {vcvtq_f32_s32(a.v)}; }
inline I4 splatInt(int s) { return {vdupq_n_s32(s)}; }
inline I4 operator+(I4 a, I4 b) { return {vaddq_s32(a.v, b.v)}; }
inline I4 operator-(I4 a, I4 b) { return {vsubq_s32(a.v, b.v)}; }
inline I4 operator^(I4 a, I4 b) { return {veorq_s32(a.v, b.v)}; }
inline I4 operator&(I4 a, I4 b) { return {vandq_s32(a.v, b.v)}; }
inline I4 shiftRight(I4 a, int s) { return {vshlq_s32(a.v, vdupq_n_s32(-s))}; }
inline I4 notGreaterEqualZero(F4 a) {
  return {vreinterpretq_s32_u32(vmvnq_u32(vcgeq_f32(a.v, vdupq_n_f32(0.0f))))};
}
inline F4 keepWhereNonZero(F4 a, F4 test) {
  const uint32x4_t zero = vceqq_f32(test.v, vdupq_n_f32(0.0f));
  return {vreinterpretq_f32_u32(vbicq_u32(vreinterpretq_u32_f32(a.v), zero))};
}
template <int i>
inline int lane(I4 a) {
  return vgetq_lane_s32(a.v, i);
}
inline M4 operator<(F4 a, F4 b) { return {vcltq_f32(a.v, b.v)}; }
inline M4 operator>(F4 a, F4 b) { return {vcgtq_f32(a.v, b.v)}; }
inline M4 operator>=(F4 a, F4 b) { return {vcgeq_f32(a.v, b.v)}; }
inline M4 operator!=(F4 a, F4 b) { return {vmvnq_u32(vceqq_f32(a.v, b.v))}; }
inline M4 operator&(M4 a, M4 b) { return {vandq_u32(a.v, b.v)}; }
inline M4 andNot(M4 a, M4 b) { return {vbicq_u32(a.v, b.v)}; }  // a and not b
inline F4 keep(M4 m, F4 a) { return {vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(a.v), m.v))}; }
inline bool any(M4 m) {
  const uint32x2_t halves = vorr_u32(vget_low_u32(m.v), vget_high_u32(m.v));
  return (vget_lane_u32(halves, 0) | vget_lane_u32(halves, 1)) != 0;
}
// Per lane sbFmin(a, b) and sbFmax(a, b) by their definition (VMIN / VMAX order signed zeros their own way).
inline F4 min(F4 a, F4 b) { return {vbslq_f32(vcltq_f32(a.v, b.v), a.v, b.v)}; }
inline F4 max(F4 a, F4 b) { return {vbslq_f32(vcgtq_f32(a.v, b.v), a.v, b.v)}; }
inline F4 select(M4 m, F4 a, F4 b) { return {vbslq_f32(m.v, a.v, b.v)}; }  // m ? a : b
inline float max012(F4 a) { return sbFmax(lane<0>(a), sbFmax(lane<1>(a), lane<2>(a))); }
inline int bits012(M4 m) {  // bit i: lane i is true (i < 3)
  return int((vgetq_lane_u32(m.v, 0) & 1u) | (vgetq_lane_u32(m.v, 1) & 2u) | (vgetq_lane_u32(m.v, 2) & 4u));
}
inline I4 count(I4 c, M4 m) { return {vsubq_s32(c.v, vreinterpretq_s32_u32(m.v))}; }  // true lanes are -1

}  // namespace simd4
}  // namespace sb

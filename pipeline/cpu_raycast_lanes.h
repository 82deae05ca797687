#pragma once
// The four-lane layer of pipeline/cpu_raycast.cpp (included there only): F4/I4 and the few operations the
// raycast needs, with SSE2 intrinsics on x86-64, NEON on armhf and plain C++ elsewhere.

#include <cstdint>
#include <cstring>

#include "kernels/common.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__ARM_NEON)
#include "pipeline/neon_f4.h"
#endif

namespace sb {
namespace raycast_lanes {

#if defined(__GNUC__)
#define SB_HOT_INLINE inline __attribute__((always_inline))
#else
#define SB_HOT_INLINE inline
#endif

// Four float lanes (F4) and four int lanes (I4). GCC's generic vectors would give SSE2 on x86-64, but on
// armhf GCC splits their float arithmetic into scalar VFP code, so each target has its intrinsics here, one
// rounded IEEE operation per lane and never contracted (-ffp-contract=off): a lane's value equals the scalar
// kernel's for the same operations in the same order. NEON flushes denormals to zero, which changes nothing
// here: the interpolation and gradient take their vector path only 1 voxel or more inside the volume, where
// the weights f and 1 - f are multiples of 2^-23, so every product and sum of their three blending levels is a
// multiple of 2^-69 (0 or far above the denormal range); the ray's s = sOrigin + t sDirection would need a
// direction component below 1e-37 to reach it.
#if defined(__SSE2__)
struct F4 {
  __m128 v;
};
struct I4 {
  __m128i v;
};
inline F4 splat(float s) { return {_mm_set1_ps(s)}; }
inline F4 make4(float x, float y, float z, float w) { return {_mm_setr_ps(x, y, z, w)}; }
inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
inline F4 operator/(F4 a, F4 b) { return {_mm_div_ps(a.v, b.v)}; }
inline void store4(float* p, F4 a) { _mm_storeu_ps(p, a.v); }
template <int i>
inline float lane(F4 a) {
  return _mm_cvtss_f32(_mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(i, i, i, i)));
}
template <int i>
inline F4 broadcast(F4 a) {
  return {_mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(i, i, i, i))};
}
// [a0 + a1, a2 + a3, b0 + b1, b2 + b3]
inline F4 pairSum(F4 a, F4 b) {
  return {_mm_add_ps(_mm_shuffle_ps(a.v, b.v, _MM_SHUFFLE(2, 0, 2, 0)),
                     _mm_shuffle_ps(a.v, b.v, _MM_SHUFFLE(3, 1, 3, 1)))};
}
inline F4 pick01(F4 a, F4 b) { return {_mm_movelh_ps(a.v, b.v)}; }  // [a0, a1, b0, b1]
inline F4 pick23(F4 a, F4 b) { return {_mm_movehl_ps(b.v, a.v)}; }  // [a2, a3, b2, b3]
inline F4 pick12(F4 a, F4 b) { return {_mm_shuffle_ps(a.v, b.v, _MM_SHUFFLE(2, 1, 2, 1))}; }  // [a1, a2, b1, b2]
// [1 - f0, f0, 1 - f0, f0] etc. from f and 1 - f.
inline F4 weights0(F4 one, F4 f) {
  const __m128 u = _mm_unpacklo_ps(one.v, f.v);
  return {_mm_movelh_ps(u, u)};
}
inline F4 weights1(F4 one, F4 f) {
  const __m128 u = _mm_unpacklo_ps(one.v, f.v);
  return {_mm_movehl_ps(u, u)};
}
inline F4 weights2(F4 one, F4 f) {
  const __m128 u = _mm_unpackhi_ps(one.v, f.v);
  return {_mm_movelh_ps(u, u)};
}
// Lanes 0-2 of a are >= lo and < hi (false for NaN).
inline bool insideXyz(F4 a, F4 lo, F4 hi) {
  return (_mm_movemask_ps(_mm_and_ps(_mm_cmpge_ps(a.v, lo.v), _mm_cmplt_ps(a.v, hi.v))) & 7) == 7;
}
// sbFmin(a0, sbFmin(a1, a2)): MINSS is `a < b ? a : b`, sbFmin's definition.
inline float min012(F4 a) {
  const __m128 yz = _mm_min_ss(_mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(1, 1, 1, 1)),
                               _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(2, 2, 2, 2)));
  return _mm_cvtss_f32(_mm_min_ss(a.v, yz));
}
// The tsdf (even shorts, sign-extended) of 8 shorts: 4 voxels.
inline F4 tsdfOf(__m128i pairs) { return {_mm_cvtepi32_ps(_mm_srai_epi32(_mm_slli_epi32(pairs, 16), 16))}; }
// The tsdf of voxels p, p + 1, p + 2, p + 3 (x fastest).
inline F4 tsdf4(const int16_t* p) { return tsdfOf(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p))); }
// The tsdf of voxels a, a + 1, b, b + 1.
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) {
  return tsdfOf(_mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(a)),
                                   _mm_loadl_epi64(reinterpret_cast<const __m128i*>(b))));
}
inline I4 truncate(F4 a) { return {_mm_cvttps_epi32(a.v)}; }  // toward zero, as (int)
inline F4 toFloat(I4 a) { return {_mm_cvtepi32_ps(a.v)}; }
inline I4 splatInt(int s) { return {_mm_set1_epi32(s)}; }
inline I4 operator+(I4 a, I4 b) { return {_mm_add_epi32(a.v, b.v)}; }
inline I4 operator-(I4 a, I4 b) { return {_mm_sub_epi32(a.v, b.v)}; }
inline I4 operator^(I4 a, I4 b) { return {_mm_xor_si128(a.v, b.v)}; }
inline I4 operator&(I4 a, I4 b) { return {_mm_and_si128(a.v, b.v)}; }
inline I4 shiftRight(I4 a, int s) { return {_mm_sra_epi32(a.v, _mm_cvtsi32_si128(s))}; }
inline I4 notGreaterEqualZero(F4 a) { return {_mm_castps_si128(_mm_cmpnge_ps(a.v, _mm_setzero_ps()))}; }
inline F4 keepWhereNonZero(F4 a, F4 test) { return {_mm_and_ps(a.v, _mm_cmpneq_ps(test.v, _mm_setzero_ps()))}; }
template <int i>
inline int lane(I4 a) {
  return _mm_cvtsi128_si32(_mm_shuffle_epi32(a.v, _MM_SHUFFLE(i, i, i, i)));
}
#elif defined(__ARM_NEON)
using neon4::F4;  // and its arithmetic (pipeline/neon_f4.h)
using neon4::splat;
struct I4 {
  int32x4_t v;
};
inline F4 make4(float x, float y, float z, float w) {
  const float a[4] = {x, y, z, w};
  return {vld1q_f32(a)};
}
inline void store4(float* p, F4 a) { vst1q_f32(p, a.v); }
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
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) { return tsdfOf(vcombine_s16(vld1_s16(a), vld1_s16(b))); }
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
#else
struct F4 {
  float v[4];
};
struct I4 {
  int32_t v[4];
};
inline F4 splat(float s) { return {{s, s, s, s}}; }
inline F4 make4(float x, float y, float z, float w) { return {{x, y, z, w}}; }
inline F4 operator+(F4 a, F4 b) { return {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2], a.v[3] + b.v[3]}}; }
inline F4 operator-(F4 a, F4 b) { return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}}; }
inline F4 operator*(F4 a, F4 b) { return {{a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2], a.v[3] * b.v[3]}}; }
inline F4 operator/(F4 a, F4 b) { return {{a.v[0] / b.v[0], a.v[1] / b.v[1], a.v[2] / b.v[2], a.v[3] / b.v[3]}}; }
inline void store4(float* p, F4 a) { std::memcpy(p, a.v, sizeof a.v); }
template <int i>
inline float lane(F4 a) {
  return a.v[i];
}
template <int i>
inline F4 broadcast(F4 a) {
  return splat(a.v[i]);
}
inline F4 pairSum(F4 a, F4 b) { return {{a.v[0] + a.v[1], a.v[2] + a.v[3], b.v[0] + b.v[1], b.v[2] + b.v[3]}}; }
inline F4 pick01(F4 a, F4 b) { return {{a.v[0], a.v[1], b.v[0], b.v[1]}}; }
inline F4 pick23(F4 a, F4 b) { return {{a.v[2], a.v[3], b.v[2], b.v[3]}}; }
inline F4 pick12(F4 a, F4 b) { return {{a.v[1], a.v[2], b.v[1], b.v[2]}}; }
inline F4 weights0(F4 one, F4 f) { return {{one.v[0], f.v[0], one.v[0], f.v[0]}}; }
inline F4 weights1(F4 one, F4 f) { return {{one.v[1], f.v[1], one.v[1], f.v[1]}}; }
inline F4 weights2(F4 one, F4 f) { return {{one.v[2], f.v[2], one.v[2], f.v[2]}}; }
inline bool insideXyz(F4 a, F4 lo, F4 hi) {
  bool inside = true;
  for (int i = 0; i < 3; ++i) inside = inside && a.v[i] >= lo.v[i] && a.v[i] < hi.v[i];
  return inside;
}
inline float min012(F4 a) { return sbFmin(a.v[0], sbFmin(a.v[1], a.v[2])); }
inline F4 tsdf4(const int16_t* p) { return {{float(p[0]), float(p[2]), float(p[4]), float(p[6])}}; }
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) { return {{float(a[0]), float(a[2]), float(b[0]), float(b[2])}}; }
inline I4 truncate(F4 a) { return {{int32_t(a.v[0]), int32_t(a.v[1]), int32_t(a.v[2]), int32_t(a.v[3])}}; }
inline F4 toFloat(I4 a) { return {{float(a.v[0]), float(a.v[1]), float(a.v[2]), float(a.v[3])}}; }
inline I4 splatInt(int s) { return {{s, s, s, s}}; }
inline I4 operator+(I4 a, I4 b) { return {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2], a.v[3] + b.v[3]}}; }
inline I4 operator-(I4 a, I4 b) { return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}}; }
inline I4 operator^(I4 a, I4 b) { return {{a.v[0] ^ b.v[0], a.v[1] ^ b.v[1], a.v[2] ^ b.v[2], a.v[3] ^ b.v[3]}}; }
inline I4 operator&(I4 a, I4 b) { return {{a.v[0] & b.v[0], a.v[1] & b.v[1], a.v[2] & b.v[2], a.v[3] & b.v[3]}}; }
inline I4 shiftRight(I4 a, int s) { return {{a.v[0] >> s, a.v[1] >> s, a.v[2] >> s, a.v[3] >> s}}; }
inline I4 notGreaterEqualZero(F4 a) {
  return {{a.v[0] >= 0.0f ? 0 : -1, a.v[1] >= 0.0f ? 0 : -1, a.v[2] >= 0.0f ? 0 : -1, a.v[3] >= 0.0f ? 0 : -1}};
}
inline F4 keepWhereNonZero(F4 a, F4 test) {
  F4 r = a;
  for (int i = 0; i < 4; ++i) r.v[i] = test.v[i] != 0.0f ? a.v[i] : 0.0f;
  return r;
}
template <int i>
inline int lane(I4 a) {
  return a.v[i];
}
#endif

}  // namespace raycast_lanes
}  // namespace sb

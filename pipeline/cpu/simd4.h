#pragma once
// The CPU backend's four-lane layer (the one SIMD layer of pipeline/cpu/): F4 (four floats), I4 (four int32)
// and M4 (four lane masks, all ones for true), with the operations track (cpu_track.cpp) and raycast
// (cpu_raycast.cpp) need. Three implementations of the same operations:
//   SSE2 intrinsics on x86-64, NEON intrinsics on armhf, plain C++ elsewhere (the portable scalar path).
// GCC's generic vectors would give SSE2 on x86-64, but on armhf GCC splits their float arithmetic into scalar
// VFP code (it keeps NEON, which flushes denormals, for -ffast-math), hence the intrinsics. Every float
// operation is one rounded IEEE operation per lane and never contracted (-ffp-contract=off): a lane's value
// equals the scalar kernel's (kernels/) for the same operations in the same order, which the bit-identity
// tests check (tests/pipeline/test_cpu_track.cpp, test_cpu_raycast.cpp). NEON flushes denormals to zero;
// cpu_track.cpp and cpu_raycast.cpp say why that changes nothing in their use.
// cpu_integrate.cpp keeps GCC's generic vectors (see there), as the one exception.

#include <cstdint>
#include <cstring>

#include "kernels/common.h"

#if defined(__SSE2__)
#include <emmintrin.h>
#elif defined(__ARM_NEON)
#include <arm_neon.h>
#endif

// SB_SIMD_CLONES: x86-64 builds of a function for AVX2 and for the baseline, picked at load time by the CPU
// (GCC function multiversioning). The lanes make the same IEEE operations either way (no FMA contraction:
// -ffp-contract=off), so results do not depend on the clone; elsewhere (armhf) one build.
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__)
#define SB_SIMD_CLONES __attribute__((target_clones("avx2", "default")))
#else
#define SB_SIMD_CLONES
#endif

#if defined(__GNUC__)
#define SB_HOT_INLINE inline __attribute__((always_inline))
#else
#define SB_HOT_INLINE inline
#endif

namespace sb {
namespace simd4 {

#if defined(__SSE2__)
struct F4 {
  __m128 v;
};
struct I4 {
  __m128i v;
};
struct M4 {
  __m128 v;  // all ones (true) or zero per lane
};
inline F4 splat(float s) {
  return {_mm_set1_ps(s)};
}
inline F4 make4(float x, float y, float z, float w) {
  return {_mm_setr_ps(x, y, z, w)};
}
inline F4 load(const float* p) {
  return {_mm_loadu_ps(p)};
}
inline void store(float* p, F4 a) {
  _mm_storeu_ps(p, a.v);
}
inline F4 operator+(F4 a, F4 b) {
  return {_mm_add_ps(a.v, b.v)};
}
inline F4 operator-(F4 a, F4 b) {
  return {_mm_sub_ps(a.v, b.v)};
}
inline F4 operator*(F4 a, F4 b) {
  return {_mm_mul_ps(a.v, b.v)};
}
inline F4 operator/(F4 a, F4 b) {
  return {_mm_div_ps(a.v, b.v)};
}
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
inline F4 pick01(F4 a, F4 b) {
  return {_mm_movelh_ps(a.v, b.v)};
}  // [a0, a1, b0, b1]
inline F4 pick23(F4 a, F4 b) {
  return {_mm_movehl_ps(b.v, a.v)};
}  // [a2, a3, b2, b3]
inline F4 pick12(F4 a, F4 b) {
  return {_mm_shuffle_ps(a.v, b.v, _MM_SHUFFLE(2, 1, 2, 1))};
}  // [a1, a2, b1, b2]
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
inline F4 tsdfOf(__m128i pairs) {
  return {_mm_cvtepi32_ps(_mm_srai_epi32(_mm_slli_epi32(pairs, 16), 16))};
}
// The tsdf of voxels p, p + 1, p + 2, p + 3 (x fastest).
inline F4 tsdf4(const int16_t* p) {
  return tsdfOf(_mm_loadu_si128(reinterpret_cast<const __m128i*>(p)));
}
// The tsdf of voxels a, a + 1, b, b + 1.
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) {
  return tsdfOf(_mm_unpacklo_epi64(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(a)),
                                   _mm_loadl_epi64(reinterpret_cast<const __m128i*>(b))));
}
inline I4 truncate(F4 a) {
  return {_mm_cvttps_epi32(a.v)};
}  // toward zero, as (int)
inline F4 toFloat(I4 a) {
  return {_mm_cvtepi32_ps(a.v)};
}
inline I4 splatInt(int s) {
  return {_mm_set1_epi32(s)};
}
inline I4 operator+(I4 a, I4 b) {
  return {_mm_add_epi32(a.v, b.v)};
}
inline I4 operator-(I4 a, I4 b) {
  return {_mm_sub_epi32(a.v, b.v)};
}
inline I4 operator^(I4 a, I4 b) {
  return {_mm_xor_si128(a.v, b.v)};
}
inline I4 operator&(I4 a, I4 b) {
  return {_mm_and_si128(a.v, b.v)};
}
inline I4 shiftRight(I4 a, int s) {
  return {_mm_sra_epi32(a.v, _mm_cvtsi32_si128(s))};
}
inline I4 notGreaterEqualZero(F4 a) {
  return {_mm_castps_si128(_mm_cmpnge_ps(a.v, _mm_setzero_ps()))};
}
inline F4 keepWhereNonZero(F4 a, F4 test) {
  return {_mm_and_ps(a.v, _mm_cmpneq_ps(test.v, _mm_setzero_ps()))};
}
template <int i>
inline int lane(I4 a) {
  return _mm_cvtsi128_si32(_mm_shuffle_epi32(a.v, _MM_SHUFFLE(i, i, i, i)));
}
inline M4 operator<(F4 a, F4 b) {
  return {_mm_cmplt_ps(a.v, b.v)};
}
inline M4 operator>(F4 a, F4 b) {
  return {_mm_cmpgt_ps(a.v, b.v)};
}
inline M4 operator>=(F4 a, F4 b) {
  return {_mm_cmpge_ps(a.v, b.v)};
}
inline M4 operator!=(F4 a, F4 b) {
  return {_mm_cmpneq_ps(a.v, b.v)};
}
inline M4 operator&(M4 a, M4 b) {
  return {_mm_and_ps(a.v, b.v)};
}
inline M4 andNot(M4 a, M4 b) {
  return {_mm_andnot_ps(b.v, a.v)};
}  // a and not b
inline F4 keep(M4 m, F4 a) {
  return {_mm_and_ps(a.v, m.v)};
}  // a where m, +0 elsewhere
inline bool any(M4 m) {
  return _mm_movemask_ps(m.v) != 0;
}
inline I4 count(I4 c, M4 m) {
  return {_mm_sub_epi32(c.v, _mm_castps_si128(m.v))};
}  // true lanes are -1
#elif defined(__ARM_NEON)
struct F4 {
  float32x4_t v;
};
struct I4 {
  int32x4_t v;
};
struct M4 {
  uint32x4_t v;  // all ones (true) or zero per lane
};
inline F4 splat(float s) {
  return {vdupq_n_f32(s)};
}
inline F4 make4(float x, float y, float z, float w) {
  const float a[4] = {x, y, z, w};
  return {vld1q_f32(a)};
}
inline F4 load(const float* p) {
  return {vld1q_f32(p)};
}
inline void store(float* p, F4 a) {
  vst1q_f32(p, a.v);
}
inline F4 operator+(F4 a, F4 b) {
  return {vaddq_f32(a.v, b.v)};
}
inline F4 operator-(F4 a, F4 b) {
  return {vsubq_f32(a.v, b.v)};
}
inline F4 operator*(F4 a, F4 b) {
  return {vmulq_f32(a.v, b.v)};
}
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
inline F4 pick01(F4 a, F4 b) {
  return {vcombine_f32(vget_low_f32(a.v), vget_low_f32(b.v))};
}
inline F4 pick23(F4 a, F4 b) {
  return {vcombine_f32(vget_high_f32(a.v), vget_high_f32(b.v))};
}
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
inline float min012(F4 a) {
  return sbFmin(lane<0>(a), sbFmin(lane<1>(a), lane<2>(a)));
}
inline F4 tsdfOf(int16x8_t pairs) {
  const int32x4_t w = vreinterpretq_s32_s16(pairs);
  return {vcvtq_f32_s32(vshrq_n_s32(vshlq_n_s32(w, 16), 16))};
}
inline F4 tsdf4(const int16_t* p) {
  return tsdfOf(vld1q_s16(p));
}
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) {
  return tsdfOf(vcombine_s16(vld1_s16(a), vld1_s16(b)));
}
inline I4 truncate(F4 a) {
  return {vcvtq_s32_f32(a.v)};
}
inline F4 toFloat(I4 a) {
  return {vcvtq_f32_s32(a.v)};
}
inline I4 splatInt(int s) {
  return {vdupq_n_s32(s)};
}
inline I4 operator+(I4 a, I4 b) {
  return {vaddq_s32(a.v, b.v)};
}
inline I4 operator-(I4 a, I4 b) {
  return {vsubq_s32(a.v, b.v)};
}
inline I4 operator^(I4 a, I4 b) {
  return {veorq_s32(a.v, b.v)};
}
inline I4 operator&(I4 a, I4 b) {
  return {vandq_s32(a.v, b.v)};
}
inline I4 shiftRight(I4 a, int s) {
  return {vshlq_s32(a.v, vdupq_n_s32(-s))};
}
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
inline M4 operator<(F4 a, F4 b) {
  return {vcltq_f32(a.v, b.v)};
}
inline M4 operator>(F4 a, F4 b) {
  return {vcgtq_f32(a.v, b.v)};
}
inline M4 operator>=(F4 a, F4 b) {
  return {vcgeq_f32(a.v, b.v)};
}
inline M4 operator!=(F4 a, F4 b) {
  return {vmvnq_u32(vceqq_f32(a.v, b.v))};
}
inline M4 operator&(M4 a, M4 b) {
  return {vandq_u32(a.v, b.v)};
}
inline M4 andNot(M4 a, M4 b) {
  return {vbicq_u32(a.v, b.v)};
}  // a and not b
inline F4 keep(M4 m, F4 a) {
  return {vreinterpretq_f32_u32(vandq_u32(vreinterpretq_u32_f32(a.v), m.v))};
}
inline bool any(M4 m) {
  const uint32x2_t halves = vorr_u32(vget_low_u32(m.v), vget_high_u32(m.v));
  return (vget_lane_u32(halves, 0) | vget_lane_u32(halves, 1)) != 0;
}
inline I4 count(I4 c, M4 m) {
  return {vsubq_s32(c.v, vreinterpretq_s32_u32(m.v))};
}  // true lanes are -1
#else
struct F4 {
  float v[4];
};
struct I4 {
  int32_t v[4];
};
struct M4 {
  int32_t v[4];  // -1 (true) or 0 per lane
};
inline F4 splat(float s) {
  return {{s, s, s, s}};
}
inline F4 make4(float x, float y, float z, float w) {
  return {{x, y, z, w}};
}
inline F4 load(const float* p) {
  return {{p[0], p[1], p[2], p[3]}};
}
inline void store(float* p, F4 a) {
  std::memcpy(p, a.v, sizeof a.v);
}
inline F4 operator+(F4 a, F4 b) {
  return {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2], a.v[3] + b.v[3]}};
}
inline F4 operator-(F4 a, F4 b) {
  return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}};
}
inline F4 operator*(F4 a, F4 b) {
  return {{a.v[0] * b.v[0], a.v[1] * b.v[1], a.v[2] * b.v[2], a.v[3] * b.v[3]}};
}
inline F4 operator/(F4 a, F4 b) {
  return {{a.v[0] / b.v[0], a.v[1] / b.v[1], a.v[2] / b.v[2], a.v[3] / b.v[3]}};
}
template <int i>
inline float lane(F4 a) {
  return a.v[i];
}
template <int i>
inline F4 broadcast(F4 a) {
  return splat(a.v[i]);
}
inline F4 pairSum(F4 a, F4 b) {
  return {{a.v[0] + a.v[1], a.v[2] + a.v[3], b.v[0] + b.v[1], b.v[2] + b.v[3]}};
}
inline F4 pick01(F4 a, F4 b) {
  return {{a.v[0], a.v[1], b.v[0], b.v[1]}};
}
inline F4 pick23(F4 a, F4 b) {
  return {{a.v[2], a.v[3], b.v[2], b.v[3]}};
}
inline F4 pick12(F4 a, F4 b) {
  return {{a.v[1], a.v[2], b.v[1], b.v[2]}};
}
inline F4 weights0(F4 one, F4 f) {
  return {{one.v[0], f.v[0], one.v[0], f.v[0]}};
}
inline F4 weights1(F4 one, F4 f) {
  return {{one.v[1], f.v[1], one.v[1], f.v[1]}};
}
inline F4 weights2(F4 one, F4 f) {
  return {{one.v[2], f.v[2], one.v[2], f.v[2]}};
}
inline bool insideXyz(F4 a, F4 lo, F4 hi) {
  bool inside = true;
  for (int i = 0; i < 3; ++i) inside = inside && a.v[i] >= lo.v[i] && a.v[i] < hi.v[i];
  return inside;
}
inline float min012(F4 a) {
  return sbFmin(a.v[0], sbFmin(a.v[1], a.v[2]));
}
inline F4 tsdf4(const int16_t* p) {
  return {{float(p[0]), float(p[2]), float(p[4]), float(p[6])}};
}
inline F4 tsdf2x2(const int16_t* a, const int16_t* b) {
  return {{float(a[0]), float(a[2]), float(b[0]), float(b[2])}};
}
inline I4 truncate(F4 a) {
  return {{int32_t(a.v[0]), int32_t(a.v[1]), int32_t(a.v[2]), int32_t(a.v[3])}};
}
inline F4 toFloat(I4 a) {
  return {{float(a.v[0]), float(a.v[1]), float(a.v[2]), float(a.v[3])}};
}
inline I4 splatInt(int s) {
  return {{s, s, s, s}};
}
inline I4 operator+(I4 a, I4 b) {
  return {{a.v[0] + b.v[0], a.v[1] + b.v[1], a.v[2] + b.v[2], a.v[3] + b.v[3]}};
}
inline I4 operator-(I4 a, I4 b) {
  return {{a.v[0] - b.v[0], a.v[1] - b.v[1], a.v[2] - b.v[2], a.v[3] - b.v[3]}};
}
inline I4 operator^(I4 a, I4 b) {
  return {{a.v[0] ^ b.v[0], a.v[1] ^ b.v[1], a.v[2] ^ b.v[2], a.v[3] ^ b.v[3]}};
}
inline I4 operator&(I4 a, I4 b) {
  return {{a.v[0] & b.v[0], a.v[1] & b.v[1], a.v[2] & b.v[2], a.v[3] & b.v[3]}};
}
inline I4 shiftRight(I4 a, int s) {
  return {{a.v[0] >> s, a.v[1] >> s, a.v[2] >> s, a.v[3] >> s}};
}
inline I4 notGreaterEqualZero(F4 a) {
  return {
      {a.v[0] >= 0.0f ? 0 : -1, a.v[1] >= 0.0f ? 0 : -1, a.v[2] >= 0.0f ? 0 : -1, a.v[3] >= 0.0f ? 0 : -1}};
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
inline M4 operator<(F4 a, F4 b) {
  return {{-(a.v[0] < b.v[0]), -(a.v[1] < b.v[1]), -(a.v[2] < b.v[2]), -(a.v[3] < b.v[3])}};
}
inline M4 operator>(F4 a, F4 b) {
  return {{-(a.v[0] > b.v[0]), -(a.v[1] > b.v[1]), -(a.v[2] > b.v[2]), -(a.v[3] > b.v[3])}};
}
inline M4 operator>=(F4 a, F4 b) {
  return {{-(a.v[0] >= b.v[0]), -(a.v[1] >= b.v[1]), -(a.v[2] >= b.v[2]), -(a.v[3] >= b.v[3])}};
}
inline M4 operator!=(F4 a, F4 b) {
  return {{-(a.v[0] != b.v[0]), -(a.v[1] != b.v[1]), -(a.v[2] != b.v[2]), -(a.v[3] != b.v[3])}};
}
inline M4 operator&(M4 a, M4 b) {
  return {{a.v[0] & b.v[0], a.v[1] & b.v[1], a.v[2] & b.v[2], a.v[3] & b.v[3]}};
}
inline M4 andNot(M4 a, M4 b) {
  return {{a.v[0] & ~b.v[0], a.v[1] & ~b.v[1], a.v[2] & ~b.v[2], a.v[3] & ~b.v[3]}};
}
inline F4 keep(M4 m, F4 a) {  // the bits of a where m, +0 elsewhere
  F4 r;
  for (int i = 0; i < 4; ++i) r.v[i] = m.v[i] ? a.v[i] : 0.0f;
  return r;
}
inline bool any(M4 m) {
  return (m.v[0] | m.v[1] | m.v[2] | m.v[3]) != 0;
}
inline I4 count(I4 c, M4 m) {
  return {{c.v[0] - m.v[0], c.v[1] - m.v[1], c.v[2] - m.v[2], c.v[3] - m.v[3]}};
}
#endif

// Operations written once over the ones above.
inline int laneSum(I4 c) {
  return lane<0>(c) + lane<1>(c) + lane<2>(c) + lane<3>(c);
}
// Pixel indices v * w + u of the lanes where m holds (u, v >= 0, integral floats), 0 elsewhere.
inline void pixelIndices(M4 m, F4 u, F4 v, int w, int32_t out[4]) {
  const I4 iu = truncate(keep(m, u)), iv = truncate(keep(m, v));
#if defined(__ARM_NEON) && !defined(__SSE2__)
  vst1q_s32(out, vaddq_s32(vmulq_n_s32(iv.v, w), iu.v));
#else  // SSE2 has no 32-bit lane product
  out[0] = lane<0>(iv) * w + lane<0>(iu);
  out[1] = lane<1>(iv) * w + lane<1>(iu);
  out[2] = lane<2>(iv) * w + lane<2>(iu);
  out[3] = lane<3>(iv) * w + lane<3>(iu);
#endif
}
// Four float3 (12 floats) as x, y and z lanes.
inline void load3(const float* p, F4& x, F4& y, F4& z) {
#if defined(__ARM_NEON) && !defined(__SSE2__)
  const float32x4x3_t t = vld3q_f32(p);
  x = {t.val[0]};
  y = {t.val[1]};
  z = {t.val[2]};
#else
  x = make4(p[0], p[3], p[6], p[9]);
  y = make4(p[1], p[4], p[7], p[10]);
  z = make4(p[2], p[5], p[8], p[11]);
#endif
}
// The float3 at four indices as x, y and z lanes.
inline void gather3(const float* p, const int32_t index[4], F4& x, F4& y, F4& z) {
#if defined(__ARM_NEON) && !defined(__SSE2__)
  float32x4x3_t t = {{vdupq_n_f32(0.0f), vdupq_n_f32(0.0f), vdupq_n_f32(0.0f)}};
  t = vld3q_lane_f32(p + 3 * index[0], t, 0);
  t = vld3q_lane_f32(p + 3 * index[1], t, 1);
  t = vld3q_lane_f32(p + 3 * index[2], t, 2);
  t = vld3q_lane_f32(p + 3 * index[3], t, 3);
  x = {t.val[0]};
  y = {t.val[1]};
  z = {t.val[2]};
#else
  const float *a = p + 3 * index[0], *b = p + 3 * index[1], *c = p + 3 * index[2], *d = p + 3 * index[3];
  x = make4(a[0], b[0], c[0], d[0]);
  y = make4(a[1], b[1], c[1], d[1]);
  z = make4(a[2], b[2], c[2], d[2]);
#endif
}

}  // namespace simd4
}  // namespace sb

#pragma once
// The four-lane layer (simd4.h) on x86-64: SSE2 intrinsics. Included by simd4.h only.

#include <emmintrin.h>

#include <cstdint>

#include "kernels/common.h"

namespace sb {
namespace simd4 {

struct F4 {
  __m128 v;
};
struct I4 {
  __m128i v;
};
struct M4 {
  __m128 v;  // all ones (true) or zero per lane
};
inline F4 splat(float s) { return {_mm_set1_ps(s)}; }
inline F4 make4(float x, float y, float z, float w) { return {_mm_setr_ps(x, y, z, w)}; }
inline F4 load(const float* p) { return {_mm_loadu_ps(p)}; }
inline void store(float* p, F4 a) { _mm_storeu_ps(p, a.v); }
inline F4 operator+(F4 a, F4 b) { return {_mm_add_ps(a.v, b.v)}; }
inline F4 operator-(F4 a, F4 b) { return {_mm_sub_ps(a.v, b.v)}; }
inline F4 operator*(F4 a, F4 b) { return {_mm_mul_ps(a.v, b.v)}; }
inline F4 operator/(F4 a, F4 b) { return {_mm_div_ps(a.v, b.v)}; }
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
inline F4 keepWhereNonZero(F4 a, F4 test) {
  return {_mm_and_ps(a.v, _mm_cmpneq_ps(test.v, _mm_setzero_ps()))};
}
template <int i>
inline int lane(I4 a) {
  return _mm_cvtsi128_si32(_mm_shuffle_epi32(a.v, _MM_SHUFFLE(i, i, i, i)));
}
inline M4 operator<(F4 a, F4 b) { return {_mm_cmplt_ps(a.v, b.v)}; }
inline M4 operator>(F4 a, F4 b) { return {_mm_cmpgt_ps(a.v, b.v)}; }
inline M4 operator>=(F4 a, F4 b) { return {_mm_cmpge_ps(a.v, b.v)}; }
inline M4 operator!=(F4 a, F4 b) { return {_mm_cmpneq_ps(a.v, b.v)}; }
inline M4 operator&(M4 a, M4 b) { return {_mm_and_ps(a.v, b.v)}; }
inline M4 andNot(M4 a, M4 b) { return {_mm_andnot_ps(b.v, a.v)}; }  // a and not b
inline F4 keep(M4 m, F4 a) { return {_mm_and_ps(a.v, m.v)}; }       // a where m, +0 elsewhere
inline bool any(M4 m) { return _mm_movemask_ps(m.v) != 0; }
// Per lane sbFmin(a, b) and sbFmax(a, b): MINPS / MAXPS are `a < b ? a : b` and `a > b ? a : b`.
inline F4 min(F4 a, F4 b) { return {_mm_min_ps(a.v, b.v)}; }
inline F4 max(F4 a, F4 b) { return {_mm_max_ps(a.v, b.v)}; }
inline F4 select(M4 m, F4 a, F4 b) { return {_mm_or_ps(_mm_and_ps(m.v, a.v), _mm_andnot_ps(m.v, b.v))}; }  // m ? a : b
// sbFmax(a0, sbFmax(a1, a2)).
inline float max012(F4 a) {
  const __m128 yz = _mm_max_ss(_mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(1, 1, 1, 1)),
                               _mm_shuffle_ps(a.v, a.v, _MM_SHUFFLE(2, 2, 2, 2)));
  return _mm_cvtss_f32(_mm_max_ss(a.v, yz));
}
inline int bits012(M4 m) { return _mm_movemask_ps(m.v) & 7; }  // bit i: lane i is true (i < 3)
inline I4 count(I4 c, M4 m) { return {_mm_sub_epi32(c.v, _mm_castps_si128(m.v))}; }  // true lanes are -1

}  // namespace simd4
}  // namespace sb

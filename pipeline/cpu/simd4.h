#pragma once
// The CPU backend's four-lane layer (the one SIMD layer of pipeline/cpu/): F4 (four floats), I4 (four int32)
// and M4 (four lane masks, all ones for true), with the operations track (cpu_track.cpp) and raycast
// (cpu_raycast.cpp) need. Three implementations of the same operations:
//   SSE2 intrinsics on x86-64, NEON intrinsics on armhf, plain C++ elsewhere (the portable scalar path).
// GCC's generic vectors would give SSE2 on x86-64, but on armhf GCC splits their float arithmetic into scalar
// VFP code (it keeps NEON, which flushes denormals, for -ffast-math), hence the intrinsics. Every float
// operation is one rounded IEEE operation per lane and never contracted (-ffp-contract=off): a lane's value
// equals the scalar kernel's (kernels/) for the same operations in the same order, which the bit-identity
// tests check (tests/pipeline/cpu/test_cpu_track.cpp, test_cpu_raycast.cpp). NEON flushes denormals to zero;
// cpu_track.cpp and cpu_raycast.cpp say why that changes nothing in their use.
// cpu_integrate.cpp keeps GCC's generic vectors (see there), as the one exception. SB_SIMD4_PORTABLE selects
// the plain C++ path on any target (test_cpu_portable runs the bit-identity tests over it).

#include <cstdint>

#include "kernels/common.h"

#if defined(SB_SIMD4_PORTABLE)
#define SB_SIMD4_SSE2 0
#define SB_SIMD4_NEON 0
#include "pipeline/cpu/simd4_portable.h"
#elif defined(__SSE2__)
#define SB_SIMD4_SSE2 1
#define SB_SIMD4_NEON 0
#include "pipeline/cpu/simd4_sse2.h"
#elif defined(__ARM_NEON)
#define SB_SIMD4_SSE2 0
#define SB_SIMD4_NEON 1
#include "pipeline/cpu/simd4_neon.h"
#else
#define SB_SIMD4_SSE2 0
#define SB_SIMD4_NEON 0
#include "pipeline/cpu/simd4_portable.h"
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

// Operations written once over the per-target ones (simd4_sse2.h, simd4_neon.h, simd4_portable.h).
inline int laneSum(I4 c) { return lane<0>(c) + lane<1>(c) + lane<2>(c) + lane<3>(c); }
// Pixel indices v * w + u of the lanes where m holds (u, v >= 0, integral floats), 0 elsewhere.
inline void pixelIndices(M4 m, F4 u, F4 v, int w, int32_t out[4]) {
  const I4 iu = truncate(keep(m, u)), iv = truncate(keep(m, v));
#if SB_SIMD4_NEON
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
#if SB_SIMD4_NEON
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
#if SB_SIMD4_NEON
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
